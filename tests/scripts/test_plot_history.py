# SPDX-License-Identifier: MIT
"""Tests of scripts/plot_history.py (ctest plot.history).

    python3 tests/scripts/test_plot_history.py OUTDIR [TALUS]

Checks the series the tool selects (default energy columns, literal group-style names, units,
NaN gaps) on a hand-written CSV, the files it writes (PNG and PDF magic bytes, identical bytes on
a second run), its errors (exit status 2, file and column named on stderr), and, given the talus
binary, a history written by talus itself: the columns read back must satisfy the energy
balance identity, which a mix-up of columns would break.
"""

import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, "..", "..", "scripts", "plot_history.py")
sys.path.insert(0, os.path.dirname(TOOL))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import plot_history  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}")


def same(a, b):
    """Equal lists of floats, NaN equal to NaN (gaps in the same places)."""
    return len(a) == len(b) and all((math.isnan(x) and math.isnan(y)) or x == y
                                    for x, y in zip(a, b))


def run(*args):
    return subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)


nan = math.nan
out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
os.makedirs(out, exist_ok=True)
talus = sys.argv[2] if len(sys.argv) > 2 else None

# ------------------------------------------------------------------ selection and values
csv_path = os.path.join(out, "plot_input.csv")
with open(csv_path, "w") as f:
    # The header as talus writes it (names only, RFC 4180 quotes), with future group-wise
    # columns and a user column that carries its unit.
    f.write('time,step,height [m],kinetic,slip,balance_error,kinetic@rock,"kinetic[rock]",'
            'empty\n')
    f.write("0,0,1,0,0,0,0,0,\n")
    f.write("0.1,10,0.9,2,,1e-9,1,2,\n")
    f.write("0.2,20,nan,nan,0.5,-2e-9,1,2,\n")
    f.write("\n")  # a blank line is skipped, not a row
    f.write("0.3,30,0.7,4,inf,0,1,2,\n")
    f.write("0.4,40,0.6,5,1,,1,2,\n")

s = plot_history.load_series([csv_path])
check([x.column for x in s] == ["kinetic", "slip", "balance_error", "kinetic@rock",
                                 "kinetic[rock]"],
      f"default columns are the energies, group forms included: {[x.column for x in s]}")
check(all(x.unit == "J" and x.x_unit == "s" and x.x_column == "time" for x in s),
      "units: energies in J against time in s")
check(same(s[0].x, [0, 0.1, 0.2, 0.3, 0.4]), f"x is time: {s[0].x}")
check(same(s[0].y, [0, 2, nan, 4, 5]), f"kinetic with a NaN gap: {s[0].y}")
check(same(s[1].y, [0, nan, 0.5, nan, 1]), f"blank and inf cells are gaps: {s[1].y}")
check(same(s[2].y, [0, 1e-9, -2e-9, 0, nan]), f"balance_error: {s[2].y}")

s = plot_history.load_series([csv_path], ["kinetic[rock]", "height"], x="step")
check([x.column for x in s] == ["kinetic[rock]", "height [m]"], "literal and unit-less names")
check(s[1].unit == "m" and s[0].unit == "J" and s[0].x_column == "step", "units from the header")
check(same(s[1].x, [0, 10, 20, 30, 40]) and same(s[1].y, [1, 0.9, nan, 0.7, 0.6]),
      f"height against step: {s[1].y}")
# A unit in the header cell is printed once on the axis ("height [m]", not "height [m] [m]").
check(plot_history.y_label([s[1]]) == "height [m]", f"y label: {plot_history.y_label([s[1]])}")
check(plot_history.x_label(s) == "step", f"x label: {plot_history.x_label(s)}")
check(plot_history.y_label(s) == "kinetic[rock] [J], height [m]",
      f"two units: {plot_history.y_label(s)}")
check(plot_history._split_columns("kinetic,height [m],kinetic[a,b]") ==
      ["kinetic", "height [m]", "kinetic[a,b]"], "--columns splits outside brackets only")

