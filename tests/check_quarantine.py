#!/usr/bin/python3
"""NaN quarantine from the command line (issue 16), read back with Python's VTK.

usage: check_quarantine.py AEROFLOCK SCENARIO WORKDIR --backend cpu|vulkan

Runs tests/data/nan_quarantine.toml (two starlings descending to the ground, 10 m apart) with
flock "doomed" given a NaN ground-effect coefficient (AEROFLOCK_TEST_NAN_FLOCK), and checks:
- the run exits 0; stderr reports bird 1 quarantined once, with its time; the summary counts it
  (nan_birds 1) and lists it with its last finite state;
- in the VTK export its flight_state is "quarantined" from that time on, never before, and it
  stays where the summary says, its numbers finite in every frame (forces zero once frozen);
- the healthy bird flies exactly as it does alone (the run with --flock doomed=0);
- with --strict the run stops with exit 2 and a message naming the bird and the time, shortly
  after it, its summary and VTK files complete.
Exits 0 when all holds, 1 with the reasons, 77 (skipped) without VTK's Python modules.
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as e:
    print(f"SKIPPED: cannot import VTK's Python modules (vtkmodules): {e}")
    sys.exit(77)

errors = []


def check(condition, message):
    if not condition:
        errors.append(message)
    return condition


def run(aeroflock, backend, scenario, out, *extra, doomed=True):
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ)
    if doomed:
        env["AEROFLOCK_TEST_NAN_FLOCK"] = "doomed"
    cmd = [aeroflock, "run", "--backend", backend, scenario, "--summary", out + ".json", "--vtk", out, *extra]
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    print(" ".join(cmd), "->", p.returncode, "\n", p.stderr)
    return p


def frames(out):
    """Each saved frame: (time, {bird_id: {array: value}})."""
    root = ET.parse(os.path.join(out, "flock.pvd")).getroot()
    result = []
    for ds in root.findall("./Collection/DataSet"):
        reader = vtkXMLPolyDataReader()
        reader.SetFileName(os.path.join(out, ds.get("file")))
        reader.Update()
        data = reader.GetOutput()
        names = data.GetFieldData().GetAbstractArray("flight_state_names")
        states = [names.GetValue(i) for i in range(names.GetNumberOfValues())]
        pd = data.GetPointData()
        birds = {}
        for i in range(data.GetNumberOfPoints()):
            row = {"position": data.GetPoint(i)}
            for a in range(pd.GetNumberOfArrays()):
                arr = pd.GetArray(a)
                row[arr.GetName()] = arr.GetTuple(i)
            row["state"] = states[int(row["flight_state"][0])]
            birds[int(row["bird_id"][0])] = row
        result.append((float(ds.get("timestep")), birds))
    return result


def finite(row):
    return all(math.isfinite(v) for key, value in row.items() if key != "state" for v in value)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("aeroflock")
    parser.add_argument("scenario")
    parser.add_argument("workdir")
    parser.add_argument("--backend", default="cpu")
    args = parser.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    out = os.path.join(args.workdir, f"quarantine_{args.backend}")

    # Quarantined, the run goes on.
    p = run(args.aeroflock, args.backend, args.scenario, out)
    check(p.returncode == 0, f"exit status {p.returncode}, expected 0")
    reports = re.findall(r"bird (\d+) quarantined: its state became non-finite in the step at t = ([0-9.]+) s", p.stderr)
    check(len(reports) == 1 and reports[0][0] == "1", f"stderr reports {reports}, expected bird 1 once")
    summary = json.load(open(out + ".json"))
    check(summary["nan_birds"] == 1, f"nan_birds {summary['nan_birds']}, expected 1")
    listed = summary["quarantined"]
    if not check(len(listed) == 1 and listed[0]["bird"] == 1, f"summary lists {listed}, expected bird 1"):
        return
    q = listed[0]
    t = q["time"]
    check(reports and abs(float(reports[0][1]) - t) < 1e-4, f"stderr time {reports} != the summary's {t}")
    # It became non-finite a wing length (40 cm) above the ground, where its k is NaN.
    check(0 < q["position"][1] < 40.0, f"last finite height {q['position'][1]} cm, expected within 40 cm of the ground")
    check(all(math.isfinite(v) for key in ("position", "velocity", "attitude") for v in q[key]),
          f"last finite state not finite: {q}")
    saved = frames(out)
    check(saved[-1][0] > t + 1.0, f"the run ends at {saved[-1][0]} s, not well after the quarantine at {t} s")
    for time, birds in saved:
        doomed = birds[1]
        check(finite(doomed) and finite(birds[0]), f"t = {time}: a bird is not finite: {birds}")
        if time <= t:
            check(doomed["state"] != "quarantined", f"t = {time}: quarantined before {t} s")
            continue
        if not check(doomed["state"] == "quarantined", f"t = {time}: bird 1 is {doomed['state']}, expected quarantined"):
            continue
        # Frozen where the summary says (float32 positions in the file's arrays are double here).
        check(all(abs(a - b) <= 1e-6 * max(1.0, abs(b)) for a, b in zip(doomed["position"], q["position"])),
              f"t = {time}: bird 1 at {doomed['position']}, not frozen at {q['position']}")
        check(doomed["aero_force"] == (0.0, 0.0, 0.0), f"t = {time}: a frozen bird has forces {doomed['aero_force']}")

    # The healthy bird flies as it does alone, to the last bit.
    alone_out = out + "_alone"
    p_alone = run(args.aeroflock, args.backend, args.scenario, alone_out, "--flock", "doomed=0", doomed=False)
    check(p_alone.returncode == 0, f"alone: exit status {p_alone.returncode}")
    alone = frames(alone_out)
    check(len(alone) == len(saved), f"alone: {len(alone)} frames, {len(saved)} with the doomed bird")
    for (time, birds), (time_alone, birds_alone) in zip(saved, alone):
        check(birds[0]["position"] == birds_alone[0]["position"] and birds[0]["velocity"] == birds_alone[0]["velocity"],
              f"t = {time}: the healthy bird at {birds[0]['position']}, alone at {birds_alone[0]['position']}")

    # --strict: the first NaN is an error; what was written so far is complete.
    strict_out = out + "_strict"
    p = run(args.aeroflock, args.backend, args.scenario, strict_out, "--strict")
    check(p.returncode == 2, f"--strict: exit status {p.returncode}, expected 2")
    check(re.search(r"error: --strict: bird 1's state became non-finite at t = " + f"{t:.4f}", p.stderr) is not None,
          f"--strict: stderr does not name bird 1 and t = {t:.4f}: {p.stderr}")
    strict_summary = json.load(open(strict_out + ".json"))
    check(t < strict_summary["sim_seconds"] < t + 0.1,
          f"--strict: stopped at {strict_summary['sim_seconds']} s, expected just after {t} s")
    check(strict_summary["quarantined"][:1] == listed, f"--strict: lists {strict_summary['quarantined']}")
    strict_frames = frames(strict_out)
    check(abs(strict_frames[-1][0] - strict_summary["sim_seconds"]) < 1e-9,
          f"--strict: the export ends at {strict_frames[-1][0]} s, the run at {strict_summary['sim_seconds']} s")
    check(not [f for f in os.listdir(os.path.join(strict_out, "frames")) if f.endswith(".tmp")],
          "--strict: temporaries left in frames/")

    if errors:
        print("\n".join(errors))
        sys.exit(1)
    print(f"ok: bird 1 quarantined at t = {t:.4f} s on {args.backend}, frozen, reported once; the healthy bird as alone; --strict exits 2")


if __name__ == "__main__":
    main()
