#!/usr/bin/python3
"""Renders an `aeroflock run --vtk DIR` export to PNG with plain VTK (no ParaView needed).

The same picture as render_run.py (the pvpython/pvbatch script), for machines with Debian's
python3-vtk9 but without ParaView's Python: the birds as points (or cones along their velocity)
coloured by speed in m/s, by species or by flight state, the trajectories behind them, a camera
that frames the flock, a legend and the time.

usage: /usr/bin/python3 tools/paraview/render_run_vtk.py RUN_DIR (--png FILE | --frames-dir DIR)
           [--time T] [--every K] [--color speed|species|flight_state|rank] [--speed-range MIN,MAX]
           [--birds points|cones] [--point-size PX] [--bird-size CM]
           [--trajectories past|full|none] [--max-trajectories N] [--camera auto|all|flock]
           [--azimuth DEG] [--elevation DEG] [--size WxH] [--title TEXT]

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

Rendering is offscreen. Debian's VTK draws through X (GLX): with no DISPLAY the script re-runs
itself under `xvfb-run -a` (package xvfb) when that exists, and stops with a message otherwise.
Examples:
  build/release/aeroflock run default --seconds 10 --vtk out/vtk --vtk-every 5
  /usr/bin/python3 tools/paraview/render_run_vtk.py out/vtk --png out/flock.png
  /usr/bin/python3 tools/paraview/render_run_vtk.py out/vtk --color species --birds cones --png out/species.png
  /usr/bin/python3 tools/paraview/render_run_vtk.py out/vtk --frames-dir out/frames --camera flock
Exit status: 0 done, 1 bad input, 2 bad options or no way to render (no vtk module; no display
and no xvfb-run).
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
    import vtkmodules.vtkInteractionStyle  # noqa: F401  (registers the default interactor style)
    import vtkmodules.vtkRenderingFreeType  # noqa: F401  (text)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the OpenGL render window)
    from vtkmodules.vtkCommonCore import vtkIdList, vtkLookupTable
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkDataObject, vtkPolyData
    from vtkmodules.vtkFiltersCore import vtkArrayCalculator, vtkClipPolyData, vtkGlyph3D
    from vtkmodules.vtkFiltersSources import vtkConeSource
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPPolyDataReader
    from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
    from vtkmodules.vtkRenderingCore import (vtkActor, vtkColorTransferFunction, vtkPolyDataMapper,
                                             vtkRenderer, vtkRenderWindow, vtkTextActor,
                                             vtkWindowToImageFilter)
except ImportError as e:
    print(f"render_run_vtk.py: cannot import VTK ({e}); install python3-vtk9 and run with "
          f"/usr/bin/python3", file=sys.stderr)
    sys.exit(2)

BACKGROUND = (0.10, 0.11, 0.14)
TRAJECTORY_COLOR = (0.62, 0.64, 0.70)
TEXT_COLOR = (0.92, 0.92, 0.92)
# ParaView's default "Cool to Warm" map (diverging colour space), so both scripts look alike.
COOL_TO_WARM = [(0.0, 0.231373, 0.298039, 0.752941), (0.5, 0.865003, 0.865003, 0.865003),
                (1.0, 0.705882, 0.0156863, 0.14902)]
# Category colours that read well on the dark background (species, flight states).
PALETTE = [(1.00, 0.60, 0.10), (0.35, 0.75, 1.00), (0.45, 0.85, 0.35), (0.95, 0.35, 0.40),
           (0.75, 0.55, 0.95), (0.95, 0.90, 0.40), (0.95, 0.55, 0.80), (0.60, 0.95, 0.90)]
# flight_state codes as docs/VTK.md documents them, for files without flight_state_names.


# ----------------------------------------------------------------------------- input

def read_polydata(path):
    # A run over many MPI ranks saves each frame as a .pvtp of one piece a rank.
    reader = vtkXMLPPolyDataReader() if path.endswith(".pvtp") else vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0 or reader.GetOutput().GetNumberOfPoints() == 0 and \
            not os.path.isfile(path):
        fail(f"{path}: cannot read it")
    data = vtkPolyData()
    data.ShallowCopy(reader.GetOutput())
    return data


# ----------------------------------------------------------------------------- camera


def some_trajectories(trajectories, most):
    """At most `most` of the polylines (every k-th bird), so that the paths stay readable."""
    lines = trajectories.GetNumberOfCells()
    if most <= 0 or lines <= most:
        return trajectories
    stride = -(-lines // most)
    cells = vtkCellArray()
    ids = vtkIdList()
    for cell in range(0, lines, stride):
        trajectories.GetCellPoints(cell, ids)
        cells.InsertNextCell(ids)
    subset = vtkPolyData()
    subset.SetPoints(trajectories.GetPoints())
    subset.GetPointData().ShallowCopy(trajectories.GetPointData())
    subset.SetLines(cells)
    return subset


# ----------------------------------------------------------------------------- display


def ensure_display():
    """Re-runs this script under xvfb-run when VTK needs X and there is no DISPLAY."""
    if os.environ.get("DISPLAY"):
        return
    window = vtkRenderWindow()
    if "XOpenGL" not in window.GetClassName():  # EGL or OSMesa builds render headless
        return
    if os.environ.get(XVFB_GUARD):
        print("render_run_vtk.py: no X display even under xvfb-run", file=sys.stderr)
        sys.exit(2)
    xvfb = shutil.which("xvfb-run")
    if not xvfb:
        print("render_run_vtk.py: VTK renders through X here (vtkXOpenGLRenderWindow) and there "
              "is no DISPLAY nor xvfb-run; install xvfb (apt-get install xvfb) or run on a "
              "desktop", file=sys.stderr)
        sys.exit(2)
    run_under_xvfb(xvfb, [sys.executable, os.path.abspath(sys.argv[0])] + sys.argv[1:],
                   "render_run_vtk.py")


# ----------------------------------------------------------------------------- scene
class Scene:
    def __init__(self, args, trajectories, categories, speed_range):
        self.args = args
        self.renderer = vtkRenderer()
        self.renderer.SetBackground(*BACKGROUND)
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(args.width, args.height)
        self.window.SetMultiSamples(0)
        self.window.AddRenderer(self.renderer)
        self.renderer.SetUseFXAA(True)

        # Trajectories, clipped to the shown time with "past".
        self.clip = None
        if trajectories is not None and args.trajectories != "none":
            mapper = vtkPolyDataMapper()
            if args.trajectories == "past":
                self.clip = vtkClipPolyData()
                trajectories.GetPointData().SetActiveScalars("time")  # what vtkClipPolyData clips
                self.clip.SetInputData(trajectories)
                self.clip.InsideOutOn()  # keep time <= value
                mapper.SetInputConnection(self.clip.GetOutputPort())
            else:
                mapper.SetInputData(trajectories)
            mapper.ScalarVisibilityOff()
            actor = vtkActor()
            actor.SetMapper(mapper)
            actor.GetProperty().SetColor(*TRAJECTORY_COLOR)
            actor.GetProperty().SetOpacity(0.45)
            actor.GetProperty().SetLineWidth(1.0)
            self.renderer.AddActor(actor)

        # Birds: speed in m/s (the files hold cm/s) computed on the fly.
        self.calculator = vtkArrayCalculator()
        self.calculator.SetAttributeTypeToPointData()
        self.calculator.AddScalarArrayName("speed")
        self.calculator.SetFunction("speed/100")
        self.calculator.SetResultArrayName("speed_m_s")
        self.cone = None
        if args.birds == "cones":
            self.cone = vtkConeSource()
            self.cone.SetResolution(12)
            self.cone.SetRadius(0.22)
            self.cone.SetHeight(1.0)
            self.glyph = vtkGlyph3D()
            self.glyph.SetInputConnection(self.calculator.GetOutputPort())
            self.glyph.SetSourceConnection(self.cone.GetOutputPort())
            self.glyph.SetInputArrayToProcess(1, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "velocity")
            self.glyph.SetVectorModeToUseVector()
            self.glyph.SetScaleModeToDataScalingOff()
            self.glyph.OrientOn()
            self.glyph.SetColorModeToColorByScalar()
            self.glyph.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                              "speed_m_s" if args.color == "speed" else args.color)
            source = self.glyph
        else:
            source = self.calculator
        self.bird_mapper = vtkPolyDataMapper()
        self.bird_mapper.SetInputConnection(source.GetOutputPort())
        self.bird_mapper.SetScalarModeToUsePointFieldData()
        self.bird_mapper.ScalarVisibilityOn()
        bird_actor = vtkActor()
        bird_actor.SetMapper(self.bird_mapper)
        prop = bird_actor.GetProperty()
        if args.birds == "points":
            prop.SetPointSize(args.point_size or max(3.0, round(args.height / 140.0 * args.enlarge)))
            prop.SetRenderPointsAsSpheres(True)
        else:
            prop.SetAmbient(0.35)
            prop.SetDiffuse(0.75)

        bar = vtkScalarBarActor()
        if args.color == "speed":
            ctf = vtkColorTransferFunction()
            ctf.SetColorSpaceToDiverging()
            lo, hi = speed_range
            for x, r, g, b in COOL_TO_WARM:
                ctf.AddRGBPoint(lo + x * (hi - lo), r, g, b)
            lut = vtkLookupTable()
            lut.SetNumberOfTableValues(256)
            lut.SetRange(lo, hi)
            for i in range(256):
                rgb = ctf.GetColor(lo + (hi - lo) * i / 255.0)
                lut.SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0)
            self.bird_mapper.SelectColorArray("speed_m_s")
            self.bird_mapper.SetScalarRange(lo, hi)
            bar.SetTitle("speed (m/s)")
            bar.SetNumberOfLabels(5)
            bar.SetLabelFormat("%.1f")
        else:
            lut = vtkLookupTable()
            lut.SetNumberOfTableValues(len(categories))
            lut.IndexedLookupOn()
            for i, name in enumerate(categories):
                r, g, b = PALETTE[i % len(PALETTE)]
                lut.SetTableValue(i, r, g, b, 1.0)
                lut.SetAnnotation(i, name)
            self.bird_mapper.SelectColorArray(args.color)
            self.bird_mapper.SetScalarRange(0, max(1, len(categories) - 1))
            bar.SetTitle({"species": "species", "rank": "MPI rank"}.get(args.color, "flight state"))
            bar.SetDrawAnnotations(True)
        self.bird_mapper.SetLookupTable(lut)
        self.bird_mapper.UseLookupTableScalarRangeOn()
        self.renderer.AddActor(bird_actor)

        bar.SetLookupTable(lut)
        bar.SetOrientationToVertical()
        bar.SetPosition(0.89, 0.10)
        bar.SetWidth(0.09)
        bar.SetHeight(0.55 if args.color == "speed" else min(0.55, 0.1 * len(categories) + 0.06))
        bar.SetMaximumWidthInPixels(110)
        for text in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty(),
                     bar.GetAnnotationTextProperty()):
            text.SetColor(*TEXT_COLOR)
            text.SetFontSize(max(12, args.height // 45))
            text.ShadowOff()
            text.ItalicOff()
        bar.GetTitleTextProperty().BoldOn()
        bar.UnconstrainedFontSizeOn()
        self.renderer.AddViewProp(bar)

        self.text = vtkTextActor()
        self.text.GetTextProperty().SetColor(*TEXT_COLOR)
        self.text.GetTextProperty().SetFontSize(max(14, args.height // 36))
        self.text.SetPosition(14, args.height - 14 - 2 * max(14, args.height // 36))
        self.renderer.AddViewProp(self.text)

    def show(self, frame, time, camera, bird_size, caption):
        self.calculator.SetInputData(frame)
        if self.cone is not None:
            self.glyph.SetScaleFactor(bird_size)
        if self.clip is not None:
            self.clip.SetValue(time + 1e-6)
        self.text.SetInput(caption)
        cam = self.renderer.GetActiveCamera()
        focal, position, up, angle = camera
        cam.SetFocalPoint(*focal)
        cam.SetPosition(*position)
        cam.SetViewUp(*up)
        cam.SetViewAngle(angle)
        self.renderer.ResetCameraClippingRange()
        self.window.Render()

    def save(self, path):
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.SetInputBufferTypeToRGB()
        grab.ReadFrontBufferOff()
        grab.Update()
        writer = vtkPNGWriter()
        writer.SetFileName(path)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
        check_written(path)


# ----------------------------------------------------------------------------- main


def main(args):
    check_outputs(args)
    plan = plan_run(args, read_polydata)
    steps, trajectories = plan.steps, plan.trajectories
    png_index, animation, shown, ends = plan.png_index, plan.animation, plan.shown, plan.ends
    categories, speed_range = plan.categories, plan.speed_range

    # The whole run for the camera: the paths drawn (all of them when none are), the last frame.
    ends_points = [sample_points([f]) for f in ends]
    if trajectories is not None and args.trajectories != "none":
        trajectories = some_trajectories(trajectories, args.max_trajectories)
    if trajectories is not None and trajectories.GetNumberOfPoints():
        run_points = ends_points[1] + sample_points([trajectories])
    else:
        run_points = ends_points[0] + ends_points[1]
    camera_mode = choose_camera_mode(args.camera, ends_points, run_points)
    aspect = args.width / args.height
    fixed_camera = frame_camera(run_points, args.azimuth, args.elevation, aspect)

    # A few birds are drawn bigger, up to 3 times for one, so that they can be seen.
    args.enlarge = min(3.0, max(1.0, (100.0 / max(ends[1].GetNumberOfPoints(), 1)) ** (1.0 / 3.0)))
    scenario = string_field(ends[-1], "scenario")
    title = args.title or (scenario[0] if scenario else os.path.basename(os.path.normpath(args.run_dir)))
    scene = Scene(args, trajectories, categories, speed_range)
    for index in shown:
        time, path = steps[index]
        frame = ends[0] if index == 0 else ends[1] if index == len(steps) - 1 else read_polydata(path)
        if camera_mode == "flock":
            camera = frame_camera(sample_points([frame]), args.azimuth, args.elevation, aspect)
        else:
            camera = fixed_camera
        # Cones: about 2 % of the picture's height at the focal point (more for a few birds),
        # at least 30 cm.
        bird_size = args.bird_size or max(30.0, 0.011 * args.enlarge * math.dist(camera[0], camera[1]))
        count = frame.GetNumberOfPoints()
        caption = f"{title}   t = {time:.2f} s   {count} bird{'' if count == 1 else 's'}"
        scene.show(frame, time, camera, bird_size, caption)
        if args.frames_dir and index in animation:
            scene.save(os.path.join(args.frames_dir, f"frame_{index // args.every:06d}.png"))
        if args.png and index == png_index:
            scene.save(args.png)
    if args.png:
        print(f"wrote {args.png} (t = {steps[png_index][0]:.2f} s, colour {args.color}, camera {camera_mode})")
    if args.frames_dir:
        print(f"wrote {len(animation)} frames to {args.frames_dir}/frame_NNNNNN.png (camera {camera_mode})")
    return 0


if __name__ == "__main__":
    arguments = parse_args(sys.argv[1:], "render_run_vtk.py", __doc__)  # --help and bad options without starting X
    read_collection(arguments.run_dir)
    ensure_display()
    sys.exit(main(arguments))