# Two files overlaid: legends name file and column.
csv2 = os.path.join(out, "plot_input2.csv")
with open(csv2, "w") as f:
    f.write("time,kinetic\n0,1\n1,2\n")
s = plot_history.load_series([csv_path, csv2], ["kinetic"])
check([x.label for x in s] == ["plot_input.csv: kinetic", "plot_input2.csv: kinetic"],
      f"overlay legends: {[x.label for x in s]}")

# ------------------------------------------------------------------ stresses in MPa
# A material test's history (docs/material.md): stresses in Pa in the file, drawn in MPa with
# --stress-unit MPa: values divided by 1e6 exactly where the unit is Pa, strains untouched.
mat_path = os.path.join(out, "plot_material.csv")
with open(mat_path, "w") as f:
    f.write("step,time,strain_axial,stress_axial [Pa],strain_lateral,stress_lateral [Pa]\n")
    f.write("0,0,0,0,0,0\n")
    f.write("50,1e-6,1e-3,6.5e7,-2.5e-4,1e7\n")
    f.write("100,2e-6,2e-3,1.3e8,-5e-4,nan\n")
mpa = plot_history.load_series([mat_path], ["stress_axial [Pa]", "stress_lateral"], "strain_axial")
plot_history.convert_stresses(mpa, "MPa")
check([s.unit for s in mpa] == ["MPa", "MPa"], f"stress units after --stress-unit MPa: {[s.unit for s in mpa]}")
check(same(mpa[0].y, [0.0, 65.0, 130.0]), f"axial stress in MPa: {mpa[0].y}")
check(same(mpa[1].y, [0.0, 10.0, nan]), f"lateral stress in MPa, the gap kept: {mpa[1].y}")
check(same(mpa[0].x, [0.0, 1e-3, 2e-3]), f"the strain axis is not scaled: {mpa[0].x}")
check(plot_history.y_label(mpa) == "stress_axial, stress_lateral [MPa]",
      f"y label in MPa: {plot_history.y_label(mpa)!r}")
check("[MPa]" in mpa[0].label, f"legend in MPa: {mpa[0].label!r}")
r = run(mat_path, "-o", os.path.join(out, "plot_material.png"), "--x", "strain_axial",
        "--columns", "stress_axial [Pa]", "--stress-unit", "MPa")
check(r.returncode == 0, f"--stress-unit MPa runs: {r.stderr}")
r = run(mat_path, "-o", os.path.join(out, "plot_material.png"), "--columns", "stress_axial [Pa]",
        "--stress-unit", "MPA")
check(r.returncode == 2 and "MPA" in r.stderr, f"an unknown stress unit is an error: {r.stderr}")
# the UCS example draws its stress-strain curve in MPa
ucs_example = open(os.path.join(HERE, "..", "..", "scripts", "examples", "ucs.lua")).read()
check("--stress-unit MPa" in ucs_example and "[MPa]" in ucs_example,
      "scripts/examples/ucs.lua plots the axial stress in MPa")

# ------------------------------------------------------------------ output files
png, pdf = os.path.join(out, "plot_output.png"), os.path.join(out, "plot_output.pdf")
for path in (png, pdf):
    if os.path.exists(path):
        os.remove(path)
r = run(csv_path, "-o", png, "--title", "test plot")
check(r.returncode == 0, f"PNG run: {r.stderr}")
with open(png, "rb") as f:
    png_bytes = f.read()
check(png_bytes.startswith(b"\x89PNG\r\n\x1a\n"), "a PNG file")
r = run(csv_path, csv2, "-o", os.path.join(out, "plot_overlay.png"), "--columns", "kinetic")
check(r.returncode == 0 and "2 series" in r.stdout, f"two files overlaid: {r.stdout} {r.stderr}")
r = run(csv_path, "-o", pdf, "--columns", "kinetic,balance_error", "--logy")
check(r.returncode == 0, f"PDF run: {r.stderr}")
check("symlog" in r.stderr, "--logy with values <= 0 says it uses symlog")
with open(pdf, "rb") as f:
    pdf_bytes = f.read()
