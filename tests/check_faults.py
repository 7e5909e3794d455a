#!/usr/bin/python3
"""Faults during `aeroflock run`, and the files they leave, read back with Python's VTK (issue 16).

usage: python3 tests/check_faults.py AEROFLOCK WORKDIR MODE [options]

  full-disk          --vtk into small tmpfs mounts (11 sizes, in a user and mount namespace of
                     unshare -rm; where none can be mounted, or with --injected, directories that
                     --fake-disk-lib LIB, tests/fake_full_disk.cpp, fills at those sizes): exit 2, "aeroflock: error: cannot write PATH: No space left on
                     device", the .pvd listing exactly the frame files there, the trajectories
                     valid, no temporary, the summary written with the error where it fits.
                     Then, at each size, the pictures (--png, --frames-dir, --video) and, where
                     the disk is too small for them, the bench's --json and --plot: the same error,
                     every file there whole (PNGs and the video read back), no temporary.
  full-disk-calls    --fake-disk-lib LIB: each write, fsync, close and rename that a run with
                     every output (and a bench with --json and --plot) makes under its directory
                     failed in turn with ENOSPC: exit 2, the error naming the file whose call
                     failed with "No space left on device", the files there whole, no temporary.
  signal             --signal INT|TERM --backend cpu|vulkan [--video]: the signal mid-run; exit
                     128 + its number, every output complete (.pvd, trajectories, video, summary).
  kill               --backend cpu|vulkan: SIGKILL mid-run; the files there are complete, a re-run
                     into the directory is refused, and with --overwrite works and clears the
                     killed run's temporaries (and nothing else).
  rerun              an earlier export's directory: refused without --overwrite (nothing touched),
                     cleared of the earlier export's files only with it.
  summary-tmp        --summary X.json beside someone's X.json.tmp: that file survives a failing
                     and a succeeding run.

Exits 0 when all is well, 1 with the reasons otherwise, 77 (skipped) when VTK's Python modules
cannot be imported or (full-disk) no tmpfs can be mounted and no --fake-disk-lib is given.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

errors = []


def check(condition, message):
    if not condition:
        errors.append(message)
    return condition


def vtk_check():
    """tests/check_vtk.py's check_export, or exit 77 without VTK."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import check_vtk  # exits 77 when vtkmodules is missing
    return check_vtk


def run(args, **kw):
    return subprocess.run(args, capture_output=True, text=True, timeout=600, **kw)


def fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def frames_listed(pvd):
    try:
        with open(pvd) as f:
            return len(re.findall(r"<DataSet ", f.read()))
    except OSError:
        return 0


def start_long_run(aeroflock, out, backend, extra=()):
    """A run that would take hours, exporting every 2nd frame of 300 birds; returns once its
    .pvd lists three frames (the writer busy, frames in flight)."""
    proc = subprocess.Popen(
        [aeroflock, "run", "default", "--backend", backend, "--birds", "300", "--seconds", "100000",
         "--vtk", os.path.join(out, "vtk"), "--vtk-every", "2", "--summary", os.path.join(out, "s.json"),
         *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 300
    while frames_listed(os.path.join(out, "vtk", "flock.pvd")) < 3 and proc.poll() is None and time.time() < deadline:
        time.sleep(0.05)
    return proc


def text_of(path):
    """The file's text, or None when it is not there."""
    try:
        with open(path) as f:
            return f.read()
    except OSError:
        return None


def remove(path):
    if os.path.exists(path):
        os.remove(path)


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        check(False, f"{path}: {e}")
        return {}


def report(cv_errors, what):
    for e in cv_errors:
        errors.append(f"{what}: {e}")


NO_SPACE = ": No space left on device"


def first_line(text):
    return text.splitlines()[0] if text else ""


def temporaries(root):
    return [f for _, _, fs in os.walk(root) for f in fs if f.endswith(".tmp")]


def png_whole(path):
    """A PNG's signature and its last chunk, IEND: a file written whole."""
    with open(path, "rb") as f:
        data = f.read()
    return data.startswith(b"\x89PNG\r\n\x1a\n") and data.endswith(b"IEND\xaeB`\x82")


def check_outputs_whole(root, what):
    """Every PNG, video and JSON under `root` reads back whole; no temporary is left."""
    check(not temporaries(root), f"{what}: temporaries left: {temporaries(root)}")
    for d, _, files in os.walk(root):
        for f in files:
            path = os.path.join(d, f)
            if f.endswith(".png"):
                check(png_whole(path), f"{what}: {path} is not a whole PNG")
            elif f.endswith(".mp4") and shutil.which("ffprobe"):
                p = run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                         "stream=nb_read_frames", "-of", "csv=p=0", path])
                check(p.returncode == 0 and p.stdout.strip().isdigit(), f"{what}: {path}: ffprobe {p.stderr!r}")
            elif f.endswith(".json"):
                read_json(path)


