#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Scaling of the dense-pack benchmark with N, Talus against LAMMPS (1 and 2 MPI ranks), on the
# same settled states, on this machine, in one session (docs/results/benchmarks-history.md, "Scaling, 1k to 1M
# disks"). One command:
#
#   scripts/bench/scaling.sh
#
# builds Release (unless told not to), makes the settled pack of every size once (cached; a size
# already in the cache is never settled again), then, for every repeat and size in turn, times
#   talus    talus_bench_dense_pack N STEPS sorted --no-profile (1 thread)
#   lammps1  lmp, 1 rank                      (OMP_NUM_THREADS=1)
#   lammps2  mpirun -n 2 lmp, 2 ranks         (OMP_NUM_THREADS=1, --bind-to none)
# appends one CSV row per timed run to scripts/bench/results/scaling_<machine>.csv as soon as it
# ends, and at the end prints the table and draws docs/figures/scaling.png
# (scripts/bench/scaling_plot.py).
#
# Sizes above TALUS_SCALING_SETTLE_MAX are not settled from the lattice (1M disks would take
# hours): they are K side-by-side copies of a settled N/K pack, every other one mirrored, relaxed
# with local damping (talus_bench_dense_pack --tiles K; docs/results/benchmarks-history.md says why this is the
# same scene per disk). Talus and LAMMPS start from the same state file either way.
#
# Settings (environment):
#   TALUS_SCALING_SIZES      "1000 3000 10000 30000 100000 300000 1000000"
#   TALUS_SCALING_WORK       1e8     particle-steps per timed run: STEPS = WORK / N (>= 100),
#                                    i.e. 10 s at 100 ns per particle-step
#   TALUS_SCALING_STEPS      ""      overrides per size, "N:STEPS N:STEPS ..."
#   TALUS_SCALING_WARMUP     200     untimed steps before each timed run (all sizes: the same
#                                    simulated time, about a dozen contact durations)
#   TALUS_SCALING_REPEATS    3       interleaved repeats (the table takes the minimum)
#   TALUS_SCALING_SETTLE_MAX 10000   largest N settled from the lattice; larger N are tiled
#   TALUS_SCALING_CODES      "talus lammps1 lammps2"  which columns to time
#   TALUS_SCALING_SESSION    (new)   resume that session: runs already in the CSV are skipped
#   TALUS_SCALING_PLOT       docs/figures/scaling.png ("" = no plot)
#   TALUS_BENCH_BUILD        build-bench   build directory of the Talus measured
#   TALUS_BENCH_NO_BUILD     0       1: use TALUS_BENCH_BUILD as it is (no cmake)
#   TALUS_BENCH_CACHE        $TALUS_BENCH_BUILD/bench-cache  settled states (shareable between
#                                    build dirs and trees: a state is only positions)
#   TALUS_NATIVE             OFF     ON adds -march=native to Talus
#   TALUS_BENCH_MACHINE      (from lscpu)  name in the results file
#   TALUS_SCALING_CSV        scripts/bench/results/scaling_<machine>.csv
#   TALUS_SCALING_MPIRUN     "mpirun -n 2 --bind-to none" (+ --allow-run-as-root as root)
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)

sizes=${TALUS_SCALING_SIZES:-"1000 3000 10000 30000 100000 300000 1000000"}
work=${TALUS_SCALING_WORK:-1e8}
steps_for=${TALUS_SCALING_STEPS:-}
warmup=${TALUS_SCALING_WARMUP:-200}
repeats=${TALUS_SCALING_REPEATS:-3}
settle_max=${TALUS_SCALING_SETTLE_MAX:-10000}
codes=${TALUS_SCALING_CODES:-"talus lammps1 lammps2"}
build=${TALUS_BENCH_BUILD:-build-bench}
native=${TALUS_NATIVE:-OFF}
plot=${TALUS_SCALING_PLOT-docs/figures/scaling.png}
report="$root/scripts/bench/scaling_plot.py"

