#!/usr/bin/python3
"""Recomputes a run's flock-structure figures (docs/FIELD.md) from its VTK export, independently of
aeroflock's code: every pair of birds for the nearest neighbours, the covariance's eigenvalues from
the characteristic cubic, in plain Python. Checks them against the summary's `structure` (one
flocking flock, every bird of it exported and flying).

usage: python3 tests/check_structure.py VTK_DIR SUMMARY.json

The snapshots are the summary's `samples`, each the first frame at or after `from` + k `every`.
Exits 0 when every figure agrees (r1, the ellipsoid's sizes and ratios, the thinnest axis from
vertical, the motion on the axes, the nearest neighbours along the motion), 1 with the
differences otherwise, and 77 (skipped) when VTK's Python modules cannot be imported. The border
and gamma(n) are left to tests/test_flock_structure.cpp's brute force.
"""
import json
import math
import sys

from vtk_snapshots import dot, read, snapshots, sub


def frame(path):
    points, arrays = read(path, ["velocity"])
    return points, arrays["velocity"]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    n = math.sqrt(dot(a, a))
    return [x / n for x in a]


def median(values):
    v = sorted(values)
    m = len(v) // 2
    return v[m] if len(v) % 2 else 0.5 * (v[m - 1] + v[m])


def eigen(m):
    """Eigenvalues of a symmetric 3x3 matrix, smallest first, from its characteristic cubic, and
    each one's eigenvector from the cross products of (m - lambda I)'s rows."""
    q = (m[0][0] + m[1][1] + m[2][2]) / 3
    p1 = m[0][1] ** 2 + m[0][2] ** 2 + m[1][2] ** 2
    p = math.sqrt(((m[0][0] - q) ** 2 + (m[1][1] - q) ** 2 + (m[2][2] - q) ** 2 + 2 * p1) / 6)
    b = [[(m[i][j] - (q if i == j else 0)) / p for j in range(3)] for i in range(3)]
    det = dot(b[0], cross(b[1], b[2]))
    phi = math.acos(max(-1.0, min(1.0, det / 2))) / 3
    values = sorted(q + 2 * p * math.cos(phi + 2 * math.pi * k / 3) for k in range(3))
    vectors = []
    for lam in values:
        rows = [[m[i][j] - (lam if i == j else 0) for j in range(3)] for i in range(3)]
        best = max((cross(rows[i], rows[j]) for i, j in ((0, 1), (0, 2), (1, 2))),
                   key=lambda c: dot(c, c))
        vectors.append(unit(best))
    return values, vectors


def figures(positions, velocities):
    n = len(positions)
    centre = [sum(p[k] for p in positions) / n for k in range(3)]
    motion = unit([sum(v[k] for v in velocities) for k in range(3)])
    cov = [[sum((p[i] - centre[i]) * (p[j] - centre[j]) for p in positions) / n for j in range(3)]
           for i in range(3)]
    values, axes = eigen(cov)
    size = [2 * math.sqrt(5 * max(v, 0.0)) for v in values]
    r1, along = [], 0.0
    for i, p in enumerate(positions):
        best, to = math.inf, None
        for j, o in enumerate(positions):
            if j != i:
                d = sub(o, p)
                d2 = dot(d, d)
                if d2 < best:
                    best, to = d2, d
        r1.append(math.sqrt(best))
        along += dot(unit(to), motion) ** 2 / n
    return {
        "median_nearest": median(r1),
        "thickness": size[0], "width": size[1], "length": size[2],
        "thickness_over_length": size[0] / size[2], "width_over_length": size[1] / size[2],
        "thinnest_from_vertical": math.degrees(math.acos(min(1.0, abs(axes[0][1])))),
        "motion_on_axes": [abs(dot(motion, a)) for a in axes],
        "nearest_along_motion": along,
    }


def main():
    vtk_dir, summary_path = sys.argv[1], sys.argv[2]
    summary = json.load(open(summary_path))
    flocks = summary["structure"]
    if len(flocks) != 1:
        print(f"FAILED: expected one flocking flock in the summary, found {len(flocks)}")
        return 1
    s = flocks[0]
    try:
        paths = snapshots(vtk_dir, s)
    except LookupError as e:
        print(f"FAILED: {e}")
        return 1
    sums, count = {}, 0
    for path in paths:
        for key, value in figures(*frame(path)).items():
            if isinstance(value, list):
                sums[key] = [a + b for a, b in zip(sums.get(key, [0.0] * 3), value)]
            else:
                sums[key] = sums.get(key, 0.0) + value
        count += 1
    errors = []
    for key, total in sums.items():
        mine = [x / count for x in total] if isinstance(total, list) else [total / count]
        theirs = s[key] if not isinstance(s[key], dict) else [s[key]["thickness"],
                                                              s[key]["width"], s[key]["length"]]
        theirs = theirs if isinstance(theirs, list) else [theirs]
        for a, b in zip(mine, theirs):
            # Velocities are exported as floats, positions as doubles.
            if abs(a - b) > 1e-5 * max(1.0, abs(a)):
                errors.append(f"{key}: python {a:.9g}, aeroflock {b:.9g}")
        print(f"{key}: python {mine}, aeroflock {theirs}")
    print(f"{count} snapshots of {vtk_dir}")
    for e in errors:
        print("FAILED:", e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
