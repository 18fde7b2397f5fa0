# SPDX-License-Identifier: MIT
# Sourced by the benchmark scripts (dense_pack.sh, scaling.sh): names this machine and the
# compiler of the build directory $build for the results files.
# Sets: cpu, family, model, ncpu, machine (TALUS_BENCH_MACHINE overrides), cxx, compiler, flags.
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
family=$(lscpu | sed -n 's/^CPU family: *//p' | head -1)
model=$(lscpu | sed -n 's/^Model: *//p' | head -1)
ncpu=$(nproc)
machine=${TALUS_BENCH_MACHINE:-$(echo "$cpu-f${family}m${model}-${ncpu}cpu" | tr '[:upper:]' '[:lower:]' |
    sed 's/[^a-z0-9]\+/-/g; s/^-//; s/-$//')}
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
compiler="$("$cxx" --version | head -1)"
flags="$(sed -n 's/^CMAKE_CXX_FLAGS_RELEASE:[A-Z]*=//p' "$build/CMakeCache.txt")"
if grep -q '^TALUS_NATIVE:BOOL=ON' "$build/CMakeCache.txt"; then flags="$flags -march=native"; fi
