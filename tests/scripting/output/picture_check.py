# SPDX-License-Identifier: MIT
"""What the picture tests share: run a scene that prints "PIXEL name x y" (out:pixel), read the
pixels back, and collect failed checks."""
import os
import re
import shutil
import subprocess
import sys


class PictureCheck:
    def __init__(self, talus, out, scene):
        """Runs `scene` (beside this file) with `talus` into a fresh `out`."""
        here = os.path.dirname(os.path.abspath(__file__))
        shutil.rmtree(out, ignore_errors=True)
        os.makedirs(out)
        r = subprocess.run([talus, "run", os.path.join(here, scene), out],
                           capture_output=True, text=True)
        sys.stdout.write(r.stdout)
        sys.stderr.write(r.stderr)
        if r.returncode != 0:
            sys.exit(f"FAIL: {scene} failed")
        self.stdout = r.stdout
        self.pix = {m.group(1): (float(m.group(2)), float(m.group(3)))
                    for m in re.finditer(r"PIXEL (\S+) (\S+) (\S+)", r.stdout)}
        self.failures = []

    def check(self, cond, what):
        if not cond:
            self.failures.append(what)
            print("check failed:", what)

    def at(self, img, name):
        """The colour (r, g, b) of `img` at the pixel the scene printed as `name`."""
        x, y = self.pix[name]
        return img.getpixel((int(x), int(y)))[:3]

    def finish(self, what):
        if self.failures:
            print(f"{len(self.failures)} checks failed")
            sys.exit(1)
        print(f"{what}: all checks passed")
