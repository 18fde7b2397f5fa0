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
3. The same with an endless m:solve, which returns "interrupted" to the script (the save is
   taken before): the save is at the step the script prints, and a restored run continues
   as the cycle's did (same state after S2 + K steps as a straight run).
4. Usage errors: the option without a file name exits 2.
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


def interrupted_run(phase, save):
    """Starts PHASE with --save-on-interrupt SAVE, sends SIGINT after the marker; returns
    (the step of the save message, stdout, stderr)."""
    marker = os.path.join(out, "marker")
    if os.path.exists(marker):
        os.remove(marker)
    p = subprocess.Popen([talus, "run", "--save-on-interrupt", save, script, phase, out],
                         stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    end = time.time() + 300
    while not os.path.exists(marker) and time.time() < end and p.poll() is None:
        time.sleep(0.02)
    check(os.path.exists(marker), f"{phase}: the run got past step 300")
    p.send_signal(signal.SIGINT)
    o, e = p.communicate(timeout=300)
    print(f"--- {phase}: exit {p.returncode}\n{o}{e}")
    check(p.returncode == 130, f"{phase}: exit status 130 (got {p.returncode})")
    m = re.search(r"saved the model at step (\d+) \(t = [^)]*\) to (.*)", e)
    check(m is not None and m.group(2) == save, f"{phase}: the save is announced with the file")
    check(os.path.exists(save), f"{phase}: the save file exists")
    check(not os.path.exists(save + ".tmp"), f"{phase}: no temporary file is left")
    return (int(m.group(1)) if m else -1), o, e


def compare(pairs):
    for a, b in pairs:
        pa, pb = os.path.join(out, a), os.path.join(out, b)
        same = os.path.exists(pa) and os.path.exists(pb) and open(pa).read() == open(pb).read()
        check(same, f"{a} and {b} are equal")


# 1. The interrupted cycle.
S, o, e = interrupted_run("run", save)
m = re.search(r"interrupted \(Ctrl-C\) at step (\d+)", e)
check(m is not None and int(m.group(1)) == S, "the error names the step of the save")
check(S >= 300, f"stopped after the marker (step {S})")

# 2. Restored and continued vs straight.
if os.path.exists(save) and S > 0:
    r = run(script, "resume", out, str(S), str(K))
    check(r.returncode == 0, "the restored run continues")
    r = run(script, "straight", out, str(S), str(K))
    check(r.returncode == 0, "the straight run")
    compare([("straight_start.txt", "resumed_start.txt"), ("straight.txt", "resumed.txt"),
             ("straight.csv", "split.csv"), ("vtk_straight/talus.pvd", "vtk_split/talus.pvd")])
    rows = open(os.path.join(out, "split.csv")).read().split("\n")[1:-1]
    check(len(rows) == (S + K) // 10 + 1, f"the history has {(S + K) // 10 + 1} rows "
          f"(got {len(rows)})")

# 3. The interrupted solve: the script goes on after m:solve returned "interrupted".
solve_save = os.path.join(out, "solve.talus")
S2, o, e = interrupted_run("run_solve", solve_save)
m = re.search(r"solve returned interrupted at step (\d+)", o)
check(m is not None and int(m.group(1)) == S2, "m:solve returned at the step of the save")
if os.path.exists(solve_save) and S2 > 0:
    r = run(script, "resume", out, str(S2), str(K), "solve.talus")
    check(r.returncode == 0, "the restored run continues (solve)")
    r = run(script, "straight", out, str(S2), str(K))
    check(r.returncode == 0, "the straight run (solve)")
    compare([("straight_start.txt", "resumed_solve_start.txt"),
             ("straight.txt", "resumed_solve.txt")])

# 4. A usage error.
r = subprocess.run([talus, "run", "--save-on-interrupt"], capture_output=True, text=True)
check(r.returncode == 2 and "needs a file name" in r.stderr, "the option needs a file name")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print(f"save on interrupt: cycle stopped at step {S}, solve at step {S2}; both restored and "
      f"continued {K} steps bit-identically")
