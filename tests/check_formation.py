#!/usr/bin/python3
"""Recomputes a run's formation figures (docs/MODEL.md "Formation flying", Portugal et al. 2014)
from its VTK export, independently of aeroflock's code (who follows whom:
tools/formation_followers.py, which tools/formation_phase.py shares), and checks them against the
summary's `structure[].formation` (one flocking flock meeting wakes, every bird and every frame of
the window exported, --vtk-precision double): the followers, the shares in V, in phase, directly
behind and in anti-phase at the snapshots, and the wings' power of each role over every frame
(`wingbeat_power`), each bird in its role at the snapshot before.

usage: python3 tests/check_formation.py VTK_DIR SUMMARY.json

A follower is a bird with another at least 0.25 spans ahead along its flight through the air
(the export's `air_velocity`), within 10 spans; the nearest such is the bird it follows. In a V
place: 30-60 degrees behind that bird's wing (in the frame of its flight through the air, level
across), the lateral offset of centres within 10 % of the summary's `optimum_lateral`. In phase:
the phase lag within pi/4 of 2 pi f dx / U (f and U, the airspeed, the leader's). Directly
behind: the lateral offset within a quarter span; in anti-phase: the lag within pi/4 of
2 pi f dx / U + pi.
Exits 0 when the followers a snapshot and the shares in V, in phase, directly behind and in
anti-phase agree, 1 otherwise, 77 (skipped) when VTK's Python modules cannot be imported.
"""
import json
import math
import os
import sys

from vtk_snapshots import frames_between, read, snapshots

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from formation_followers import directly_behind, followers, in_v_place  # noqa: E402


def frame(path):
    points, arrays = read(path, ["air_velocity", "wingbeat_phase", "frequency", "wingbeat_power"])
    return [{"p": p, "v": v, "phase": phase[0], "f": f[0], "w": w[0]}
            for p, v, phase, f, w in zip(points, arrays["air_velocity"], arrays["wingbeat_phase"],
                                         arrays["frequency"], arrays["wingbeat_power"])]


def remainder(x, y):
    return x - y * round(x / y)


def figures(birds, span, optimum, roles=None):
    """The snapshot's followers, in V, in phase, directly behind and in anti-phase; `roles` (a
    list) gets each bird's: "head", "follower" or "in_v"."""
    found = followers(birds, span)
    in_v = in_phase = behind = anti_phase = 0
    if roles is not None:
        roles[:] = ["head"] * len(birds)
    for i, lead, dx, dy, speed in found:
        place = in_v_place(dx, dy, optimum)
        if roles is not None:
            roles[i] = "in_v" if place else "follower"
        lag = lead["phase"] - birds[i]["phase"]
        off_path = abs(remainder(lag - 2 * math.pi * lead["f"] * dx / speed, 2 * math.pi))
        if directly_behind(dy, span):
            behind += 1
            anti_phase += off_path >= 0.75 * math.pi
        if place:
            in_v += 1
            in_phase += off_path <= math.pi / 4
    return len(found), in_v, in_phase, behind, anti_phase


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
    total = [0, 0, 0, 0, 0]
    # The wings' power of each role over every exported frame of the window (the export must hold
    # every frame of it), each bird in its role at the snapshot before.
    snapshot_paths = set(paths)
    power = {"head": [0.0, 0], "follower": [0.0, 0], "in_v": [0.0, 0]}
    roles = []
    for t, path in frames_between(vtk_dir, s["from"], s["to"]):
        birds = frame(path)
        if path in snapshot_paths:
            total = [a + b for a, b in zip(total, figures(birds, s["wingspan"],
                                                          v["optimum_lateral"], roles))]
        for b, role in zip(birds, roles):
            for r in (role, "follower") if role == "in_v" else (role,):
                power[r][0] += b["w"]
                power[r][1] += 1
    mine = {"followers": total[0] / v["samples"],
            "in_v": total[1] / total[0] if total[0] else None,
            "in_phase": total[2] / total[1] if total[1] else None,
            "behind": total[3] / total[0] if total[0] else None,
            "anti_phase": total[4] / total[3] if total[3] else None}
    for role in power:
        mine[f"{role}_power"] = 1e-7 * power[role][0] / power[role][1] if power[role][1] else None
    errors = [f"{key}: recomputed {mine[key]}, summary {v[key]}" for key in mine
              if (mine[key] is None) != (v[key] is None)
              or (mine[key] is not None and abs(mine[key] - v[key]) > 1e-9 * max(1, abs(v[key])))]
    for e in errors:
        print("FAILED:", e)
    if not errors:
        print(f"ok: {v['samples']} snapshots, {mine['followers']:.2f} followers, "
              f"in V {mine['in_v']}, in phase {mine['in_phase']}, directly behind "
              f"{mine['behind']}, in anti-phase {mine['anti_phase']}; power W: a head "
              f"{mine['head_power']}, a follower {mine['follower_power']}, in V {mine['in_v_power']}")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
