"""What the two render scripts share: reading an `aeroflock run --vtk DIR` export (the collection,
field data, the codes' names), framing it with a camera, checking outputs, and running under
xvfb-run. Plain Python and whatever VTK the interpreter has (python3-vtk9 or ParaView's own):
render_run.py (pvbatch/pvpython) and render_run_vtk.py (python3-vtk9) import it from their folder.
"""
import argparse
import math
import os
import random
import subprocess
import sys
import types
import xml.etree.ElementTree as ET


def fail(message):
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "render"
    print(f"{name}: {message}", file=sys.stderr)
    sys.exit(1)


XVFB_GUARD = "AEROFLOCK_RENDER_UNDER_XVFB"


def xvfb_command(xvfb):
    """xvfb-run searching a free display number from a random start (fewer clashes when several
    renders start at once)."""
    return [xvfb, "-n", str(random.randrange(100, 2000)), "-a", "-s", "-screen 0 1280x1024x24"]


def run_under_xvfb(xvfb, command, name):
    """Runs command under xvfb-run, passing its output on, and exits with its status. Tries up to
    three times when the X connection fails: Xvfb 21.1 (Debian 12) now and then hangs up on a
    client that connects just after another one closed ("bad X server connection", SIGABRT)."""
    env = dict(os.environ, **{XVFB_GUARD: "1"})
    sys.stdout.flush()
    sys.stderr.flush()
    for attempt in range(3):
        proc = subprocess.Popen(xvfb_command(xvfb) + command, env=env, stderr=subprocess.PIPE)
        refused = False
        for line in proc.stderr:
            os.write(2, line)
            refused = refused or b"bad X server connection" in line
        status = proc.wait()
        if status == 0 or not refused or attempt == 2:
            break
        os.write(2, f"{name}: the X connection failed under xvfb-run; trying again\n".encode())
    os._exit(status if status >= 0 else 128 - status)


def read_collection(run_dir):
    """[(time, path)] from RUN_DIR/flock.pvd, sorted by time."""
    pvd = os.path.join(run_dir, "flock.pvd")
    if not os.path.isfile(pvd):
        fail(f"{pvd}: no such file (is {run_dir} an `aeroflock run --vtk` directory?)")
    try:
        root = ET.parse(pvd).getroot()
    except ET.ParseError as e:
        fail(f"{pvd}: {e}")
    steps = [(float(ds.get("timestep")), os.path.join(run_dir, ds.get("file")))
             for ds in root.iter("DataSet")]
    if not steps:
        fail(f"{pvd}: no frames")
    return sorted(steps)


def string_field(data, name):
    """The entries of the string field array `name`, or None when the file has none."""
    array = data.GetFieldData().GetAbstractArray(name)
    if array is None or not array.IsA("vtkStringArray"):
        return None
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def category_names(frames, array_name, field_name, fallback):
    """Names for the integer codes of `array_name`: from field data when present, else fallback."""
    names = string_field(frames[-1], field_name) or string_field(frames[0], field_name)
    top = max(int(f.GetPointData().GetArray(array_name).GetRange()[1])
              if f.GetPointData().GetArray(array_name) and f.GetNumberOfPoints() else 0
              for f in frames)
    if names:
        return names + [f"{array_name} {i}" for i in range(len(names), top + 1)]
    return [fallback(i) for i in range(top + 1)]


