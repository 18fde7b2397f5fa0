#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Threads against ranks on the dense pack (docs/results/benchmarks-history.md, "Threads by
# ownership"): per repeat and size, in turn, Talus on 1 and on 2 threads, on 1 thread with the
# models' FDlaw instead of the host's kernels (--no-kernels), and LAMMPS on 1 and on 2 MPI ranks,
# from the settled states of scripts/bench/dense_pack.sh (run that first: it builds and caches
# them).
#
#   scripts/bench/threads.sh            # 3 repeats, 10k (2000 steps) and 50k (600 steps)
#
# Settings (environment): TALUS_BENCH_BUILD (build-bench), TALUS_BENCH_REPEATS (3),
# TALUS_BENCH_WARMUP (300). Prints one line per run; compare minima (the host is noisy).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/bench/lammps_dense_pack.sh
build=${TALUS_BENCH_BUILD:-build-bench}
repeats=${TALUS_BENCH_REPEATS:-3}
warmup=${TALUS_BENCH_WARMUP:-300}
bench=$build/tests/bench/talus_bench_dense_pack
cache=$build/bench-cache
[[ -x $bench ]] || { echo "no $bench: run scripts/bench/dense_pack.sh first" >&2; exit 1; }
export TALUS_PLUGIN_PATH=$build/plugins
for rep in $(seq 1 "$repeats"); do
    for n in 10000 50000; do
        steps=2000
        [[ $n == 50000 ]] && steps=600
        [[ -f $cache/state_n${n}_seed1.txt ]] || { echo "no settled state for $n" >&2; exit 1; }
        for variant in "1" "2" "1 --no-kernels"; do
            read -r th extra <<<"$variant"
            r=$(TALUS_THREADS=$th OMP_NUM_THREADS=$th "$bench" "$n" "$steps" sorted \
                --state "$cache/state_n${n}_seed1.txt" --warmup "$warmup" --no-profile $extra 2>&1 |
                grep -o "ns_per_particle_step=[^ ]*")
            echo "rep=$rep n=$n talus threads=$th ${extra:-} $r load=$(cut -d' ' -f1 /proc/loadavg)"
        done
        for np in 1 2; do
            r="ns_per_particle_step=$(lammps_dense_pack_ns "$cache/pack_n${n}.data" "$n" "$steps" "$warmup" "$np")"
            echo "rep=$rep n=$n lammps ranks=$np $r"
        done
    done
done
