#!/usr/bin/python3
"""`aeroflock run` under mpiexec against the same run on one process (engine/dist, issue 42).

usage: python3 tests/check_ranks.py MPIEXEC AEROFLOCK WORKDIR [cpu|vulkan]

On the backend named (the CPU unless said) 1, 6 and 7; on the CPU 2 to 5 as well, which do not
depend on the backend. The Vulkan cases are the validate tier's (python_check_ranks_vulkan).

With the environment OpenMPI needs as root and oversubscribed (tests/CMakeLists.txt sets it):
  1. `default` for 3 s (on Vulkan a device a rank), alone and on 2, 3 and 4 ranks:
     every figure of the summaries equal (the flock is the same bird for bird) but the device, the
     times and `ranks`; `ranks` has one entry per rank, their birds sum to the flock, ghosts were
     sent. Then `ibis-v` (wakes, formation flying) for 10 s alone and on 3 ranks: the same, its
     formation figures included but the wings' power (null over many ranks).
  2. a command that runs on one process (envelope) and a mistake in the options are refused:
     exit 2, said once.
  3. an unknown scenario: exit 2, said once.
  4. one rank failing mid-run (AEROFLOCK_TEST_FAIL_RANK=2:10), with --vtk and --structure-from
     (observers whose calls are collective): every rank ends, no hang, a non-zero exit, the
     failing rank's message once and rank 0's summary saying so.
  5. SIGTERM mid-run (with --vtk), to mpiexec and to the ranks: the .pvd lists exactly the .pvtp
     files there, each with all its pieces; sent to the ranks, every rank stops on the same frame
     and rank 0 writes the summary (`interrupted`, SIGTERM) and the trajectories (sent to mpiexec,
     OpenMPI kills the ranks a second later, maybe before that).
  6. --vtk on 3 ranks: each frame a .pvtp of 3 pieces listed in the
     .pvd at one process's times, every bird once with the same values in every array as one
     process writes, a `rank` array, the same trajectories (read with python3-vtk9; skipped
     without it).
  7. --png and --structure-from on 3 ranks: the same PNG byte for byte and the
     same structure figures as one process's.
Exits 0 when all hold, 1 with what did not.
"""
import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

MPIEXEC, AEROFLOCK, WORK = sys.argv[1:4]
BACKEND = sys.argv[4] if len(sys.argv) > 4 else "cpu"
os.makedirs(WORK, exist_ok=True)
failures = []
UNEQUAL = {"device", "wall_seconds", "bird_steps_per_second", "ranks"}


def run(ranks, args, env=None, timeout=120):
    command = ([MPIEXEC, "-n", str(ranks)] if ranks else []) + [AEROFLOCK] + args
    return subprocess.run(command, capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, **(env or {})})


def check(ok, what):
    if not ok:
        failures.append(what)


# 1. The same summary on any number of ranks, on either backend.
base = ["run", "default", "--backend", "cpu", "--seconds", "3", "--threads", "1"]
for backend in (BACKEND,):
    command = ["run", "default", "--backend", backend, "--seconds", "3", "--threads", "1"]
    alone = os.path.join(WORK, f"alone-{backend}.json")
    r = run(0, command + ["--summary", alone])
    check(r.returncode == 0, f"{backend}, one process: exit {r.returncode}: {r.stderr}")
    one = json.load(open(alone))
    check(one["ranks"] is None, f"{backend}, one process: ranks should be null")
    for n in (2, 3, 4):
        path = os.path.join(WORK, f"ranks{n}-{backend}.json")
        r = run(n, command + ["--summary", path])
        check(r.returncode == 0, f"{backend}, {n} ranks: exit {r.returncode}: {r.stderr}")
        check(r.stdout.count("scenario ") == 1,
              f"{backend}, {n} ranks: the summary printed more than once")
        many = json.load(open(path))
        for key in one:
            if key not in UNEQUAL and one[key] != many[key]:
                failures.append(f"{backend}, {n} ranks: {key} differs: {many[key]} against "
                                f"{one[key]}")
        shares = many["ranks"] or []
        check(len(shares) == n, f"{backend}, {n} ranks: {len(shares)} entries in ranks")
        check(sum(s["birds"] for s in shares) == one["birds"],
              f"{backend}, {n} ranks: birds do not sum up")
        check(sum(s["ghosts_sent"] for s in shares) > 0, f"{backend}, {n} ranks: no ghost sent")
        check(f"on {n} MPI ranks" in many["device"],
              f"{backend}, {n} ranks: device says {many['device']}")
        check(many["backend"] == backend, f"{n} ranks: backend {many['backend']}")

