#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Quick start, command 1: set up, build, and run the main job -- a rock falling down the stepped
# slope of thesis B. Writes out/rockfall_history.csv and out/rockfall_history.svg.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
mkdir -p out
"${TALUS_BUILD_DIR:-build}/talus" run scripts/examples/rockfall.lua out
