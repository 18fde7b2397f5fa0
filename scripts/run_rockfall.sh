#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Quick start, command 1: set up, build, and run the main job -- a rock falling down the stepped
# slope of thesis B. Writes out/rockfall_history.csv and plots it with scripts/plot_history.py
# (matplotlib): out/rockfall_history.png (the energies against time) and out/rockfall_path.png
# (the path of the rock's centre over the slope profile, out/rockfall_slope.csv).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
mkdir -p out
"${TALUS_BUILD_DIR:-build}/talus" run scripts/examples/rockfall.lua out
# plot_history.py re-runs itself with Debian's /usr/bin/python3 when the python3 on PATH has no
# matplotlib (pyenv, a venv).
python3 scripts/plot_history.py out/rockfall_history.csv -o out/rockfall_history.png \
    --title "Rockfall on the thesis B slope: energies"
python3 scripts/plot_history.py out/rockfall_history.csv out/rockfall_slope.csv \
    -o out/rockfall_path.png --x x --columns y --equal --size 10,4 \
    --xlabel "x [m]" --ylabel "y [m]" --title "Rockfall on the thesis B slope: path of the rock centre"
