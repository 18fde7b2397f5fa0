#!/bin/sh
# SPDX-License-Identifier: MIT
# Work-precision of the linear, hertz, ng and hysdamp contact models (docs/models/<model>.md,
# "Measured accuracy"): restitution error over random phases of first touch against run time, as
# the step varies (stability rule at safety 0.9 ... 0.05 with the resolution rule off, and the
# resolution rule at 5 ... 100 steps per contact). Builds what it needs, prints Markdown tables.
#   scripts/bench/model_accuracy.sh [build dir] [--phases N] [--model NAME]... [--seed S]
# The build dir must be configured already (cmake -S . -B <dir>); default: build-b1, then build.
set -eu
here=$(cd "$(dirname "$0")/../.." && pwd)
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then
  build=$1
  shift
elif [ -d "$here/build-b1" ]; then
  build=$here/build-b1
else
  build=$here/build
fi
cmake --build "$build" --target talus_model_accuracy talus_linear talus_hertz talus_ng \
  talus_hysdamp >/dev/null
TALUS_PLUGIN_PATH="$build/plugins" exec "$build/tests/bench/talus_model_accuracy" "$@"
