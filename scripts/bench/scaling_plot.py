#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Helper of scripts/bench/scaling.sh (docs/results/benchmarks-history.md, "Scaling, 1k to 1M disks").

  scaling_plot.py row CSV CODE LOG N KEY=VAL..   read one timed run's log (Talus RESULT line or
                                                 LAMMPS log), append a row to CSV, print a summary
  scaling_plot.py has CSV SESSION CODE N REP     exit 0 if that run is in CSV already, 3 if not
  scaling_plot.py table CSV [--session S] [-o PNG]
                                                 markdown table (minimum over the repeats) of a
                                                 session (default: the last one) and the plot:
                                                 ns per particle-step against N, log x

CODE is talus (talus_bench_dense_pack, 1 thread), lammps1 (1 MPI rank) or lammps2 (2 ranks).
"""
import argparse
import csv
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dense_pack_report import parse_lammps  # noqa: E402  (the one LAMMPS log reader)

COLUMNS = [
    "session", "date_utc", "machine", "cpu", "code", "code_version", "compiler", "flags", "build",
    "ranks", "n", "tiles", "steps", "warmup", "rep", "load1", "load1_end", "wall_s", "cpu_s",
    "cpu_use", "ns_per_particle_step", "contacts_per_particle", "ball_contacts_per_particle",
    "pairs_per_particle", "neigh_builds", "ke_start", "ke_end",
]
CODES = ["talus", "lammps1", "lammps2"]
LABEL = {"talus": "Talus, 1 thread", "lammps1": "LAMMPS, 1 rank", "lammps2": "LAMMPS, 2 ranks"}


def parse_talus(path, n):
    text = open(path).read()
    lines = [ln for ln in text.splitlines() if ln.startswith("RESULT ")]
    if not lines:
        sys.exit(f"no RESULT line in {path}:\n{text}")
    r = dict(kv.split("=", 1) for kv in lines[-1].split()[1:])
    if int(r["n"]) != n:
        sys.exit(f"{path}: n={r['n']}, expected {n}")
    r["ranks"] = "1"
    r["cpu_use"] = f"{float(r['cpu_s']) / float(r['wall_s']):.3f}"
    return r


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def cmd_row(a):
    meta = dict(kv.split("=", 1) for kv in a.meta)
    r = parse_talus(a.log, a.n) if a.code == "talus" else parse_lammps(a.log, a.n)
    row = dict(meta)
    row.update(r)
    row["code"] = a.code
    row["code_version"] = meta["talus_version"] if a.code == "talus" else meta["lammps_version"]
    if a.code != "talus":
        row["compiler"], row["flags"], row["build"] = "Debian package", "", ""
    new = not os.path.exists(a.csv)
    with open(a.csv, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        if new:
            w.writeheader()
        w.writerow(row)
    print(f"{float(r['ns_per_particle_step']):.1f} ns/particle-step, {r['steps']} steps, "
          f"{float(r['wall_s']):.1f} s, CPU use {float(r['cpu_use']):.2f}, load {meta['load1']}")


def cmd_has(a):
    for r in read_csv(a.csv):
        if (r["session"], r["code"], r["n"], r["rep"]) == (a.session, a.code, str(a.n),
                                                            str(a.rep)):
            sys.exit(0)
    sys.exit(3)


def cmd_table(a):
    if a.output:
        # Debian's matplotlib when the python3 on PATH has none: re-runs this script once with
        # /usr/bin/python3, so it must come before anything is printed.
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
        from plot_history import ensure_matplotlib
        ensure_matplotlib(__file__)
    rows = read_csv(a.csv)
    if not rows:
        sys.exit(f"no rows in {a.csv}")
    session = a.session or rows[-1]["session"]
    rows = [r for r in rows if r["session"] == session]
    if not rows:
        sys.exit(f"no rows of session {session} in {a.csv}")
    best = {}  # (code, n) -> fastest run
    runs = {}
    for r in rows:
        key = (r["code"], int(r["n"]))
        runs.setdefault(key, []).append(float(r["ns_per_particle_step"]))
        if key not in best or float(r["ns_per_particle_step"]) < float(
                best[key]["ns_per_particle_step"]):
            best[key] = r
    sizes = sorted({n for _, n in best})
    codes = [c for c in CODES if any((c, n) in best for n in sizes)]
    loads = [float(r["load1"]) for r in rows] + [float(r["load1_end"]) for r in rows]
    talus = next((r for r in rows if r["code"] == "talus"), None)
    lammps = next((r for r in rows if r["code"] != "talus"), None)
    print(f"Session {session}, {rows[0]['cpu']} ({rows[0]['machine']}), "
          f"{min(r['date_utc'] for r in rows)} to {max(r['date_utc'] for r in rows)}; "
          f"1-minute load {min(loads):.2f}-{max(loads):.2f}")
    if talus:
        print(f"Talus {talus['code_version']}, {talus['compiler']}, {talus['flags']}")
    if lammps:
        print(f"LAMMPS {lammps['code_version']} (Debian package)")
    print("ns per particle-step, minimum over the repeats (runs); CPU use of that run")

    def cell(c, n, what="ns"):
        r = best.get((c, n))
        if r is None:
            return "-"
        if what == "ns":
            return f"{float(r['ns_per_particle_step']):.1f}"
        return f"{float(r['cpu_use']):.2f}"

    def ratio(c1, c2, n):
        if (c1, n) in best and (c2, n) in best:
            x = float(best[(c1, n)]["ns_per_particle_step"])
            return f"{x / float(best[(c2, n)]['ns_per_particle_step']):.2f}"
        return "-"

    print()
    print("| N | steps | " + " | ".join(f"{LABEL[c]} [ns]" for c in codes) +
          " | LAMMPS 1 / Talus | LAMMPS 2 / Talus | LAMMPS 1 / LAMMPS 2 | "
          "Talus contacts/particle | runs | CPU use (" + ", ".join(codes) + ") |")
    print("|---" * (len(codes) + 8) + "|")
    for n in sizes:
        any_r = next(best[(c, n)] for c in codes if (c, n) in best)
        t = best.get(("talus", n))
        contacts = f"{float(t['contacts_per_particle']):.3f}" if t else "-"
        tiles = int(any_r.get("tiles") or 1)
        label = f"{n:,}".replace(",", " ") + (f" (tiled x{tiles})" if tiles > 1 else "")
        nruns = "/".join(str(len(runs.get((c, n), []))) for c in codes)
        print(f"| {label} | {any_r['steps']} | " + " | ".join(cell(c, n) for c in codes) +
              f" | {ratio('lammps1', 'talus', n)} | {ratio('lammps2', 'talus', n)} | "
              f"{ratio('lammps1', 'lammps2', n)} | {contacts} | {nruns} | " +
              ", ".join(cell(c, n, "cpu") for c in codes) + " |")

    # On a shared machine the wall time of a run counts the time its process waited for a core;
    # the CPU time does not (cache and memory bandwidth are still shared). For 2 ranks it is the
    # CPU time of both, including time spent polling in MPI while waiting for the other rank.
    def cpu_ns(r):
        return 1e9 * float(r["cpu_s"]) / (int(r["steps"]) * int(r["n"]))

    print("\nCPU time (all processes of the run) per particle-step [ns], same runs:\n")
    print("| N | " + " | ".join(LABEL[c] for c in codes) + " |")
    print("|---" * (len(codes) + 1) + "|")
    for n in sizes:
        print(f"| {n:,} | ".replace(",", " ") + " | ".join(
            f"{cpu_ns(best[(c, n)]):.1f}" if (c, n) in best else "-" for c in codes) + " |")

    if not a.output:
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.6), dpi=110)
    style = {"talus": ("o-", "C0"), "lammps1": ("s--", "C1"), "lammps2": ("^:", "C2")}
    tiled = [n for n in sizes if any(int(best[(c, n)].get("tiles") or 1) > 1
                                     for c in codes if (c, n) in best)]
    panels = [(lambda r: float(r["ns_per_particle_step"]), "wall time / (steps N) [ns]",
               "ns per particle-step (wall time)"),
              (cpu_ns, "CPU time of all processes / (steps N) [ns]",
               "CPU time per particle-step")]
    for ax, (value, ylabel, title) in zip(axes, panels):
        for c in codes:
            ns = [n for n in sizes if (c, n) in best]
            ax.plot(ns, [value(best[(c, n)]) for n in ns], style[c][0], color=style[c][1],
                    label=LABEL[c])
        if tiled:
            ax.axvspan(min(tiled) / 1.4, max(tiled) * 1.4, color="0.92", zorder=0,
                       label="tiled packs (K copies of a settled N/K pack)")
        ax.set_xscale("log")
        ax.set_ylim(bottom=0)
        ax.set_xlabel("N (disks)")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    version = ", ".join(sorted({r["code_version"] for r in rows if r["code"] == "talus"}))
    fig.suptitle(f"Dense pack, scaling with N (Talus {version}, session {session})", fontsize=10)
    fig.text(0.01, 0.01, f"{rows[0]['cpu']}, load {min(loads):.1f}-{max(loads):.1f}; "
             "minimum over the repeats", fontsize=7, color="0.4")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    os.makedirs(os.path.dirname(a.output) or ".", exist_ok=True)
    fig.savefig(a.output)
    print(f"\nplot: {a.output}")


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("row")
    s.add_argument("csv")
    s.add_argument("code", choices=CODES)
    s.add_argument("log")
    s.add_argument("n", type=int)
    s.add_argument("meta", nargs="*")
    s.set_defaults(func=cmd_row)
    s = sub.add_parser("has")
    s.add_argument("csv")
    s.add_argument("session")
    s.add_argument("code")
    s.add_argument("n", type=int)
    s.add_argument("rep", type=int)
    s.set_defaults(func=cmd_has)
    s = sub.add_parser("table")
    s.add_argument("csv")
    s.add_argument("--session", default="")
    s.add_argument("-o", "--output", default="")
    s.set_defaults(func=cmd_table)
    a = p.parse_args()
    a.func(a)


if __name__ == "__main__":
    main()
