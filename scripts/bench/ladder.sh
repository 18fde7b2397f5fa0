#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# The force loop's ladder (docs/results/force-loop-ladder.md): the dense pack's step from a loop
# as plain as a textbook kernel over the engine's own data up to the whole engine, one rung at a
# time (tests/bench/ladder.cpp names the rungs), measured three ways:
#   ns        ns per particle-step, minimum over the repeats; every rung, LAMMPS (1 rank) and the
#             reference kernel (TALUS_BENCH_KERNEL) interleaved in each repeat
#   Ir/pair   instructions per pair and step of the timed steps alone (callgrind: the bench
#             switches instrumentation on for them), over every candidate pair
#   B/disk    bytes per disk and step moved into the first-level data cache (D1 misses x 64)
#             and into the core's 2 MiB second level (callgrind's cache simulation, its last
#             level set to this machine's L2: --LL=2097152,16,64)
# Instructions and bytes are deterministic (a loaded machine changes only the ns column).
#
#   scripts/bench/dense_pack.sh            # once: builds and caches the settled states
#   TALUS_BENCH_BUILD=build TALUS_BENCH_KERNEL=<kernel.cpp> scripts/bench/ladder.sh
#
# Settings (environment): TALUS_BENCH_BUILD (build-bench), TALUS_LADDER_SIZES ("10000 50000"),
# TALUS_LADDER_REPEATS (3), TALUS_LADDER_WARMUP (300), TALUS_LADDER_RUNGS (all of the bench's),
# TALUS_LADDER_CALLGRIND (1; 0 skips it), TALUS_LADDER_CG_STEPS ("10000:100 50000:40"),
# TALUS_BENCH_KERNEL (a plain-array kernel's .cpp), TALUS_LADDER_LAMMPS (1 when lmp is there),
# TALUS_LADDER_RAW (the raw lines; default $build/bench-cache/ladder-<session>.txt).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/bench/lammps_dense_pack.sh
build=${TALUS_BENCH_BUILD:-build-bench}
sizes=${TALUS_LADDER_SIZES:-"10000 50000"}
repeats=${TALUS_LADDER_REPEATS:-3}
warmup=${TALUS_LADDER_WARMUP:-300}
rungs=${TALUS_LADDER_RUNGS:-"plain law pair narrow dispatch finish engine guard autostep energy bands robin threads2"}
callgrind=${TALUS_LADDER_CALLGRIND:-1}
cg_steps=${TALUS_LADDER_CG_STEPS:-"10000:100 50000:40"}
lammps=${TALUS_LADDER_LAMMPS:-$(command -v lmp >/dev/null && echo 1 || echo 0)}
bench=$build/tests/bench/talus_bench_ladder
cache=$build/bench-cache
[[ -x $bench ]] || { echo "no $bench (cmake --build $build --target talus_bench_ladder)" >&2; exit 1; }
export TALUS_PLUGIN_PATH=$build/plugins
session=$(date -u +%Y%m%dT%H%M%SZ)
raw=${TALUS_LADDER_RAW:-$cache/ladder-$session.txt}
kernel=""
if [[ -n ${TALUS_BENCH_KERNEL:-} ]]; then
    kernel=$cache/plain_kernel
    g++ -O3 -fopenmp -g -o "$kernel" "$TALUS_BENCH_KERNEL"
fi
steps_of() { [[ $1 == 50000 ]] && echo 600 || echo 2000; }
cg_steps_of() {
    local pair
    for pair in $cg_steps; do [[ ${pair%%:*} == "$1" ]] && { echo "${pair#*:}"; return; }; done
    echo 50
}
note() { echo "$*" | tee -a "$raw"; }
threads_of() { [[ $1 == threads2 ]] && echo 2 || echo 1; }

echo "ladder, session $session; cpu: $(lscpu | sed -n 's/^Model name: *//p' | head -1)," \
     "$(nproc) cpus; load $(cut -d' ' -f1-3 /proc/loadavg); talus $(git describe --always --dirty)" |
    tee "$raw"
for n in $sizes; do
    [[ -f $cache/state_n${n}_seed1.txt ]] || { echo "no settled state for $n (dense_pack.sh)" >&2; exit 1; }
done

# ---------------------------------------------------------------- wall time, interleaved
for rep in $(seq 1 "$repeats"); do
    for n in $sizes; do
        steps=$(steps_of "$n")
        state=$cache/state_n${n}_seed1.txt
        for rung in $rungs; do
            th=$(threads_of "$rung")
            r=$(OMP_NUM_THREADS=$th "$bench" "$n" "$steps" --state "$state" --warmup "$warmup" \
                --rung "$rung" | grep -o "ns_per_particle_step=[^ ]*" | cut -d= -f2)
            note "rep=$rep n=$n rung=$rung ns=$r"
        done
        if [[ -n $kernel ]]; then
            r=$(OMP_NUM_THREADS=1 "$kernel" "$state" "$steps" "$warmup" |
                sed -n 's/.*ns_per_particle_step \([0-9.]*\).*/\1/p')
            note "rep=$rep n=$n rung=kernel ns=$r"
        fi
        if [[ $lammps == 1 ]]; then
            r=$(lammps_dense_pack_ns "$cache/pack_n${n}.data" "$n" "$steps" "$warmup" 1)
            note "rep=$rep n=$n rung=lammps ns=$r"
        fi
    done