# 1b. Flocks that meet each other's wakes (issue 43): `ibis-v`'s formation over 3 ranks, the same
# summary and formation figures as on one process.
command = ["run", "ibis-v", "--backend", BACKEND, "--seconds", "10", "--threads", "1",
           "--structure-from", "5"]
summaries = []
for n in (0, 3):
    path = os.path.join(WORK, f"ibis-v-{n}-{BACKEND}.json")
    r = run(n, command + ["--summary", path])
    check(r.returncode == 0, f"ibis-v, {n or 1} ranks: exit {r.returncode}: {r.stderr}")
    summaries.append(json.load(open(path)) if r.returncode == 0 else {})
# The formation's wings' power is summed over every frame's forces, which the ranks do not gather:
# null over many ranks (docs/MODEL.md "Its figures in a run"), and left out of the comparison.
POWER = ("head_power", "follower_power", "in_v_power")
if all(summaries):
    one, many = summaries
    for summary, ranks in ((one, 1), (many, 3)):
        for f in summary.get("structure") or []:
            power = [(f.get("formation") or {}).pop(k, None) for k in POWER]
            if f.get("formation"):
                check(all(p is not None for p in power) if ranks == 1 else
                      all(p is None for p in power),
                      f"ibis-v, {ranks} ranks: the formation's power {power}")
    for key in one:
        if key not in UNEQUAL and one[key] != many[key]:
            failures.append(f"ibis-v, 3 ranks: {key} differs: {many[key]} against {one[key]}")
    check(any(f.get("formation") for f in one.get("structure") or []),
          "ibis-v: no formation figures in the summary")
    check(sum(s["ghosts_sent"] for s in many["ranks"] or []) > 0, "ibis-v, 3 ranks: no ghost sent")

