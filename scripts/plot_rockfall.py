#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""plot_rockfall: one figure of a rockfall Monte Carlo from the CSV files of rockfall_stats.

    python3 scripts/plot_rockfall.py out/rockfall                  # -> out/rockfall/rockfall.png
    python3 scripts/plot_rockfall.py out/rockfall -o fig.pdf --trajectories 5 --logy-energy

DIR is the directory that `rockfall_stats.write(records, analysis, DIR)` filled
(rockfall.stats, scripts/lib/rockfall/stats/; columns in docs/rockfall-statistics.md). The figure has up to
four panels sharing the x axis, and a fifth with its own:
  1. the slope profile (profile.csv: x,y), a few trajectories (trajectories.csv: rock,t,x,y,
     when present), the end points coloured by stop rule (endpoints.csv), collector and barrier
     lines (collectors.csv, barriers.csv);
  2. the end-point histogram (endpoint_hist.csv) and the reach probability with its Wilson
     interval (reach.csv), the end-point percentiles p50/p95/p99 as vertical lines
     (endpoint_percentiles.csv);
  3. the bounce-height envelope: mean, median and 95 % quantile per bin, each quantile with its
     order-statistic confidence band (envelopes.csv);
  4. the total kinetic-energy envelope, the same way;
  5. catchment retention: the percentage of the rocks retained within a distance of the toe
     (Pierson et al. 2001's cumulative curve) with its Wilson band (retention.csv), named
     catchments shaded with their retention (catchments.csv).
Missing optional files (profile, trajectories, envelopes, collectors, barriers, retention)
leave their part out. Cells written `nan` (no rock in a bin, an interval side out of reach) leave gaps; a
band is shaded only where both sides exist, and a lone lower bound is drawn as a dotted line.

Errors (missing directory or required file, unknown output type) are printed on stderr as
"plot_rockfall: error: ..." with exit status 2. As a module, load_results(DIR) returns the
tables read (dict of file stem -> dict of column -> list) without plotting.
"""

import argparse
import csv
import math
import os
import sys
from typing import Dict, List, Optional, Sequence

from plot_history import ensure_matplotlib  # the same tools directory

OUTPUT_TYPES = (".png", ".pdf", ".svg")
REQUIRED = ("endpoints", "endpoint_hist", "reach")
OPTIONAL = ("endpoint_percentiles", "envelopes", "collectors", "barriers", "profile",
            "trajectories", "stops", "angles", "retention", "catchments")
STOP_COLOURS = {"rest": "C2", "left": "C3", "time": "C1", "barrier": "C4"}


class PlotError(Exception):
    pass


def _value(text: str):
    """A float for numeric cells (nan, inf included), NaN for blanks, else the string."""
    t = text.strip()
    if t == "":
        return math.nan
    try:
        return float(t)
    except ValueError:
        return t


def read_table(path: str) -> Dict[str, list]:
    """Columns of a CSV file with a header row: name -> list of values (floats or strings)."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r]
    if not rows:
        raise PlotError(f"{path}: empty file (no header)")
    header = rows[0]
    cols: Dict[str, list] = {h: [] for h in header}
    for n, r in enumerate(rows[1:], start=2):
        if len(r) != len(header):
            raise PlotError(f"{path}:{n}: {len(r)} cells, header has {len(header)}")
        for h, c in zip(header, r):
            cols[h].append(_value(c))
    return cols


def load_results(directory: str) -> Dict[str, Dict[str, list]]:
    """The tables rockfall_stats wrote into `directory` (required ones must exist)."""
    if not os.path.isdir(directory):
        raise PlotError(f"'{directory}' is not a directory (give the outdir of "
                        "rockfall_stats.write)")
    out: Dict[str, Dict[str, list]] = {}
    for stem in REQUIRED + OPTIONAL:
        path = os.path.join(directory, stem + ".csv")
        if os.path.exists(path):
            out[stem] = read_table(path)
        elif stem in REQUIRED:
            raise PlotError(f"{path}: missing (rockfall_stats.write writes it)")
    return out


def _finite(v) -> bool:
    return isinstance(v, float) and math.isfinite(v)


def _col(table: Dict[str, list], name: str, stem: str) -> list:
    if name not in table:
        raise PlotError(f"{stem}.csv: no column '{name}' (columns: {', '.join(table)})")
    return table[name]


def _band(ax, x, mid, lo, hi, colour, label):
    """A quantile line with its confidence band (shaded where both sides exist; a lone
    lower bound dotted)."""
    ax.plot(x, mid, color=colour, linewidth=1.6, marker=".", label=label)
    both = [_finite(a) and _finite(b) for a, b in zip(lo, hi)]
    if any(both):
        ax.fill_between(x, [a if w else math.nan for a, w in zip(lo, both)],
                        [b if w else math.nan for b, w in zip(hi, both)], where=both,
                        color=colour, alpha=0.2, linewidth=0, label=f"{label} CI")
    lone = [a if (_finite(a) and not _finite(b)) else math.nan for a, b in zip(lo, hi)]
    if any(_finite(v) for v in lone):
        ax.plot(x, lone, color=colour, linestyle=":", linewidth=1.0,
                label=f"{label} lower bound (no upper)")


def _retention_panel(ax, ret, catchments):
    """Retained [%] against the distance from the toe, with its band; named catchments shaded."""
    dist = _col(ret, "distance", "retention")
    pct = [100 * v if _finite(v) else math.nan for v in _col(ret, "fraction", "retention")]
    lo = [100 * v if _finite(v) else math.nan for v in _col(ret, "ci_lo", "retention")]
    hi = [100 * v if _finite(v) else math.nan for v in _col(ret, "ci_hi", "retention")]
    _band(ax, dist, pct, lo, hi, "C2", "retained")
    toe = _col(ret, "x", "retention")[0] if dist else math.nan
    if catchments:
        for k, (name, a, b, f) in enumerate(zip(_col(catchments, "catchment", "catchments"),
                                                 _col(catchments, "x_from", "catchments"),
                                                 _col(catchments, "x_to", "catchments"),
                                                 _col(catchments, "fraction", "catchments"))):
            if not (_finite(a) and _finite(b) and _finite(toe)):
                continue
            d0, d1 = sorted((abs(a - toe), abs(b - toe)))
            ax.axvspan(d0, d1, color=f"C{(k + 4) % 10}", alpha=0.15, linewidth=0)
            ax.annotate(f"{name}: {100 * f:.1f} %" if _finite(f) else str(name),
                        (0.5 * (d0 + d1), 0.03), xycoords=("data", "axes fraction"),
                        ha="center", fontsize=7)
    low = [v for v in lo + pct if _finite(v)]
    ax.set_ylim(max(0.0, min(low) - 5) if low else 0.0, 101)
    # The curve up to where it levels off (every rock retained, or the most there are), and a
    # half again beyond: the flat rest of a long run-out says nothing more.
    top = max((v for v in pct if _finite(v)), default=math.nan)
    full = next((d for d, v in zip(dist, pct) if _finite(v) and v >= top), None)
    if full is not None and dist and full > 0:
        ax.set_xlim(0, min(dist[-1], 1.5 * full))
    ax.set_xlabel(f"distance from the toe (x = {toe:g} m) [m]" if _finite(toe)
                  else "distance from the toe [m]")
    ax.set_ylabel("retained [%]")
    ax.grid(True, linewidth=0.3)
    ax.legend(fontsize=7, loc="lower right")


def plot(results: Dict[str, Dict[str, list]], output: str, title: Optional[str] = None,
         trajectories: int = 10, logy_energy: bool = False, dpi: int = 120) -> str:
    ext = os.path.splitext(output)[1].lower()
    if ext not in OUTPUT_TYPES:
        raise PlotError(f"output '{output}': unknown type '{ext or '(none)'}' "
                        f"(use {', '.join(OUTPUT_TYPES)})")
    import matplotlib
    matplotlib.use("Agg")  # no display: files only
    import matplotlib.pyplot as plt
    matplotlib.rcParams["svg.hashsalt"] = "talus"

    env = results.get("envelopes")
    ret = results.get("retention")
    nshared = 4 if env else 2
    npanel = nshared + (1 if ret else 0)
    fig, all_axes = plt.subplots(npanel, 1, figsize=(10, 3.0 * npanel), squeeze=False,
                                 constrained_layout=True)
    all_axes = list(all_axes[:, 0])
    axes = all_axes[:nshared]
    for ax in axes[1:]:
        ax.sharex(axes[0])
    ep = results["endpoints"]
    n = len(ep.get("rock", []))

    # 1. profile, trajectories, end points, lines
    ax = axes[0]
    prof = results.get("profile")
    if prof:
        px, py = _col(prof, "x", "profile"), _col(prof, "y", "profile")
        ax.plot(px, py, color="k", linewidth=1.5, label="profile")
        ax.fill_between(px, py, min(py) - 0.05 * (max(py) - min(py) + 1), color="0.85")
    traj = results.get("trajectories")
    if traj and trajectories > 0:
        rocks = _col(traj, "rock", "trajectories")
        tx, ty = _col(traj, "x", "trajectories"), _col(traj, "y", "trajectories")
        order: List = []
        for r in rocks:
            if r not in order:
                order.append(r)
        for k, rock in enumerate(order[:trajectories]):
            xs = [x for r, x in zip(rocks, tx) if r == rock]
            ys = [y for r, y in zip(rocks, ty) if r == rock]
            ax.plot(xs, ys, linewidth=0.8, color=f"C{k % 10}", alpha=0.8,
                    label="trajectories" if k == 0 else None)
    stops = _col(ep, "stop", "endpoints")
    ex, ey = _col(ep, "end_x", "endpoints"), _col(ep, "end_y", "endpoints")
    for rule in sorted(set(s for s in stops if isinstance(s, str))):
        sel = [i for i, s in enumerate(stops) if s == rule]
        ax.plot([ex[i] for i in sel], [ey[i] for i in sel], linestyle="none", marker="o",
                markersize=3, color=STOP_COLOURS.get(rule, "C7"),
                label=f"end: {rule} ({len(sel)})")
    for stem, style, colour in (("collectors", "--", "C0"), ("barriers", "-", "C4")):
        t = results.get(stem)
        if not t:
            continue
        names = _col(t, stem[:-1], stem)
        xs = _col(t, "x", stem)
        seen = set()
        for name, x in zip(names, xs):
            if name in seen or not _finite(x):
                continue
            seen.add(name)
            ax.axvline(x, color=colour, linestyle=style, linewidth=1.0)
            ax.annotate(str(name), (x, 1.0), xycoords=("data", "axes fraction"),
                        xytext=(2, -10), textcoords="offset points", fontsize=7, color=colour)
    ax.set_ylabel("y [m]")
    ax.set_title(title or f"Rockfall: {n} rocks")
    ax.legend(fontsize=7, loc="upper right")

    # 2. end-point histogram and reach probability
    ax = axes[1]
    h = results["endpoint_hist"]
    lo, hi = _col(h, "x_lo", "endpoint_hist"), _col(h, "x_hi", "endpoint_hist")
    counts = _col(h, "count", "endpoint_hist")
    if lo:
        ax.bar(lo, counts, width=[b - a for a, b in zip(lo, hi)], align="edge", color="C0",
               alpha=0.6, edgecolor="C0", label="end points")
    ax.set_ylabel("rocks per bin")
    pc = results.get("endpoint_percentiles")
    if pc:
        for p, x in zip(_col(pc, "p", "endpoint_percentiles"),
                        _col(pc, "end_x", "endpoint_percentiles")):
            if p in (0.5, 0.95, 0.99) and _finite(x):
                ax.axvline(x, color="k", linestyle=":", linewidth=0.9)
                ax.annotate(f"p{int(round(p * 100))}", (x, 0.95),
                            xycoords=("data", "axes fraction"), fontsize=7,
                            xytext=(2, 0), textcoords="offset points")
    r = results["reach"]
    ax2 = ax.twinx()
    rx = _col(r, "x", "reach")
    _band(ax2, rx, _col(r, "reach", "reach"), _col(r, "ci_lo", "reach"),
          _col(r, "ci_hi", "reach"), "C3", "reach probability")
    ax2.set_ylim(-0.02, 1.02)
    ax2.set_ylabel("reach probability")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper right")

    # 3, 4. envelopes
    if env:
        x = _col(env, "x_mid", "envelopes")
        for ax, q, unit, name in ((axes[2], "height", "m", "bounce height"),
                                  (axes[3], "ke", "J", "kinetic energy")):
            ax.plot(x, _col(env, f"{q}_mean", "envelopes"), color="0.4", linestyle="--",
                    linewidth=1.0, label="mean")
            _band(ax, x, _col(env, f"{q}_median", "envelopes"),
                  _col(env, f"{q}_median_lo", "envelopes"),
                  _col(env, f"{q}_median_hi", "envelopes"), "C0", "median")
            _band(ax, x, _col(env, f"{q}_q95", "envelopes"),
                  _col(env, f"{q}_q95_lo", "envelopes"), _col(env, f"{q}_q95_hi", "envelopes"),
                  "C3", "95 %")
            ax.set_ylabel(f"{name} [{unit}]")
            if q == "ke" and logy_energy:
                vals = [v for v in _col(env, "ke_q95", "envelopes") if _finite(v) and v > 0]
                if vals:
                    ax.set_yscale("log")
            ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("x [m]")
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    if ret:
        _retention_panel(all_axes[-1], ret, results.get("catchments"))
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    fig.savefig(output, dpi=dpi, metadata={"Software": None} if ext == ".png" else None)
    plt.close(fig)
    return output


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(
        prog="plot_rockfall.py",
        description="Plot the statistics CSV files of a rockfall Monte Carlo "
        "(rockfall_stats.write).")
    p.add_argument("dir", metavar="DIR", help="directory of the CSV files")
    p.add_argument("-o", "--output", help="output file, .png/.pdf/.svg (default DIR/rockfall.png)")
    p.add_argument("--title", help="figure title")
    p.add_argument("--trajectories", type=int, default=10, metavar="N",
                   help="draw at most N trajectories from trajectories.csv (default 10)")
    p.add_argument("--logy-energy", action="store_true", help="log scale for the energy panel")
    p.add_argument("--dpi", type=int, default=120)
    a = p.parse_args(argv)
    if argv is None:
        ensure_matplotlib(__file__)
    try:
        results = load_results(a.dir)
        out = plot(results, a.output or os.path.join(a.dir, "rockfall.png"), a.title,
                   a.trajectories, a.logy_energy, a.dpi)
    except (PlotError, OSError) as e:
        print(f"plot_rockfall: error: {e}", file=sys.stderr)
        return 2
    print(f"plot_rockfall: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