def pictures_run(opt, root, env):
    """A run that draws into `root`: --png, --frames-dir, --video (where ffmpeg is), --summary."""
    args = [opt.aeroflock, "run", "fig21-moving-target", "--backend", "cpu", "--birds", "20",
            "--seconds", "2", "--size", "160x96", "--msaa", "1",
            "--png", os.path.join(root, "last.png"), "--frames-dir", os.path.join(root, "frames"),
            "--summary", os.path.join(root, "s.json")]
    if shutil.which("ffmpeg"):
        args += ["--video", os.path.join(root, "run.mp4")]
    return run(args, env=env)


def bench_run(opt, root, env):
    return run([opt.aeroflock, "bench", "--quick", "--backend", "cpu", "--max-birds", "100", "--repetitions", "1",
                "--json", os.path.join(root, "bench.json"), "--plot", os.path.join(root, "bench.png")], env=env)


def check_no_space(r, root, what):
    """Exit 2 and a first line saying that a file (or directory) under `root` had no space."""
    first = first_line(r.stderr)
    check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2\n{r.stderr}")
    check(first.startswith("aeroflock: error: ") and first.endswith(NO_SPACE) and root in first,
          f"{what}: stderr {r.stderr!r}")
    return first


def full_disk(opt):
    tmpfs = not opt.injected
    if tmpfs and os.geteuid() != 0 and not opt.in_namespace:
        # Root in a namespace of our own: mount may then make a tmpfs.
        if shutil.which("unshare") and run(["unshare", "-rm", "true"]).returncode == 0:
            os.execvp("unshare", ["unshare", "-rm", sys.executable, os.path.abspath(__file__), *sys.argv[1:], "--in-namespace"])
        tmpfs = False
    cv = vtk_check()
    # The export needs about 1.3 MB (67 frames of 100 birds, ~20 kB each): every size fills up, at
    # a different file (the first frame, a later one, the .pvd, the trajectories).
    sizes_kib = [4, 8, 16, 24, 32, 48, 64, 96, 128, 200, 400]
    for i, kib in enumerate(sizes_kib):
        mount = fresh(os.path.join(opt.workdir, f"disk{kib}k"))
        env = None
        if tmpfs:
            m = run(["mount", "-t", "tmpfs", "-o", f"size={kib}k", "tmpfs", mount])
            if m.returncode != 0:
                print(f"cannot mount a tmpfs: {m.stderr.strip()}")
                tmpfs = False
        if not tmpfs:
            if not opt.fake_disk_lib:
                print("SKIPPED: no tmpfs can be mounted, and no --fake-disk-lib")
                sys.exit(77)
            env = dict(os.environ, LD_PRELOAD=opt.fake_disk_lib, AEROFLOCK_FAKE_DISK=f"{mount}:{kib * 1024}",
                       ASAN_OPTIONS="verify_asan_link_order=0:" + os.environ.get("ASAN_OPTIONS", ""))
        try:
            vtk = os.path.join(mount, "vtk")
            # The summary beside the export (on the full disk) every other size, else elsewhere.
            summary = os.path.join(mount if i % 2 else opt.workdir, f"s{kib}k.json")
            r = run([opt.aeroflock, "run", "fig21-moving-target", "--backend", "cpu", "--birds", "100",
                     "--seconds", "2", "--vtk", vtk, "--summary", summary], env=env)
            what = f"{kib} KiB" + ("" if env is None else " (injected)")
            check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2\n{r.stderr}")
            first = r.stderr.splitlines()[0] if r.stderr else ""
            check(re.fullmatch(rf"aeroflock: error: (cannot write {re.escape(mount)}/\S+|VTK export directory \S+: "
                               r"cannot write there): No space left on device", first),
                  f"{what}: stderr {r.stderr!r}")
            if os.path.isdir(vtk) and os.path.exists(os.path.join(vtk, "flock.pvd")):
                cv_errors, times, _ = cv.check_export(vtk, birds=100, min_frames=0, trajectories_prefix=True)
                report(cv_errors, what)
                print(f"{what}: {len(times)} frames listed, {first}")
            else:
                # Only when the disk could not take even the checks before the run.
                check("cannot write there" in first, f"{what}: no flock.pvd after the run")
                print(f"{what}: refused before the run: {first}")
            leftovers = temporaries(mount)
            check(not leftovers, f"{what}: temporaries left: {leftovers}")
            if os.path.exists(summary):
                s = read_json(summary)
                check("No space left on device" in (s.get("error") or ""), f"{what}: summary error {s.get('error')!r}")
            else:
                check(summary.startswith(mount) and f"cannot write {summary}" in r.stderr,
                      f"{what}: no summary, and no error about it: {r.stderr!r}")
            # The pictures, and (where the disk cannot take its plot) the bench, on the same disk.
            for name, command in [("pictures", pictures_run)] + ([("bench", bench_run)] if kib <= 16 else []):
                root = fresh(os.path.join(mount, name))
                r = command(opt, root, env)
                first = check_no_space(r, root, f"{what}, {name}")
                check_outputs_whole(root, f"{what}, {name}")
                print(f"{what}, {name}: {first}")
        finally:
            if env is None:
                run(["umount", mount])