check(pdf_bytes.startswith(b"%PDF-") and b"%%EOF" in pdf_bytes[-32:], "a complete PDF file")
check(b"CreationDate" not in pdf_bytes, "no date in the PDF")
r = run(csv_path, "-o", png, "--title", "test plot")
with open(png, "rb") as f:
    check(f.read() == png_bytes, "the same PNG bytes on a second run")
r = run(csv_path, "-o", pdf, "--columns", "kinetic,balance_error", "--logy")
with open(pdf, "rb") as f:
    check(f.read() == pdf_bytes, "the same PDF bytes on a second run")

# ------------------------------------------------------------------ panels and line styles
# A history of a rockfall-like scene: 7 model energies, 6 of each of two groups and three balance
# errors, 22 series. By default: the model's panel, one per group, the balance errors below.
import json  # noqa: E402

items = ["kinetic", "body", "boundary", "strain", "slip", "dashpot", "damping"]
heads = items + [f"{i}@{g}" for g in ("rock", "slope") for i in items[:6]] + \
    ["balance_error", "balance_error@rock", "balance_error@slope"]
grouped = os.path.join(out, "plot_groups.csv")
with open(grouped, "w") as f:
    f.write("time," + ",".join(heads) + "\n")
    for row in range(4):
        f.write(",".join([str(0.1 * row)] + [str(row * (k + 1)) for k in range(len(heads))])
                + "\n")
r = run(grouped, "-o", os.path.join(out, "plot_groups.png"), "--describe")
check(r.returncode == 0, f"grouped history plotted: {r.stderr}")
try:
    panels = json.loads(r.stdout[:r.stdout.rindex("]") + 1])
except ValueError:
    panels = []
check([p["title"] for p in panels] == ["all bodies", "group rock", "group slope",
                                       "energy balance error"],
      f"one panel per group, the balance error last: {[p['title'] for p in panels]}")
if len(panels) == 4:
    check([ln["label"] for ln in panels[0]["lines"]] == items, "model panel: its 7 items")
    check([ln["label"] for ln in panels[1]["lines"]] == items[:6],
          f"group panel: the items without '@rock': {[ln['label'] for ln in panels[1]['lines']]}")
    check([ln["label"] for ln in panels[3]["lines"]] ==
          ["balance_error", "balance_error@rock", "balance_error@slope"],
          "the balance errors alone in the last panel")
    check(panels[3]["ylabel"] == "balance error [J]" and panels[0]["ylabel"] == "energy [J]",
          "axis labels of the panels")
    check(panels[3]["xlabel"] == "time [s]", "the shared x label under the last panel")
    for p in panels:
        looks = [(ln["color"], ln["linestyle"], ln["marker"]) for ln in p["lines"]]
        check(len(set(looks)) == len(looks), f"panel '{p['title']}': every line its own look")
    look = {ln["label"]: (ln["color"], ln["linestyle"]) for ln in panels[0]["lines"]}
    check(all(look[ln["label"]] == (ln["color"], ln["linestyle"]) for ln in panels[2]["lines"]),
          "an item keeps its look from panel to panel")
r = run(grouped, "-o", os.path.join(out, "plot_groups_one.png"), "--describe", "--panels", "one")
try:
    one = json.loads(r.stdout[:r.stdout.rindex("]") + 1])
except ValueError:
    one = []
check(len(one) == 1 and len(one[0]["lines"]) == len(heads),
      f"--panels one: all {len(heads)} series on one axis")
if one:
    looks = [(ln["color"], ln["linestyle"], ln["marker"]) for ln in one[0]["lines"]]
    check(len(set(looks)) == len(looks),
          f"22 series on one axis: 22 looks ({len(set(looks))} distinct)")
