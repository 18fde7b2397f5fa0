#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Quick start, command 2: set up, build, and run every test through ctest.
# TALUS_SANITIZE=1 builds with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan, and
# the save-file fuzz target with clang (tests/fuzz; ctest fuzz.restore runs it for 30 s).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if [[ "${TALUS_SANITIZE:-0}" == 1 ]]; then
    export TALUS_BUILD_DIR="${TALUS_BUILD_DIR:-build-asan}"
    export TALUS_BUILD_TYPE="${TALUS_BUILD_TYPE:-RelWithDebInfo}"
    scripts/build.sh -DTALUS_SANITIZE=ON -DTALUS_WERROR=ON -DTALUS_FUZZ=ON
else
    scripts/build.sh -DTALUS_WERROR=ON
fi
ctest --test-dir "${TALUS_BUILD_DIR:-build}" --output-on-failure -j "$(nproc)"
