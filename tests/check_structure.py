#!/usr/bin/python3
"""Recomputes a run's flock-structure figures (docs/FIELD.md) from its VTK export, independently of
aeroflock's code: every pair of birds for the nearest neighbours, the covariance's eigenvalues from
the characteristic cubic, in plain Python. Checks them against the summary's `structure` (one
flocking flock, every bird of it exported and flying).

usage: python3 tests/check_structure.py VTK_DIR SUMMARY.json

The snapshots are the summary's `samples`, each the first frame at or after `from` + k `every`.
Exits 0 when every figure agrees (r1, the ellipsoid's sizes and ratios, the thinnest axis from
vertical, the motion on the axes, the nearest neighbours along the motion, the border's share and
its r1 over the interior's, gamma(n)), 1 with the differences otherwise, and 77 (skipped) when
VTK's Python modules cannot be imported. A mean is over the snapshots that measured the figure
(a NaN, null in the summary, is left out), as aeroflock's.
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


# The border's ball, in the snapshot's median r1 (flock_structure.h kBorderBallNearest), and the
# neighbours gamma(n) is measured for (kStructureRanks).
BORDER_BALL_NEAREST = 3.0
RANKS = 10


def clear(u, caps):
    """Whether the ball of radius R centred at p + R u holds none of the neighbours: u . n <= h
    for every cap (n the unit offset to a neighbour, h its distance over 2R)."""
    return all(dot(u, n) <= h + 1e-9 for n, h in caps)


def some_clear(caps):
    """Whether any direction u leaves the ball at p + R u clear. The clear set's boundary is made
    of the caps' circles: if it is not empty, it holds a point where two circles cross, or a whole
    circle that no other crosses (any point of it)."""
    for a, (na, ha) in enumerate(caps):
        side = cross(na, [1.0, 0.0, 0.0] if abs(na[0]) < 0.6 else [0.0, 1.0, 0.0])
        side = unit(side)
        s = math.sqrt(max(0.0, 1.0 - ha * ha))
        if clear([ha * na[k] + s * side[k] for k in range(3)], caps):
            return True
        for nb, hb in caps[a + 1:]:
            g = dot(na, nb)
            axis = cross(na, nb)
            axis2 = dot(axis, axis)
            if axis2 < 1e-12:
                continue
            # u = ca na + cb nb + t axis, with u . na = ha, u . nb = hb and |u| = 1.
            ca, cb = (ha - g * hb) / (1 - g * g), (hb - g * ha) / (1 - g * g)
            base = [ca * na[k] + cb * nb[k] for k in range(3)]
            rest = 1.0 - dot(base, base)
            if rest < 0.0:
                continue
            t = math.sqrt(rest / axis2)
            if any(clear([base[k] + sign * t * axis[k] for k in range(3)], caps)
                   for sign in (1.0, -1.0)):
                return True
    return not caps


def on_border(positions, i, radius):
    """Whether some ball of `radius` through bird i holds no other bird (2008a's alpha shape)."""
    near = []
    for j, q in enumerate(positions):
        d = sub(q, positions[i])
        r = math.sqrt(dot(d, d))
        if j != i and 0.0 < r < 2.0 * radius:
            near.append((r, [x / r for x in d]))
    near.sort(key=lambda t: t[0])
    # Fewer caps leave at least as much clear: the nearest 16, 32, ... first.
    take = min(16, len(near))
    while True:
        if not some_clear([(n, r / (2.0 * radius)) for r, n in near[:take]]):
            return False
        if take == len(near):
            return True
        take = min(2 * take, len(near))


def figures(positions, velocities):
    n = len(positions)
    centre = [sum(p[k] for p in positions) / n for k in range(3)]
    motion = unit([sum(v[k] for v in velocities) for k in range(3)])
    cov = [[sum((p[i] - centre[i]) * (p[j] - centre[j]) for p in positions) / n for j in range(3)]
           for i in range(3)]
    values, axes = eigen(cov)
    size = [2 * math.sqrt(5 * max(v, 0.0)) for v in values]
    # Every bird's neighbours, nearest first (ties by index), from every pair.
    neighbours = []
    for i, p in enumerate(positions):
        others = sorted((math.dist(o, p), j) for j, o in enumerate(positions) if j != i)
        neighbours.append([(r, j, sub(positions[j], p)) for r, j in others[:RANKS]])
    r1 = [near[0][0] for near in neighbours]
    along = sum(dot(unit(near[0][2]), motion) ** 2 for near in neighbours if near[0][0] > 0) / n
    ball = BORDER_BALL_NEAREST * median(r1)
    border = [on_border(positions, i, ball) for i in range(n)]
    on, off = [r for r, b in zip(r1, border) if b], [r for r, b in zip(r1, border) if not b]
    # An internal bird is nearer its n-th neighbour than the nearest border bird (2008b).
    edge = [p for p, b in zip(positions, border) if b]
    from_border = [min((math.dist(q, p) for q in edge), default=math.inf) for p in positions]
    anisotropy = []
    for rank in range(RANKS):
        m, counted = [[0.0] * 3 for _ in range(3)], 0
        for i, near in enumerate(neighbours):
            if rank >= len(near):
                break  # fewer birds than ranks: not measured
            r, _, d = near[rank]
            if r == 0.0 or r >= from_border[i]:
                continue
            u = [x / r for x in d]
            for a in range(3):
                for b in range(3):
                    m[a][b] += u[a] * u[b]
            counted += 1
        if counted == 0:
            anisotropy.append(math.nan)
            continue
        _, vectors = eigen([[x / counted for x in row] for row in m])
        anisotropy.append(dot(vectors[0], motion) ** 2)
    return {
        "median_nearest": median(r1),
        "thickness": size[0], "width": size[1], "length": size[2],
        "thickness_over_length": size[0] / size[2], "width_over_length": size[1] / size[2],
        "thinnest_from_vertical": math.degrees(math.acos(min(1.0, abs(axes[0][1])))),
        "motion_on_axes": [abs(dot(motion, a)) for a in axes],
        "nearest_along_motion": along,
        "border_fraction": len(on) / n,
        "border_over_interior_nearest": median(on) / median(off) if on and off else math.nan,
        "anisotropy": anisotropy,
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
    # Each figure's values, a list per snapshot.
    values = {}
    for path in paths:
        for key, value in figures(*frame(path)).items():
            values.setdefault(key, []).append(value if isinstance(value, list) else [value])
    errors = []
    for key, per_snapshot in values.items():
        mine = []
        for column in zip(*per_snapshot):
            measured = [x for x in column if not math.isnan(x)]
            mine.append(sum(measured) / len(measured) if measured else math.nan)
        theirs = s[key] if not isinstance(s[key], dict) else [s[key]["thickness"],
                                                              s[key]["width"], s[key]["length"]]
        theirs = [math.nan if x is None else x
                  for x in (theirs if isinstance(theirs, list) else [theirs])]
        if len(mine) != len(theirs):
            errors.append(f"{key}: python {len(mine)} values, aeroflock {len(theirs)}")
        for a, b in zip(mine, theirs):
            # Velocities are exported as floats, positions as doubles.
            if math.isnan(a) != math.isnan(b) or abs(a - b) > 1e-5 * max(1.0, abs(a)):
                errors.append(f"{key}: python {a:.9g}, aeroflock {b:.9g}")
        print(f"{key}: python {mine}, aeroflock {theirs}")
    print(f"{len(paths)} snapshots of {vtk_dir}")
    for e in errors:
        print("FAILED:", e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