steps_of() {
    local n=$1 pair
    for pair in $steps_for; do
        if [[ ${pair%%:*} == "$n" ]]; then echo "${pair#*:}"; return; fi
    done
    python3 -c "import sys; print(max(100, round(float(sys.argv[1]) / int(sys.argv[2]))))" \
        "$work" "$n"
}

# Tiles of size N: 1 if N is settled from the lattice, else the least K with N/K <= settle_max
# and K dividing N.
tiles_of() {
    local n=$1 k=1
    while ((n / k > settle_max || n % k != 0)); do k=$((k + 1)); done
    echo "$k"
}

for n in $sizes; do
    [[ $n =~ ^[0-9]+$ ]] && ((n >= 1)) || { echo "scaling: bad size '$n'" >&2; exit 2; }
done
for c in $codes; do
    [[ $c == talus || $c == lammps1 || $c == lammps2 ]] ||
        { echo "scaling: unknown code '$c' (talus, lammps1, lammps2)" >&2; exit 2; }
done

# ---------------------------------------------------------------------------- build
if [[ ${TALUS_BENCH_NO_BUILD:-0} != 1 ]]; then
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DTALUS_NATIVE="$native" >/dev/null
    cmake --build "$build" --target talus_bench_dense_pack talus_linear -j "$(nproc)" >/dev/null
fi
build=$(cd "$build" && pwd)
bench="$build/tests/bench/talus_bench_dense_pack"
# A program other than build/talus finds the models through TALUS_PLUGIN_PATH.
export TALUS_PLUGIN_PATH="$build/plugins${TALUS_PLUGIN_PATH:+:$TALUS_PLUGIN_PATH}"
[[ -x $bench ]] || { echo "scaling: no $bench (build it, or unset TALUS_BENCH_NO_BUILD)" >&2; exit 1; }
cache=${TALUS_BENCH_CACHE:-$build/bench-cache}
mkdir -p "$cache" scripts/bench/results
cache=$(cd "$cache" && pwd)

# ---------------------------------------------------------------------------- machine
source "$root/scripts/bench/machine.sh"
# The commit of the tree the build was configured from (it may be another work tree).
src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:[A-Z]*=//p' "$build/CMakeCache.txt")
talus_version="$(git -C "${src:-.}" describe --always --dirty 2>/dev/null || echo unknown)"
lammps_version=""
mpirun_cmd=()
if [[ " $codes " == *" lammps"* ]]; then
    command -v lmp >/dev/null || { echo "scaling: lmp not found (Debian package lammps)" >&2; exit 1; }
    lmp_help=$(lmp -h)
    grep -q GRANULAR <<<"$lmp_help" || { echo "scaling: this LAMMPS has no GRANULAR package" >&2; exit 1; }
    lammps_version="$(sed -n 's/^Large-scale [^-]* - //p' <<<"$lmp_help" | head -1)"
fi
if [[ " $codes " == *" lammps2 "* ]]; then
    command -v mpirun >/dev/null || { echo "scaling: mpirun not found (Debian package openmpi-bin)" >&2; exit 1; }
    if [[ -n ${TALUS_SCALING_MPIRUN:-} ]]; then
        read -r -a mpirun_cmd <<<"$TALUS_SCALING_MPIRUN"
    else
        # --bind-to none: Open MPI would pin each rank to a core, and on a machine shared with
        # other jobs a pinned rank waits for its core while the other core is free.
        mpirun_cmd=(mpirun -n 2 --bind-to none)
        [[ $(id -u) == 0 ]] && mpirun_cmd+=(--allow-run-as-root)
    fi
    mpirun_cmd+=(-x OMP_NUM_THREADS)
fi

session=${TALUS_SCALING_SESSION:-$(date -u +%Y%m%dT%H%M%SZ)}
csv=${TALUS_SCALING_CSV:-scripts/bench/results/scaling_$machine.csv}
logs="$cache/scaling-$session"
mkdir -p "$logs"
t_start=$(date +%s)
echo "scaling benchmark, session $session"
echo "  cpu: $cpu (family $family model $model, $ncpu cpus); load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "  talus: $talus_version ($build), $compiler, $flags"
[[ -n $lammps_version ]] && echo "  lammps: $lammps_version; 2 ranks: ${mpirun_cmd[*]}"
echo "  states: $cache"

