#!/usr/bin/python3
"""Renders a short `aeroflock run --vtk` export with tools/paraview/render_run.py (ParaView) or
tools/paraview/render_run_vtk.py (plain VTK) and checks that the pictures are not blank.

usage: /usr/bin/python3 tests/check_paraview_render.py (paraview|vtk) --aeroflock BIN --work DIR
           [--vtk-dir EXPORT] [--interpreter PROGRAM]

  paraview   runs render_run.py with $PVBATCH, else pvbatch, else pvpython from PATH
  vtk        runs render_run_vtk.py with /usr/bin/python3 (python3-vtk9), or --interpreter
  --aeroflock BIN   makes the export: BIN run default --seconds 1 --birds 200 --backend cpu
                    --vtk DIR/vtk (2 s); or give --vtk-dir EXPORT to use one already made
  --work DIR        where the export and the pictures go (made if missing)

Renders two pictures: DIR/<mode>_speed.png (birds as points coloured by speed) and
DIR/<mode>_species.png with three animation frames under DIR/<mode>_frames (cones coloured by
species), 640x360 each. Each must have the expected size, a uniform background and many pixels
that differ from it inside the drawing area (not only the legend and the caption), and the
species picture many strongly coloured ones. Without a display the scripts run themselves under
xvfb-run.

Exit status: 0 pass, 1 fail, 77 skipped (ctest SKIP_RETURN_CODE) with "SKIPPED: ..." when the
interpreter is missing (no pvbatch/pvpython, or one without ParaView's Python modules: Debian's
paraview without python3-paraview; no python3 with vtk), or there is no DISPLAY and no xvfb-run.
"""
import argparse
import collections
import os
import random
import shlex
import shutil
import signal
import struct
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPTS = {"paraview": os.path.join(ROOT, "tools", "paraview", "render_run.py"),
           "vtk": os.path.join(ROOT, "tools", "paraview", "render_run_vtk.py")}
WIDTH, HEIGHT = 640, 360
TIMEOUT = 120  # seconds a command may take


def skip(message):
    print(f"SKIPPED: {message}")
    sys.exit(77)


def run(command, timeout=TIMEOUT, env=None):
    """(status, output) of command; on timeout kills its whole process group (xvfb-run, Xvfb,
    pvbatch and its MPI helper) and returns status None."""
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True, env=env)
    try:
        output, _ = proc.communicate(timeout=timeout)
        return proc.returncode, output.decode(errors="replace")
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        output, _ = proc.communicate()
        return None, output.decode(errors="replace") + f"\n(killed after {timeout} s)"


def tail(text, lines=15):
    # Drop Loguru's stack-trace lines, keep the messages.
    kept = [l for l in text.splitlines() if not l.lstrip()[:1].isdigit() or "0x" not in l]
    return "\n".join(kept[-lines:])


# ----------------------------------------------------------------------------- interpreters
def paraview_interpreter():
    """$PVBATCH, else pvbatch, else pvpython; whether it has ParaView's Python shows in the first
    run (render_run.py exits 2 with "cannot import ParaView's Python")."""
    program = os.environ.get("PVBATCH") or shutil.which("pvbatch") or shutil.which("pvpython")
    if not program:
        skip("no pvbatch or pvpython on PATH (install ParaView; see the README, Analysis)")
    if os.path.basename(program).startswith("pvpython"):
        return [program, "--force-offscreen-rendering"]
    return [program]


def vtk_interpreter(program):
    if not program:
        program = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else shutil.which("python3")
    if not program:
        skip("no python3")
    status, output = run([program, "-c", "import vtkmodules.vtkIOXML, vtkmodules.vtkRenderingOpenGL2"],
                         timeout=60)
    if status != 0:
        skip(f"{program} cannot import vtk (install python3-vtk9): {tail(output, 1)}")
    return [program]


# ----------------------------------------------------------------------------- pictures
def read_png(path):
    """(width, height, rows of (r, g, b) tuples), with VTK when there is, else with zlib."""
    try:
        from vtkmodules.vtkIOImage import vtkPNGReader
    except ImportError:
        return read_png_zlib(path)
    reader = vtkPNGReader()
    if not reader.CanReadFile(path):
        raise ValueError("not a PNG file")
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    scalars = image.GetPointData().GetScalars()
    n = scalars.GetNumberOfComponents()
    values = [scalars.GetTuple(i) for i in range(w * h)]
    pixels = [tuple(int(v[c if n >= 3 else 0]) for c in range(3)) for v in values]
    # VTK's rows run bottom to top.
    return w, h, [pixels[(h - 1 - y) * w:(h - y) * w] for y in range(h)]