def full_disk_calls(opt):
    """Each write, fsync, close and rename under the directory failed in turn (the injected disk)."""
    if not opt.fake_disk_lib:
        print("SKIPPED: full-disk-calls needs --fake-disk-lib")
        sys.exit(77)
    cv = vtk_check()
    counts_file = os.path.join(opt.workdir, "calls.txt")

    def export_run(root, env):
        return run([opt.aeroflock, "run", "fig21-moving-target", "--backend", "cpu", "--birds", "20",
                    "--seconds", "0.1", "--vtk", os.path.join(root, "vtk"), "--summary", os.path.join(root, "s.json"),
                    "--png", os.path.join(root, "last.png"), "--frames-dir", os.path.join(root, "frames"),
                    "--size", "64x48", "--msaa", "1"]
                   + (["--video", os.path.join(root, "run.mp4")] if shutil.which("ffmpeg") else []), env=env)

    def injected(root, fail=None):
        env = dict(os.environ, LD_PRELOAD=opt.fake_disk_lib, AEROFLOCK_FAKE_DISK=f"{root}:{1 << 40}",
                   AEROFLOCK_FAKE_DISK_COUNT=counts_file,
                   ASAN_OPTIONS="verify_asan_link_order=0:" + os.environ.get("ASAN_OPTIONS", ""))
        if fail:
            env["AEROFLOCK_FAKE_DISK_FAIL"] = fail
        return env

    def calls():
        counts, failed = {}, None
        for line in (text_of(counts_file) or "").splitlines():
            word, rest = line.split(" ", 1)
            if word == "failed":
                failed = rest.split(" ", 1)[1]
            else:
                counts[word] = int(rest)
        return counts, failed

    total = 0
    for name, command in [("run", export_run), ("bench", bench_run)]:
        root = fresh(os.path.join(opt.workdir, name))
        r = command(root, injected(root)) if name == "run" else command(opt, root, injected(root))
        check(r.returncode == 0, f"{name}: exit {r.returncode} without a failure\n{r.stderr}")
        counts, _ = calls()
        print(f"{name}: {counts}")
        for call in ["write", "fsync", "close", "rename"]:
            check(counts.get(call, 0) >= 1, f"{name}: no {call} call under {root}")
            for k in range(1, counts.get(call, 0) + 1):
                root = fresh(os.path.join(opt.workdir, name))
                env = injected(root, f"{call}:{k}")
                r = command(root, env) if name == "run" else command(opt, root, env)
                what = f"{name}, {call} {k} of {counts[call]}"
                first = check_no_space(r, root, what)
                _, failed = calls()
                # The error names the file whose call failed (its temporary: the file it becomes).
                output = re.sub(r"\.aeroflock-\d+-\d+\.tmp$", "", failed or "")
                check(failed and (f" {output}:" in first or first.startswith(f"aeroflock: error: cannot write {output}")
                                  or f"{os.path.dirname(output)}: cannot write there" in first),
                      f"{what}: the failed call was on {failed}, the error says {first!r}")
                check_outputs_whole(root, what)
                vtk = os.path.join(root, "vtk")
                if name == "run" and os.path.exists(os.path.join(vtk, "flock.pvd")):
                    cv_errors, _, _ = cv.check_export(vtk, birds=20, min_frames=0, trajectories_prefix=True)
                    report(cv_errors, what)
                total += 1
    print(f"{total} runs, each with one call failed: every one reported No space left on device")


