# SPDX-License-Identifier: MIT
"""Tests of scripts/plot_rockfall.py (ctest plot.rockfall).

    python3 tests/scripts/test_plot_rockfall.py OUTDIR TALUS

Runs the hand-computed statistics regression (tests/scripting/regress/rockfall_statistics.lua)
with talus, so that rockfall_stats writes its CSV files into OUTDIR/rockfall_stats, then:
reads them back with the plot tool's loader and compares a few cells with the hand values of
that test (a column mix-up would break them); plots them (PNG: magic bytes, size, a drawn
figure rather than a blank canvas, identical bytes on a second run; PDF); plots the 0-rock
output; and checks the errors (missing directory or file: exit status 2, the path named).
"""

import math
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
TOOL = os.path.join(ROOT, "scripts", "plot_rockfall.py")
LUA_TEST = os.path.join(ROOT, "tests", "scripting", "regress", "rockfall_statistics.lua")
sys.path.insert(0, os.path.dirname(TOOL))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import plot_rockfall  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}")


def run(*args):
    return subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)


out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
talus = sys.argv[2] if len(sys.argv) > 2 else None
if not talus:
    print("usage: test_plot_rockfall.py OUTDIR TALUS")
    sys.exit(2)
os.makedirs(out, exist_ok=True)
data = os.path.join(out, "rockfall_stats")
shutil.rmtree(data, ignore_errors=True)  # files from an older run must not pass the test

# ------------------------------------------------------------------ the CSV files, by talus
env = dict(os.environ, TALUS_LUA_PATH=os.path.join(ROOT, "tests", "scripting"))
r = subprocess.run([talus, "run", LUA_TEST, out], capture_output=True, text=True, env=env)
check(r.returncode == 0 and "checks passed" in r.stdout,
      f"the statistics regression ran: {r.returncode} {r.stdout[-300:]} {r.stderr}")

res = plot_rockfall.load_results(data)
check(set(("endpoints", "endpoint_hist", "reach", "envelopes", "collectors", "barriers",
           "profile", "trajectories")) <= set(res), f"tables read: {sorted(res)}")
# Hand values of rockfall_statistics.lua: reach(20) = 15/20; bin 3 median height 3.08 with the
# interval [3.04, 3.12]; bin 7 reached by no rock (NaN); end-point p50 25.5 in [20, 31].
reach = res["reach"]
i20 = reach["x"].index(20.0)
check(reach["reach"][i20] == 0.75 and reach["count"][i20] == 15, "reach at x = 20")
e = res["envelopes"]
check(math.isclose(e["height_median"][2], 3.08) and math.isclose(e["height_median_lo"][2], 3.04)
      and math.isclose(e["height_median_hi"][2], 3.12), "envelope bin 3 median and interval")
check(math.isnan(e["height_median"][6]) and e["n"][6] == 0, "envelope bin 7: no rock, NaN")
pc = res["endpoint_percentiles"]
check(pc["end_x"][0] == 25.5 and pc["ci_lo"][0] == 20 and pc["ci_hi"][0] == 31, "p50 row")
check(res["endpoints"]["stop"][:3] == ["left", "barrier", "time"], "stop rules as strings")
check(len(set(res["trajectories"]["rock"])) == 3, "three trajectories")
# Retention from the toe x = 25 (the foot of the talus): 10 of the 20 rocks rest at x <= 25.
ret = res.get("retention", {})
check(ret.get("distance", [None])[0] == 0 and ret["x"][0] == 25 and ret["fraction"][0] == 0.5,
      "retention at the toe: 10 of 20")

# ------------------------------------------------------------------ the figure
png = os.path.join(out, "rockfall.png")
r = run(data, "-o", png, "--title", "test")
check(r.returncode == 0 and os.path.exists(png), f"PNG written: {r.stderr}")
if os.path.exists(png):
    with open(png, "rb") as f:
        first = f.read()
    check(first[:8] == b"\x89PNG\r\n\x1a\n", "PNG magic")
    check(len(first) > 30000, f"PNG is a real figure ({len(first)} bytes)")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    img = mpimg.imread(png)
    h, w = img.shape[:2]
    check(h > 1700 and w > 1000, f"five panels: {w} x {h} pixels")
    # Share of pixels that are not white: axes, bars, bands and lines cover far more than 2 %
    # of a figure with data; a figure with empty axes only covers ~1 %.
    inked = sum(1 for row in img[::4] for px in row[::4] if min(px[:3]) < 0.9)
    share = inked / (len(img[::4]) * len(img[0][::4]))
    check(share > 0.05, f"the figure has content: {share:.3f} of pixels drawn")
    r = run(data, "-o", png, "--title", "test")
    with open(png, "rb") as f:
        check(f.read() == first, "identical PNG bytes on a second run")
r = run(data, "-o", os.path.join(out, "rockfall.pdf"), "--logy-energy", "--trajectories", "1")
with open(os.path.join(out, "rockfall.pdf"), "rb") as f:
    check(r.returncode == 0 and f.read(5) == b"%PDF-", f"PDF written: {r.stderr}")
r = run(os.path.join(data, "empty"))
check(r.returncode == 0 and os.path.exists(os.path.join(data, "empty", "rockfall.png")),
      f"0 rocks: plotted without data: {r.stderr}")

# ------------------------------------------------------------------ errors
r = run(os.path.join(out, "no_such_dir"))
check(r.returncode == 2 and "no_such_dir" in r.stderr and "plot_rockfall: error:" in r.stderr,
      f"missing directory: exit 2: {r.returncode} {r.stderr!r}")
partial = os.path.join(out, "partial")
shutil.rmtree(partial, ignore_errors=True)
shutil.copytree(data, partial, ignore=shutil.ignore_patterns("reach.csv", "empty"))
r = run(partial)
check(r.returncode == 2 and "reach.csv: missing" in r.stderr, f"missing reach.csv: {r.stderr!r}")
r = run(data, "-o", os.path.join(out, "x.jpg"))
check(r.returncode == 2 and "unknown type" in r.stderr, f"unknown output type: {r.stderr!r}")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("plot_rockfall: all checks passed")
