#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""plot_history: plot history CSV files written by talus (m:history) with matplotlib.

One command, PNG or PDF (or SVG) by the extension of -o:

    python3 scripts/plot_history.py out/h.csv -o out/h.png
    python3 scripts/plot_history.py a.csv b.csv -o cmp.pdf --columns kinetic,slip --logy
    python3 scripts/plot_history.py out/h.csv -o path.png --x x --columns y --equal

Columns (docs/plotting.md):
  - by default every *energy* column of each file (kinetic, body, slip, ..., balance_error, and
    group-wise forms such as kinetic@rock or kinetic[rock]), against time (or step when a file
    has no time column);
  - --columns a,b,... names columns literally as the header spells them (any name, so group
    columns like `kinetic@rock` or `kinetic[rock]` work as written); a header cell written as
    "name [unit]" may also be named by "name" alone;
  - --x time | step | <column> picks the abscissa.

Panels (--panels, default "group"): one panel per group, all sharing the time axis: the
model's own columns (kinetic, body, ...) in the panel "all bodies", each group's columns
(kinetic@rock, ...) in a panel named after the group, and every balance_error column in a panel
of its own below (its size is a check of the run, not one more energy, and on the energies' axis
it would be a flat line at 0). Columns that belong to no group and are not energies (x, y, ...)
share the first panel. --panels one draws every series on one axis. Within a figure each
series has its own look: colour and dash pattern cycle together (10 colours x 4 dashes, then
markers), and the same column of the same file keeps its look from panel to panel. --describe
prints the panels drawn (JSON: title, axis labels, and each line's label, colour and dashes).

Units: talus's history header holds column names only; the units of talus's own quantities
follow from the name (time and dt in s, energies in J, step a count), and a user column whose
header reads "name [unit]" carries its own unit. Both go into the axis labels.

Cells that are blank, non-numeric, NaN or infinite leave a gap in the line; they never stop the
plot (an isolated point between gaps is drawn as a dot). Log axes: --logy uses a log scale when
every plotted value is > 0; when some are <= 0 (balance_error, energies that start at 0) it
uses a symmetric log scale (linear within +-linthresh, see --linthresh) so that signs and zeros
stay visible instead of being dropped. --logx works the same way on the abscissa.

Errors (missing file, unknown column, no numeric data, unknown output type) are printed on
stderr as "plot_history: error: ..." naming the file and column, with exit status 2.

As a module, load_series() returns the selected series (with NaN for gaps) without plotting.
"""

import argparse
import csv
import math
import os
import re
import sys
from dataclasses import dataclass, field
from typing import List, Optional, Sequence

# The energy items a talus history can record (docs/lua-api.md, "Histories"), all in joules.
# "exchanged" is the per-group item; listing it early costs nothing.
ENERGY_ITEMS = (
    "kinetic", "body", "boundary", "strain", "bond", "slip", "dashpot", "plastic", "damping",
    "released", "deleted", "initial_kinetic", "initial_strain", "placement", "balance_error",
    "exchanged", "script",
)
# Units of talus's other built-in columns.
BUILTIN_UNITS = {"time": "s", "dt": "s", "step": ""}

# "name [unit]" (a space before the bracket): a unit given in the header itself.
_UNIT_RE = re.compile(r"^(?P<name>.*\S)\s+\[(?P<unit>[^\[\]]*)\]$")
# Group-wise forms of an energy item: kinetic@rock, kinetic[rock], kinetic:rock.
_GROUP_RE = re.compile(r"^(?P<item>[A-Za-z_]+)(?:@(?P<at>.+)|\[(?P<br>[^\]]*)\]|:(?P<co>.+))$")

OUTPUT_TYPES = (".png", ".pdf", ".svg")


class PlotError(Exception):
    """A user error: reported on stderr with exit status 2."""


@dataclass
class Column:
    header: str  # the header cell, literally
    name: str    # without a " [unit]" suffix
    unit: str    # "" when unknown or dimensionless
    energy: bool
    group: str = ""  # kinetic@rock, kinetic[rock], kinetic:rock -> "rock"
    item: str = ""   # kinetic@rock -> "kinetic"; the name for other columns


@dataclass
class Series:
    file: str
    column: str        # header cell of the y column
    label: str         # legend entry
    x_column: str
    x_unit: str
    unit: str
    energy: bool
    x: List[float] = field(default_factory=list)
    y: List[float] = field(default_factory=list)
    name: str = ""     # the y column's name without its " [unit]" (the axis label adds the unit)
    group: str = ""    # the group of a group-wise energy column (kinetic@rock -> rock), else ""
    item: str = ""     # the energy item (kinetic@rock -> kinetic), else the name


def describe_column(header: str) -> Column:
    """Name, unit and kind of one header cell."""
    name, unit = header, None
    m = _UNIT_RE.match(header)
    if m:
        name, unit = m.group("name"), m.group("unit")
    item, group = name, ""
    g = _GROUP_RE.match(name)
    if g and g.group("item") in ENERGY_ITEMS:
        item = g.group("item")
        group = g.group("at") or g.group("br") or g.group("co") or ""
    energy = item in ENERGY_ITEMS
    if unit is None:
        unit = "J" if energy else BUILTIN_UNITS.get(name, "")
    return Column(header=header, name=name, unit=unit, energy=energy, group=group, item=item)


def _number(cell: str) -> float:
    """A finite float, or NaN for anything else (blank, text, nan, inf)."""
    try:
        v = float(cell)
    except ValueError:
        return math.nan
    return v if math.isfinite(v) else math.nan


def read_csv(path: str):
    """Returns (columns, data): the described header and one list of floats per header cell."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = [r for r in csv.reader(f) if any(c.strip() for c in r)]
    except OSError as e:
        raise PlotError(f"cannot read '{path}' ({e.strerror or e})") from None
    except (UnicodeDecodeError, csv.Error) as e:
        raise PlotError(f"'{path}' is not a CSV text file ({e})") from None
    if not rows:
        raise PlotError(f"'{path}' is empty (no header row)")
    columns = [describe_column(c.strip()) for c in rows[0]]
    data = [[_number(r[k].strip()) if k < len(r) else math.nan for r in rows[1:]]
            for k in range(len(columns))]
    return columns, data


def _find(columns: Sequence[Column], spec: str, path: str, what: str) -> int:
    """Index of the column named `spec`: the header cell literally, else its name without unit."""
    spec = spec.strip()
    for k, c in enumerate(columns):
        if c.header == spec:
            return k
    hits = [k for k, c in enumerate(columns) if c.name == spec]
    if len(hits) == 1:
        return hits[0]
    known = ", ".join(c.header for c in columns)
    raise PlotError(f"'{path}' has no {what} column '{spec}' (columns: {known})")


def _split_columns(text: Optional[str]) -> Optional[List[str]]:
    """--columns a,b,c; commas inside [...] (a unit or a group list) do not split."""
    if text is None:
        return None
    out, depth, cur = [], 0, ""
    for ch in text:
        depth += (ch == "[") - (ch == "]")
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    out.append(cur)
    out = [c.strip() for c in out if c.strip()]
    return out or None


def load_series(paths: Sequence[str], columns: Optional[Sequence[str]] = None,
                x: Optional[str] = None) -> List[Series]:
    """The series to plot: for each file, each selected column against the x column.

    columns=None selects every energy column of each file; x=None picks time, else step, else
    the first column. Values that are not finite numbers are NaN (gaps)."""
    if not paths:
        raise PlotError("no input file")
    series: List[Series] = []
    basenames = [os.path.basename(p) for p in paths]
    # Legends name the file by its base name, or by its path when two base names are equal.
    names = basenames if len(set(basenames)) == len(basenames) else list(paths)
    for path, fname in zip(paths, names):
        cols, data = read_csv(path)
        if x is not None:
            xi = _find(cols, x, path, "x")
        else:
            headers = [c.header for c in cols]
            xi = headers.index("time") if "time" in headers else (
                headers.index("step") if "step" in headers else 0)
        if columns is None:
            ys = [k for k, c in enumerate(cols) if c.energy and k != xi]
            if not ys:
                known = ", ".join(c.header for c in cols)
                raise PlotError(f"'{path}' has no energy column (columns: {known}); "
                                "choose columns with --columns")
        else:
            ys = [_find(cols, spec, path, "y") for spec in columns]
        xcol = cols[xi]
        if not any(math.isfinite(v) for v in data[xi]):
            raise PlotError(f"column '{xcol.header}' of '{path}' has no numeric data")
        for k in ys:
            c = cols[k]
            if not any(math.isfinite(v) for v in data[k]):
                raise PlotError(f"column '{c.header}' of '{path}' has no numeric data")
            label = c.header if len(paths) == 1 else f"{fname}: {c.header}"
            series.append(Series(file=path, column=c.header, label=label, x_column=xcol.name,
                                 x_unit=xcol.unit, unit=c.unit, energy=c.energy,
                                 x=list(data[xi]), y=list(data[k]), name=c.name,
                                 group=c.group, item=c.item))
    return series


def _axis_label(names: Sequence[str], units: Sequence[str], energies: bool) -> str:
    """'energy [J]' for energies, 'x, y [m]' for one shared unit, 'vx [m/s], spin' otherwise."""
    if energies:
        return "energy [J]"
    uniq_names = list(dict.fromkeys(names))
    uniq_units = list(dict.fromkeys(units))
    if len(uniq_units) == 1:
        return ", ".join(uniq_names) + (f" [{uniq_units[0]}]" if uniq_units[0] else "")
    pairs = list(dict.fromkeys(f"{n} [{u}]" if u else n for n, u in zip(names, units)))
    return ", ".join(pairs)


def x_label(series: Sequence[Series]) -> str:
    """The x axis label: 'time [s]'."""
    return _axis_label([s.x_column for s in series], [s.x_unit for s in series], False)


def y_label(series: Sequence[Series]) -> str:
    """The y axis label: 'energy [J]', 'stress_axial [Pa]' (the unit once, also when the header
    cell carries it), 'vx [m/s], spin'."""
    return _axis_label([s.name or s.column for s in series], [s.unit for s in series],
                       all(s.energy for s in series))


def _linthresh(values: Sequence[float]) -> float:
    """Symlog linear range: the smallest non-zero |value|, but at least 1e-9 of the largest, so
    a balance error of 1e-8 J shows next to 1e4 J of kinetic energy (13 decades at most)."""
    mags = [abs(v) for v in values if math.isfinite(v) and v != 0.0]
    if not mags:
        return 1.0
    return max(min(mags), 1e-9 * max(mags))


def _set_log(ax, which: str, values: Sequence[float], linthresh: Optional[float]) -> str:
    finite = [v for v in values if math.isfinite(v)]
    setter = ax.set_yscale if which == "y" else ax.set_xscale
    if finite and min(finite) > 0.0:
        setter("log")
        return "log"
    setter("symlog", linthresh=linthresh or _linthresh(finite))
    return "symlog"


ALL_PANEL = "all bodies"
BALANCE_PANEL = "energy balance error"
_COLOURS = 10
_DASHES = ("-", "--", "-.", ":")
_MARKERS = ("o", "s", "^", "v", "D", "x", "+")


def panels(series: Sequence[Series], mode: str = "group") -> List[tuple]:
    """The panels to draw: a list of (name, [series index, ...]).

    mode "one": a single panel with every series. mode "group": the model's columns first
    ("all bodies", with every column that names no group), then one panel per group in the order
    the groups first appear, then every balance_error column in a panel of its own."""
    if mode == "one":
        return [("", list(range(len(series))))]
    if mode != "group":
        raise PlotError(f"--panels must be 'group' or 'one' (got '{mode}')")
    members: dict = {}
    for k, s in enumerate(series):
        key = BALANCE_PANEL if s.item == "balance_error" else (s.group or ALL_PANEL)
        members.setdefault(key, []).append(k)
    order = ([ALL_PANEL] if ALL_PANEL in members else []) + \
        [g for g in members if g not in (ALL_PANEL, BALANCE_PANEL)] + \
        ([BALANCE_PANEL] if BALANCE_PANEL in members else [])
    return [(name, members[name]) for name in order]


def line_style(k: int) -> dict:
    """Style number k: colour and dash pattern cycle together (10 x 4 looks), then a marker."""
    style = {"color": f"C{k % _COLOURS}",
             "linestyle": _DASHES[(k // _COLOURS) % len(_DASHES)]}
    rounds = k // (_COLOURS * len(_DASHES))
    if rounds:
        style.update(marker=_MARKERS[(rounds - 1) % len(_MARKERS)], markevery=0.1,
                     markersize=4)
    return style


def assign_styles(series: Sequence[Series], layout: Sequence[tuple]) -> List[int]:
    """A style number per series: the same file and item keep one look in every panel (kinetic
    of the model and kinetic@rock alike), and no two series of one panel share a look."""
    by_key: dict = {}
    styles = [0] * len(series)
    fresh = 0
    for _, idx in layout:
        used = set()
        for k in idx:
            s = series[k]
            key = (s.file, s.item or s.column)
            n = by_key.get(key)
            if n is None or n in used:
                while fresh in used or fresh in by_key.values():
                    fresh += 1
                n = fresh
                by_key.setdefault(key, n)
            used.add(n)
            styles[k] = n
    return styles


def _panel_label(s: Series, name: str) -> str:
    """A series' legend entry: the item alone in a group's panel (the title names the group)."""
    if name in ("", ALL_PANEL, BALANCE_PANEL) or not s.group:
        return s.label
    # "a.csv: kinetic@rock" -> "a.csv: kinetic"
    return s.label[:len(s.label) - len(s.column)] + s.item


def _draw_series(ax, s: Series, label: str, style: dict) -> None:
    ax.plot(s.x, s.y, linewidth=1.4, label=label, **style)
    # A point with gaps on both sides draws no line segment: mark it.
    lone = [i for i in range(len(s.y))
            if math.isfinite(s.x[i]) and math.isfinite(s.y[i])
            and (i == 0 or not (math.isfinite(s.y[i - 1]) and math.isfinite(s.x[i - 1])))
            and (i + 1 == len(s.y)
                 or not (math.isfinite(s.y[i + 1]) and math.isfinite(s.x[i + 1])))]
    if lone:
        ax.plot([s.x[i] for i in lone], [s.y[i] for i in lone], linestyle="none",
                marker="o", markersize=3, color=style["color"])


def describe_figure(fig) -> List[dict]:
    """What the figure shows, panel by panel: title, axis labels and each labelled line's label,
    colour (hex) and dash pattern (--describe prints it as JSON)."""
    from matplotlib.colors import to_hex
    out = []
    for ax in fig.axes:
        lines = [{"label": ln.get_label(), "color": to_hex(ln.get_color()),
                  "linestyle": ln.get_linestyle(), "marker": str(ln.get_marker())}
                 for ln in ax.get_lines() if not ln.get_label().startswith("_")]
        out.append({"title": ax.get_title(), "xlabel": ax.get_xlabel(),
                    "ylabel": ax.get_ylabel(), "lines": lines})
    return out


def plot(series: Sequence[Series], output: str, title: Optional[str] = None,
         logx: bool = False, logy: bool = False, linthresh: Optional[float] = None,
         equal: bool = False, xlabel: Optional[str] = None, ylabel: Optional[str] = None,
         size=None, dpi: int = 120, panel_mode: str = "group",
         describe: Optional[list] = None) -> str:
    """Draws the series into `output` (.png, .pdf or .svg), one panel per group (panels());
    returns the path. `describe`: a list that receives describe_figure() of the figure."""
    ext = os.path.splitext(output)[1].lower()
    if ext not in OUTPUT_TYPES:
        raise PlotError(f"output '{output}': unknown type '{ext or '(none)'}' "
                        f"(use {', '.join(OUTPUT_TYPES)})")
    layout = panels(series, panel_mode)
    import matplotlib
    matplotlib.use("Agg")  # no display: files only
    import matplotlib.pyplot as plt
    # Deterministic files: fixed SVG ids, no dates or version strings in the metadata.
    matplotlib.rcParams["svg.hashsalt"] = "talus"
    matplotlib.rcParams["path.simplify"] = True

    n = len(layout)
    if size is None:
        size = (8.0, 5.0) if n == 1 else (8.0, 1.2 + 2.6 * n)
    fig, axes = plt.subplots(n, 1, figsize=size, sharex=True, squeeze=False)
    axes = list(axes[:, 0])
    styles = assign_styles(series, layout)
    notes = []
    for ax, (name, idx) in zip(axes, layout):
        members = [series[k] for k in idx]
        for k in idx:
            _draw_series(ax, series[k], _panel_label(series[k], name), line_style(styles[k]))
        if logy:
            kind = _set_log(ax, "y", [v for s in members for v in s.y], linthresh)
            if kind == "symlog" and "symlog y" not in notes:
                notes.append("symlog y")
        if equal:
            ax.set_aspect("equal", adjustable="datalim")
        if name == BALANCE_PANEL:
            ax.set_ylabel("balance error [J]")
        else:
            ax.set_ylabel(ylabel or y_label(members))
        if n > 1:
            ax.set_title(name if name in (ALL_PANEL, BALANCE_PANEL) else f"group {name}",
                         fontsize="medium")
        ax.grid(True, color="#e5e5e5", linewidth=0.8)
        if len(members) > 1:
            ax.legend(loc="best", fontsize="small", ncol=1 if len(members) <= 6 else 2)
    if logx:
        kind = _set_log(axes[-1], "x", [v for s in series for v in s.x], linthresh)
        if kind == "symlog":
            notes.append("symlog x")
    axes[-1].set_xlabel(xlabel or x_label(series))
    if title:
        if n == 1:
            axes[0].set_title(title)
        else:
            fig.suptitle(title)
    fig.tight_layout()
    if describe is not None:
        describe.extend(describe_figure(fig))
    meta = {"png": {"Software": None},
            "pdf": {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None},
            "svg": {"Date": None, "Creator": None}}[ext[1:]]
    try:
        fig.savefig(output, dpi=dpi, metadata=meta)
    except OSError as e:
        raise PlotError(f"cannot write '{output}' ({e.strerror or e})") from None
    finally:
        plt.close(fig)
    for note in notes:
        print(f"plot_history: {note}: some values are <= 0, so the axis is symmetric-log "
              "(linear near 0)", file=sys.stderr)
    return output


def _size(text: str):
    try:
        w, h = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected W,H in inches, got '{text}'") from None
    if w <= 0 or h <= 0:
        raise argparse.ArgumentTypeError(f"W and H must be > 0, got '{text}'")
    return (w, h)


def ensure_matplotlib(script: str) -> None:
    """Debian's python3-matplotlib is visible to Debian's /usr/bin/python3 only. When another
    python3 comes first on PATH (pyenv, a venv) and has no matplotlib, run `script` (the
    calling tool's __file__) again with /usr/bin/python3 (once: the environment variable stops a
    loop). Shared with plot_rockfall.py."""
    try:
        import matplotlib  # noqa: F401
        return
    except ImportError:
        pass
    system = "/usr/bin/python3"
    if (os.environ.get("TALUS_PLOT_REEXEC") != "1" and os.path.exists(system)
            and os.path.realpath(sys.executable) != os.path.realpath(system)):
        os.environ["TALUS_PLOT_REEXEC"] = "1"
        sys.stdout.flush()
        os.execv(system, [system, os.path.abspath(script)] + sys.argv[1:])


# --stress-unit: the factor from Pa to each unit a stress axis may be drawn in.
STRESS_UNITS = {"Pa": 1.0, "kPa": 1e-3, "MPa": 1e-6, "GPa": 1e-9}


def convert_stresses(series: Sequence[Series], unit: str) -> None:
    """Draw every series in Pa (a talus stress column, or a header cell "name [Pa]") in `unit`:
    the values scaled, the axis label and the legend saying the new unit."""
    if unit not in STRESS_UNITS:
        raise PlotError(f"unknown stress unit '{unit}' (known: {', '.join(STRESS_UNITS)})")
    factor = STRESS_UNITS[unit]
    for s in series:
        if s.unit != "Pa" or unit == "Pa":
            continue
        s.y = [v * factor for v in s.y]
        s.unit = unit
        s.label = s.label.replace("[Pa]", f"[{unit}]")
    for s in series:
        if s.x_unit == "Pa" and unit != "Pa":
            s.x = [v * factor for v in s.x]
            s.x_unit = unit


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(
        prog="plot_history.py",
        description="Plot talus history CSV files (default: every energy column against time).")
    p.add_argument("files", nargs="+", metavar="CSV", help="history files (overlaid)")
    p.add_argument("-o", "--output", required=True,
                   help="output file; the extension picks the format (.png, .pdf, .svg)")
    p.add_argument("--columns", help="comma-separated column names as in the header "
                   "(default: every energy column)")
    p.add_argument("--x", dest="x", help="abscissa: time, step or any column (default: time, "
                   "else step, else the first column)")
    p.add_argument("--logy", action="store_true", help="log y axis (symlog when values <= 0)")
    p.add_argument("--logx", action="store_true", help="log x axis (symlog when values <= 0)")
    p.add_argument("--linthresh", type=float,
                   help="linear range of a symlog axis (default: smallest non-zero |value|, "
                   "at least 1e-9 of the largest)")
    p.add_argument("--title", help="plot title")
    p.add_argument("--xlabel", help="x axis label (default: column name [unit])")
    p.add_argument("--ylabel", help="y axis label (default: energy [J], or names [unit])")
    p.add_argument("--stress-unit", default="Pa", choices=list(STRESS_UNITS),
                   help="unit of the stress columns (those in Pa) on the axes (default Pa)")
    p.add_argument("--equal", action="store_true",
                   help="same scale on both axes (trajectories)")
    p.add_argument("--size", type=_size, help="figure size W,H in inches (default 8,5 for one "
                   "panel, taller with more)")
    p.add_argument("--panels", choices=("group", "one"), default="group",
                   help="group (default): one panel per group and the balance error in its own; "
                   "one: every series on one axis")
    p.add_argument("--describe", action="store_true",
                   help="also print the panels drawn as JSON (titles, labels, line styles)")
    p.add_argument("--dpi", type=int, default=120, help="PNG resolution (default 120)")
    args = p.parse_args(argv)
    described: list = []
    try:
        series = load_series(args.files, _split_columns(args.columns), args.x)
        convert_stresses(series, args.stress_unit)
        out = plot(series, args.output, title=args.title, logx=args.logx, logy=args.logy,
                   linthresh=args.linthresh, equal=args.equal, xlabel=args.xlabel,
                   ylabel=args.ylabel, size=args.size, dpi=args.dpi,
                   panel_mode=args.panels, describe=described)
    except PlotError as e:
        print(f"plot_history: error: {e}", file=sys.stderr)
        return 2
    except ImportError as e:
        print(f"plot_history: error: matplotlib is missing ({e}); run scripts/setup.sh "
              "(Debian package python3-matplotlib)", file=sys.stderr)
        return 2
    if args.describe:
        import json
        print(json.dumps(described, indent=1))
    print(f"plot_history: wrote {out} ({len(series)} series)")
    return 0


if __name__ == "__main__":
    ensure_matplotlib(__file__)
    sys.exit(main())