def signal_run(opt):
    cv = vtk_check()
    out = fresh(os.path.join(opt.workdir, f"sig{opt.signal}-{opt.backend}"))
    video = os.path.join(out, "run.mp4")
    if opt.video and not (shutil.which("ffmpeg") and shutil.which("ffprobe")):
        print("no ffmpeg: the run without --video")
        opt.video = False
    extra = ["--video", video, "--size", "160x96", "--msaa", "1"] if opt.video else []
    proc = start_long_run(opt.aeroflock, out, opt.backend, extra)
    sig = {"INT": signal.SIGINT, "TERM": signal.SIGTERM}[opt.signal]
    if proc.poll() is None:
        proc.send_signal(sig)
        if opt.twice:  # the same stop delivered twice at once, as `timeout -s INT` does: one stop
            time.sleep(0.003)  # the first handled, the run not yet done (a second sent at once may merge)
            proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=300)
    check(proc.returncode == 128 + sig, f"exit {proc.returncode}, expected {128 + sig}\n{stdout}\n{stderr}")
    check(re.search(rf"interrupted +at t = [0-9.]+ s \(SIG{opt.signal}", stdout), f"stdout: {stdout}")
    s = read_json(os.path.join(out, "s.json"))
    check(s.get("interrupted") is True and s.get("signal") == f"SIG{opt.signal}" and s.get("error") is None,
          f"summary: interrupted {s.get('interrupted')}, signal {s.get('signal')}, error {s.get('error')}")
    cv_errors, times, _ = cv.check_export(os.path.join(out, "vtk"), birds=300, min_frames=3)
    report(cv_errors, "export")
    q = s.get("vtk_queue") or {}
    check(q.get("bound_frames") == 4 and 1 <= q.get("high_water_frames", 0) <= 4 and q.get("high_water_bytes", 0) > 0,
          f"summary: vtk_queue {q}")
    # The files end at the last frame due for export (every 2nd, 0.03 s each) up to the stop.
    stop = s.get("sim_seconds", -1)
    check(times and stop - 0.06 - 1e-9 < times[-1] <= stop + 1e-9, f"last frame {times[-1:]} s, stopped at {stop} s")
    if opt.video:
        check(os.path.isfile(video), f"{video}: not written")
        p = run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                 "stream=nb_read_frames", "-of", "csv=p=0", video])
        check(p.returncode == 0 and p.stdout.strip().isdigit() and int(p.stdout) >= 1,
              f"{video}: ffprobe: {p.returncode} {p.stdout!r} {p.stderr!r}")
    leftovers = [f for _, _, fs in os.walk(out) for f in fs if f.endswith(".tmp")]
    check(not leftovers, f"temporaries left: {leftovers}")
    print(f"SIG{opt.signal} on {opt.backend}: exit {proc.returncode}, {len(times)} frames to t = {times[-1:]} s")