def sample_points(datasets, cap=20000):
    """Up to about `cap` points (cm) spread over the datasets, for fitting the camera."""
    points = []
    for data in datasets:
        n = data.GetNumberOfPoints()
        for i in range(0, n, max(1, n // cap)):
            points.append(data.GetPoint(i))
    return points


def extent(points):
    """Diagonal of the points' bounding box, cm."""
    lo = [min(p[i] for p in points) for i in range(3)]
    hi = [max(p[i] for p in points) for i in range(3)]
    return math.dist(lo, hi)


def choose_camera_mode(mode, flock_points, run_points):
    """auto: frame the flock when the whole run is over ten times as big as the flock (taken as
    at least 30 m across), as on a long migration; else the whole run."""
    if mode != "auto":
        return mode
    flock = max(max(extent(points) for points in flock_points), 3000.0)
    return "flock" if extent(run_points) > 10.0 * flock else "all"


def frame_camera(points, azimuth, elevation, aspect, view_angle=30.0, minimum=500.0,
                 region=(-0.97, 0.60, -0.95, 0.80)):
    """Focal point, position, up vector and view angle that fit `points` (cm) in the picture.

    Looks from the azimuth/elevation direction (degrees; azimuth 0 from +z, 90 from +x; world y
    up) and backs off until every point is inside `region` of the picture (x0, x1, y0, y1 in
    -1..1 screen units: the legend is on the right, the title at the top). Groups smaller than
    `minimum` cm (one bird) are shown as if that big."""
    az, el = math.radians(azimuth), math.radians(elevation)
    back = (math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az))  # to camera
    right = (math.cos(az), 0.0, -math.sin(az))
    up = (back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
          back[0] * right[1] - back[1] * right[0])
    projected = [(p[0] * right[0] + p[1] * right[1] + p[2] * right[2],
                  p[0] * up[0] + p[1] * up[1] + p[2] * up[2],
                  p[0] * back[0] + p[1] * back[1] + p[2] * back[2]) for p in points]
    lo = [min(q[i] for q in projected) for i in range(3)]
    hi = [max(q[i] for q in projected) for i in range(3)]
    mid = [(lo[i] + hi[i]) / 2 for i in range(3)]
    tan_v = math.tan(math.radians(view_angle) / 2)
    tan_h = tan_v * aspect
    fit_h = tan_h * (region[1] - region[0]) / 2
    fit_v = tan_v * (region[3] - region[2]) / 2
    distance = max(minimum / 2 / fit_v, minimum / 2 / fit_h)
    for x, y, z in projected:
        distance = max(distance, z - mid[2] + max(abs(x - mid[0]) / fit_h, abs(y - mid[1]) / fit_v))
    # Then, as near points come out bigger than far ones, move the camera sideways and back or
    # forth until the points' picture just fills the region, never closer than a bird's length in
    # front of the nearest point; if that does not settle, keep the safe distance found above.
    safe = (mid[0], mid[1], distance)
    nearest = max(z for _, _, z in projected) - mid[2]
    dx, dy = mid[0], mid[1]
    settled = False
    for _ in range(30):
        camera_z = mid[2] + distance
        sx = [(x - dx) / (max(camera_z - z, 1e-6) * tan_h) for x, _, z in projected]
        sy = [(y - dy) / (max(camera_z - z, 1e-6) * tan_v) for _, y, z in projected]
        scale = max((max(sx) - min(sx)) / (region[1] - region[0]),
                    (max(sy) - min(sy)) / (region[3] - region[2]), 1e-3)
        shift_x = (max(sx) + min(sx)) / 2 - (region[0] + region[1]) / 2
        shift_y = (max(sy) + min(sy)) / 2 - (region[2] + region[3]) / 2
        dx += shift_x * distance * tan_h
        dy += shift_y * distance * tan_v
        distance = max(distance * scale, nearest + minimum, minimum / 2 / fit_v, minimum / 2 / fit_h)
        if abs(scale - 1) < 1e-3 and abs(shift_x) < 1e-3 and abs(shift_y) < 1e-3:
            settled = True
            break
    if not settled:
        dx, dy, distance = safe
    distance *= 1.03  # a margin
    focal = [dx * right[i] + dy * up[i] + mid[2] * back[i] for i in range(3)]
    position = [focal[i] + distance * back[i] for i in range(3)]
    return focal, position, (0.0, 1.0, 0.0), view_angle


def check_outputs(args):
    """Fail before rendering, as aeroflock does: a PNG's name ends in .png and its directory
    exists; a frames directory is made only inside one that exists."""
    if args.png:
        if not args.png.lower().endswith(".png"):
            sys.exit(f"--png {args.png}: expected a file name ending in .png")
        folder = os.path.dirname(args.png) or "."
        if not os.path.isdir(folder):
            sys.exit(f"--png {args.png}: directory {folder} does not exist (create it first)")
    if args.frames_dir and not os.path.isdir(args.frames_dir):
        parent = os.path.dirname(os.path.normpath(args.frames_dir)) or "."
        if not os.path.isdir(parent):
            sys.exit(f"--frames-dir {args.frames_dir}: directory {parent} does not exist (create it first)")
        os.mkdir(args.frames_dir)


def check_written(path):
    """VTK and ParaView report a failed write only in their log: look at the file."""
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        sys.exit(f"{path}: the picture was not written")

def parse_args(argv, prog, doc):
    """The options both scripts take; `doc` (the script's docstring) is the help's text."""
    p = argparse.ArgumentParser(prog=prog, description=doc.split("\n\n")[0],
                                epilog=doc.split("\n\n", 1)[-1],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run_dir")
    p.add_argument("--png")
    p.add_argument("--frames-dir")
    p.add_argument("--time", type=float)
    p.add_argument("--every", type=int, default=1)
    p.add_argument("--color", choices=["speed", "species", "flight_state", "rank"], default="speed")
    p.add_argument("--speed-range")
    p.add_argument("--birds", choices=["points", "cones"], default="points")
    p.add_argument("--point-size", type=float)
    p.add_argument("--bird-size", type=float)
    p.add_argument("--trajectories", choices=["past", "full", "none"], default="past")
    p.add_argument("--max-trajectories", type=int, default=100)
    p.add_argument("--camera", choices=["auto", "all", "flock"], default="auto")
    p.add_argument("--azimuth", type=float, default=35.0)
    p.add_argument("--elevation", type=float, default=25.0)
    p.add_argument("--size", default="1280x720")
    p.add_argument("--title")
    a = p.parse_args(argv)
    if not a.png and not a.frames_dir:
        p.error("give --png FILE and/or --frames-dir DIR")
    try:
        a.width, a.height = (int(v) for v in a.size.lower().split("x"))
        assert 16 <= a.width <= 8192 and 16 <= a.height <= 8192
    except (ValueError, AssertionError):
        p.error(f"--size {a.size}: expected WxH between 16x16 and 8192x8192, e.g. 1280x720")
    if a.speed_range:
        text = a.speed_range
        try:
            a.speed_range = tuple(float(v) for v in a.speed_range.split(","))
            assert len(a.speed_range) == 2 and a.speed_range[0] < a.speed_range[1]
        except (ValueError, AssertionError):
            p.error(f"--speed-range {text}: expected MIN,MAX in m/s, MIN < MAX")
    if a.every < 1:
        p.error("--every must be at least 1")
    return a


# What both scripts' main() works out before drawing.
FLIGHT_STATES = ["flying", "standing", "taking off", "landing", "perched", "quarantined"]


def plan_run(args, read_polydata):
    """The run's frames and what to draw of them: steps [(time, path)], the trajectories (None
    when the file is missing), the frame for --png, the animation's frames, the first and last
    frames, the colour categories and the speed range (m/s)."""
    plan = types.SimpleNamespace()
    plan.steps = steps = read_collection(args.run_dir)
    missing = [p for _, p in steps if not os.path.isfile(p)]
    if missing:
        fail(f"{missing[0]}: no such file ({len(missing)} frames of flock.pvd missing)")
    plan.traj_path = os.path.join(args.run_dir, "trajectories.vtp")
    plan.trajectories = read_polydata(plan.traj_path) if os.path.isfile(plan.traj_path) else None
    if plan.trajectories is None:
        print(f"{os.path.basename(sys.argv[0])}: {plan.traj_path} missing, drawing the birds only",
              file=sys.stderr)
    plan.png_index = None
    if args.png:
        if args.time is None:
            plan.png_index = len(steps) - 1
        else:
            plan.png_index = min(range(len(steps)), key=lambda i: abs(steps[i][0] - args.time))
    plan.animation = range(0, len(steps), args.every) if args.frames_dir else range(0)
    plan.shown = list(plan.animation)
    if args.png and plan.png_index not in plan.shown:
        plan.shown.append(plan.png_index)
    plan.ends = ends = [read_polydata(steps[0][1]), read_polydata(steps[-1][1])]
    if args.color == "species":
        plan.categories = category_names(ends, "species", "species_names", lambda i: f"species {i}")
    elif args.color == "flight_state":
        plan.categories = category_names(
            ends, "flight_state", "flight_state_names",
            lambda i: FLIGHT_STATES[i] if i < len(FLIGHT_STATES) else f"state {i}")
    elif args.color == "rank":
        # Every rank of the run, also those that held no bird (the field data's `ranks`).
        field = ends[-1].GetFieldData().GetArray("ranks")
        ranks = int(field.GetTuple1(0)) if field is not None else 0
        plan.categories = category_names(ends, "rank", "rank_names", lambda i: f"rank {i}")
        plan.categories += [f"rank {i}" for i in range(len(plan.categories), ranks)]
    else:
        plan.categories = []
    if args.speed_range:
        plan.speed_range = args.speed_range
    else:
        trajectories = plan.trajectories
        source = trajectories if trajectories is not None and \
            trajectories.GetPointData().GetArray("speed") else ends[-1]
        lo, hi = source.GetPointData().GetArray("speed").GetRange()
        plan.speed_range = (lo / 100.0, hi / 100.0) if hi > lo else (lo / 100.0 - 1, hi / 100.0 + 1)
    return plan
