#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Configures and builds Talus (Release by default) in ${TALUS_BUILD_DIR:-build}.
# Extra arguments go to CMake, e.g. scripts/build.sh -DTALUS_SANITIZE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${TALUS_BUILD_DIR:-build}"
# ccache, when present, makes rebuilds in several build trees cheap (it is optional).
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${TALUS_BUILD_TYPE:-Release}" "${launcher[@]}" "$@" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