def read_png_zlib(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG file")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + length
    w, h, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        raise ValueError(f"unsupported PNG (depth {depth}, colour type {colour}, interlace {interlace})")
    raw, stride, rows, previous = zlib.decompress(idat), w * channels, [], bytearray(w * channels)
    for y in range(h):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = previous[i], previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        previous = line
        rows.append([tuple(line[x * channels + (k if channels >= 3 else 0)] for k in range(3))
                     for x in range(w)])
    return w, h, rows


def check_picture(path, want_saturated, errors):
    if not os.path.isfile(path):
        errors.append(f"{path}: not written")
        return
    try:
        w, h, rows = read_png(path)
    except (ValueError, OSError, zlib.error) as e:
        errors.append(f"{path}: cannot read it: {e}")
        return
    if (w, h) != (WIDTH, HEIGHT):
        errors.append(f"{path}: {w}x{h}, expected {WIDTH}x{HEIGHT}")
        return
    counts = collections.Counter(p for row in rows for p in row)
    background, share = counts.most_common(1)[0]
    # The drawing area: left of the legend, below the caption.
    drawn = saturated = 0
    for y in range(int(0.12 * h), h):
        for x in range(int(0.78 * w)):
            p = rows[y][x]
            if max(abs(p[k] - background[k]) for k in range(3)) > 24:
                drawn += 1
                if max(p) - min(p) > 90:
                    saturated += 1
    print(f"{path}: {w}x{h}, background {background} on {100.0 * share / (w * h):.1f} %, "
          f"{drawn} drawn pixels, {saturated} strongly coloured, {len(counts)} colours")
    if share < 0.5 * w * h:
        errors.append(f"{path}: no uniform background (the most common colour covers "
                      f"{100.0 * share / (w * h):.1f} %)")
    if drawn < 800:
        errors.append(f"{path}: only {drawn} pixels differ from the background in the drawing area")
    if share > 0.995 * w * h:
        errors.append(f"{path}: blank ({100.0 * share / (w * h):.2f} % background)")
    if want_saturated and saturated < 150:
        errors.append(f"{path}: only {saturated} strongly coloured pixels (birds by species)")


# ----------------------------------------------------------------------------- main
def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mode", choices=["paraview", "vtk"])
    parser.add_argument("--aeroflock")
    parser.add_argument("--vtk-dir")
    parser.add_argument("--work", required=True)
    parser.add_argument("--interpreter")
    args = parser.parse_args()
    if not args.aeroflock and not args.vtk_dir:
        parser.error("give --aeroflock BIN or --vtk-dir EXPORT")
    os.makedirs(args.work, exist_ok=True)
    started = time.monotonic()

    # Without a display, one Xvfb per picture from here (the scripts would start it themselves,
    # but pvbatch would then start twice). The display number is searched from a random start:
    # one just given back may still be held by the Xvfb going away.
    xvfb = None
    if not os.environ.get("DISPLAY"):
        xvfb = shutil.which("xvfb-run")
        if not xvfb:
            skip("no DISPLAY and no xvfb-run (apt-get install xvfb)")
    if args.mode == "paraview":
        interpreter = [args.interpreter] if args.interpreter else paraview_interpreter()
    else:
        interpreter = vtk_interpreter(args.interpreter)

    export = args.vtk_dir
    if not export:
        export = os.path.join(args.work, "vtk")
        shutil.rmtree(export, ignore_errors=True)
        command = [args.aeroflock, "run", "default", "--seconds", "1", "--birds", "200",
                   "--backend", "cpu", "--vtk", export]
        status, output = run(command)
        if status != 0:
            print(f"FAIL: {' '.join(command)} exited {status}:\n{tail(output)}")
            return 1

    prefix = os.path.join(args.work, args.mode)
    frames = prefix + "_frames"
    shutil.rmtree(frames, ignore_errors=True)
    jobs = [(prefix + "_speed.png", False, []),
            (prefix + "_species.png", True,
             ["--color", "species", "--birds", "cones", "--frames-dir", frames, "--every", "15"])]
    errors = []
    for png, saturated, options in jobs:
        if os.path.exists(png):
            os.remove(png)
        script = interpreter + [SCRIPTS[args.mode], export, "--png", png,
                                "--size", f"{WIDTH}x{HEIGHT}"] + options
        for attempt in (1, 2, 3):
            command = script
            if xvfb:
                command = [xvfb, "-n", str(random.randrange(100, 2000)), "-a", "-s",
                           "-screen 0 1280x1024x24"] + script
            began = time.monotonic()
            status, output = run(command)
            # Xvfb 21.1 (Debian 12) now and then hangs up on a client that connects just after
            # another one closed, which ParaView does: try again.
            if status != 0 and "bad X server connection" in output and attempt < 3:
                print(f"retrying after an X connection failure:\n{tail(output, 3)}")
                continue
            break
        print(f"$ {shlex.join(command)}\n  exit {status} in {time.monotonic() - began:.1f} s")
        if status == 2 and "cannot import ParaView's Python" in output:
            skip(f"{interpreter[0]} has no ParaView Python modules (Debian: paraview without "
                 f"python3-paraview; see the README, Analysis): {tail(output, 1)}")
        if status != 0:
            errors.append(f"{os.path.basename(SCRIPTS[args.mode])} exited {status}:\n{tail(output)}")
            continue
        check_picture(png, saturated, errors)
    written = sorted(os.listdir(frames)) if os.path.isdir(frames) else []
    steps = len(ET.parse(os.path.join(export, "flock.pvd")).getroot().findall("./Collection/DataSet"))
    expected = [f"frame_{i:06d}.png" for i in range(len(range(0, steps, 15)))]
    if not errors and written != expected:
        errors.append(f"{frames}: frames {written}, expected {expected}")

    print(f"total {time.monotonic() - started:.1f} s")
    if errors:
        print("FAIL:\n" + "\n".join(errors))
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
