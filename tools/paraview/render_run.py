"""Renders an `aeroflock run --vtk DIR` export to PNG with ParaView (pvbatch or pvpython).

Loads RUN_DIR/flock.pvd (the birds over time) and RUN_DIR/trajectories.vtp (their paths), draws
the birds as points (or cones along their velocity) coloured by speed in m/s, by species or by
flight state, the trajectories behind them, frames the flock with the camera, adds a legend and
the time, and saves one PNG or one PNG per time step. render_run_vtk.py draws the same picture
with plain VTK (Debian's python3-vtk9) where ParaView's Python is not installed.

usage: pvbatch tools/paraview/render_run.py RUN_DIR (--png FILE | --frames-dir DIR)
           [--time T] [--every K] [--color speed|species|flight_state|rank] [--speed-range MIN,MAX]
           [--birds points|cones] [--point-size PX] [--bird-size CM]
           [--trajectories past|full|none] [--max-trajectories N] [--camera auto|all|flock]
           [--azimuth DEG] [--elevation DEG] [--size WxH] [--title TEXT]
       (or pvpython --force-offscreen-rendering tools/paraview/render_run.py ...)

  RUN_DIR              the export: RUN_DIR/flock.pvd, RUN_DIR/frames/*.vtp, RUN_DIR/trajectories.vtp
  --png FILE           render one time step (the last, or the one nearest --time T) to FILE
  --frames-dir DIR     render every saved time step (every K-th with --every K) to
                       DIR/frame_NNNNNN.png (turn them into a video with e.g.
                       ffmpeg -framerate 30 -i DIR/frame_%06d.png -pix_fmt yuv420p flock.mp4)
  --color              speed (m/s, default), species, flight_state or rank (the MPI rank that
                       owned each bird, in an export of a run over many ranks); species and
                       flight-state names come from the frames' field data (species_names,
                       flight_state_names) when present, else "species N" and the documented
                       state names
  --speed-range        colour-scale range in m/s (default: the run's range, from trajectories.vtp)
  --birds              points (spheres of --point-size pixels, default) or cones (3D glyphs
                       --bird-size cm long, pointing along the velocity)
  --trajectories       past (each bird's path up to the shown time, default), full or none
  --max-trajectories N draw the paths of at most N birds (every k-th; default 100, 0: all)
  --camera             all (the whole run: trajectories and birds), flock (the birds at the shown
                       time) or auto (default: flock when the run is over ten times as big as
                       the flock, taken as at least 30 m across, e.g. a long migration)
  --azimuth/--elevation  view direction in degrees (defaults 35 and 25; azimuth 0 looks north,
                       from +z towards -z; world y is up)

Which ParaView: any 5.10 or later whose Python works (`pvbatch` can `from paraview.simple import *`):
ParaView's own binaries from paraview.org (kitware tarball: bin/pvbatch), or Debian's `paraview`
together with its Python modules. On Debian 12 those are in python3-paraview, which conflicts with
python3-vtk9 (and so with libvtk9-dev, which aeroflock's build needs); Debian's pvbatch without
them stops with "ModuleNotFoundError: No module named 'paraview'". See docs/ANALYSIS.md ("ParaView's
Python next to python3-vtk9") for the way round that (the modules unpacked into a directory of their own).

Debian's ParaView draws through X (GLX). With no DISPLAY the script re-runs itself under
`xvfb-run -a` (package xvfb) when ParaView cannot render headless (EGL or OSMesa builds can).
Examples:
  build/release/aeroflock run default --seconds 10 --vtk out/vtk --vtk-every 5
  pvbatch tools/paraview/render_run.py out/vtk --png out/flock.png
  pvbatch tools/paraview/render_run.py out/vtk --color species --birds cones --png out/species.png
  pvbatch tools/paraview/render_run.py out/vtk --frames-dir out/frames --camera flock
Exit status: 0 done, 1 bad input, 2 bad options or no way to render (no ParaView Python; no
display and no xvfb-run).
"""
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_files import (XVFB_GUARD, check_outputs, check_written,  # noqa: E402
                       choose_camera_mode, fail, frame_camera, parse_args, plan_run,
                       read_collection, run_under_xvfb, sample_points, string_field)

