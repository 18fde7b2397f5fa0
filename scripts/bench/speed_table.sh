#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# The current speed table of docs/benchmarks.md: the dense pack (10 000 and 50 000 disks, the
# settled states of scripts/bench/dense_pack.sh) run interleaved in one session by
#   Talus    1 thread (energy off, guard on), energy on, energy on with 8 groups in vertical
#            bands (contacts cross group borders only at the bands' edges) and round-robin
#            (nearly every contact crosses one), guard off (every feature off), 2 threads
#   LAMMPS   1 and 2 MPI ranks (gran/hooke/history, scripts/bench/lammps/in.dense_pack)
#   a plain  1 and 2 threads, when TALUS_BENCH_KERNEL names a plain-array DEM kernel's source
#   kernel   (same scene and physics; compiled here with g++ -O3 -fopenmp)
# with OpenMP's default wait policy (what a user gets; OMP_WAIT_POLICY=passive puts the second
# thread to sleep between the step's parallel regions: no gain at 10k), and prints the minimum of
# each over the repeats (ns per particle-step) with the ratios the
# page quotes, and the memory per disk: the peak resident memory of Talus's 1-thread run over
# the peak before its model was made, and of a LAMMPS run over LAMMPS with no input (first
# repeat only; memory does not depend on the machine's load). Speed varies by tens of percent between sessions on a shared machine: compare
# within one run of this script, never across runs.
#
#   scripts/bench/dense_pack.sh                      # once: builds and caches the states
#   TALUS_BENCH_REPEATS=3 scripts/bench/speed_table.sh
#
# With TALUS_BENCH_BASELINE naming the build tree of another commit (its talus_bench_dense_pack
# and plugins), that build runs beside, 1 thread with energy off and on: before/after in one run.
#
# Settings (environment): TALUS_BENCH_BUILD (build-bench), TALUS_BENCH_REPEATS (3),
# TALUS_BENCH_WARMUP (300), TALUS_BENCH_SIZES ("10000 50000"), TALUS_BENCH_STEPS (timed steps
# per size, "10000:2000 50000:600"), TALUS_BENCH_KERNEL (a .cpp), TALUS_BENCH_RAW (the raw lines,
# default $build/bench-cache/speed-<session>.txt). A smoke run of the script itself:
#   TALUS_BENCH_BUILD=build TALUS_BENCH_REPEATS=1 TALUS_BENCH_SIZES=10000 \
#   TALUS_BENCH_STEPS=10000:20 TALUS_BENCH_WARMUP=10 scripts/bench/speed_table.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/bench/lammps_dense_pack.sh
build=${TALUS_BENCH_BUILD:-build-bench}
repeats=${TALUS_BENCH_REPEATS:-3}
warmup=${TALUS_BENCH_WARMUP:-300}
sizes=${TALUS_BENCH_SIZES:-"10000 50000"}
bench=$build/tests/bench/talus_bench_dense_pack
cache=$build/bench-cache
[[ -x $bench ]] || { echo "no $bench: run scripts/bench/dense_pack.sh first" >&2; exit 1; }
export TALUS_PLUGIN_PATH=$build/plugins
session=$(date -u +%Y%m%dT%H%M%SZ)
raw=${TALUS_BENCH_RAW:-$cache/speed-$session.txt}
kernel=""
if [[ -n ${TALUS_BENCH_KERNEL:-} ]]; then
    kernel=$cache/plain_kernel
    g++ -O3 -fopenmp -o "$kernel" "$TALUS_BENCH_KERNEL"
fi
steps_for=${TALUS_BENCH_STEPS:-"10000:2000 50000:600"}
steps_of() {
    local pair
    for pair in $steps_for; do [[ ${pair%%:*} == "$1" ]] && { echo "${pair#*:}"; return; }; done
    echo 1000
}
note() { echo "$*" | tee -a "$raw"; }
# One timed run of a build's dense-pack benchmark: talus_ns BUILD_DIR THREADS [options...];
# prints "NS BYTES" (ns per particle-step, memory per disk; a build without the latter: "NS ")
talus_ns() {
    local dir=$1 th=$2
    shift 2
    TALUS_PLUGIN_PATH=$dir/plugins TALUS_THREADS=$th OMP_NUM_THREADS=$th \
        "$dir/tests/bench/talus_bench_dense_pack" "$n" "$steps" sorted --state "$state" \
        --warmup "$warmup" --no-profile "$@" 2>&1 | grep "^RESULT" |
        python3 -c 'import re, sys; m = dict(re.findall(r"(\w+)=(\S+)", sys.stdin.read()));
print(m.get("ns_per_particle_step", ""), m.get("bytes_per_disk", ""))'
}

echo "speed table, session $session; cpu: $(lscpu | sed -n 's/^Model name: *//p' | head -1)," \
     "$(nproc) cpus; talus $(git describe --always --dirty 2>/dev/null)" | tee "$raw"
