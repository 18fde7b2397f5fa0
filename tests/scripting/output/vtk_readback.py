#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Reads the ParaView files of vtk_scene.lua back with VTK's own readers (python3-vtk9) and
compares every array with the state the script dumped (docs/output.md, "ParaView output").

usage: vtk_readback.py TALUS OUTDIR
Exit 77 (ctest: skipped) when VTK's Python module is missing, except under CI (CI=true), where
scripts/setup.sh installs python3-vtk9 and a missing module is a failure.
"""
import csv
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

try:
    from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader, vtkXMLPolyDataReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
except ImportError as e:
    if os.environ.get("CI"):
        print(f"FAIL: VTK's Python module is missing under CI ({e}); scripts/setup.sh installs "
              "python3-vtk9")
        sys.exit(1)
    print(f"SKIP: VTK's Python module is missing ({e}): apt-get install python3-vtk9")
    sys.exit(77)

talus, out = sys.argv[1], sys.argv[2]
here = os.path.dirname(os.path.abspath(__file__))
shutil.rmtree(os.path.join(out, "vtk"), ignore_errors=True)
os.makedirs(out, exist_ok=True)
r = subprocess.run([talus, "run", os.path.join(here, "vtk_scene.lua"), out], capture_output=True,
                   text=True)
sys.stdout.write(r.stdout)
sys.stderr.write(r.stderr)
if r.returncode != 0:
    sys.exit("FAIL: vtk_scene.lua failed")

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


vtk_dir = os.path.join(out, "vtk")

# ---- the collection: six frames at increasing times, each a multiblock VTK reads
pvd = ET.parse(os.path.join(vtk_dir, "talus.pvd")).getroot()
check(pvd.get("type") == "Collection", "the .pvd is a VTK collection")
entries = pvd.find("Collection").findall("DataSet")
check(len(entries) == 6, f"6 frames in talus.pvd (got {len(entries)})")
times = [float(e.get("timestep")) for e in entries]
check(all(b > a for a, b in zip(times, times[1:])), f"frame times increase: {times}")
check(times[0] == 0.0, "the first frame is at t = 0")

for e in entries:
    mb = vtkXMLMultiBlockDataReader()
    mb.SetFileName(os.path.join(vtk_dir, e.get("file")))
    mb.Update()
    data = mb.GetOutput()
    check(data.GetNumberOfBlocks() == 3, f"{e.get('file')}: three blocks")
    names = [data.GetMetaData(i).Get(data.NAME()) for i in range(data.GetNumberOfBlocks())]
    check(names == ["balls", "walls", "contacts"], f"block names {names}")
    balls = data.GetBlock(0)
    tv = vtk_to_numpy(balls.GetFieldData().GetArray("TimeValue"))
    check(tv[0] == float(e.get("timestep")), f"TimeValue {tv[0]} = the .pvd's {e.get('timestep')}")


def read(path):
    rd = vtkXMLPolyDataReader()
    rd.SetFileName(path)
    rd.Update()
    return rd.GetOutput()


# ---- the last frame, array by array, against the script's own dump
stem = os.path.join(vtk_dir, entries[-1].get("file"))[: -len(".vtm")]
t_end, step_end = open(os.path.join(out, "expected_meta.txt")).read().split()
balls = read(stem + "_balls.vtp")
check(vtk_to_numpy(balls.GetFieldData().GetArray("step"))[0] == int(step_end), "step")
check(vtk_to_numpy(balls.GetFieldData().GetArray("TimeValue"))[0] == float(t_end), "time")
pd = balls.GetPointData()
want = list(csv.DictReader(open(os.path.join(out, "expected_balls.csv"))))
pebbles = list(csv.DictReader(open(os.path.join(out, "expected_pebbles.csv"))))
check(len(pebbles) == 2, "the clump has two pebbles")
n = len(want) + len(pebbles)
check(balls.GetNumberOfPoints() == n, f"{len(want)} balls + {len(pebbles)} pebbles")
check(balls.GetNumberOfVerts() == n, "one vertex cell per particle")
pts = vtk_to_numpy(balls.GetPoints().GetData())
arr = {n: vtk_to_numpy(pd.GetArray(n)) for n in
       ["id", "radius", "velocity", "spin", "clump", "mass", "force", "speed", "height",
        "double_vel", "group_even", "group_odd", "group_rock"]}
for i, w in enumerate(want):
    check(arr["group_rock"][i] == 0, f"ball {w['id']}: not in group rock")
    # Float64 arrays hold the doubles the engine has: exact equality (the dump is %.17g).
    check(arr["id"][i] == int(w["id"]), f"ball {i}: id")
    check(pts[i][0] == float(w["x"]) and pts[i][1] == float(w["y"]) and pts[i][2] == 0.0,
          f"ball {w['id']}: position")
    check(arr["radius"][i] == float(w["radius"]), f"ball {w['id']}: radius")
    check(arr["velocity"][i][0] == float(w["vx"]) and arr["velocity"][i][1] == float(w["vy"]),
          f"ball {w['id']}: velocity")
    check(arr["spin"][i] == float(w["spin"]), f"ball {w['id']}: spin")
    check(arr["mass"][i] == float(w["mass"]), f"ball {w['id']}: mass")
    check(arr["force"][i][0] == float(w["fx"]) and arr["force"][i][1] == float(w["fy"]),
          f"ball {w['id']}: force")
    check(arr["height"][i] == float(w["y"]), f"ball {w['id']}: Lua field 'height'")
    check(arr["double_vel"][i][0] == 2 * float(w["vx"]), f"ball {w['id']}: Lua vector field")
    check(abs(arr["speed"][i] - (float(w["vx"]) ** 2 + float(w["vy"]) ** 2) ** 0.5)
          <= 1e-15 * max(1.0, arr["speed"][i]), f"ball {w['id']}: speed")
    g = w["group"]
    for name in ("even", "odd"):
        check(arr["group_" + name][i] == (1 if g == name else 0), f"ball {w['id']}: group {name}")
    check(arr["clump"][i] == 0, f"ball {w['id']}: a free ball has clump 0")
# Pebbles after the free balls: position, radius, clump, group exact; the rigid velocity
# v_c + w x r to rounding (the engine forms r from the body-frame offset, the script from the
# positions: a few ulps of 1 m/s apart).
for k, w in enumerate(pebbles):
    i = len(want) + k
    check(pts[i][0] == float(w["x"]) and pts[i][1] == float(w["y"]), f"pebble {k}: position")
    check(arr["radius"][i] == float(w["radius"]), f"pebble {k}: radius")
    check(arr["clump"][i] == int(w["clump"]), f"pebble {k}: clump {arr['clump'][i]}")
    check(arr["group_rock"][i] == 1, f"pebble {k}: the clump's group")
    check(arr["spin"][i] == float(w["spin"]), f"pebble {k}: the clump's spin")
    for j, key in enumerate(("vx", "vy")):
        check(abs(arr["velocity"][i][j] - float(w[key])) <= 1e-12, f"pebble {k}: {key}")

walls = read(stem + "_walls.vtp")
check(walls.GetNumberOfLines() == 2, "two wall polylines")
lines = walls.GetLines()
ids = vtk_to_numpy(lines.GetConnectivityArray())
offs = vtk_to_numpy(lines.GetOffsetsArray())
check(list(offs) == [0, 5, 7], f"closed box: 4 points + the first again; open wall 2 ({offs})")
check(ids[0] == ids[4], "the closed wall ends where it starts")
check(vtk_to_numpy(walls.GetCellData().GetArray("group_box"))[0] == 1, "wall group array")

contacts = read(stem + "_contacts.vtp")
cd = contacts.GetCellData()
wantc = list(csv.DictReader(open(os.path.join(out, "expected_contacts.csv"))))
check(contacts.GetNumberOfLines() == len(wantc), f"{len(wantc)} contact lines")
fn = vtk_to_numpy(cd.GetArray("normal_force"))
fs = vtk_to_numpy(cd.GetArray("shear_force"))
ov = vtk_to_numpy(cd.GetArray("overlap"))
e1 = vtk_to_numpy(cd.GetArray("end1"))
e2 = vtk_to_numpy(cd.GetArray("end2"))
wall = vtk_to_numpy(cd.GetArray("wall"))
model = cd.GetAbstractArray("model")
check(model is not None and model.GetNumberOfValues() == len(wantc), "string array 'model'")
for i, w in enumerate(wantc):
    check(e1[i] == int(w["end1"]) and e2[i] == int(w["end2"]) and wall[i] == int(w["wall"]),
          f"contact {i}: ends")
    check(fn[i] == float(w["fn"]) and fs[i] == float(w["fs"]) and ov[i] == float(w["overlap"]),
          f"contact {i}: forces and overlap")
    check(model.GetValue(i) == "linear", f"contact {i}: model name '{model.GetValue(i)}'")
check(any(f > 0 for f in fn), "some contact carries force")

# ---- the continued series: frames 0, 1, 2 (0 kept from the first run, 1-2 from the second)
cont = ET.parse(os.path.join(vtk_dir, "cont.pvd")).getroot().find("Collection")
files = [e.get("file") for e in cont.findall("DataSet")]
check(files == ["cont_000000.vtm", "cont_000001.vtm", "cont_000002.vtm"], f"continued: {files}")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print("vtk readback: all arrays match")