try:
    from paraview import simple as pv
    from vtkmodules.vtkCommonCore import vtkIdList
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPPolyDataReader
except ImportError as e:
    print(f"render_run.py: cannot import ParaView's Python ({e}). Run it with pvbatch or pvpython "
          "from a ParaView that has its Python modules (paraview.org binaries, or Debian's "
          "paraview with python3-paraview or its modules on PYTHONPATH; see the README, Analysis), or use "
          "render_run_vtk.py with /usr/bin/python3 (python3-vtk9).", file=sys.stderr)
    sys.exit(2)

BACKGROUND = (0.10, 0.11, 0.14)
TRAJECTORY_COLOR = (0.62, 0.64, 0.70)
TEXT_COLOR = (0.92, 0.92, 0.92)
# Category colours that read well on the dark background (species, flight states).
PALETTE = [(1.00, 0.60, 0.10), (0.35, 0.75, 1.00), (0.45, 0.85, 0.35), (0.95, 0.35, 0.40),
           (0.75, 0.55, 0.95), (0.95, 0.90, 0.40), (0.95, 0.55, 0.80), (0.60, 0.95, 0.90)]
# flight_state codes as docs/VTK.md documents them, for files without flight_state_names.


# ----------------------------------------------------------------------------- input

def read_polydata(path):
    """The file read here, with ParaView's VTK, for what the pipeline set-up needs to know."""
    if not os.path.isfile(path):
        fail(f"{path}: no such file")
    # A run over many MPI ranks saves each frame as a .pvtp of one piece a rank.
    reader = vtkXMLPPolyDataReader() if path.endswith(".pvtp") else vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        fail(f"{path}: cannot read it")
    data = vtkPolyData()
    data.ShallowCopy(reader.GetOutput())
    return data


# ----------------------------------------------------------------------------- camera


