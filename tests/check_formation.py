#!/usr/bin/python3
"""Recomputes a run's formation figures (docs/MODEL.md "Formation flying", Portugal et al. 2014)
from its VTK export, independently of aeroflock's code, and checks them against the summary's
`structure[].formation` (one flocking flock meeting wakes, every bird exported, --vtk-precision
double).

usage: python3 tests/check_formation.py VTK_DIR SUMMARY.json

A follower is a bird with another at least 0.25 spans ahead along its flight through the air
(the export's `air_velocity`), within 10 spans; the nearest such is the bird it follows. In a V
place: 30-60 degrees behind that bird's wing (in the frame of its flight through the air, level
across), the lateral offset of centres within 10 % of the summary's `optimum_lateral`. In phase:
the phase lag within pi/4 of 2 pi f dx / U (f and U, the airspeed, the leader's).
Exits 0 when the followers a snapshot, the share in V and the share of those in phase agree, 1
otherwise, 77 (skipped) when VTK's Python modules cannot be imported.
"""
import json
import math
import sys

from vtk_snapshots import dot, read, snapshots, sub


def frame(path):
    points, arrays = read(path, ["air_velocity", "wingbeat_phase", "frequency"])
    return [{"p": p, "v": v, "phase": phase[0], "f": f[0]}
            for p, v, phase, f in zip(points, arrays["air_velocity"], arrays["wingbeat_phase"],
                                      arrays["frequency"])]


def norm(a):
    return math.sqrt(dot(a, a))


def remainder(x, y):
    return x - y * round(x / y)


def figures(birds, span, optimum):
    followers = in_v = in_phase = 0
    for i, b in enumerate(birds):
        ahead_b = [x / norm(b["v"]) for x in b["v"]]
        lead, nearest = None, 10.0 * span
        for j, o in enumerate(birds):
            offset = sub(o["p"], b["p"])
            d = norm(offset)
            if j != i and dot(offset, ahead_b) >= 0.25 * span and d <= nearest:
                lead, nearest = o, d
        if lead is None:
            continue
        followers += 1
        speed = norm(lead["v"])
        ahead = [x / speed for x in lead["v"]]
        across = [-ahead[2], 0.0, ahead[0]]  # ahead x up, normalised below
        side = [x / norm(across) for x in across]
        offset = sub(b["p"], lead["p"])
        dx, dy = -dot(offset, ahead), abs(dot(offset, side))
        bearing = math.atan2(dx, dy)
        if bearing < math.pi / 6 or bearing > math.pi / 3 or abs(dy - optimum) > 0.1 * optimum:
            continue
        in_v += 1
        lag = lead["phase"] - b["phase"]
        spatial = 2 * math.pi * lead["f"] * dx / speed
        in_phase += abs(remainder(lag - spatial, 2 * math.pi)) <= math.pi / 4
    return followers, in_v, in_phase


def main():
    vtk_dir, summary_path = sys.argv[1], sys.argv[2]
    flocks = json.load(open(summary_path))["structure"]
    if len(flocks) != 1 or not flocks[0].get("formation"):
        print("FAILED: expected one flocking flock with formation figures in the summary")
        return 1
    s, v = flocks[0], flocks[0]["formation"]
    try:
        paths = snapshots(vtk_dir, s)
    except LookupError as e:
        print(f"FAILED: {e}")
        return 1
    total = [0, 0, 0]
    for path in paths:
        total = [a + b for a, b in zip(total, figures(frame(path), s["wingspan"],
                                                      v["optimum_lateral"]))]
    mine = {"followers": total[0] / v["samples"],
            "in_v": total[1] / total[0] if total[0] else None,
            "in_phase": total[2] / total[1] if total[1] else None}
    errors = [f"{key}: recomputed {mine[key]}, summary {v[key]}" for key in mine
              if (mine[key] is None) != (v[key] is None)
              or (mine[key] is not None and abs(mine[key] - v[key]) > 1e-9)]
    for e in errors:
        print("FAILED:", e)
    if not errors:
        print(f"ok: {v['samples']} snapshots, {mine['followers']:.2f} followers, "
              f"in V {mine['in_v']}, in phase {mine['in_phase']}")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
