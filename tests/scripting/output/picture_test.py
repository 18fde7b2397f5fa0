#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""m:picture (docs/output.md, "Pictures"): runs picture_scene.lua and checks the files: PNG size,
the colour at the centre of balls whose colour the docs define (group palette, viridis ends,
background), SVG and PDF signatures, numbered frames.

usage: picture_test.py TALUS OUTDIR
"""
import os
import sys

from PIL import Image  # python3-pil, a dependency of python3-matplotlib (scripts/setup.sh)

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from picture_check import PictureCheck  # noqa: E402 (beside this file)

t = PictureCheck(sys.argv[1], sys.argv[2], "picture_scene.lua")
out, pix, check = sys.argv[2], t.pix, t.check


def hexrgb(h):
    return ((h >> 16) & 255, (h >> 8) & 255, h & 255)


at = t.at


# The colours docs/output.md promises: Tableau 10's first two for the first two groups, light
# grey for no group, viridis' ends for the bottom and top of a numeric scale, white background.
# The centre of a disk 20+ px across is far from its antialiased rim: exact equality.
g = Image.open(os.path.join(out, "groups.png")).convert("RGB")
check(g.size == (400, 300), f"groups.png is 400 x 300 (got {g.size})")
check(at(g, "groups.a") == hexrgb(0x4E79A7), f"group a is blue (got {at(g, 'groups.a')})")
check(at(g, "groups.b") == hexrgb(0xF28E2B), f"group b is orange (got {at(g, 'groups.b')})")
check(at(g, "groups.c") == hexrgb(0xD9D9D9), f"no group is grey (got {at(g, 'groups.c')})")
check(at(g, "groups.empty") == (255, 255, 255), "the background is white")
# The ball of group a spans 2 m = 2 * scale px: its colour at 0.8 radius, not beyond 1.2.
xa, ya = pix["groups.a"]
xb, _ = pix["groups.b"]
scale = (xb - xa) / 4.0  # the balls are 4 m apart
check(g.getpixel((int(xa + 0.8 * scale), int(ya)))[:3] == hexrgb(0x4E79A7), "ball a's extent")
check(g.getpixel((int(xa + 1.2 * scale), int(ya)))[:3] == (255, 255, 255), "ball a ends at r")

v = Image.open(os.path.join(out, "value.png")).convert("RGB")
check(at(v, "value.lo") == hexrgb(0x440154), f"lowest value: viridis' bottom ({at(v, 'value.lo')})")
check(at(v, "value.hi") == hexrgb(0xFDE725), f"highest value: viridis' top ({at(v, 'value.hi')})")
s = Image.open(os.path.join(out, "speed.png")).convert("RGB")
check(at(s, "speed.hi") == hexrgb(0xFDE725), f"4 m/s in range {{0, 4}} is the top colour")

svg = open(os.path.join(out, "scene.svg"), "rb").read(400)
check(b"<svg" in svg, "scene.svg is an SVG")
check(open(os.path.join(out, "scene.pdf"), "rb").read(5) == b"%PDF-", "scene.pdf is a PDF")
frames = sorted(os.listdir(os.path.join(out, "frames")))
check(frames == [f"frame_{i:06d}.png" for i in range(5)], f"numbered frames: {frames}")
check(Image.open(os.path.join(out, "frames", frames[-1])).size == (160, 120), "frame size")

t.finish("picture")
