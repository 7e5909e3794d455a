#!/usr/bin/python3
"""`aeroflock run` under mpiexec against the same run on one process (engine/dist, issue 42).

usage: python3 tests/check_ranks.py MPIEXEC AEROFLOCK WORKDIR

With the environment OpenMPI needs as root and oversubscribed (tests/CMakeLists.txt sets it):
  1. `default` for 3 s on the CPU, alone and on 2, 3 and 4 ranks: every figure of the summaries
     equal (the flock is the same bird for bird) but the device, the times and `ranks`; `ranks`
     has one entry per rank, their birds sum to the flock, ghosts were sent.
  2. what is not built over ranks (--backend vulkan, --vtk) is refused: exit 2, said once.
  3. an unknown scenario: exit 2, said once.
  4. one rank failing mid-run (AEROFLOCK_TEST_FAIL_RANK=2:10): every rank ends, no hang, a
     non-zero exit, the failing rank's message once and rank 0's summary saying so.
  5. SIGTERM to mpiexec mid-run: every rank stops on the same frame and rank 0 writes the
     summary, `interrupted` true and `signal` SIGTERM.
Exits 0 when all hold, 1 with what did not.
"""
import json
import os
import signal
import subprocess
import sys
import time

MPIEXEC, AEROFLOCK, WORK = sys.argv[1:4]
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


# 1. The same summary on any number of ranks.
base = ["run", "default", "--backend", "cpu", "--seconds", "3", "--threads", "1"]
alone = os.path.join(WORK, "alone.json")
r = run(0, base + ["--summary", alone])
check(r.returncode == 0, f"one process: exit {r.returncode}: {r.stderr}")
one = json.load(open(alone))
check(one["ranks"] is None, "one process: ranks should be null")
for n in (2, 3, 4):
    path = os.path.join(WORK, f"ranks{n}.json")
    r = run(n, base + ["--summary", path])
    check(r.returncode == 0, f"{n} ranks: exit {r.returncode}: {r.stderr}")
    check(r.stdout.count("scenario ") == 1, f"{n} ranks: the summary printed more than once")
    many = json.load(open(path))
    for key in one:
        if key not in UNEQUAL and one[key] != many[key]:
            failures.append(f"{n} ranks: {key} differs: {many[key]} against {one[key]}")
    shares = many["ranks"] or []
    check(len(shares) == n, f"{n} ranks: {len(shares)} entries in ranks")
    check(sum(s["birds"] for s in shares) == one["birds"], f"{n} ranks: birds do not sum up")
    check(sum(s["ghosts_sent"] for s in shares) > 0, f"{n} ranks: no ghost sent")
    check(f"on {n} MPI ranks" in many["device"], f"{n} ranks: device says {many['device']}")

# 2, 3. Refusals and a scenario error, said once.
for args, said in ((["run", "default"], "--backend vulkan does not run over many ranks yet"),
                   (base + ["--vtk", os.path.join(WORK, "vtk")], "--vtk does not run over many"),
                   (["run", "no-such-scenario", "--backend", "cpu"], 'unknown scenario "no-such')):
    r = run(3, args)
    check(r.returncode != 0, f"{args}: exit 0")
    check(r.stderr.count(said) == 1, f"{args}: '{said}' said {r.stderr.count(said)} times")
check(not os.path.exists(os.path.join(WORK, "vtk")), "a refused --vtk made its directory")

# 4. One rank fails: all end, its message once, rank 0's summary says another rank stopped.
failed = os.path.join(WORK, "failed.json")
try:
    r = run(3, base + ["--summary", failed], env={"AEROFLOCK_TEST_FAIL_RANK": "2:10"}, timeout=60)
    check(r.returncode != 0, "a failing rank: exit 0")
    check(r.stderr.count("error (rank 2 of 3): AEROFLOCK_TEST_FAIL_RANK") == 1,
          f"a failing rank: its message not once: {r.stderr}")
    s = json.load(open(failed))
    check("another rank" in (s["error"] or ""), f"a failing rank: summary error {s['error']}")
    check(abs(s["sim_seconds"] - 0.3) < 1e-9, f"a failing rank: stopped at {s['sim_seconds']} s")
except subprocess.TimeoutExpired:
    failures.append("a failing rank: the run hung")

# 5. SIGTERM to mpiexec: every rank stops together, the summary is written.
stopped = os.path.join(WORK, "stopped.json")
if os.path.exists(stopped):
    os.remove(stopped)
p = subprocess.Popen([MPIEXEC, "-n", "3", AEROFLOCK, "run", "migration-flock", "--backend", "cpu",
                      "--summary", stopped], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
time.sleep(3)
p.send_signal(signal.SIGTERM)
try:
    out, err = p.communicate(timeout=60)
    check(p.returncode != 0, "SIGTERM: exit 0")
    s = json.load(open(stopped))
    check(s["interrupted"] and s["signal"] == "SIGTERM", f"SIGTERM: summary {s['signal']}")
    check(s["sim_seconds"] < 500, "SIGTERM: the run was not stopped")
except subprocess.TimeoutExpired:
    p.kill()
    failures.append("SIGTERM: the run hung")
except (OSError, ValueError) as e:
    failures.append(f"SIGTERM: no summary: {e}")

for f in failures:
    print("FAIL:", f)
print("ok" if not failures else f"{len(failures)} failures")
sys.exit(1 if failures else 0)