state_of() {  # the state file of size N
    local n=$1 k
    k=$(tiles_of "$n")
    if ((k == 1)); then echo "$cache/state_n${n}_seed1.txt"; else echo "$cache/state_n${n}_seed1_tiles$k.txt"; fi
}
data_of() {  # the LAMMPS data file exported from that state
    local n=$1 k
    k=$(tiles_of "$n")
    if ((k == 1)); then echo "$cache/pack_n${n}.data"; else echo "$cache/pack_n${n}_tiles$k.data"; fi
}
tile_args() {  # the options that make (or load) the state of size N
    local n=$1 k
    k=$(tiles_of "$n")
    echo "--state $(state_of "$n")"
    ((k == 1)) || echo "--tiles $k --tile-state $cache/state_n$((n / k))_seed1.txt"
}

# ---------------------------------------------------------------------------- settle (cached)
for n in $sizes; do
    state=$(state_of "$n")
    data=$(data_of "$n")
    if [[ -s $state && -s $data && ! $data -ot $state ]]; then
        echo "  N=$n: cached ($state)"
        continue
    fi
    t0=$(date +%s)
    # shellcheck disable=SC2046  # tile_args is a list of words without spaces
    "$bench" "$n" 1 --settle-only $(tile_args "$n") --export-lammps "$data.tmp" | sed 's/^/  /'
    mv "$data.tmp" "$data"
    echo "  N=$n: state made in $(($(date +%s) - t0)) s, load $(cut -d' ' -f1-3 /proc/loadavg)"
done

# ---------------------------------------------------------------------------- timed runs
export OMP_NUM_THREADS=1
meta=("session=$session" "machine=$machine" "cpu=$cpu" "talus_version=$talus_version"
    "compiler=$compiler" "flags=$flags" "lammps_version=$lammps_version" "build=$build")
for rep in $(seq 1 "$repeats"); do
    for n in $sizes; do
        steps=$(steps_of "$n")
        tiles=$(tiles_of "$n")
        for code in $codes; do
            has=0
            python3 "$report" has "$csv" "$session" "$code" "$n" "$rep" || has=$?
            if ((has == 0)); then
                echo "  rep $rep  N=$n  $code: in the CSV already"
                continue
            fi
            ((has == 3)) || exit 1
            load=$(cut -d' ' -f1 /proc/loadavg)
            log="$logs/${code}_n${n}_rep${rep}.log"
            case $code in
            talus)
                # shellcheck disable=SC2046
                "$bench" "$n" "$steps" sorted $(tile_args "$n") --warmup "$warmup" --no-profile \
                    >"$log" 2>&1 || { cat "$log" >&2; exit 1; }
                ;;
            lammps1)
                lmp -in scripts/bench/lammps/in.dense_pack -var data "$(data_of "$n")" \
                    -var steps "$steps" -var warmup "$warmup" -log "$log" -screen none
                ;;
            lammps2)
                "${mpirun_cmd[@]}" lmp -in scripts/bench/lammps/in.dense_pack \
                    -var data "$(data_of "$n")" -var steps "$steps" -var warmup "$warmup" \
                    -log "$log" -screen none
                ;;
            esac
            line=$(python3 "$report" row "$csv" "$code" "$log" "$n" "${meta[@]}" "rep=$rep" \
                "load1=$load" "load1_end=$(cut -d' ' -f1 /proc/loadavg)" "tiles=$tiles" \
                "date_utc=$(date -u +%Y-%m-%dT%H:%M:%SZ)")
            echo "  rep $rep  N=$n  $code: $line"
        done
    done
done

echo
python3 "$report" table "$csv" --session "$session" ${plot:+-o "$plot"}
echo
echo "load at the end: $(cut -d' ' -f1-3 /proc/loadavg); $(($(date +%s) - t_start)) s;" \
    "rows in $csv (session $session)"
