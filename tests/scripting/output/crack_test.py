#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Cracks in the outputs (docs/output.md): runs crack_scene.lua and reads its files back.
ParaView: the frame's multiblock has a "cracks" block (VTK's own reader, python3-vtk9) with one
line per crack of m:cracks(), through the contact point, across the bond (perpendicular to its
normal), as long as the bond is wide, with its mode, width and balls. Picture (python3-pil): at
each crack's centre the crack's colour (tension #E41A1C, shear #377EB8), and in the same
picture drawn without cracks not.

usage: crack_test.py TALUS OUTDIR [picture]   (picture: also check the pictures, built with cairo)
Exit 77 (ctest: skipped) when VTK's Python module is missing, except under CI.
"""
import math
import os
import re
import shutil
import subprocess
import sys

try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
except ImportError as e:
    if os.environ.get("CI"):
        print(f"FAIL: VTK's Python module is missing under CI ({e})")
        sys.exit(1)
    print(f"SKIP: VTK's Python module is missing ({e}): apt-get install python3-vtk9")
    sys.exit(77)

talus, out = sys.argv[1], sys.argv[2]
pictures = len(sys.argv) > 3 and sys.argv[3] == "picture"
here = os.path.dirname(os.path.abspath(__file__))
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
r = subprocess.run([talus, "run", os.path.join(here, "crack_scene.lua"), out, "picture" if pictures else ""],
                   capture_output=True, text=True)
sys.stderr.write(r.stderr)
if r.returncode != 0:
    sys.stdout.write(r.stdout)
    sys.exit("FAIL: crack_scene.lua failed")

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


cracks = []
for m in re.finditer(r"^CRACK (\d+) (\S+) (\S+) (\S+) (\S+) (\S+) (\w+) (\d+) (\d+) (\S+) (\d+)$", r.stdout, re.M):
    g = m.groups()
    cracks.append(dict(x=float(g[1]), y=float(g[2]), nx=float(g[3]), ny=float(g[4]), width=float(g[5]),
                       mode=g[6], ball1=int(g[7]), ball2=int(g[8]), time=float(g[9]), step=int(g[10])))
pix = {m.group(1): (float(m.group(2)), float(m.group(3)))
       for m in re.finditer(r"^PIXEL (\S+) (\S+) (\S+)$", r.stdout, re.M)}
check(len(cracks) >= 5, f"the scene has cracks ({len(cracks)})")

# ---- ParaView: the multiblock lists the cracks block; one line per crack
vtm = open(os.path.join(out, "vtk", "cracks_000000.vtm")).read()
check('name="cracks" file="cracks_000000_cracks.vtp"' in vtm, "the frame has a cracks block")
rd = vtkXMLPolyDataReader()
rd.SetFileName(os.path.join(out, "vtk", "cracks_000000_cracks.vtp"))
rd.Update()
pd = rd.GetOutput()
check(pd.GetNumberOfLines() == len(cracks), f"{pd.GetNumberOfLines()} lines for {len(cracks)} cracks")
pts = vtk_to_numpy(pd.GetPoints().GetData())
cd = pd.GetCellData()
arr = {cd.GetArrayName(i): vtk_to_numpy(cd.GetArray(i)) for i in range(cd.GetNumberOfArrays())}
lines = vtk_to_numpy(pd.GetLines().GetConnectivityArray())
for i, c in enumerate(cracks):
    a, b = pts[lines[2 * i]], pts[lines[2 * i + 1]]
    # the centre is the contact point, the segment across the bond, as long as it is wide
    check(math.isclose((a[0] + b[0]) / 2, c["x"], abs_tol=1e-15) and math.isclose((a[1] + b[1]) / 2, c["y"], abs_tol=1e-15),
          f"crack {i + 1}: centred at the contact point")
    length = math.hypot(b[0] - a[0], b[1] - a[1])
    check(math.isclose(length, c["width"], rel_tol=1e-12), f"crack {i + 1}: length {length} = width {c['width']}")
    check(abs((b[0] - a[0]) * c["nx"] + (b[1] - a[1]) * c["ny"]) <= 1e-12 * length, f"crack {i + 1}: across the bond")
    check(a[2] == 0 and b[2] == 0, "z = 0")
    check(arr["mode"][i] == (1 if c["mode"] == "tension" else 2), f"crack {i + 1}: mode")
    check(arr["width"][i] == c["width"], f"crack {i + 1}: width array")
    check(arr["ball1"][i] == c["ball1"] and arr["ball2"][i] == c["ball2"], f"crack {i + 1}: balls")
    check(arr["time"][i] == c["time"] and arr["step"][i] == c["step"], f"crack {i + 1}: time, step")
    check(math.isclose(arr["normal"][i][0], c["nx"], abs_tol=1e-15), f"crack {i + 1}: normal")

# ---- pictures: the crack's colour at its centre, where no crack drawn later passes near (a
# later crack's white rim would cover it); the centre of a line >= 3 px wide covers its pixel
if pictures:
    from PIL import Image  # python3-pil
    colour = {"tension": (0xE4, 0x1A, 0x1C), "shear": (0x37, 0x7E, 0xB8)}
    w = Image.open(os.path.join(out, "cracks.png")).convert("RGB")
    p = Image.open(os.path.join(out, "plain.png")).convert("RGB")

    def seg_dist(q, a, b):
        ax, ay, bx, by = a[0], a[1], b[0], b[1]
        t = ((q[0] - ax) * (bx - ax) + (q[1] - ay) * (by - ay)) / max((bx - ax) ** 2 + (by - ay) ** 2, 1e-12)
        t = min(1.0, max(0.0, t))
        return math.hypot(q[0] - ax - t * (bx - ax), q[1] - ay - t * (by - ay))

    checked = 0
    for i, c in enumerate(cracks):
        q = pix[f"c{i + 1}"]
        later = [j for j in range(i + 1, len(cracks))
                 if seg_dist(q, pix[f"c{j + 1}.a"], pix[f"c{j + 1}.b"]) < 8 + 1.5 + 2]
        if later:
            continue
        checked += 1
        got = w.getpixel((int(q[0]), int(q[1])))
        check(got == colour[c["mode"]], f"crack {i + 1} ({c['mode']}) drawn in its colour (got {got})")
        check(p.getpixel((int(q[0]), int(q[1]))) not in colour.values(), f"crack {i + 1}: not drawn without cracks")
    check(checked >= len(cracks) // 2, f"{checked} of {len(cracks)} crack centres checked")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print(f"cracks: all checks passed ({len(cracks)} cracks" + (f", {checked} centres in the picture" if pictures else "") + ")")
