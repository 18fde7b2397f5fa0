#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# scripts/frames_to_mp4.sh: eight frames of a falling ball become a video of eight frames.
# usage: mp4_test.sh TALUS SOURCE_DIR OUTDIR. Exit 77 (skipped) without ffmpeg, which
# scripts/setup.sh installs; under CI (CI set, a machine made by scripts/setup.sh) a missing
# ffmpeg is a failure, so the test cannot be skipped there unnoticed.
set -euo pipefail
talus="$1" src="$2" out="$3"
if ! command -v ffmpeg >/dev/null || ! command -v ffprobe >/dev/null; then
    if [[ -n "${CI:-}" ]]; then
        echo "FAIL: ffmpeg is not installed under CI; scripts/setup.sh installs it"
        exit 1
    fi
    echo "SKIP: ffmpeg is not installed (scripts/setup.sh installs it)"
    exit 77
fi
rm -rf "$out" && mkdir -p "$out"
cat > "$out/fall.lua" <<LUA
local m = talus.model{ gravity = {0, -9.81} }
m:wall{ points = {{-1, 0}, {1, 0}} }
m:ball{ pos = {0, 0.5}, radius = 0.05, density = 2600 }
m:timestep{ fixed = 0.01 }
m:picture{ file = "$out/f.png", every = 5, size = {161, 121} }  -- odd sizes: padded
m:cycle(35)
LUA
"$talus" run "$out/fall.lua"
"$src/scripts/frames_to_mp4.sh" "$out/f.png" "$out/fall.mp4" 10
frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
         -of csv=p=0 "$out/fall.mp4")
if [[ "$frames" != 8 ]]; then
    echo "FAIL: the video has $frames frames (want 8)"
    exit 1
fi
echo "mp4: 8 frames"
