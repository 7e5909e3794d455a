"""What tests/check_structure.py and tests/check_formation.py share: a run's VTK export read back
at the snapshots of its summary's `structure` (each the first frame at or after `from` + k
`every`), and the little vector algebra they recompute the figures with. Importing it exits 77
(skipped) when VTK's Python modules cannot be imported.
"""
import os
import sys
import xml.etree.ElementTree as ET

try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as e:
    print(f"SKIPPED: cannot import VTK's Python modules (vtkmodules): {e}")
    sys.exit(77)


def exported_frames(vtk_dir):
    """(time, path) of every exported frame, in order of time."""
    collection = ET.parse(os.path.join(vtk_dir, "flock.pvd")).getroot().find("Collection")
    return sorted((float(d.get("timestep")), os.path.join(vtk_dir, d.get("file")))
                  for d in collection.findall("DataSet"))


def frames_between(vtk_dir, start, end):
    """(time, path) of the exported frames from `start` to `end` s (a frame on either, within
    1e-9 s, counts), in order of time."""
    return [(t, f) for t, f in exported_frames(vtk_dir) if start - 1e-9 <= t <= end + 1e-9]


def snapshots(vtk_dir, structure):
    """The frame files of the summary's snapshots, in order; raises LookupError for one missing."""
    frames = exported_frames(vtk_dir)
    paths = []
    for k in range(structure["samples"]):
        t = structure["from"] + k * structure["every"]
        path = next((f for time, f in frames if time >= t - 1e-9), None)
        if path is None:
            raise LookupError(f"no exported frame at or after {t} s, the summary's snapshot {k}")
        paths.append(path)
    return paths


def read(path, arrays):
    """The birds' positions and the named point-data arrays (each a list of tuples) of a frame."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    n = data.GetNumberOfPoints()
    points = [data.GetPoints().GetPoint(i) for i in range(n)]
    return points, {name: [data.GetPointData().GetArray(name).GetTuple(i) for i in range(n)]
                    for name in arrays}


def sub(a, b):
    return [a[k] - b[k] for k in range(3)]


def dot(a, b):
    return sum(a[k] * b[k] for k in range(3))