if BACKEND == "cpu":
    # 2, 3. Refusals and a scenario error, said once.
    for args, said in ((["envelope", "--quick"], "envelope runs on one process"),
                       (base + ["--structure-from", "5", "--structure-to", "2"],
                        "--structure-to must not be before"),
                       (["run", "no-such-scenario", "--backend", "cpu"], 'unknown scenario "no-such')):
        r = run(3, args)
        check(r.returncode != 0, f"{args}: exit 0")
        check(r.stderr.count(said) == 1, f"{args}: '{said}' said {r.stderr.count(said)} times")

    # 4. One rank fails: all end, its message once, rank 0's summary says another rank stopped.
    failed = os.path.join(WORK, "failed.json")
    subprocess.run(["rm", "-rf", os.path.join(WORK, "failed_vtk")])
    try:
        # With the observers whose calls are collective (the VTK pieces, the gathered structure).
        r = run(3, base + ["--summary", failed, "--vtk", os.path.join(WORK, "failed_vtk"),
                           "--structure-from", "0.1"],
                env={"AEROFLOCK_TEST_FAIL_RANK": "2:10"}, timeout=60)
        check(r.returncode != 0, "a failing rank: exit 0")
        check(r.stderr.count("error (rank 2 of 3): AEROFLOCK_TEST_FAIL_RANK") == 1,
              f"a failing rank: its message not once: {r.stderr}")
        s = json.load(open(failed))
        check("another rank" in (s["error"] or ""), f"a failing rank: summary error {s['error']}")
        check(abs(s["sim_seconds"] - 0.3) < 1e-9, f"a failing rank: stopped at {s['sim_seconds']} s")
    except subprocess.TimeoutExpired:
        failures.append("a failing rank: the run hung")

    # 5. SIGTERM mid-run (with --vtk), to mpiexec and to the ranks themselves.

    def stop_mid_run(name, to_ranks):
        """Runs migration-flock on 3 ranks, SIGTERM once the run is under way (its first frames
        listed), and checks what it leaves: the .pvd lists exactly the .pvtp files there, each with all
        its pieces, and the summary, where there is one, says SIGTERM. Returns whether the summary
        was written."""
        stopped, vtk_dir = os.path.join(WORK, name + ".json"), os.path.join(WORK, name)
        subprocess.run(["rm", "-rf", stopped, vtk_dir])
        p = subprocess.Popen([MPIEXEC, "-n", "3", AEROFLOCK, "run", "migration-flock", "--backend",
                              "cpu", "--birds", "500", "--summary", stopped, "--vtk", vtk_dir],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # Not while the ranks start: a signal before a rank has its handler ends it at once.
        for _ in range(600):
            if os.path.exists(os.path.join(vtk_dir, "flock.pvd")) or p.poll() is not None:
                break
            time.sleep(0.1)
        time.sleep(0.5)
        if to_ranks:
            ranks = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True)
            for pid in ranks.stdout.split():
                os.kill(int(pid), signal.SIGTERM)
        else:
            p.send_signal(signal.SIGTERM)
        try:
            p.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            p.kill()
            failures.append(f"SIGTERM ({name}): the run hung")
            return False
        check(p.returncode != 0, f"SIGTERM ({name}): exit 0")
        listed = [d.get("file") for d in ET.parse(os.path.join(vtk_dir, "flock.pvd")).iter("DataSet")]
        frames = sorted(f for f in os.listdir(os.path.join(vtk_dir, "frames")) if f.endswith(".pvtp"))
        check(listed == ["frames/" + f for f in frames] and len(frames) > 1,
              f"SIGTERM ({name}): the .pvd lists {len(listed)} frames, {len(frames)} .pvtp there")
        for f in frames:
            for piece in ET.parse(os.path.join(vtk_dir, "frames", f)).iter("Piece"):
                check(os.path.exists(os.path.join(vtk_dir, "frames", piece.get("Source"))),
                      f"SIGTERM ({name}): {f} lists a piece that is not there")
        if not os.path.exists(stopped):
            return False
        s = json.load(open(stopped))
        check(s["interrupted"] and s["signal"] == "SIGTERM", f"SIGTERM ({name}): summary {s['signal']}")
        check(s["sim_seconds"] < 500, f"SIGTERM ({name}): the run was not stopped")
        check(os.path.exists(os.path.join(vtk_dir, "trajectories.vtp")),
              f"SIGTERM ({name}): no trajectories")
        return True


    # mpiexec hands the signal on and kills the ranks a second later (OpenMPI's
    # odls_base_sigkill_timeout): the summary may not be written yet on a loaded machine.
    stop_mid_run("stopped_mpiexec", False)
    # Sent to the ranks themselves, every rank stops on the same frame and the files are finished.
    check(stop_mid_run("stopped_ranks", True), "SIGTERM to the ranks: no summary")

# 6. The VTK export over 3 ranks against one process's: every frame a .pvtp of one piece a rank,
#    listed in the .pvd with the same times; every bird once a frame with the same values in every
#    array (a `rank` array besides); the trajectories the same polylines.
try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPPolyDataReader
    from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: F401 (numpy may be missing)
    have_vtk = True
except ImportError:
    try:
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPPolyDataReader
        have_vtk = True
    except ImportError:
        have_vtk = False
