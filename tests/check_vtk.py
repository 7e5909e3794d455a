#!/usr/bin/python3
"""Checks an `aeroflock run --vtk DIR` export with Python's VTK: Debian's python3-vtk9 under
/usr/bin/python3, or ParaView's own under pvpython (whichever is present; both have vtkmodules).

usage: python3 tests/check_vtk.py DIR [--birds N] [--frames N] [--min-frames N] [--last-time T]

Parses DIR/flock.pvd as XML, checks that every file it lists exists, that the first is t = 0 and
the times rise strictly without float noise, opens each file with vtkXMLPolyDataReader and checks
its point count, arrays (reals Float32, time Float64) and the field data that describes it
(species and flight-state names, every array's unit, TimeValue), and opens DIR/trajectories.vtp
(one polyline per bird, one point per saved frame), and that frames/ holds no frame file the
collection does not list and DIR no temporary. Exits 0 when all is well, 1 with the reasons
otherwise, and 77 (skipped) when VTK's Python modules cannot be imported.

check_export() is the same check for other scripts (tests/check_faults.py), with allowances for a
run that was stopped by a fault: trajectories through the first frames only, a frame file written
but not yet listed.
"""
import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET

try:
    from vtkmodules.vtkCommonCore import vtkIdList
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as e:  # neither python3-vtk9 nor ParaView's Python
    print(f"SKIPPED: cannot import VTK's Python modules (vtkmodules): {e}")
    sys.exit(77)

# Point arrays of a frame file and their numbers of components.
FRAME_ARRAYS = {
    "bird_id": 1, "species": 1, "time": 1, "velocity": 3, "speed": 1, "attitude": 4,
    "heading_pitch_bank": 3, "wingbeat_phase": 1, "frequency": 1, "amplitude": 1,
    "tail_bend": 1, "tail_twist": 1, "tail_opening": 1, "aero_force": 3, "tail_force": 3,
    "wingbeat_power": 1, "wake_air": 3,
    "flight_state": 1, "target": 1, "neighbours": 1, "nearest_neighbour": 1, "social_direction": 3,
}
# Arrays that are not Float32 (the reals are, by default).
NOT_FLOAT = {"bird_id": "unsigned int", "species": "int", "time": "double", "flight_state": "int",
             "target": "int", "neighbours": "int"}
FLIGHT_STATES = ["flying", "standing", "taking_off", "landing", "perched", "quarantined"]

errors = []


def check(condition, message):
    if not condition:
        errors.append(message)
    return condition


