#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""plot_calibration: plot a multi-target calibration (material.calibrate's CSV) with matplotlib.

    python3 scripts/plot_calibration.py out/calib.csv -o out/calib.png

Reads CSV (one row per evaluated point: index, batch, phase, the parameters, each output with
its sd over seeds, misfit, met, best) and CSV_targets.csv beside it (name, value, tol, weight),
both written by material.calibrate (docs/material.md, "Calibration against several targets").
Draws one panel per target: the output of every point against the point's number, with its
scatter over seeds as an error bar, the target as a line and its tolerance as a band; the
design's points are circles, the steps squares, the best point a star; and a last panel with
the misfit (log scale). A point whose tests gave no value for a target (a tensile strength where
no Brazilian disk split: tensile_valid 0) is drawn as a red cross at the foot of that panel and of
the misfit panel, labelled "not measured". PNG, PDF or SVG by the extension of -o.

Errors (missing file, no rows, a target with no column) are printed on stderr as
"plot_calibration: error: ..." with exit status 2.
"""

import argparse
import csv
import math
import os
import sys

UNITS = {"E": (1e-9, "GPa"), "E_elastic": (1e-9, "GPa"), "ucs": (1e-6, "MPa"), "tensile": (1e-6, "MPa"),
         "nu": (1, ""), "nu_elastic": (1, ""), "phi": (1, "deg"), "ratio": (1, "")}
LABELS = {"E": "E", "nu": "ν", "E_elastic": "E (elastic part)", "nu_elastic": "ν (elastic part)", "ucs": "UCS",
          "tensile": "σ_t", "ratio": "UCS/σ_t", "phi": "φ"}


class PlotError(Exception):
    pass


def number(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return math.nan
    return v if math.isfinite(v) else math.nan


def load(path):
    """The rows of a calibration CSV (dicts of strings) and its targets [(name, value, tol)]."""
    if not os.path.isfile(path):
        raise PlotError(f"no such file: {path}")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise PlotError(f"{path}: no rows")
    tpath = path[:-4] + "_targets.csv" if path.endswith(".csv") else path + "_targets.csv"
    if not os.path.isfile(tpath):
        raise PlotError(f"no targets file beside {path}: {tpath}")
    with open(tpath, newline="") as f:
        targets = [(r["name"], number(r["value"]), number(r["tol"])) for r in csv.DictReader(f)]
    for name, _, _ in targets:
        if name not in rows[0]:
            raise PlotError(f"{path}: no column '{name}' for the target '{name}'")
    return rows, targets


def unmeasured(rows, name):
    """The rows that have no value of output `name` (a point without a valid tensile strength)."""
    return [i for i, r in enumerate(rows) if math.isnan(number(r.get(name)))]


def plot(rows, targets, out, title=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(targets) + 1
    fig, axes = plt.subplots(n, 1, figsize=(7, 1.9 * n + 0.6), sharex=True)
    idx = [int(number(r["index"])) for r in rows]
    phase = [r["phase"] for r in rows]
    best = [r.get("best") == "1" for r in rows]
    for ax, (name, value, tol) in zip(axes, targets):
        scale, unit = UNITS.get(name, (1, ""))
        ys = [number(r[name]) * scale for r in rows]
        sds = [number(r.get(name + "_sd")) * scale for r in rows]
        ax.axhspan(value * scale * (1 - tol), value * scale * (1 + tol), color="0.88", lw=0)
        ax.axhline(value * scale, color="0.4", lw=1, ls="--")
        for marker, which in (("o", "design"), ("s", "step")):
            sel = [i for i, p in enumerate(phase) if p == which]
            if sel:
                ax.errorbar([idx[i] for i in sel], [ys[i] for i in sel],
                            yerr=[0 if math.isnan(sds[i]) else sds[i] for i in sel], fmt=marker, ms=5,
                            capsize=2, color="C0" if which == "design" else "C1", label=which)
        for i, b in enumerate(best):
            if b:
                ax.plot(idx[i], ys[i], "*", ms=14, color="C3", label="best")
        missing = unmeasured(rows, name)
        if missing:
            # at the foot of the panel (axes coordinates in y): no value to draw
            ax.plot([idx[i] for i in missing], [0.04] * len(missing), "x", ms=8, mew=2, color="C3",
                    transform=ax.get_xaxis_transform(), label="not measured")
            ax.legend(loc="best", fontsize=7)
        ax.set_ylabel(f"{LABELS.get(name, name)} [{unit}]" if unit else LABELS.get(name, name))
    axes[0].legend(loc="best", fontsize=8)
    mis = [number(r["misfit"]) for r in rows]
    axes[-1].semilogy(idx, mis, "k.-")
    nomis = [i for i, m in enumerate(mis) if math.isnan(m)]
    if nomis:
        axes[-1].plot([idx[i] for i in nomis], [0.04] * len(nomis), "x", ms=8, mew=2, color="C3",
                      transform=axes[-1].get_xaxis_transform(), label="a target not measured")
        axes[-1].legend(loc="best", fontsize=7)
    axes[-1].set_ylabel("misfit")
    axes[-1].set_xlabel("point")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=120, metadata={"Software": None} if out.endswith(".png") else None)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description="plot a material.calibrate CSV")
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--title")
    a = ap.parse_args(argv)
    try:
        if not a.output.endswith((".png", ".pdf", ".svg")):
            raise PlotError(f"unknown output type: {a.output} (.png, .pdf, .svg)")
        rows, targets = load(a.csv)
        plot(rows, targets, a.output, a.title)
    except PlotError as e:
        print(f"plot_calibration: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
