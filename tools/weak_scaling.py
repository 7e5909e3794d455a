#!/usr/bin/python3
"""The weak-scaling study over MPI ranks (docs/DISTRIBUTED.md "Speed").

usage: tools/weak_scaling.py [--birds N0] [--ranks 1,2,4] [--scenario migration] [--frames F]
                             [--backend cpu|vulkan] [--json OUT.json]
                             [--aeroflock build/release/aeroflock]

Runs `mpirun -n P aeroflock bench SCENARIO --weak-scaling N0 --backends BACKEND` for each P (P ranks fly P x N0 birds,
the flock P times as long along x), prints each point and E(P) = t(1, N0) / t(P, P N0), then
projects E to 64 and 1,024 ranks from the measured step time and halo volume for links of 10 and
25 GB/s at a latency of 2 microseconds:

  t(P) = t_step x imbalance + exchanges x (latency x messages + bytes / bandwidth)

with t_step the one-rank frame, the imbalance and the busiest rank's bytes a frame measured at the
largest P, two exchanges a frame (migrants, ghosts). Messages: an interior slab talks to its two
neighbours (neighbourhood exchange, 2 x 2 a frame) plus one allreduce (log2 P steps) for stopping
together; as built today MPI_Alltoall of the counts costs P latencies an exchange instead, shown
beside it. On fewer cores than ranks the measured E(P) is the cores' share, not the method's.
"""
import argparse
import json
import math
import os
import subprocess
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--birds", type=int, default=500000)
parser.add_argument("--ranks", default="1,2,4")
parser.add_argument("--scenario", default="migration")
parser.add_argument("--frames", type=int, default=5)
parser.add_argument("--backend", default="cpu", choices=("cpu", "vulkan"))
parser.add_argument("--json")
parser.add_argument("--aeroflock", default="build/release/aeroflock")
args = parser.parse_args()

env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_btl_vader_single_copy_mechanism="none",
           OMP_NUM_THREADS="1")
points = []
for p in [int(x) for x in args.ranks.split(",")]:
    out = f"/tmp/weak_scaling_{os.getpid()}_{p}.json"
    r = subprocess.run(["mpirun", "-n", str(p), args.aeroflock, "bench", args.scenario,
                        "--weak-scaling", str(args.birds), "--repetitions", str(args.frames),
                        "--backends", args.backend,
                        "--json", out], env=env, capture_output=True, text=True)
    sys.stdout.write(r.stdout)
    if r.returncode != 0:
        sys.stderr.write(r.stderr)
        sys.exit(1)
    points.append(json.load(open(out)))
    os.remove(out)

t1 = points[0]["frame_seconds"]
print("\n| ranks | birds | frame (s) | E(P) measured | ghosts / bird (most) | bytes / frame (most) | communication share |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for pt in points:
    print(f"| {pt['ranks']} | {pt['birds']:,} | {pt['frame_seconds']:.3f} | "
          f"{t1 / pt['frame_seconds']:.3f} | {pt['most_ghosts_per_bird']:.3f} | "
          f"{pt['most_bytes_per_frame'] / 1e6:.1f} MB | "
          f"{100 * pt['most_communication_seconds_per_frame'] / pt['frame_seconds']:.1f} % |")

last = points[-1]
latency = 2e-6
projection = []
print(f"\nprojected E(P) from t_step {t1:.3f} s, imbalance {last['imbalance']:.3f}, "
      f"{last['most_bytes_per_frame'] / 1e6:.1f} MB a frame on the busiest rank, latency 2 us:")
print("| ranks | link | E, neighbour exchange | E, as built (alltoall counts) |")
print("| --- | --- | --- | --- |")
for p in (64, 1024):
    for gbs in (10, 25):
        bandwidth = gbs * 1e9
        exchange = last["most_bytes_per_frame"] / bandwidth
        neighbour = 2 * (4 * latency) + exchange + math.ceil(math.log2(p)) * latency
        built = 2 * (p * latency + 2 * latency) + exchange + math.ceil(math.log2(p)) * latency
        step = t1 * last["imbalance"]
        e_n, e_b = t1 / (step + neighbour), t1 / (step + built)
        projection.append({"ranks": p, "link_gb_per_s": gbs, "efficiency_neighbour": e_n,
                           "efficiency_as_built": e_b})
        print(f"| {p} | {gbs} GB/s | {e_n:.3f} | {e_b:.3f} |")
# The frame time a rank's step must take for E = 0.9 at each link (the step, not the exchange, is
# what a faster device shrinks).
print("\nstep time a frame for E(P) = 0.9 (neighbour exchange), the exchange as measured:")
breakeven = []
for p in (64, 1024):
    for gbs in (10, 25):
        comm = (2 * (4 * latency) + last["most_bytes_per_frame"] / (gbs * 1e9) +
                math.ceil(math.log2(p)) * latency)
        need = 9.0 * comm / last["imbalance"]
        breakeven.append({"ranks": p, "link_gb_per_s": gbs, "step_seconds": need})
        print(f"  {p} ranks, {gbs} GB/s: {1e3 * need:.1f} ms a frame "
              f"({last['birds'] / last['ranks'] * last['steps_per_frame'] / need:.3g} bird-steps/s a rank)")
if args.json:
    with open(args.json, "w") as f:
        json.dump({"points": points, "latency_seconds": latency, "projection": projection,
                   "break_even": breakeven}, f, indent=2)
        f.write("\n")