def kill_run(opt):
    cv = vtk_check()
    out = fresh(os.path.join(opt.workdir, f"kill-{opt.backend}"))
    vtk = os.path.join(out, "vtk")
    proc = start_long_run(opt.aeroflock, out, opt.backend)
    proc.kill()
    proc.communicate(timeout=60)
    check(proc.returncode == -signal.SIGKILL, f"exit {proc.returncode}: the run ended before it was killed")
    # What is there is complete: every listed and unlisted frame, the .pvd, the trajectories.
    cv_errors, times, _ = cv.check_export(vtk, birds=300, min_frames=3, trajectories_prefix=True,
                                          unlisted_frames=1, temporaries=True)
    report(cv_errors, "after SIGKILL")
    killed_tmps = [f for _, _, fs in os.walk(out) for f in fs if f.endswith(".tmp")]
    # A stale temporary of the killed run's (certain, whatever the kill hit), others' files that
    # must stay: one named as aeroflock's but of a live process (this one), and plain .tmp files.
    stale = os.path.join(vtk, "frames", f"flock_000123.vtp.aeroflock-{proc.pid}-7.tmp")
    alive = os.path.join(vtk, "frames", f"flock_000123.vtp.aeroflock-{os.getpid()}-1.tmp")
    foreign = [os.path.join(vtk, "flock.pvd.tmp"), os.path.join(vtk, "frames", "notes.txt"),
               os.path.join(vtk, "frames", "flock_1.vtp"), os.path.join(out, "s.json.tmp")]
    for path in [stale, alive, *foreign]:
        with open(path, "w") as f:
            f.write("not aeroflock's\n" if path != stale else "half a frame")
    r = run([opt.aeroflock, "run", "fig21-moving-target", "--backend", opt.backend, "--birds", "8",
             "--seconds", "0.3", "--vtk", vtk])
    check(r.returncode == 2 and "holds an earlier run's export" in r.stderr and "--overwrite" in r.stderr,
          f"re-run without --overwrite: exit {r.returncode}, {r.stderr!r}")
    check(frames_listed(os.path.join(vtk, "flock.pvd")) == len(times), "the refused re-run changed flock.pvd")
    r = run([opt.aeroflock, "run", "fig21-moving-target", "--backend", opt.backend, "--birds", "8",
             "--seconds", "0.3", "--vtk", vtk, "--overwrite", "--summary", os.path.join(out, "s.json")])
    check(r.returncode == 0, f"re-run with --overwrite: exit {r.returncode}, {r.stderr!r}")
    for path in [alive, *foreign]:
        check(text_of(path) == "not aeroflock's\n", f"{path}: removed or changed, but it is not the killed run's")
        remove(path)
    check(not os.path.exists(stale), f"{stale}: the killed run's temporary is still there")
    cv_errors, _, _ = cv.check_export(vtk, birds=8, frames=11, last_time=0.3)
    report(cv_errors, "re-run")
    check(read_json(os.path.join(out, "s.json")).get("sim_seconds") == 0.3, "re-run: summary")
    print(f"SIGKILL on {opt.backend}: {len(times)} frames listed, temporaries left {killed_tmps}; re-run ok")