done

# ---------------------------------------------------------------- instructions and bytes
# callgrind's totals of one run: Ir, D1 misses (read + write), LL misses
cg_totals() {
    python3 - "$1" <<'EOF'
import sys
events, totals = None, None
for line in open(sys.argv[1]):
    if line.startswith("events:"):
        events = line.split()[1:]
    elif line.startswith("totals:") or line.startswith("summary:"):
        totals = [int(x) for x in line.split()[1:]]
e = dict(zip(events, totals + [0] * (len(events) - len(totals))))
print(e.get("Ir", 0), e.get("D1mr", 0) + e.get("D1mw", 0), e.get("DLmr", 0) + e.get("DLmw", 0))
EOF
}
cg=(valgrind --tool=callgrind --cache-sim=yes --D1=49152,12,64 --LL=2097152,16,64)
if [[ $callgrind == 1 ]]; then
    tmp=$(mktemp -d)
    for n in $sizes; do
        steps=$(cg_steps_of "$n")
        state=$cache/state_n${n}_seed1.txt
        for rung in $rungs; do
            th=$(threads_of "$rung")
            out=$(OMP_NUM_THREADS=$th "${cg[@]}" --instr-atstart=no \
                  --callgrind-out-file="$tmp/cg" "$bench" "$n" "$steps" --state "$state" \
                  --warmup "$warmup" --rung "$rung" 2>/dev/null | grep RESULT)
            pairs=$(grep -o "pairs=[0-9]*" <<<"$out" | cut -d= -f2)
            read -r ir d1 ll < <(cg_totals "$tmp/cg")
            note "n=$n rung=$rung cg_steps=$steps pairs=$pairs ir=$ir d1=$d1 ll=$ll"
            rm -f "$tmp"/cg*
        done
        if [[ -n $kernel ]]; then
            # The kernel counts its whole run: the difference of two run lengths is the steps'.
            for s in "$steps" $((2 * steps)); do
                OMP_NUM_THREADS=1 "${cg[@]}" --callgrind-out-file="$tmp/cg$s" "$kernel" \
                    "$state" "$s" 0 >"$tmp/out$s" 2>/dev/null
            done
            read -r ir1 d11 ll1 < <(cg_totals "$tmp/cg$steps")
            read -r ir2 d12 ll2 < <(cg_totals "$tmp/cg$((2 * steps))")
            ppp=$(sed -n 's/.*pairs\/particle \([0-9.]*\).*/\1/p' "$tmp/out$steps")
            pairs=$(python3 -c "print(round($ppp * $n))")
            note "n=$n rung=kernel cg_steps=$steps pairs=$pairs ir=$((ir2 - ir1))" \
                 "d1=$((d12 - d11)) ll=$((ll2 - ll1))"
            rm -f "$tmp"/*
        fi
    done
    rmdir "$tmp"
fi

# ---------------------------------------------------------------- the table
python3 - "$raw" "$rungs" <<'EOF'
import re, sys
raw, rungs = sys.argv[1], sys.argv[2].split()
ns, cg = {}, {}
for line in open(raw):
    m = dict(re.findall(r"(\w+)=(\S+)", line))
    if "rung" not in m:
        continue
    key = (int(m["n"]), m["rung"])
    if "ns" in m and m["ns"]:
        ns[key] = min(ns.get(key, float("inf")), float(m["ns"]))
    if "ir" in m:
        cg[key] = m
sizes = sorted({k[0] for k in list(ns) + list(cg)})
cols = []
for n in sizes:
    k = f"{n // 1000}k"
    cols += [f"ns {k}", f"Ir/pair {k}", f"D1 B/disk {k}", f"L2 B/disk {k}"]
print("\n| rung | " + " | ".join(cols) + " |")
print("|---|" + "---|" * len(cols))
for rung in rungs + ["kernel", "lammps"]:
    row = []
    for n in sizes:
        t = ns.get((n, rung))
        row.append(f"{t:.1f}" if t else "")
        c = cg.get((n, rung))
        if c:
            steps, pairs = int(c["cg_steps"]), int(c["pairs"])
            row += [f"{int(c['ir']) / (steps * pairs):.0f}",
                    f"{64 * int(c['d1']) / (steps * n):.0f}",
                    f"{64 * int(c['ll']) / (steps * n):.0f}"]
        else:
            row += ["", "", ""]
    if any(row):
        print(f"| {rung} | " + " | ".join(row) + " |")
EOF
echo "raw runs: $raw"