if have_vtk:
    def read(path, parallel=False):
        reader = vtkXMLPPolyDataReader() if parallel else vtkXMLPolyDataReader()
        reader.SetFileName(path)
        reader.Update()
        return reader.GetOutput()

    def by_id(data):
        pd = data.GetPointData()
        ids = pd.GetArray("bird_id")
        rows = {}
        for i in range(data.GetNumberOfPoints()):
            values = [data.GetPoint(i)]
            for a in range(pd.GetNumberOfArrays()):
                array = pd.GetArray(a)
                if array.GetName() != "rank":
                    values.append((array.GetName(), array.GetTuple(i)))
            bird = int(ids.GetTuple1(i))
            if bird in rows:
                failures.append(f"vtk: bird {bird} twice in a frame")
            rows[bird] = values
        return rows

    def collection(path):
        return [(d.get("timestep"), d.get("file")) for d in ET.parse(path).iter("DataSet")]

    for backend in (BACKEND,):
        vtk = {}
        for n in (1, 3):
            out = os.path.join(WORK, f"vtk{n}-{backend}")
            subprocess.run(["rm", "-rf", out])
            r = run(n if n > 1 else 0, ["run", "default", "--backend", backend, "--seconds", "0.3",
                                        "--threads", "1", "--vtk", out])
            check(r.returncode == 0, f"vtk on {n} ({backend}): exit {r.returncode}: {r.stderr}")
            vtk[n] = out
        one = collection(os.path.join(vtk[1], "flock.pvd"))
        many = collection(os.path.join(vtk[3], "flock.pvd"))
        check([t for t, _ in one] == [t for t, _ in many], f"vtk ({backend}): the .pvd's times differ")
        check(all(f.endswith(".pvtp") for _, f in many),
              f"vtk ({backend}): the .pvd does not list .pvtp files")
        for (_, f1), (_, f3) in zip(one, many):
            pieces = [p.get("Source") for p in ET.parse(os.path.join(vtk[3], f3)).iter("Piece")]
            check(len(pieces) == 3, f"vtk ({backend}): {f3} has {len(pieces)} pieces")
            a, b = by_id(read(os.path.join(vtk[1], f1))), by_id(read(os.path.join(vtk[3], f3), True))
            check(a == b, f"vtk ({backend}): {f3} differs from {f1} ({len(a)} against {len(b)} birds)")
            ranks = read(os.path.join(vtk[3], f3), True).GetPointData().GetArray("rank")
            check(ranks is not None, f"vtk ({backend}): {f3} has no rank array")
        t1 = read(os.path.join(vtk[1], "trajectories.vtp"))
        t3 = read(os.path.join(vtk[3], "trajectories.vtp"))
        check(t1.GetNumberOfPoints() == t3.GetNumberOfPoints() and
              all(t1.GetPoint(i) == t3.GetPoint(i) for i in range(t1.GetNumberOfPoints())),
              f"vtk ({backend}): the trajectories differ")
else:
    print("vtk: not checked (no VTK Python modules)")

# 7. Pictures and the flock's structure over 3 ranks: drawn and measured on rank 0 from every
#    rank's birds, the same PNG byte for byte and the same structure figures as one process's.
for backend in (BACKEND,):
    pictures = {}
    for n in (1, 3):
        png = os.path.join(WORK, f"last{n}-{backend}.png")
        summary = os.path.join(WORK, f"structure{n}-{backend}.json")
        for f in (png, summary):
            if os.path.exists(f):
                os.remove(f)
        r = run(n if n > 1 else 0, ["run", "default", "--backend", backend, "--seconds", "2",
                                    "--threads", "1", "--png", png, "--structure-from", "1",
                                    "--summary", summary])
        check(r.returncode == 0, f"pictures on {n} ({backend}): exit {r.returncode}: {r.stderr}")
        pictures[n] = (open(png, "rb").read() if os.path.exists(png) else b"",
                       json.load(open(summary))["structure"] if os.path.exists(summary) else None)
    check(pictures[1][0] and pictures[1][0] == pictures[3][0], f"pictures ({backend}): the PNGs differ")
    check(pictures[1][1] and pictures[1][1] == pictures[3][1],
          f"pictures ({backend}): the structure differs")

for f in failures:
    print("FAIL:", f)
print("ok" if not failures else f"{len(failures)} failures")
sys.exit(1 if failures else 0)
