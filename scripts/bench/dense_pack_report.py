#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Helper of scripts/bench/dense_pack.sh (docs/benchmarks.md).

  dense_pack_report.py lammps-log LOG N        one RESULT line from a LAMMPS log
  dense_pack_report.py report RAW CSV KEY=VAL.. append the session's runs to CSV, print tables

A RESULT line is "RESULT key=value key=value ..." (talus_bench_dense_pack prints them; this
script makes the same for LAMMPS). Values hold no spaces.
"""
import csv
import os
import re
import sys

# Column order of the results CSV (one row per timed run).
COLUMNS = [
    "session", "date_utc", "machine", "cpu", "compiler", "flags", "code", "code_version",
    "mode", "n", "steps", "warmup", "rep", "load1", "wall_s", "cpu_s", "ns_per_particle_step",
    "contacts_per_particle", "ball_contacts_per_particle", "wall_contacts",
    "pairs_per_particle", "t_timestep", "t_motion", "t_detection", "t_force", "t_bookkeeping",
    "t_pair", "t_neigh", "t_comm", "t_output", "t_modify", "t_other", "neigh_builds",
    "proxy_moves", "pairs_created", "contacts_created", "ke_start", "ke_end", "guard",
]

TALUS_PHASES = [("t_timestep", "timestep"), ("t_motion", "law of motion"),
                ("t_detection", "contact detection"), ("t_force", "force-displacement"),
                ("t_bookkeeping", "bookkeeping")]
LAMMPS_PHASES = [("t_pair", "Pair"), ("t_neigh", "Neigh"), ("t_comm", "Comm"),
                 ("t_output", "Output"), ("t_modify", "Modify"), ("t_other", "Other")]


def parse_lammps(path, n):
    """The timed run is the last `run` in the log (any rank count: `mpirun -n 2 lmp` too): its
    loop time, section table, thermo line, neighbour count and the warm-up run's length.
    Shared with scaling_plot.py."""
    text = open(path).read()
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) "
                       r"atoms\s+([0-9.]+)% CPU use", text)
    if not loops:
        sys.exit(f"no 'Loop time' in {path} (did LAMMPS fail? see the log)")
    wall, procs, steps, atoms, cpu_pct = loops[-1]
    wall, steps, atoms = float(wall), int(steps), int(atoms)
    if atoms != n:
        sys.exit(f"{path}: {atoms} atoms at the end, expected {n} (particles lost?)")
    head, last = text[:text.rfind("Loop time of")], text[text.rfind("Loop time of"):]
    # "% CPU use" is the CPU time of the ranks over their wall time, averaged over the ranks.
    r = {"code": "lammps", "n": n, "steps": steps, "ranks": procs, "wall_s": f"{wall:.6f}",
         "cpu_s": f"{wall * float(cpu_pct) / 100 * int(procs):.6f}",
         "cpu_use": f"{float(cpu_pct) / 100:.3f}",
         "ns_per_particle_step": f"{1e9 * wall / (steps * n):.4f}"}
    for key, name in LAMMPS_PHASES:
        m = re.search(rf"^{name}\s*\|\s*([0-9.eE+-]+)\s*\|\s*([0-9.eE+-]+)", last, re.M)
        if m:
            r[key] = f"{float(m.group(2)):.6f}"
        elif name == "Other":  # the Other row has only the average column
            m = re.search(r"^Other\s*\|\s*\|\s*([0-9.eE+-]+)", last, re.M)
            if m:
                r[key] = f"{float(m.group(1)):.6f}"
    # Thermo: "step atoms ke c_zsum v_cpp", the last line before the last Loop time.
    rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+([0-9.eE+-]+)\s+([0-9.eE+-]+)\s+([0-9.eE+-]+)\s*$",
                      head, re.M)
    if rows:
        r["ball_contacts_per_particle"] = f"{float(rows[-1][4]):.5f}"
        r["contacts_per_particle"] = r["ball_contacts_per_particle"]  # walls not counted
    m = re.search(r"Total # of neighbors = (\d+)", last)
    if m:
        r["pairs_per_particle"] = f"{int(m.group(1)) / n:.5f}"
    m = re.search(r"Neighbor list builds = (\d+)", last)
    if m:
        r["neigh_builds"] = m.group(1)
    m = re.search(r"^run\s+(\d+)\s*$", head, re.M)  # the first run is the warm-up
    if m:
        r["warmup"] = m.group(1)
    return r


def read_raw(path):
    runs = []
    for line in open(path):
        if line.startswith("RESULT "):
            runs.append(dict(kv.split("=", 1) for kv in line.split()[1:]))
    return runs


def fmt(x, digits=1):
    return f"{x:.{digits}f}"


def report(raw, csv_path, meta):
    runs = read_raw(raw)
    if not runs:
        sys.exit(f"no runs in {raw}")
    # Older files may have fewer columns: rewrite them under the current header first, so that
    # every row of a file matches its header.
    if os.path.exists(csv_path):
        with open(csv_path, newline="") as f:
            old = list(csv.DictReader(f))
            f.seek(0)
            header = next(csv.reader(f), [])
        if header != COLUMNS:
            with open(csv_path, "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
                w.writeheader()
                w.writerows(old)
    new = not os.path.exists(csv_path)
    with open(csv_path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        if new:
            w.writeheader()
        for r in runs:
            row = dict(meta)
            row.update(r)
            if r["code"] == "lammps":
                row["code_version"] = meta.get("lammps_version", "")
                row["compiler"] = meta.get("lammps_compiler", "")
                row["flags"] = "Debian package"
                row["mode"] = "sorted"
            else:
                row["code_version"] = meta.get("talus_version", "")
            w.writerow(row)

    # Group: (n, code, mode) -> runs; report the minimum and the spread.
    groups = {}
    for r in runs:
        groups.setdefault((int(r["n"]), r["code"], r.get("mode", "sorted")), []).append(r)
    label = {("talus", "sorted"): "Talus (sort every 1000 steps)",
             ("talus", "unsorted"): "Talus (no sort, random memory order)",
             ("lammps", "sorted"): "LAMMPS gran/hooke/history"}
    print(f"\nSession {meta.get('session')} on {meta.get('cpu')} ({meta.get('machine')}); "
          f"Talus {meta.get('compiler')} {meta.get('flags')}; LAMMPS {meta.get('lammps_version')}")
    print("\n| N | code | ns/particle-step (min) | spread | CPU use | ball-ball contacts/particle "
          "| pairs/particle | steps | wall time (min) | runs |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    best = {}
    for key in sorted(groups, key=lambda k: (k[0], k[1] != "talus", k[2])):
        rs = groups[key]
        ns = [float(r["ns_per_particle_step"]) for r in rs]
        b = rs[ns.index(min(ns))]
        best[key] = b
        spread = 100.0 * (max(ns) - min(ns)) / min(ns)
        cpu_use = 100.0 * float(b.get("cpu_s", 0)) / float(b["wall_s"])
        print(f"| {key[0]} | {label.get(key[1:], key[1] + ' ' + key[2])} | {fmt(min(ns))} | "
              f"{fmt(spread, 0)}% | {fmt(cpu_use, 0)}% | "
              f"{float(b.get('ball_contacts_per_particle', 'nan')):.3f} | "
              f"{float(b.get('pairs_per_particle', 'nan')):.3f} | {b['steps']} | "
              f"{float(b['wall_s']):.2f} s | {len(rs)} |")
    print("\nPer-phase time of the fastest run, ns per particle-step (share of the total):\n")
    for key, b in sorted(best.items(), key=lambda kv: (kv[0][0], kv[0][1] != "talus", kv[0][2])):
        n, steps = int(b["n"]), int(b["steps"])
        phases = TALUS_PHASES if key[1] == "talus" else LAMMPS_PHASES
        vals = [(name, float(b[k])) for k, name in phases if b.get(k, "") != ""]
        total = sum(v for _, v in vals) or 1.0
        parts = ", ".join(f"{name} {1e9 * v / (steps * n):.1f} ({100 * v / total:.0f}%)"
                          for name, v in vals)
        print(f"- N = {n}, {label.get(key[1:], key[1])}: {parts}")


def main():
    if len(sys.argv) >= 4 and sys.argv[1] == "lammps-log":
        r = parse_lammps(sys.argv[2], int(sys.argv[3]))
        print("RESULT " + " ".join(f"{k}={v}" for k, v in r.items()))
    elif len(sys.argv) >= 4 and sys.argv[1] == "report":
        meta = dict(a.split("=", 1) for a in sys.argv[4:])
        report(sys.argv[2], sys.argv[3], meta)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
