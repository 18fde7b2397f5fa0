#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Progress in a batch job and the watch on m:solve{ratio =} (docs/output.md, "The progress
line"; docs/lua-api.md, "Running"), on a scene that never settles (stall_scene.lua: its ratio
stays at 1 whatever the solve does). The intervals are shortened through the environment
(TALUS_PROGRESS_INTERVAL, TALUS_STALL_FIRST, TALUS_STALL_EVERY: 0.5 s instead of 60, 60 and
300 s) so that the test takes seconds.

usage: progress_log.py TALUS SCRIPT_DIR
Checks, with stderr a pipe (not a terminal):
  * a progress line of its own ("talus: progress: step ...", with the ratio and its target)
    every interval of a run longer than that;
  * "not getting closer to its target" on stderr, with the ratio now, its trend, the step and
    the simulated time, at the first check and again later;
  * --quiet: no progress lines, but the notices stay (they are warnings, not progress);
  * with m:on_warning set, the notices go to the script's handler, not to stderr;
  * default intervals (a minute): a 1.5 s run writes neither;
  * a bad TALUS_PROGRESS_INTERVAL is an error naming the variable.
"""
import os
import re
import subprocess
import sys

talus, here = sys.argv[1], sys.argv[2]
script = os.path.join(here, "stall_scene.lua")
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("check failed:", what)


def run(args, fast=True, env_extra=None):
    env = dict(os.environ)
    for k in ("TALUS_PROGRESS_INTERVAL", "TALUS_STALL_FIRST", "TALUS_STALL_EVERY"):
        env.pop(k, None)
    if fast:
        env.update(TALUS_PROGRESS_INTERVAL="0.5", TALUS_STALL_FIRST="0.5", TALUS_STALL_EVERY="0.5")
    env.update(env_extra or {})
    p = subprocess.run([talus, "run"] + args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, env=env, timeout=120)
    return p.returncode, p.stdout.decode(), p.stderr.decode()


PROGRESS = re.compile(r"^talus: progress: step [\d,]+  t = \S+ s  ratio 1 \(target 1e-05\)  "
                      r"[\d,]+ steps/s  \(running \d+:\d\d\)$", re.M)
NOTICE = re.compile(r"^warning: solve: the unbalanced-force ratio is not getting closer to its "
                    r"target 1e-05: 1 now; the best of the last \d+:\d\d is 1 against 1 in the "
                    r"\d+:\d\d before \([+-]0%\); at step [\d,]+, t = \S+ s after", re.M)

# 1. A 2.2 s run, stderr a pipe: progress lines and notices.
rc, out, err = run([script, "2.2"])
check(rc == 0, f"the run ends normally (status {rc}): {err}")
check("solve ended by max_time" in out, "the solve is ended by its max_time cap: " + out)
lines = PROGRESS.findall(err)
check(2 <= len(lines) <= 6, f"a progress line every 0.5 s of a 2.2 s run: {len(lines)}\n{err}")
notices = NOTICE.findall(err)
check(2 <= len(notices) <= 6, f"the notice at the first check and again: {len(notices)}\n{err}")
check("\r" not in err and "\033[K" not in err, "no terminal control characters in a log")

# 2. --quiet: no progress line; the notices stay.
rc, out, err = run(["--quiet", script, "1.2"])
check(rc == 0, f"--quiet: status {rc}")
check(not PROGRESS.search(err), "--quiet: no progress line:\n" + err)
check(NOTICE.search(err), "--quiet: the notice is still there:\n" + err)

# 3. The script's own warning handler receives the notices.
rc, out, err = run(["--quiet", script, "1.2", "handler"])
m = re.search(r"notices to the handler: (\d+)", out)
check(m and int(m.group(1)) >= 1, "on_warning receives the notices: " + out)
check("not getting closer" not in err, "... and stderr has none:\n" + err)

# 4. Default intervals: a run shorter than a minute leaves nothing.
rc, out, err = run([script, "1.5"], fast=False)
check(rc == 0 and not PROGRESS.search(err) and "not getting closer" not in err,
      "default intervals: nothing in a 1.5 s run:\n" + err)

# 5. A bad interval is named.
rc, out, err = run([script, "0.2"], fast=False, env_extra={"TALUS_PROGRESS_INTERVAL": "soon"})
check(rc == 1 and "TALUS_PROGRESS_INTERVAL must be a positive number of seconds (got 'soon')"
      in err, "a bad TALUS_PROGRESS_INTERVAL is an error: " + err)

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("progress_log: all checks passed")
