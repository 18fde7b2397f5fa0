#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs what Talus needs from Debian's packages (idempotent: installs only what is missing).
# Works as root on a fresh machine, or through sudo.
set -euo pipefail

# python3-matplotlib: scripts/plot_history.py, the plotting tool (and its test).
# libopenmpi-dev, openmpi-bin: talus.map across machines (mpirun); optional for the build.
# libcairo2-dev: m:picture (optional for the build: without it m:picture says so).
# python3-vtk9, python3-pil: the output tests read ParaView files back with VTK's own readers
# and check picture pixels (docs/output.md).
# clang, libclang-rt-dev: the save-file fuzz target (tests/fuzz, libFuzzer; -DTALUS_FUZZ=ON).
# ffmpeg: scripts/frames_to_mp4.sh (picture frames to a video) and its test, lua.output.mp4.
# dpkg-dev, file: the Debian package (cpack -G DEB reads its Depends off the binaries with
# dpkg-shlibdeps) and its test, install.deb_contents.
packages=(build-essential cmake pkg-config libeigen3-dev libbox2d-dev liblua5.4-dev catch2
          python3 python3-matplotlib libopenmpi-dev openmpi-bin libcairo2-dev python3-vtk9
          python3-pil clang libclang-rt-dev ffmpeg dpkg-dev file)
if [[ "${TALUS_WITH_LAMMPS:-0}" == 1 ]]; then packages+=(lammps); fi

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
if ((${#missing[@]} == 0)); then
    echo "setup: all packages present (${packages[*]})"
    exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then
    if command -v sudo >/dev/null; then sudo="sudo"; else
        echo "setup: need root (or sudo) to install: ${missing[*]}" >&2
        exit 1
    fi
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
