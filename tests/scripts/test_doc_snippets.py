# SPDX-License-Identifier: MIT
"""Runs every ```lua block of a documentation page with talus (ctest docs.coming_from): a page
that says its code runs as it is must keep saying the truth.

    python3 tests/scripts/test_doc_snippets.py TALUS PAGE.md WORKDIR
"""
import os
import re
import subprocess
import sys

talus, page, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
blocks = re.findall(r"^```lua\n(.*?)^```", open(page, encoding="utf-8").read(), re.S | re.M)
if not blocks:
    print(f"FAIL: no Lua block in {page}")
    sys.exit(1)
failed = 0
for k, code in enumerate(blocks, 1):
    script = os.path.join(work, f"block{k}.lua")
    with open(script, "w") as f:
        f.write(code)
    p = subprocess.run([talus, "run", "--quiet", script], cwd=work, capture_output=True,
                       text=True, timeout=240)
    print(f"--- block {k} (status {p.returncode})\n{p.stdout}{p.stderr}")
    if p.returncode != 0:
        failed += 1
if failed:
    print(f"FAIL: {failed} of {len(blocks)} Lua blocks of {os.path.basename(page)} failed")
    sys.exit(1)
print(f"{len(blocks)} Lua blocks of {os.path.basename(page)} ran")
