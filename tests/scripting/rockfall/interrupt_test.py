#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Ctrl-C in rockfall.monte_carlo (docs/rockfall.md, "Reruns resume"): a batch stopped half way
writes no statistics and no per-rock files, says how many rocks were done, and the rerun resumes
from the checkpoint to the same files, byte for byte, as one uninterrupted run.

usage: interrupt_test.py TALUS SCENE OUTDIR
SIGINT goes to the whole process group, as Ctrl-C on a terminal sends it (the caller and the
talus.map workers), once the checkpoint holds a few rocks.
"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import time

talus, scene, out = sys.argv[1], sys.argv[2], sys.argv[3]
N = 60
failures = []


def check(cond, what):
    print(("ok: " if cond else "check failed: ") + what)
    if not cond:
        failures.append(what)


def fresh_dir(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def run(outdir, *extra):
    p = subprocess.run([talus, "run", scene, outdir, str(N), *extra], stdin=subprocess.DEVNULL,
                       capture_output=True, text=True, timeout=600)
    return p.returncode, p.stdout + p.stderr


def csv_files(d):
    return sorted(os.path.basename(f) for f in glob.glob(os.path.join(d, "*.csv")))


# 1. Interrupted: SIGINT to the process group once a few rocks are in the checkpoint.
stopped = fresh_dir(os.path.join(out, "interrupted"))
ckpt = os.path.join(stopped, "checkpoint")
p = subprocess.Popen([talus, "run", scene, stopped, str(N)], stdin=subprocess.DEVNULL,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                     start_new_session=True)
deadline = time.time() + 120
while time.time() < deadline and p.poll() is None:
    if len(glob.glob(os.path.join(ckpt, "item_*.tmv"))) >= 4:
        break
    time.sleep(0.01)
check(p.poll() is None, "the batch was still running when Ctrl-C came (else raise N)")
os.killpg(p.pid, signal.SIGINT)
o, e = p.communicate(timeout=120)
text = o + e
print("--- interrupted run:\n" + text.strip()[-800:])
check(p.returncode == 130, f"exit status 130 after Ctrl-C (got {p.returncode})")
m = re.search(r"rockfall\.monte_carlo: map: interrupted \(Ctrl-C\) with (\d+) of (\d+) items done", text)
check(m is not None, "the error says how many rocks were done")
kept = len(glob.glob(os.path.join(ckpt, "item_*.tmv")))
if m:
    done = int(m.group(1))
    check(int(m.group(2)) == N and 0 < done < N, f"{done} of {N} rocks done: a part")
    check(done == kept, f"the checkpoint holds the {done} rocks done (found {kept})")
check(csv_files(stopped) == [], "no statistics and no per-rock file written: "
      + ", ".join(csv_files(stopped)))
check("interrupt_scene:" not in text, "the script did not go on after the interrupted batch")

# 2. The rerun resumes from the checkpoint ...
rc, text = run(stopped)
print("--- resumed run:\n" + text.strip()[-400:])
check(rc == 0, f"the rerun exits 0 (got {rc})")
check(f"{kept} of {N} items taken from the checkpoint" in text,
      f"the rerun takes the {kept} rocks from the checkpoint")
# 3. ... to the files of one uninterrupted run, byte for byte.
reference = fresh_dir(os.path.join(out, "uninterrupted"))
rc, text = run(reference, "fresh")
check(rc == 0, f"the uninterrupted run exits 0 (got {rc})")
names = csv_files(reference)
check(len(names) >= 10 and names == csv_files(stopped),
      f"the same files ({len(names)}: {', '.join(names)})")
for name in names:
    same = open(os.path.join(reference, name), "rb").read() == \
        open(os.path.join(stopped, name), "rb").read()
    check(same, f"{name}: resumed == uninterrupted, byte for byte")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("rockfall interrupt: all checks passed")