def read(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    check(reader.GetErrorCode() == 0, f"{path}: VTK read error {reader.GetErrorCode()}")
    return reader.GetOutput()


def strings(data, name):
    a = data.GetFieldData().GetAbstractArray(name)
    return None if a is None else [a.GetValue(i) for i in range(a.GetNumberOfValues())]


def check_field_data(path, data, arrays):
    """The file names its codes and the unit of its points and of each of `arrays`."""
    species = strings(data, "species_names")
    check(species is not None and len(species) >= 1 and all(species), f"{path}: no species_names")
    check(strings(data, "flight_state_names") == FLIGHT_STATES,
          f"{path}: flight_state_names {strings(data, 'flight_state_names')}")
    units = strings(data, "array_units") or []
    named = [u.split(": ")[0] for u in units]
    check(named[:1] == ["points"], f"{path}: array_units does not start with the points' unit: {units[:1]}")
    for name in arrays:
        check(name in named, f"{path}: array_units has no unit for {name}")
    for name in ("scenario", "scenario_hash"):
        check(strings(data, name) not in (None, [], [""]), f"{path}: no field data {name}")
    check(data.GetFieldData().GetArray("dt") is not None, f"{path}: no field data dt")
    return species


def check_export(dir, birds=None, frames=None, min_frames=1, last_time=None,
                 trajectories_prefix=False, unlisted_frames=0, temporaries=False):
    """The errors found in the export in `dir` (an empty list when all is well), and the times of
    its frames. trajectories_prefix: the trajectories may end before the collection or be missing
    (a write of them failed, or one was due); unlisted_frames: that many frame files may follow the listed
    ones (written, the process killed before it listed them); temporaries: allowed (a killed
    run's, named as only aeroflock names them)."""
    errors.clear()
    pvd = os.path.join(dir, "flock.pvd")
    root = ET.parse(pvd).getroot()
    check(root.tag == "VTKFile" and root.get("type") == "Collection", f"{pvd}: not a collection")
    datasets = root.findall("./Collection/DataSet")
    check(len(datasets) >= min_frames, f"{pvd}: {len(datasets)} frames, expected at least {min_frames}")
    if frames is not None:
        check(len(datasets) == frames, f"{pvd}: {len(datasets)} frames, expected {frames}")

    times = []
    if datasets:
        check(float(datasets[0].get("timestep")) == 0.0, f"{pvd}: the first frame is at t = {datasets[0].get('timestep')}, not 0")
    for ds in datasets:
        text = ds.get("timestep")
        check(not re.search(r"(9{6}|0{6})[0-9]$", text), f"{pvd}: timestep {text} carries float noise")
        t = float(text)
        path = os.path.join(dir, ds.get("file"))
        if times:
            check(t > times[-1], f"{pvd}: time {t} after {times[-1]} does not rise")
        times.append(t)
        if not check(os.path.isfile(path), f"{path}: listed in {pvd} but missing"):
            continue
        data = read(path)
        n = data.GetNumberOfPoints()
        if birds is None:
            birds = n
        check(n == birds, f"{path}: {n} points, expected {birds}")
        check(data.GetNumberOfVerts() == n, f"{path}: {data.GetNumberOfVerts()} vertices for {n} points")
        pd = data.GetPointData()
        for name, components in FRAME_ARRAYS.items():
            a = pd.GetArray(name)
            if not check(a is not None, f"{path}: no point array {name}"):
                continue
            check(a.GetNumberOfComponents() == components,
                  f"{path}: {name} has {a.GetNumberOfComponents()} components, expected {components}")
            check(a.GetNumberOfTuples() == n, f"{path}: {name} has {a.GetNumberOfTuples()} tuples")
            want = NOT_FLOAT.get(name, "float")
            check(a.GetDataTypeAsString() == want, f"{path}: {name} is {a.GetDataTypeAsString()}, expected {want}")
        species = check_field_data(path, data, FRAME_ARRAYS)
        if species and pd.GetArray("species") is not None and n > 0:
            lo, hi = pd.GetArray("species").GetRange()
            check(0 <= lo <= hi < len(species), f"{path}: species codes {lo}..{hi} but {len(species)} names")
        tv = data.GetFieldData().GetArray("TimeValue")
        check(tv is not None and tv.GetValue(0) == t, f"{path}: TimeValue is not the collection's {t}")
        if pd.GetArray("time") is not None and n > 0:
            check(abs(pd.GetArray("time").GetValue(0) - t) <= 1e-12 * max(1.0, abs(t)),
                  f"{path}: time {pd.GetArray('time').GetValue(0)} but the collection says {t}")
        if pd.GetArray("speed") is not None:
            lo, hi = pd.GetArray("speed").GetRange()
            check(0 <= lo <= hi < 1e5, f"{path}: speeds {lo}..{hi} cm/s out of range")

    if last_time is not None:
        check(times and times[-1] == last_time, f"{pvd}: the last frame is at {times[-1] if times else '-'} s, expected {last_time}")

    # No frame file but those listed (an earlier run's would be stale), unless allowed.
    listed = {os.path.normpath(os.path.join(dir, ds.get("file"))) for ds in datasets}
    frames_dir = os.path.join(dir, "frames")
    on_disk = sorted(f for f in os.listdir(frames_dir) if re.fullmatch(r"flock_[0-9]{6,}\.vtp", f)) \
        if os.path.isdir(frames_dir) else []
    unlisted = [f for f in on_disk if os.path.join(frames_dir, f) not in listed]
    check(len(unlisted) <= unlisted_frames, f"{frames_dir}: frame files the collection does not list: {unlisted[:5]}")
    for f in unlisted:  # complete, and the next ones
        data = read(os.path.join(frames_dir, f))
        check(birds is None or data.GetNumberOfPoints() == birds, f"{f}: {data.GetNumberOfPoints()} points")
        check(int(f[6:-4]) >= len(datasets), f"{frames_dir}: {f} is not after the listed frames")

    traj_path = os.path.join(dir, "trajectories.vtp")
    if check(os.path.isfile(traj_path) or trajectories_prefix, f"{traj_path}: missing") and os.path.isfile(traj_path):
        traj = read(traj_path)
        frames = len(times)
        if trajectories_prefix:
            # Through the first frames: its times are theirs.
            t = traj.GetPointData().GetArray("time")
            frames = traj.GetNumberOfPoints() // max(birds or 1, 1)
            check(frames <= len(times), f"{traj_path}: {frames} frames, more than the collection's {len(times)}")
            check(t is None or [t.GetValue(i) for i in range(min(frames, t.GetNumberOfTuples()))] == times[:frames],
                  f"{traj_path}: its times are not the collection's first {frames}")
        cells = traj.GetNumberOfCells()
        check(cells == (birds or 0 if frames > 0 else 0), f"{traj_path}: {cells} cells, expected one per bird ({birds})")
        check(traj.GetNumberOfPoints() == (birds or 0) * frames,
              f"{traj_path}: {traj.GetNumberOfPoints()} points, expected {birds} x {frames}")
        if frames >= 2:
            check(traj.GetNumberOfLines() == cells, f"{traj_path}: cells are not polylines")
        for name in ("time", "speed"):
            check(traj.GetPointData().GetArray(name) is not None, f"{traj_path}: no point array {name}")
        check(traj.GetCellData().GetArray("bird_id") is not None, f"{traj_path}: no cell array bird_id")
        check(traj.GetCellData().GetArray("species") is not None, f"{traj_path}: no cell array species")
        check_field_data(traj_path, traj, ("time", "speed"))
        ids = vtkIdList()
        for c in range(min(cells, 3)):
            traj.GetCellPoints(c, ids)
            check(ids.GetNumberOfIds() == frames, f"{traj_path}: bird {c} has {ids.GetNumberOfIds()} points")

    leftovers = [f for _, _, files in os.walk(dir) for f in files if f.endswith(".tmp")]
    if temporaries:
        leftovers = [f for f in leftovers if not re.fullmatch(r".+\.aeroflock-[0-9]+-[0-9]+\.tmp", f)]
    check(not leftovers, f"{dir}: temporary files left: {leftovers}")
    return list(errors), times, birds


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("dir")
    parser.add_argument("--birds", type=int, help="birds expected in every frame")
    parser.add_argument("--frames", type=int, help="frames expected in the collection")
    parser.add_argument("--min-frames", type=int, default=1, help="at least this many frames")
    parser.add_argument("--last-time", type=float, help="the last frame's time, s")
    args = parser.parse_args()
    errors, times, birds = check_export(args.dir, args.birds, args.frames, args.min_frames, args.last_time)
    if errors:
        print("\n".join(errors))
        return 1
    print(f"ok: {len(times)} frames of {birds} birds, t = {times[0] if times else '-'} .. "
          f"{times[-1] if times else '-'} s, trajectories ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
