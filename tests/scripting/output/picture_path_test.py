#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""m:picture{path =, paths =} (docs/output.md, "Pictures"): runs picture_path_scene.lua and
checks the pixels along the paths: the tracked centres of a thrown ball drawn in the first path
colour (Dark2 #1B9E77), 0.25 m (25 px) below them background; the paths given as {x, y} and
{t, x, y} points in the second and third colours; the same points white in a picture without
paths; a series' first frame without the flight and its last with it.

usage: picture_path_test.py TALUS OUTDIR
"""
import os
import re
import sys

from PIL import Image  # python3-pil, a dependency of python3-matplotlib (scripts/setup.sh)

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from picture_check import PictureCheck  # noqa: E402 (beside this file)

t = PictureCheck(sys.argv[1], sys.argv[2], "picture_path_scene.lua")
out, pix, check, at = sys.argv[2], t.pix, t.check, t.at
frames = int(re.search(r"FRAMES (\d+)", t.stdout).group(1))


DARK2 = [(0x1B, 0x9E, 0x77), (0xD9, 0x5F, 0x02), (0x75, 0x70, 0xB3)]
WHITE = (255, 255, 255)


def near(c, want, tol=12):
    """A 3 px line: its centre pixel is the colour itself, up to cairo's antialiasing of a
    centre that falls between pixels (a few units)."""
    return all(abs(a - b) <= tol for a, b in zip(c, want))


paths = Image.open(os.path.join(out, "paths.png")).convert("RGB")
bare = Image.open(os.path.join(out, "bare.png")).convert("RGB")
on = sorted(k for k in pix if k.startswith("on."))
check(len(on) == 8, f"eight points along the flight ({len(on)})")
for k in on:
    below = "below." + k[3:]
    check(near(at(paths, k), DARK2[0]), f"{k}: the tracked path drawn ({at(paths, k)})")
    check(at(paths, below) == WHITE, f"{below}: background 25 px below ({at(paths, below)})")
    check(at(bare, k) == WHITE, f"{k}: white without paths ({at(bare, k)})")
check(near(at(paths, "line2"), DARK2[1]), f"path 2 ({{x, y}} points): {at(paths, 'line2')}")
check(near(at(paths, "line3"), DARK2[2]), f"path 3 ({{t, x, y}} points): {at(paths, 'line3')}")
check(near(at(paths, "start"), DARK2[0]), f"the start dot: {at(paths, 'start')}")
check(at(bare, "line2") == WHITE and at(bare, "line3") == WHITE, "no paths, no lines")

# The series: frame 0 at t = 0 (one point, the start dot), the last at t = 0.8 s.
check(frames == 81, f"81 frames (every 100 of 8000 steps): {frames}")
first = Image.open(os.path.join(out, "flight_000000.png")).convert("RGB")
last = Image.open(os.path.join(out, f"flight_{frames - 1:06d}.png")).convert("RGB")
check(at(first, "mid") == WHITE, f"frame 0: the flight is still ahead ({at(first, 'mid')})")
check(near(at(first, "start"), DARK2[0]), f"frame 0: the start dot ({at(first, 'start')})")
check(near(at(last, "mid"), DARK2[0]), f"last frame: the path at x = 2 m ({at(last, 'mid')})")

t.finish("picture paths")
