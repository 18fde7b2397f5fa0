# SPDX-License-Identifier: MIT
"""Tests of scripts/plot_calibration.py (ctest plot.calibration).

    python3 tests/scripts/test_plot_calibration.py OUTDIR TALUS

Has talus write a calibration CSV with material's writer (M.write_calibration) from made-up
rows, reads it back with the tool's loader (values, targets), plots it (PNG magic bytes, a drawn
figure, identical bytes on a second run; PDF), and checks the errors (missing file, a target
without its column: exit status 2, the path named).
"""

import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
TOOL = os.path.join(ROOT, "scripts", "plot_calibration.py")
sys.path.insert(0, os.path.dirname(TOOL))
sys.dont_write_bytecode = True
import plot_calibration  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}")


out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
talus = sys.argv[2] if len(sys.argv) > 2 else None
if not talus:
    print("usage: test_plot_calibration.py OUTDIR TALUS")
    sys.exit(2)
os.makedirs(out, exist_ok=True)
csv_path = os.path.join(out, "calib_plot.csv")
for p in (csv_path, csv_path[:-4] + "_targets.csv"):
    if os.path.exists(p):
        os.remove(p)

lua = os.path.join(out, "calib_plot.lua")
with open(lua, "w") as f:
    f.write(f"""
local M = require("material")
local rows = {{}}
for i = 1, 6 do
    rows[i] = {{ index = i, batch = i <= 4 and 1 or i - 3, phase = i <= 4 and "design" or "step",
                 params = {{ fj_ten = 1e7 * i, fj_coh = 5e7 }},
                 out = {{ E = 6e10 + 1e9 * i, E_sd = 1e9, ucs = 1.5e8 + 1e7 * i, ucs_sd = 5e6,
                          -- points 2 and 4: no disk split, no tensile strength, no misfit
                          tensile = (i ~= 2 and i ~= 4) and 9e6 + 1e5 * i or nil,
                          tensile_valid = (i ~= 2 and i ~= 4) and 2 or 0, disks = 2 }},
                 misfit = (i ~= 2 and i ~= 4) and 1 / i or math.huge, met = i == 6 }}
end
local result = {{ rows = rows, best = rows[6] }}
M.write_calibration({csv_path!r}, result, {{ {{ name = "fj_ten" }}, {{ name = "fj_coh" }} }},
    {{ {{ name = "E", value = 6.9e10, tol = 0.05 }}, {{ name = "ucs", value = 2e8, tol = 0.1 }},
       {{ name = "tensile", value = 9.3e6 }} }})
""")
env = dict(os.environ)
r = subprocess.run([talus, "run", lua], capture_output=True, text=True, env=env)
check(r.returncode == 0, f"talus wrote the CSV: {r.stderr}")

rows, targets = plot_calibration.load(csv_path)
check(len(rows) == 6, f"6 rows, got {len(rows)}")
check(targets == [("E", 6.9e10, 0.05), ("ucs", 2e8, 0.1), ("tensile", 9.3e6, 0.05)], f"targets {targets}")
check(float(rows[2]["E"]) == 6.3e10 and float(rows[2]["fj_ten"]) == 3e7, "row 3 values")
check(rows[5]["best"] == "1" and rows[0]["best"] == "0", "best flag")
check(rows[0]["phase"] == "design" and rows[5]["phase"] == "step", "phases")
check(rows[1]["tensile"] == "" and rows[1]["tensile_valid"] == "0" and rows[1]["misfit"] == "",
      f"a point without a split disk: no tensile value, tensile_valid 0, no misfit ({rows[1]})")
check(plot_calibration.unmeasured(rows, "tensile") == [1, 3], "the points without sigma_t are found")
check(plot_calibration.unmeasured(rows, "ucs") == [], "every point has a UCS")

png = os.path.join(out, "calib_plot.png")
r1 = subprocess.run([sys.executable, TOOL, csv_path, "-o", png, "--title", "test"], capture_output=True, text=True)
check(r1.returncode == 0, f"plot ran: {r1.stderr}")
data = open(png, "rb").read()
check(data[:8] == b"\x89PNG\r\n\x1a\n", "PNG magic")
check(len(data) > 20000, f"a drawn figure ({len(data)} bytes)")
subprocess.run([sys.executable, TOOL, csv_path, "-o", png, "--title", "test"], check=True)
check(open(png, "rb").read() == data, "identical bytes on a second run")
pdf = os.path.join(out, "calib_plot.pdf")
r2 = subprocess.run([sys.executable, TOOL, csv_path, "-o", pdf], capture_output=True, text=True)
check(r2.returncode == 0 and open(pdf, "rb").read()[:4] == b"%PDF", "PDF")

r3 = subprocess.run([sys.executable, TOOL, os.path.join(out, "nope.csv"), "-o", png], capture_output=True, text=True)
check(r3.returncode == 2 and "nope.csv" in r3.stderr, f"missing file: {r3.stderr}")
with open(csv_path[:-4] + "_targets.csv", "a") as f:
    f.write('"density",2630,0.1,1\n')
r4 = subprocess.run([sys.executable, TOOL, csv_path, "-o", png], capture_output=True, text=True)
check(r4.returncode == 2 and "no column 'density'" in r4.stderr, f"target without column: {r4.stderr}")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("plot_calibration: all checks passed")