# The style cycle: colour and dashes together give 40 looks, markers then 280 more.
looks = [tuple(sorted(plot_history.line_style(k).items())) for k in range(120)]
check(len(set(looks)) == 120, "120 style numbers, 120 looks")
# A path plot (no energies, no groups) stays one panel.
r = run(csv_path, "-o", os.path.join(out, "plot_path.png"), "--columns", "height", "--describe")
check(r.returncode == 0 and r.stdout.count('"title"') == 1, f"one column, one panel: {r.stdout}")

# ------------------------------------------------------------------ errors
r = run(csv_path, "-o", png, "--columns", "kinetic,nope")
check(r.returncode == 2 and "'nope'" in r.stderr and "plot_input.csv" in r.stderr,
      f"unknown column: exit 2 naming file and column: {r.returncode} {r.stderr!r}")
r = run(os.path.join(out, "no_such.csv"), "-o", png)
check(r.returncode == 2 and "no_such.csv" in r.stderr, f"missing file: {r.stderr!r}")
r = run(csv_path, "-o", png, "--columns", "empty")
check(r.returncode == 2 and "'empty'" in r.stderr and "no numeric data" in r.stderr,
      f"column with no numeric data: {r.stderr!r}")
nonenergy = os.path.join(out, "plot_noenergy.csv")
with open(nonenergy, "w") as f:
    f.write("time,x\n0,1\n")
r = run(nonenergy, "-o", png)
check(r.returncode == 2 and "no energy column" in r.stderr, f"no energy column: {r.stderr!r}")
r = run(csv_path, "-o", os.path.join(out, "plot.jpg"))
check(r.returncode == 2 and ".jpg" in r.stderr, f"unknown output type: {r.stderr!r}")

# ------------------------------------------------------------------ a history written by talus
if talus:
    script = os.path.join(out, "plot_drop.lua")
    hist = os.path.join(out, "plot_drop.csv")
    with open(script, "w") as f:
        f.write(f"""
local m = talus.model{{ gravity = {{0, -9.81}} }}
m:contact_model("linear", {{ kn = 1e6, ks = 1e6, fric = 0.5, dp_nratio = 0.2 }})
m:wall{{ points = {{{{-1, 0}}, {{1, 0}}}} }}
local b = m:ball{{ pos = {{0, 0.2}}, radius = 0.05, density = 2600 }}
m:energy{{ on = true }}
m:history{{ file = "{hist}", every = 5, columns = {{ "time", "step",
    {{"y", function() return b.pos[2] end}}, "kinetic", "body", "strain", "dashpot",
    "balance_error" }} }}
m:solve{{ time = 0.6 }}
""")
    r = subprocess.run([talus, "run", script], capture_output=True, text=True)
    check(r.returncode == 0, f"talus wrote the history: {r.stderr}")
    s = plot_history.load_series([hist])
    cols = {x.column: x.y for x in s}
    check(list(cols) == ["kinetic", "body", "strain", "dashpot", "balance_error"],
          f"default columns of a talus history: {list(cols)}")
    # balance_error = body - (kinetic + strain + dashpot) for a ball dropped from rest on a
    # wall (no slip, no damping, no boundary work; docs/lua-api.md "Energies"). The CSV holds 12
    # significant digits, so the identity holds to ~1e-11 of the largest term; 1e-9 leaves room.
    scale = max(abs(v) for v in cols["body"])
    worst = max(abs(cols["body"][i] - cols["kinetic"][i] - cols["strain"][i]
                    - cols["dashpot"][i] - cols["balance_error"][i])
                for i in range(len(cols["body"])))
    check(scale > 0 and worst <= 1e-9 * scale,
          f"energy identity on the columns read back: {worst:.3g} J of {scale:.3g} J")
    check(max(cols["dashpot"]) > 0, "the ball bounced (dashpot energy > 0)")
    r = run(hist, "-o", os.path.join(out, "plot_drop.png"))
    check(r.returncode == 0, f"talus history plotted: {r.stderr}")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("plot_history: all checks passed")
