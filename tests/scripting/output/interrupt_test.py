#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Ctrl-C and the progress line (docs/output.md): talus is sent SIGINT in the middle of a long
m:cycle; the run must stop at the end of a step, with the history complete up to that step.

usage: interrupt_test.py TALUS SCRIPT_DIR OUTDIR
Checks, for each run:
  * exit status 130 and "interrupted (Ctrl-C) at step N" on stderr;
  * the history (a row every 10 steps, the first at step 0) has exactly N // 10 + 1 rows, each
    whole (three numbers), the last at step 10 * (N // 10): nothing lost, nothing torn;
  * on a pseudo-terminal the progress line ("steps/s") is drawn; with --quiet, or on pipes,
    it is not.
"""
import os
import pty
import re
import select
import signal
import subprocess
import sys
import time

talus, here, out = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out, exist_ok=True)
script = os.path.join(here, "interrupt_scene.lua")
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


def wait_for_rows(csv, minimum, timeout=60):
    """Waits until the history has `minimum` rows: the cycle is under way."""
    end = time.time() + timeout
    while time.time() < end:
        try:
            with open(csv) as f:
                if sum(1 for _ in f) > minimum:
                    return True
        except FileNotFoundError:
            pass
        time.sleep(0.05)
    return False


def run(mode, use_pty, quiet=False):
    csv = os.path.join(out, f"interrupt_{mode}.csv")
    if os.path.exists(csv):
        os.remove(csv)
    cmd = [talus, "run"] + (["--quiet"] if quiet else []) + [script, out, mode]
    if use_pty:
        master, slave = pty.openpty()
        p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=slave, stderr=slave)
        os.close(slave)
    else:
        p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE)
    # Histories are flushed only at the end of a run call, so rows appear on disk when the
    # stdio buffer fills: wait for some, then long enough for the progress line (drawn after
    # one second of a run call).
    started = wait_for_rows(csv, 5)
    check(started, f"{mode}: the cycle started (history rows on disk)")
    time.sleep(1.6)
    p.send_signal(signal.SIGINT)
    text = b""
    if use_pty:
        end = time.time() + 60
        while time.time() < end:
            r, _, _ = select.select([master], [], [], 0.5)
            if r:
                try:
                    chunk = os.read(master, 65536)
                except OSError:  # EIO: the child closed the terminal
                    break
                if not chunk:
                    break
                text += chunk
            elif p.poll() is not None:
                break
        os.close(master)
        p.wait(timeout=60)
    else:
        o, e = p.communicate(timeout=60)
        text = o + e
    text = text.decode(errors="replace")
    return p.returncode, text, csv


def check_history(csv, step, mode):
    rows = open(csv).read().split("\n")
    check(rows[-1] == "", f"{mode}: the history ends with a whole line")
    rows = rows[1:-1]
    check(len(rows) == step // 10 + 1, f"{mode}: {len(rows)} rows for step {step} (want "
          f"{step // 10 + 1})")
    for r in rows:
        cells = r.split(",")
        check(len(cells) == 3 and all(re.fullmatch(r"[-+0-9.eE]+", c) for c in cells),
              f"{mode}: row {r!r} is whole")
    check(int(rows[-1].split(",")[0]) == 10 * (step // 10), f"{mode}: the last row is at step "
          f"{rows[-1].split(',')[0]}, want {10 * (step // 10)}")


for mode, use_pty, quiet in [("plain", False, False), ("catch", False, False), ("solve", False, False),
                             ("plain", True, False), ("plain", True, True)]:
    label = f"{mode}{' pty' if use_pty else ''}{' --quiet' if quiet else ''}"
    rc, text, csv = run(mode, use_pty, quiet)
    print(f"--- {label}: exit {rc}\n{text.strip()[-600:]}")
    check(rc == 130, f"{label}: exit status 130 (got {rc})")
    m = re.search(r"interrupted \(Ctrl-C\) at step (\d+)" if mode != "solve" else
                  r"solve returned interrupted at step (\d+)", text)
    check(m is not None, f"{label}: the message names the step")
    if m:
        check_history(csv, int(m.group(1)), label)
    if mode == "catch":
        check("caught:" in text and "the script ended normally" in text,
              f"{label}: the script caught the interrupt and ended")
    drawn = "steps/s" in text
    check(drawn == (use_pty and not quiet), f"{label}: progress line drawn = {drawn}")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print("interrupt: all checks passed")
