#!/bin/sh
# SPDX-License-Identifier: MIT
# Measures the accuracy of the `power` contact model (docs/models/power.md, "Measured accuracy"):
# restitution error against impact speed and step rule over random phases of first touch, and
# the exponent that matches An's (2006) calibration target. Prints Markdown.
#   scripts/bench/power_accuracy.sh [build dir] [--phases N] [--only restitution|exponent]
set -eu
here=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$here/build}
[ $# -gt 0 ] && shift
cmake --build "$build" --target talus_power_accuracy talus_power >/dev/null
TALUS_PLUGIN_PATH="$build/plugins" exec "$build/tests/bench/talus_power_accuracy" "$@"
