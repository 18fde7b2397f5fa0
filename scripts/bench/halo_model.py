#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Communication against compute per step for N disks on P MPI ranks (docs/scaling.md).

Inputs are the counts measured on one machine by scripts/bench/halo_estimate.cpp (ghosts and
contacts per metre of border, number density of the pack) and the force-loop time per
particle-step of docs/benchmarks.md; the interconnect figures are assumptions, stated in the
table. Plain Python, no packages:

    python3 scripts/bench/halo_model.py                 # the defaults below (measured 24 Nov)
    python3 scripts/bench/halo_model.py --rho 258486 --ghosts-per-m 1240.24 ...

Model, per rank and step (the cycle of docs/scaling.md):
  forward:   every ghost's x, v, spin (40 B) from its owner            -> phases x latency + B/BW
  reverse:   per contact across a border, owned here (about half):     -> phases x latency + B/BW
             key 8 + force 16 + moment 8 + k_tran, k_rot 16 = 48 B
  time step: MPI_Allreduce(MIN) of one double                          -> log2(P) x latency
  pack/unpack of all of the above at the measured ns per item
  compute:   (N/P) x ns per particle-step
A slab has two neighbours, exchanged at once (one latency per phase); a square has eight,
exchanged as x then y with the corners forwarded (two latencies per phase), as LAMMPS does.
One rank per node is assumed (the link is not shared); ranks on one node share it, see the doc.
"""
import argparse
import math


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--n", type=float, default=1e7, help="disks")
    ap.add_argument("--ranks", default="16,64,256")
    ap.add_argument("--rho", type=float, default=258486.0, help="disks per m^2 (measured)")
    ap.add_argument("--ghosts-per-m", type=float, default=1240.24,
                    help="ghosts per metre of border, both directions (measured)")
    ap.add_argument("--contacts-per-m", type=float, default=577.0,
                    help="contacts across the border per metre (measured)")
    ap.add_argument("--ghost-bytes", type=float, default=40.0)
    ap.add_argument("--force-bytes", type=float, default=48.0)
    ap.add_argument("--pack-ns", type=float, default=11.0,
                    help="pack + unpack per item [ns] (measured gather from 25 MB arrays)")
    ap.add_argument("--compute-ns", default="90,35",
                    help="ns per particle-step: the measured 50k value, and its target")
    a = ap.parse_args()

    nets = [  # name, latency [s], bandwidth [B/s]
        ("local shared memory (measured, 2 ranks)", 0.33e-6, 8.6e9),
        ("InfiniBand EDR (assumed)", 1.5e-6, 12.0e9),
        ("10 Gb/s Ethernet (assumed)", 20e-6, 1.25e9),
    ]
    side = math.sqrt(a.n / a.rho)  # the whole pack as a square [m]
    print(f"N = {a.n:.3g} disks, square pack of side {side:.3f} m at {a.rho:.6g} disks/m^2\n")
    print("| P | split | disks/rank | ghosts/rank | ghost share | contacts sent/rank | "
          "bytes/step/rank | network | comm [us] | compute 90 ns [us] | ratio | "
          "compute 35 ns [us] | ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for p in [int(x) for x in a.ranks.split(",")]:
        for split in ("slab", "square"):
            if split == "slab":
                border = 2 * side  # an interior slab: two full-height borders
                phases_lat = 1
            else:
                q = math.isqrt(p)
                if q * q != p:
                    continue
                border = 4 * side / q
                phases_lat = 2
            owned = a.n / p
            ghosts = a.ghosts_per_m / 2 * border  # received from the neighbours
            contacts = a.contacts_per_m * border / 2  # owned here, other end a ghost
            bytes_step = ghosts * a.ghost_bytes + contacts * a.force_bytes
            pack = (ghosts + contacts) * a.pack_ns * 1e-9
            computes = [float(c) for c in a.compute_ns.split(",")]
            for name, lat, bw in nets:
                comm = (2 * phases_lat * lat + bytes_step / bw + math.log2(p) * lat + pack)
                row = [f"{p}", split, f"{owned:.0f}", f"{ghosts:.0f}",
                       f"{ghosts / owned * 100:.1f}%", f"{contacts:.0f}", f"{bytes_step / 1e3:.0f} kB",
                       name, f"{comm * 1e6:.0f}"]
                for c in computes:
                    t = owned * c * 1e-9
                    row += [f"{t * 1e6:.0f}", f"{comm / t:.3f}"]
                print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
