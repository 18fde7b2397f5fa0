# SPDX-License-Identifier: MIT
#
# Sourced by the benchmark scripts (run from the repository's top): one LAMMPS run of the dense
# pack (scripts/bench/lammps/in.dense_pack, gran/hooke/history) on RANKS MPI ranks, printing its
# ns per particle-step.
#
#   lammps_dense_pack_ns DATA N STEPS WARMUP RANKS
lammps_dense_pack_ns() {
    local data=$1 n=$2 steps=$3 warmup=$4 ranks=$5 log
    log=$(mktemp)
    local args=(-in scripts/bench/lammps/in.dense_pack -var data "$data" -var steps "$steps"
                -var warmup "$warmup" -log "$log" -screen none)
    if [[ $ranks == 1 ]]; then
        OMP_NUM_THREADS=1 lmp "${args[@]}"
    else
        local root_flag=()
        [[ $(id -u) == 0 ]] && root_flag=(--allow-run-as-root)
        OMP_NUM_THREADS=1 mpirun "${root_flag[@]}" -n "$ranks" --bind-to none lmp "${args[@]}"
    fi
    python3 scripts/bench/dense_pack_report.py lammps-log "$log" "$n" |
        grep -o "ns_per_particle_step=[^ ]*" | cut -d= -f2
    rm -f "$log"
}

# The peak resident memory [bytes per disk] of one LAMMPS run on one rank, over that of LAMMPS
# with no input (lmp -h): lammps_dense_pack_bytes DATA N STEPS WARMUP
lammps_dense_pack_bytes() {
    local data=$1 n=$2 steps=$3 warmup=$4 log empty full
    log=$(mktemp)
    empty=$( { /usr/bin/time -f "%M" lmp -h >/dev/null; } 2>&1 | tail -1)
    full=$( { OMP_NUM_THREADS=1 /usr/bin/time -f "%M" lmp -in scripts/bench/lammps/in.dense_pack \
              -var data "$data" -var steps "$steps" -var warmup "$warmup" -log "$log" \
              -screen none >/dev/null; } 2>&1 | tail -1)
    rm -f "$log"
    python3 -c "print(round(1024 * ($full - $empty) / $n, 1))"
}
