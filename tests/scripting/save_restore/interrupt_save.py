#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`talus run --save-on-interrupt FILE` (docs/output.md, "Ctrl-C"; docs/save-format.md).

usage: interrupt_save.py TALUS SCRIPT_DIR OUTDIR
1. Starts interrupt_scene.lua's endless cycle with --save-on-interrupt, waits for its marker
   (step 300 done), sends SIGINT. Requires exit status 130, the step S in "interrupted (Ctrl-C)
   at step S", "saved the model at step S ... to FILE", FILE present and no FILE.tmp left.
2. Restores FILE in a fresh process (it must be at step S) and runs K more steps; runs the scene
   straight for S then K steps. The time and step at S, the state after S + K (every number
   %a), the CSV history (the restored run appends to the interrupted run's file) and the .pvd
   of the ParaView series (continued through the save) must be equal byte for byte: the save
   taken on Ctrl-C holds the whole state at the step where the run stopped.
3. Usage errors: the option without a file name exits 2.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

talus, here, out = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
script = os.path.join(here, "interrupt_scene.lua")
save = os.path.join(out, "int.talus")
K = 500
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


def run(*args):
    r = subprocess.run([talus, "run", *args], capture_output=True, text=True, timeout=600)
    print(f"--- talus run {' '.join(args[-4:])}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    return r


# 1. The interrupted run.
p = subprocess.Popen([talus, "run", "--save-on-interrupt", save, script, "run", out],
                     stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                     text=True)
marker = os.path.join(out, "marker")
end = time.time() + 300
while not os.path.exists(marker) and time.time() < end and p.poll() is None:
    time.sleep(0.02)
check(os.path.exists(marker), "the run got past step 300")
p.send_signal(signal.SIGINT)
o, e = p.communicate(timeout=300)
print(f"--- interrupted run: exit {p.returncode}\n{o}{e}")
check(p.returncode == 130, f"exit status 130 (got {p.returncode})")
m = re.search(r"interrupted \(Ctrl-C\) at step (\d+)", e)
check(m is not None, "the message names the step")
S = int(m.group(1)) if m else -1
check(S >= 300, f"stopped after the marker (step {S})")
m2 = re.search(r"saved the model at step (\d+) \(t = [^)]*\) to (.*)", e)
check(m2 is not None and int(m2.group(1)) == S and m2.group(2) == save,
      "the save is announced with the step and the file")
check(os.path.exists(save), "the save file exists")
check(not os.path.exists(save + ".tmp"), "no temporary file is left")

# 2. Restored and continued vs straight.
if os.path.exists(save) and S > 0:
    r = run(script, "resume", out, str(S), str(K))
    check(r.returncode == 0, "the restored run continues")
    r = run(script, "straight", out, str(S), str(K))
    check(r.returncode == 0, "the straight run")
    for a, b in [("straight_start.txt", "resumed_start.txt"), ("straight.txt", "resumed.txt"),
                 ("straight.csv", "split.csv"),
                 ("vtk_straight/talus.pvd", "vtk_split/talus.pvd")]:
        pa, pb = os.path.join(out, a), os.path.join(out, b)
        same = os.path.exists(pa) and os.path.exists(pb) and open(pa).read() == open(pb).read()
        check(same, f"{a} and {b} are equal")
    rows = open(os.path.join(out, "split.csv")).read().split("\n")[1:-1]
    check(len(rows) == (S + K) // 10 + 1, f"the history has {(S + K) // 10 + 1} rows "
          f"(got {len(rows)})")

# 3. A usage error.
r = subprocess.run([talus, "run", "--save-on-interrupt"], capture_output=True, text=True)
check(r.returncode == 2 and "needs a file name" in r.stderr, "the option needs a file name")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print(f"save on interrupt: stopped at step {S}, restored and continued {K} steps bit-identically")
