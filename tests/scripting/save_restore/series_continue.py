#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""ParaView and picture series through save and restore (docs/save-format.md, section HOST;
docs/output.md). Runs series_scene.lua straight (2N steps) in OUTDIR/straight, and split (N
steps, save, restore in a fresh process, N steps) in OUTDIR/split, then reads both back.

usage: series_continue.py TALUS SCRIPT_DIR OUTDIR
For each series (talus, slow, fn) the split run's .pvd must list every frame once, in order,
numbered 0, 1, 2, ... with increasing times, and be the straight run's collection (same
files, same timesteps). Every frame is opened with VTK's own multiblock reader
(python3-vtk9): its blocks, TimeValue (= the .pvd's timestep) and step, and every point and
cell array of every block equal to the straight run's (the continuation is bit-identical, so
the frames are too). Pictures: the same numbered files, the same pixels (Pillow).
Exit 77 (ctest: skipped) when VTK's Python module is missing, except under CI (CI=true).
"""
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

try:
    import numpy as np
    from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
except ImportError as e:
    if os.environ.get("CI"):
        print(f"FAIL: VTK's Python module is missing under CI ({e}); scripts/setup.sh installs "
              "python3-vtk9")
        sys.exit(1)
    print(f"SKIP: VTK's Python module is missing ({e}): apt-get install python3-vtk9")
    sys.exit(77)

talus, here, out = sys.argv[1], sys.argv[2], sys.argv[3]
script = os.path.join(here, "series_scene.lua")
shutil.rmtree(out, ignore_errors=True)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


pictures = True
for run_dir, phases in [("straight", ["straight"]), ("split", ["first", "second"])]:
    d = os.path.join(out, run_dir)
    os.makedirs(d)
    for phase in phases:
        r = subprocess.run([talus, "run", script, phase, d], capture_output=True, text=True,
                           timeout=600)
        print(f"--- {phase}: exit {r.returncode}\n{r.stdout}{r.stderr}")
        if r.returncode != 0:
            sys.exit(f"FAIL: series_scene.lua {phase} failed")
        pictures = pictures and "no cairo" not in r.stdout


def collection(d, name):
    root = ET.parse(os.path.join(d, name + ".pvd")).getroot()
    return [(e.get("timestep"), e.get("file")) for e in root.find("Collection").findall("DataSet")]


def frame(d, file):
    rd = vtkXMLMultiBlockDataReader()
    rd.SetFileName(os.path.join(d, file))
    rd.Update()
    return rd.GetOutput()


def arrays(data):
    """Every array of every block, by block and name (points as 'points')."""
    out = {}
    for i in range(data.GetNumberOfBlocks()):
        block = data.GetBlock(i)
        name = data.GetMetaData(i).Get(data.NAME())
        if block.GetPoints() is not None:
            out[(name, "points")] = vtk_to_numpy(block.GetPoints().GetData())
        for kind, fd in (("point", block.GetPointData()), ("cell", block.GetCellData()),
                         ("field", block.GetFieldData())):
            for k in range(fd.GetNumberOfArrays()):
                a = fd.GetArray(k)
                if a is not None:  # the string arrays (model names) are abstract arrays
                    out[(name, kind, a.GetName())] = vtk_to_numpy(a)
    return out


straight, split = os.path.join(out, "straight"), os.path.join(out, "split")
expected = {"talus": (15, ["balls", "walls", "contacts"]), "slow": (5, ["balls", "contacts"]),
            "fn": (9, ["balls", "walls", "contacts"])}
for name, (count, blocks) in expected.items():
    a, b = collection(straight, name), collection(split, name)
    check(len(b) == count, f"{name}: {count} frames in the split run's .pvd (got {len(b)})")
    check(a == b, f"{name}: the split run's .pvd lists the straight run's frames")
    files = [f for _, f in b]
    check(len(set(files)) == len(files), f"{name}: every frame listed once")
    check(files == [f"{name}_{k:06d}.vtm" for k in range(len(files))],
          f"{name}: frames numbered 0, 1, 2, ... in order: {files}")
    times = [float(t) for t, _ in b]
    check(all(y > x for x, y in zip(times, times[1:])), f"{name}: times increase")
    for (t, f), (_, fa) in zip(b, a):
        data = frame(split, f)
        names = [data.GetMetaData(i).Get(data.NAME()) for i in range(data.GetNumberOfBlocks())]
        check(names == blocks, f"{name} {f}: blocks {names}")
        tv = vtk_to_numpy(data.GetBlock(0).GetFieldData().GetArray("TimeValue"))[0]
        check(tv == float(t), f"{name} {f}: TimeValue {tv!r} = the .pvd's {t}")
        got, want = arrays(data), arrays(frame(straight, fa))
        check(sorted(got) == sorted(want), f"{name} {f}: the same arrays")
        for key in want:
            if key in got:
                check(got[key].shape == want[key].shape and np.array_equal(got[key], want[key]),
                      f"{name} {f}: {key} equal")
    print(f"{name}: {len(b)} frames read back, equal to the straight run's")

if pictures:
    from PIL import Image
    pa, pb = sorted(os.listdir(os.path.join(straight, "pic"))), \
        sorted(os.listdir(os.path.join(split, "pic")))
    check(pb == [f"f_{k:06d}.png" for k in range(6)], f"pictures f_000000 .. f_000005: {pb}")
    check(pa == pb, "the same pictures as the straight run")
    for f in pb:
        if f in pa:
            ia = Image.open(os.path.join(straight, "pic", f)).convert("RGB")
            ib = Image.open(os.path.join(split, "pic", f)).convert("RGB")
            check(ia.size == ib.size and ia.tobytes() == ib.tobytes(), f"picture {f}: same pixels")
    print(f"pictures: {len(pb)} frames, equal to the straight run's")
else:
    print("pictures: talus has no cairo; not checked")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print("series through save and restore: all checks passed")
