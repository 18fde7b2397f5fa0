#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Turns numbered picture frames (m:picture{file = "out/f.png", every = N}: out/f_000000.png,
# out/f_000001.png, ...) into an MP4 video with ffmpeg (docs/output.md, "Animations").
#
#   scripts/frames_to_mp4.sh out/f.png [video.mp4] [frames per second, default 25]
#
# Needs ffmpeg (scripts/setup.sh installs it; or apt-get install ffmpeg).
set -euo pipefail
if [[ $# -lt 1 || $# -gt 3 ]]; then
    echo "usage: $0 FRAMES.png [VIDEO.mp4] [FPS]   (FRAMES.png: the file given to m:picture)" >&2
    exit 2
fi
base="$1"
stem="${base%.*}"
ext="${base##*.}"
video="${2:-$stem.mp4}"
fps="${3:-25}"
if ! command -v ffmpeg >/dev/null; then
    echo "$0: ffmpeg is not installed (apt-get install ffmpeg)" >&2
    exit 1
fi
if [[ "$ext" != png ]]; then
    echo "$0: frames must be PNG (got .$ext)" >&2
    exit 2
fi
if [[ ! -e "${stem}_000000.png" ]]; then
    echo "$0: no frames found: ${stem}_000000.png does not exist" >&2
    exit 1
fi
# H.264 needs even dimensions: pad by one pixel where needed. yuv420p plays everywhere.
ffmpeg -hide_banner -loglevel error -y -framerate "$fps" -i "${stem}_%06d.png" \
    -vf "pad=ceil(iw/2)*2:ceil(ih/2)*2:color=white" -c:v libx264 -pix_fmt yuv420p "$video"
n=$(ls "${stem}"_[0-9][0-9][0-9][0-9][0-9][0-9].png | wc -l)
echo "wrote $video ($n frames at $fps fps)"