def trajectory_cells(lines, most):
    """The polylines drawn: every k-th, at most `most` of them (all when most <= 0)."""
    if most <= 0 or lines <= most:
        return range(lines)
    return range(0, lines, -(-lines // most))


def some_trajectories(trajectories, most):
    """The polylines of trajectory_cells() as a polydata of their own (for the camera)."""
    cells = vtkCellArray()
    ids = vtkIdList()
    for cell in trajectory_cells(trajectories.GetNumberOfCells(), most):
        trajectories.GetCellPoints(cell, ids)
        cells.InsertNextCell(ids)
    subset = vtkPolyData()
    subset.SetPoints(trajectories.GetPoints())
    subset.SetLines(cells)
    return subset


# ----------------------------------------------------------------------------- display


def ensure_display():
    """Re-runs this script under xvfb-run when ParaView needs X and there is no DISPLAY."""
    if os.environ.get("DISPLAY"):
        return
    try:
        from paraview.modules.vtkRemotingViews import vtkPVRenderingCapabilitiesInformation as caps
        if caps.GetLocalCapabilities() & caps.HEADLESS_RENDERING:
            return  # an EGL or OSMesa build (e.g. paraview.org's headless pvbatch)
    except (ImportError, AttributeError):
        pass  # cannot tell: go on and hope
    if os.environ.get(XVFB_GUARD):
        print("render_run.py: no X display even under xvfb-run", file=sys.stderr)
        sys.exit(2)
    xvfb = shutil.which("xvfb-run")
    if not xvfb:
        print("render_run.py: this ParaView renders through X and there is no DISPLAY nor "
              "xvfb-run; install xvfb (apt-get install xvfb), run on a desktop, or use a "
              "headless (EGL/OSMesa) ParaView", file=sys.stderr)
        sys.exit(2)
    # Re-run the very command line (pvbatch or pvpython, its options, this script, its options).
    try:
        with open("/proc/self/cmdline", "rb") as f:
            command = [a.decode() for a in f.read().split(b"\0") if a]
        command[0] = os.readlink("/proc/self/exe")
    except OSError:
        print("render_run.py: no DISPLAY; run it under xvfb-run -a", file=sys.stderr)
        sys.exit(2)
    # Not exec: pvbatch has started an OpenMPI helper (orted) as its child, and xvfb-run, given
    # that child, would stop waiting for Xvfb when it ends and start the command too early.
    run_under_xvfb(xvfb, command, "render_run.py")


# ----------------------------------------------------------------------------- scene
def set_if(proxy, name, value):
    """Sets a property that only some ParaView versions have."""
    if name in proxy.ListProperties():
        setattr(proxy, name, value)


class Scene:
    def __init__(self, args, pvd, traj_path, trajectories, categories, speed_range):
        self.args = args
        view = pv.CreateView("RenderView")
        self.view = view
        view.ViewSize = [args.width, args.height]
        set_if(view, "UseColorPaletteForBackground", 0)
        set_if(view, "BackgroundColorMode", "Single Color")
        view.Background = list(BACKGROUND)
        view.OrientationAxesVisibility = 0
        set_if(view, "UseFXAA", 1)
        pv.SetActiveView(view)

        # Trajectories: at most --max-trajectories of them, clipped to the shown time ("past").
        self.clip = None
        if trajectories is not None and args.trajectories != "none":
            paths = pv.XMLPolyDataReader(registrationName="trajectories", FileName=[traj_path])
            lines = trajectories.GetNumberOfCells()
            if 0 < args.max_trajectories < lines:
                ids = []
                for cell in trajectory_cells(lines, args.max_trajectories):
                    ids += [0, cell]  # (process, cell id) pairs
                selection = pv.IDSelectionSource(IDs=ids, FieldType="CELL")
                paths = pv.ExtractSelection(Input=paths, Selection=selection)
            if args.trajectories == "past":
                self.clip = pv.Clip(Input=paths)
                self.clip.ClipType = "Scalar"
                self.clip.Scalars = ["POINTS", "time"]
                self.clip.Invert = 1  # keep time <= value
                paths = self.clip
            display = pv.Show(paths, view)
            display.SetRepresentationType("Surface")
            display.ColorArrayName = ["POINTS", ""]
            display.AmbientColor = list(TRAJECTORY_COLOR)
            display.DiffuseColor = list(TRAJECTORY_COLOR)
            display.Opacity = 0.45
            display.LineWidth = 1.0

        # Birds: speed in m/s (the files hold cm/s).
        self.flock = pv.PVDReader(registrationName="flock", FileName=pvd)
        birds = pv.Calculator(registrationName="speed_m_s", Input=self.flock)
        birds.AttributeType = "Point Data"
        birds.ResultArrayName = "speed_m_s"
        birds.Function = "speed/100"
        self.glyph = None
        if args.birds == "cones":
            self.glyph = pv.Glyph(Input=birds, GlyphType="Cone")
            self.glyph.GlyphType.Radius = 0.22
            self.glyph.GlyphType.Height = 1.0
            self.glyph.GlyphType.Resolution = 12
            self.glyph.OrientationArray = ["POINTS", "velocity"]
            self.glyph.ScaleArray = ["POINTS", "No scale array"]
            self.glyph.GlyphMode = "All Points"
            birds = self.glyph
        display = pv.Show(birds, view)
        if args.birds == "points":
            display.SetRepresentationType("Points")
            display.PointSize = args.point_size or max(3.0, round(args.height / 140.0 * args.enlarge))
            display.RenderPointsAsSpheres = 1
        else:
            display.SetRepresentationType("Surface")
            display.Ambient = 0.35
            display.Diffuse = 0.75
        array = "speed_m_s" if args.color == "speed" else args.color
        pv.ColorBy(display, ("POINTS", array))
        lut = pv.GetColorTransferFunction(array)
        if args.color == "speed":
            lut.ApplyPreset("Cool to Warm", True)
            set_if(lut, "AutomaticRescaleRangeMode", "Never")
            lut.RescaleTransferFunction(*speed_range)
            title = "speed (m/s)"
        else:
            lut.InterpretValuesAsCategories = 1
            set_if(lut, "AnnotationsInitialized", 1)
            lut.Annotations = sum(([str(i), name] for i, name in enumerate(categories)), [])
            lut.IndexedColors = sum((list(PALETTE[i % len(PALETTE)]) for i in range(len(categories))), [])
            title = {"species": "species", "rank": "MPI rank"}.get(args.color, "flight state")
        display.SetScalarBarVisibility(view, True)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = title
        bar.ComponentTitle = ""
        bar.WindowLocation = "Any Location"
        bar.Orientation = "Vertical"
        bar.Position = [0.89, 0.10]
        bar.ScalarBarLength = 0.55 if args.color == "speed" else min(0.55, 0.1 * len(categories) + 0.06)
        bar.TitleColor = list(TEXT_COLOR)
        bar.LabelColor = list(TEXT_COLOR)
        bar.TitleFontSize = max(12, args.height // 45)
        bar.LabelFontSize = max(11, args.height // 50)
        bar.TitleBold = 1
        if args.color == "speed":
            bar.AutomaticLabelFormat = 0
            bar.LabelFormat = "%-#6.1f"
            bar.RangeLabelFormat = "%-#6.1f"

        self.text = pv.Text(registrationName="caption")
        text_display = pv.Show(self.text, view)
        text_display.WindowLocation = "Upper Left Corner"
        text_display.Color = list(TEXT_COLOR)
        text_display.FontSize = max(14, args.height // 36)
        # paraview.simple resets the camera on the first Render(): have it now, not over ours.
        pv.Render(view)

    def show(self, time, camera, bird_size, caption):
        if self.glyph is not None:
            self.glyph.ScaleFactor = bird_size
        if self.clip is not None:
            self.clip.Value = time + 1e-6
        self.text.Text = caption
        self.view.ViewTime = time
        focal, position, up, angle = camera
        self.view.CameraFocalPoint = list(focal)
        self.view.CameraPosition = list(position)
        self.view.CameraViewUp = list(up)
        self.view.CameraViewAngle = angle
        self.view.CameraParallelProjection = 0
        pv.Render(self.view)

    def save(self, path):
        pv.SaveScreenshot(path, self.view, ImageResolution=[self.args.width, self.args.height])
        check_written(path)


# ----------------------------------------------------------------------------- main


def main(args):
    check_outputs(args)
    pvd = os.path.join(args.run_dir, "flock.pvd")
    plan = plan_run(args, read_polydata)
    steps, traj_path, trajectories = plan.steps, plan.traj_path, plan.trajectories
    png_index, animation, shown, ends = plan.png_index, plan.animation, plan.shown, plan.ends
    categories, speed_range = plan.categories, plan.speed_range

    # The whole run for the camera: the paths drawn (all of them when none are), the last frame.
    ends_points = [sample_points([f]) for f in ends]
    if trajectories is not None and trajectories.GetNumberOfPoints():
        drawn = trajectories
        if args.trajectories != "none":
            drawn = some_trajectories(trajectories, args.max_trajectories)
        run_points = ends_points[1] + sample_points([drawn])
    else:
        run_points = ends_points[0] + ends_points[1]
    camera_mode = choose_camera_mode(args.camera, ends_points, run_points)
    aspect = args.width / args.height
    fixed_camera = frame_camera(run_points, args.azimuth, args.elevation, aspect)

    # A few birds are drawn bigger, up to 3 times for one, so that they can be seen.
    args.enlarge = min(3.0, max(1.0, (100.0 / max(ends[1].GetNumberOfPoints(), 1)) ** (1.0 / 3.0)))
    scenario = string_field(ends[-1], "scenario")
    title = args.title or (scenario[0] if scenario else os.path.basename(os.path.normpath(args.run_dir)))
    scene = Scene(args, pvd, traj_path, trajectories, categories, speed_range)
    for index in shown:
        time, path = steps[index]
        frame = ends[0] if index == 0 else ends[1] if index == len(steps) - 1 else None
        if camera_mode == "flock" and frame is None:
            frame = read_polydata(path)
        if camera_mode == "flock":
            camera = frame_camera(sample_points([frame]), args.azimuth, args.elevation, aspect)
        else:
            camera = fixed_camera
        # Cones: about 2 % of the picture's height at the focal point (more for a few birds),
        # at least 30 cm.
        bird_size = args.bird_size or max(30.0, 0.011 * args.enlarge * math.dist(camera[0], camera[1]))
        count = frame.GetNumberOfPoints() if frame is not None else ends[1].GetNumberOfPoints()
        caption = f"{title}   t = {time:.2f} s   {count} bird{'' if count == 1 else 's'}"
        scene.show(time, camera, bird_size, caption)
        if args.frames_dir and index in animation:
            scene.save(os.path.join(args.frames_dir, f"frame_{index // args.every:06d}.png"))
        if args.png and index == png_index:
            scene.save(args.png)
    if args.png:
        print(f"wrote {args.png} (t = {steps[png_index][0]:.2f} s, colour {args.color}, camera {camera_mode})")
    if args.frames_dir:
        print(f"wrote {len(animation)} frames to {args.frames_dir}/frame_NNNNNN.png (camera {camera_mode})")
    # Delete the view while its window is still there: ParaView 5.11 (Debian) otherwise crashes
    # on exit (SIGSEGV in XGetErrorText, releasing the scalar bar's graphics) after the work is done.
    pv.Delete(scene.view)
    return 0


if __name__ == "__main__":
    arguments = parse_args(sys.argv[1:], "render_run.py", __doc__)  # --help and bad options without starting X
    read_collection(arguments.run_dir)
    ensure_display()
    sys.exit(main(arguments))
