#!/bin/sh
# SPDX-License-Identifier: MIT
# Prints the guard-against-a-lying-model table of docs/physics/guard.md.
#   scripts/bench/guard_table.sh [build dir]
set -eu
here=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$here/build}
cmake --build "$build" --target talus_guard_table >/dev/null
# liar is a test-only model: it lives in the test plugin directory.
TALUS_PLUGIN_PATH="$build/plugins:$build/test_plugins" exec "$build/tests/bench/talus_guard_table"