def rerun(opt):
    cv = vtk_check()
    out = fresh(os.path.join(opt.workdir, "rerun"))
    vtk = os.path.join(out, "vtk")
    base = [opt.aeroflock, "run", "fig21-moving-target", "--backend", "cpu", "--birds", "8", "--vtk", vtk]
    r = run(base + ["--seconds", "0.99"])
    check(r.returncode == 0, f"first run: exit {r.returncode} {r.stderr!r}")
    mine = {os.path.join(vtk, "notes.txt"): "mine\n", os.path.join(vtk, "frames", "flock_a.vtp"): "mine\n",
            os.path.join(vtk, "frames", "flock_000001.vtp.bak"): "mine\n", os.path.join(vtk, "flock.pvd.tmp"): "mine\n"}
    for path, text in mine.items():
        with open(path, "w") as f:
            f.write(text)
    before = {f: os.path.getmtime(os.path.join(vtk, "frames", f)) for f in os.listdir(os.path.join(vtk, "frames"))}
    r = run(base + ["--seconds", "0.12"])
    check(r.returncode == 2, f"re-run without --overwrite: exit {r.returncode}")
    check(re.search(r"aeroflock: error: VTK export directory \S+ holds an earlier run's export \(flock\.pvd, "
                    r"trajectories\.vtp, 34 frames\): --overwrite replaces it", r.stderr), f"stderr {r.stderr!r}")
    after = {f: os.path.getmtime(os.path.join(vtk, "frames", f)) for f in os.listdir(os.path.join(vtk, "frames"))}
    check(before == after, "the refused run changed frames/")
    r = run(base + ["--seconds", "0.12", "--overwrite"])
    check(r.returncode == 0, f"re-run with --overwrite: exit {r.returncode} {r.stderr!r}")
    for path, text in mine.items():
        check(text_of(path) == text, f"{path}: not aeroflock's, but changed or removed")
        remove(path)
    cv_errors, times, _ = cv.check_export(vtk, birds=8, frames=5, last_time=0.12)
    report(cv_errors, "after --overwrite")
    print(f"re-run: refused, then {len(times)} frames with --overwrite, others' files kept")


def summary_tmp(opt):
    out = fresh(os.path.join(opt.workdir, "summary-tmp"))
    summary = os.path.join(out, "x.json")
    theirs = summary + ".tmp"
    with open(theirs, "w") as f:
        f.write("someone else's\n")
    bad = os.path.join(out, "bad.toml")
    with open(bad, "w") as f:
        f.write("name = \"bad\"\ndt = -1\n")
    r = run([opt.aeroflock, "run", bad, "--summary", summary])
    check(r.returncode == 2, f"failing run: exit {r.returncode} {r.stderr!r}")
    check(text_of(theirs) == "someone else's\n", f"{theirs}: changed or removed by a failing run")
    r = run([opt.aeroflock, "run", "fig17-ground-effect", "--backend", "cpu", "--seconds", "0.1", "--summary", summary])
    check(r.returncode == 0, f"succeeding run: exit {r.returncode} {r.stderr!r}")
    check(text_of(theirs) == "someone else's\n", f"{theirs}: changed or removed by a succeeding run")
    check(read_json(summary).get("scenario") == "fig17-ground-effect", f"{summary}: not written")
    check(sorted(os.listdir(out)) == ["bad.toml", "x.json", "x.json.tmp"], f"{out}: {sorted(os.listdir(out))}")
    print("summary-tmp: someone's x.json.tmp kept by a failing and a succeeding run")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("aeroflock")
    parser.add_argument("workdir")
    parser.add_argument("mode", choices=["full-disk", "full-disk-calls", "signal", "kill", "rerun", "summary-tmp"])
    parser.add_argument("--signal", choices=["INT", "TERM"], default="TERM")
    parser.add_argument("--backend", choices=["cpu", "vulkan"], default="cpu")
    parser.add_argument("--video", action="store_true", help="signal: with --video (needs ffmpeg)")
    parser.add_argument("--twice", action="store_true", help="signal: sent again 3 ms after the first")
    parser.add_argument("--injected", action="store_true", help="full-disk: a disk filled by --fake-disk-lib, not a tmpfs")
    parser.add_argument("--fake-disk-lib", help="full-disk: tests/fake_full_disk.cpp built, for LD_PRELOAD")
    parser.add_argument("--in-namespace", action="store_true", help=argparse.SUPPRESS)
    opt = parser.parse_args()
    opt.aeroflock = os.path.abspath(opt.aeroflock)
    opt.workdir = os.path.realpath(opt.workdir)
    os.makedirs(opt.workdir, exist_ok=True)
    {"full-disk": full_disk, "full-disk-calls": full_disk_calls, "signal": signal_run, "kill": kill_run, "rerun": rerun,
     "summary-tmp": summary_tmp}[opt.mode](opt)
    if errors:
        print("\n".join(errors))
        return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
