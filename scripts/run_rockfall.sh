#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Quick start, command 1: set up, build, and run the main job -- a small rockfall analysis on the
# stepped slope of Nejati (2008) (scripts/examples/rockfall_analysis.lua, docs/rockfall.md): 300 clump
# rocks from a line seeder, two slope materials, a barrier and two collectors, on all cores.
# Writes the statistics CSVs and out/rockfall_analysis/rockfall.png (end points, reach,
# envelopes, trajectories; scripts/plot_rockfall.py) and rockfall_endpoints.png (where each rock
# stopped, m:picture; docs/output.md), then one rock's energy history
# (scripts/examples/single_rock.lua): out/rockfall_history.csv and .png, out/rockfall_path.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
talus="${TALUS_BUILD_DIR:-build}/talus"
mkdir -p out
"$talus" run scripts/examples/rockfall_analysis.lua out/rockfall_analysis
# The plot scripts re-run themselves with Debian's /usr/bin/python3 when the python3 on PATH has
# no matplotlib (pyenv, a venv).
python3 scripts/plot_rockfall.py out/rockfall_analysis -o out/rockfall_analysis/rockfall.png \
    --title "Rockfall analysis on the Nejati (2008) slope (300 rocks)"
"$talus" run scripts/examples/single_rock.lua out
python3 scripts/plot_history.py out/rockfall_history.csv -o out/rockfall_history.png \
    --title "One rock on the Nejati (2008) slope: energies"
python3 scripts/plot_history.py out/rockfall_history.csv out/rockfall_slope.csv \
    -o out/rockfall_path.png --x x --columns y --equal --size 10,4 \
    --xlabel "x [m]" --ylabel "y [m]" --title "One rock on the Nejati (2008) slope: path of the rock centre"