for rep in $(seq 1 "$repeats"); do
    for n in $sizes; do
        steps=$(steps_of "$n")
        state=$cache/state_n${n}_seed1.txt
        [[ -f $state ]] || { echo "no settled state for $n (dense_pack.sh)" >&2; exit 1; }
        for variant in "1 off" "1 on" "1 bands" "1 groups" "1 guardoff" "2 off"; do
            read -r th what <<<"$variant"
            extra=()
            case $what in
                on) extra=(--energy on) ;;
                bands) extra=(--energy on --groups 8 --group-layout bands) ;;
                groups) extra=(--energy on --groups 8 --group-layout robin) ;;
                guardoff) extra=(--guard off) ;;
            esac
            r=$(talus_ns "$build" "$th" "${extra[@]}")
            note "rep=$rep n=$n code=talus threads=$th variant=$what ns=${r% *}" \
                 "$( [[ $rep == 1 && $variant == "1 off" ]] && echo "bytes=${r#* }")"
        done
        if [[ -n ${TALUS_BENCH_BASELINE:-} ]]; then
            for what in off on; do
                r=$(talus_ns "$TALUS_BENCH_BASELINE" 1 --energy "$what")
                note "rep=$rep n=$n code=baseline threads=1 variant=$what ns=${r% *}"
            done
        fi
        for np in 1 2; do
            r=$(lammps_dense_pack_ns "$cache/pack_n${n}.data" "$n" "$steps" "$warmup" "$np")
            note "rep=$rep n=$n code=lammps threads=$np variant=off ns=$r"
        done
        if [[ $rep == 1 ]]; then
            r=$(lammps_dense_pack_bytes "$cache/pack_n${n}.data" "$n" "$steps" "$warmup")
            note "rep=$rep n=$n code=lammps threads=1 variant=memory bytes=$r"
        fi
        if [[ -n $kernel ]]; then
            for th in 1 2; do
                r=$(OMP_NUM_THREADS=$th "$kernel" "$state" "$steps" "$warmup" |
                    sed -n 's/.*ns_per_particle_step \([0-9.]*\).*/\1/p')
                note "rep=$rep n=$n code=kernel threads=$th variant=off ns=$r"
            done
        fi
    done
done
python3 - "$raw" <<'EOF'
import re, sys
best, memory = {}, {}
for line in open(sys.argv[1]):
    m = dict(re.findall(r"(\w+)=(\S+)", line))
    if "bytes" in m and m["bytes"]:
        memory[(int(m["n"]), m["code"])] = float(m["bytes"])
    if "ns" not in m or not m["ns"]:
        continue
    key = (int(m["n"]), m["code"], int(m["threads"]), m["variant"])
    best[key] = min(best.get(key, float("inf")), float(m["ns"]))
print("\nminimum ns per particle-step (ratios within this session)\n")
print("| | " + " | ".join(f"{n // 1000}k" for n in sorted({k[0] for k in best})) + " |")
print("|---|" + "---|" * len({k[0] for k in best}))
rows = [("Talus, 1 thread", ("talus", 1, "off")), ("Talus, energy on", ("talus", 1, "on")),
        ("Talus, energy on, 8 groups in bands", ("talus", 1, "bands")),
        ("Talus, energy on, 8 groups round-robin", ("talus", 1, "groups")),
        ("Talus, guard off", ("talus", 1, "guardoff")), ("Talus, 2 threads", ("talus", 2, "off")),
        ("baseline build, 1 thread", ("baseline", 1, "off")),
        ("baseline build, energy on", ("baseline", 1, "on")),
        ("LAMMPS, 1 rank", ("lammps", 1, "off")), ("LAMMPS, 2 ranks", ("lammps", 2, "off")),
        ("plain kernel, 1 thread", ("kernel", 1, "off")),
        ("plain kernel, 2 threads", ("kernel", 2, "off"))]
sizes = sorted({k[0] for k in best} | {k[0] for k in memory})
for label, (code, th, var) in rows:
    if not any((n, code, th, var) in best for n in sizes):
        continue
    print(f"| {label} | " + " | ".join(f"{best.get((n, code, th, var), float('nan')):.1f}"
                                       for n in sizes) + " |")
for label, code in [("memory per disk, Talus [bytes]", "talus"),
                    ("memory per disk, LAMMPS [bytes]", "lammps")]:
    if any((n, code) in memory for n in sizes):
        print(f"| {label} | " + " | ".join(f"{memory.get((n, code), float('nan')):.0f}"
                                           for n in sizes) + " |")
print()
for n in sizes:
    g = lambda c, t, v: best.get((n, c, t, v), float("nan"))
    t1 = g("talus", 1, "off")
    print(f"{n}: Talus/LAMMPS {t1 / g('lammps', 1, 'off'):.2f}; energy on +{100 * (g('talus', 1, 'on') / t1 - 1):.0f}%; "
          f"8 groups in bands +{100 * (g('talus', 1, 'bands') / t1 - 1):.0f}% "
          f"(+{100 * (g('talus', 1, 'bands') / g('talus', 1, 'on') - 1):.0f}% over energy on), "
          f"round-robin +{100 * (g('talus', 1, 'groups') / t1 - 1):.0f}%; "
          f"every feature off {g('talus', 1, 'guardoff') / g('kernel', 1, 'off'):.2f}x the kernel; guard on "
          f"+{100 * (t1 / g('talus', 1, 'guardoff') - 1):.0f}%; 2 threads {t1 / g('talus', 2, 'off'):.2f}x "
          f"(LAMMPS {g('lammps', 1, 'off') / g('lammps', 2, 'off'):.2f}x, "
          f"kernel {g('kernel', 1, 'off') / g('kernel', 2, 'off'):.2f}x)")
    # Amdahl's law from the two-thread speed-up S2: the serial share s = 2/S2 - 1, and on
    # P cores 1/(s + (1-s)/P) (an upper bound: it leaves out the memory bandwidth shared by
    # more cores).
    s2 = t1 / g("talus", 2, "off")
    serial = min(max(2 / s2 - 1, 0.0), 1.0) if s2 == s2 else float("nan")
    print(f"{n}: serial share {100 * serial:.0f}%: expected at most "
          + ", ".join(f"{1 / (serial + (1 - serial) / p):.1f}x on {p} cores" for p in (8, 16)))
    if (n, "baseline", 1, "off") in best:
        print(f"{n}: Talus/baseline {t1 / g('baseline', 1, 'off'):.2f} (energy on "
              f"{g('talus', 1, 'on') / g('baseline', 1, 'on'):.2f})")
EOF
echo "raw runs: $raw"
