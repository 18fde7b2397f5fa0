#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Dense-pack benchmark, Talus against LAMMPS, on the same settled state, on this machine, in
# one session (docs/benchmarks.md). One command:
#
#   scripts/bench/dense_pack.sh
#
# builds Release in its own directory, settles the pack once per size (cached), then repeats
# { Talus sorted, Talus unsorted, LAMMPS } for every size, appends every timed run to
# scripts/bench/results/<machine>.csv and prints markdown tables (minimum over the repeats and
# the spread). Settings (environment):
#   TALUS_BENCH_SIZES    "10000 50000"          particle counts
#   TALUS_BENCH_STEPS    "10000:5000 50000:1000" timed steps per size (default 1000)
#   TALUS_BENCH_WARMUP   1000                   untimed steps before each timed run
#   TALUS_BENCH_REPEATS  3
#   TALUS_BENCH_BUILD    build-bench            build directory (settled states cached in it)
#   TALUS_NATIVE         OFF                    ON adds -march=native to Talus
#   TALUS_BENCH_MACHINE  (from lscpu)           name of the results file
#   TALUS_BENCH_CSV      scripts/bench/results/<machine>.csv
#   TALUS_BENCH_SKIP_LAMMPS 0                   1: Talus only
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)

sizes=${TALUS_BENCH_SIZES:-"10000 50000"}
steps_for=${TALUS_BENCH_STEPS:-"10000:5000 50000:1000"}
warmup=${TALUS_BENCH_WARMUP:-1000}
repeats=${TALUS_BENCH_REPEATS:-3}
build=${TALUS_BENCH_BUILD:-build-bench}
native=${TALUS_NATIVE:-OFF}
skip_lammps=${TALUS_BENCH_SKIP_LAMMPS:-0}

steps_of() {
    local n=$1 pair
    for pair in $steps_for; do
        if [[ ${pair%%:*} == "$n" ]]; then echo "${pair#*:}"; return; fi
    done
    echo 1000
}

# ---------------------------------------------------------------------------- build
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DTALUS_NATIVE="$native" >/dev/null
cmake --build "$build" --target talus_bench_dense_pack talus_linear -j "$(nproc)" >/dev/null
bench="$root/$build/tests/bench/talus_bench_dense_pack"
# A program other than build/talus finds the models through TALUS_PLUGIN_PATH.
export TALUS_PLUGIN_PATH="$root/$build/plugins${TALUS_PLUGIN_PATH:+:$TALUS_PLUGIN_PATH}"
cache="$root/$build/bench-cache"
mkdir -p "$cache" scripts/bench/results

# ---------------------------------------------------------------------------- machine
source "$root/scripts/bench/machine.sh"
talus_version="$(git describe --always --dirty 2>/dev/null || echo unknown)"
lammps_version=""
lammps_compiler=""
if [[ $skip_lammps != 1 ]]; then
    command -v lmp >/dev/null || { echo "lmp not found (Debian package lammps)" >&2; exit 1; }
    lmp_help=$(lmp -h)
    grep -q GRANULAR <<<"$lmp_help" || { echo "this LAMMPS has no GRANULAR package" >&2; exit 1; }
    lammps_version="$(sed -n 's/^Large-scale [^-]* - //p' <<<"$lmp_help" | head -1)"
    lammps_compiler="$(sed -n 's/^Compiler: //p' <<<"$lmp_help" | head -1)"
fi
session=$(date -u +%Y%m%dT%H%M%SZ)
raw="$cache/session-$session.txt"
csv=${TALUS_BENCH_CSV:-scripts/bench/results/$machine.csv}
echo "dense-pack benchmark, session $session"
echo "  cpu: $cpu (family $family model $model, $ncpu cpus); load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "  talus: $talus_version, $compiler, $flags"
[[ -n $lammps_version ]] && echo "  lammps: $lammps_version, $lammps_compiler"

# ---------------------------------------------------------------------------- settle (cached)
for n in $sizes; do
    state="$cache/state_n${n}_seed1.txt"
    "$bench" "$n" 1 --settle-only --state "$state" --export-lammps "$cache/pack_n${n}.data" |
        sed 's/^/  /'
done

# ---------------------------------------------------------------------------- timed runs
export OMP_NUM_THREADS=1
for rep in $(seq 1 "$repeats"); do
    for n in $sizes; do
        steps=$(steps_of "$n")
        state="$cache/state_n${n}_seed1.txt"
        for mode in sorted unsorted; do
            load=$(cut -d' ' -f1 /proc/loadavg)
            out=$("$bench" "$n" "$steps" "$mode" --state "$state" --warmup "$warmup" 2>&1)
            line=$(grep '^RESULT ' <<<"$out") || { echo "$out" >&2; exit 1; }
            echo "$line rep=$rep load1=$load" >>"$raw"
            echo "  rep $rep  N=$n  talus $mode: $(grep -o 'ns_per_particle_step=[^ ]*' <<<"$line")"
        done
        if [[ $skip_lammps != 1 ]]; then
            load=$(cut -d' ' -f1 /proc/loadavg)
            log="$cache/lammps_n${n}_rep${rep}.log"
            lmp -in scripts/bench/lammps/in.dense_pack -var data "$cache/pack_n${n}.data" \
                -var steps "$steps" -var warmup "$warmup" -log "$log" -screen none
            line=$(python3 scripts/bench/dense_pack_report.py lammps-log "$log" "$n")
            echo "$line warmup=$warmup rep=$rep load1=$load" >>"$raw"
            echo "  rep $rep  N=$n  lammps: $(grep -o 'ns_per_particle_step=[^ ]*' <<<"$line")"
        fi
    done
done

python3 scripts/bench/dense_pack_report.py report "$raw" "$csv" "session=$session" \
    "date_utc=$(date -u +%Y-%m-%dT%H:%MZ)" "machine=$machine" "cpu=$cpu" "compiler=$compiler" \
    "flags=$flags" "talus_version=$talus_version" "lammps_version=$lammps_version" \
    "lammps_compiler=$lammps_compiler"
echo
echo "load at the end: $(cut -d' ' -f1-3 /proc/loadavg); rows appended to $csv"
