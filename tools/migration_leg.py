#!/usr/bin/python3
"""A migration leg from its VTK export: how whole the flock stays and how far off its line.

    /usr/bin/python3 tools/migration_leg.py SCENARIO.toml DIR [DIR ...] [--svg OUT.svg] [--csv OUT.csv]

For each export DIR (`aeroflock run ... --vtk DIR`), and for each of its frames, it measures:
- the largest cluster, with birds linked within 5 m (docs/MODEL.md "What a flock must show");
- the centroid's horizontal distance from the line it flies: from the flock's start to its first
  target, then from target to target, and on along the last leg past the last target;
- the median nearest-neighbour distance;
- when the centroid first passes within each target's radius.
The targets and the route come from the scenario file (metres, [units] length = "m"). The SVG
plots the cluster and the distance off the line against time, one line per DIR. It needs VTK's
Python module (Debian's python3-vtk9) and nothing else.
"""
import argparse
import glob
import math
import statistics
import sys
import tomllib
from collections import defaultdict

import vtk

LINK = 5.0  # m


def frame(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    d = r.GetOutput()
    t = d.GetFieldData().GetArray("TimeValue").GetValue(0)
    # Positions are in cm (docs/VTK.md).
    return t, [tuple(c / 100.0 for c in d.GetPoint(i)) for i in range(d.GetNumberOfPoints())]


def clusters_and_nearest(p):
    """The largest cluster's share and each bird's nearest neighbour within LINK (else inf)."""
    n = len(p)
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    cells = defaultdict(list)
    for i, q in enumerate(p):
        cells[tuple(math.floor(c / LINK) for c in q)].append(i)
    nearest = [math.inf] * n
    for c, members in cells.items():
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for j in cells.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        for i in members:
                            if i < j:
                                d = math.dist(p[i], p[j])
                                nearest[i] = min(nearest[i], d)
                                nearest[j] = min(nearest[j], d)
                                if d < LINK:
                                    a, b = find(i), find(j)
                                    if a != b:
                                        parent[a] = b
    sizes = defaultdict(int)
    for i in range(n):
        sizes[find(i)] += 1
    return max(sizes.values()) / n, nearest


def across(p, a, b, onward=False):
    """Horizontal (x-z) distance from p to the segment a-b (`onward`: to the line on past b)."""
    ax, az, bx, bz = a[0], a[2], b[0], b[2]
    px, pz = p[0] - ax, p[2] - az
    ex, ez = bx - ax, bz - az
    s = max(0.0, (px * ex + pz * ez) / (ex * ex + ez * ez))
    if not onward:
        s = min(1.0, s)
    return math.hypot(px - s * ex, pz - s * ez)


def leg(directory, targets):
    rows, reached = [], {}
    start = prev = None
    for path in sorted(glob.glob(directory + "/frames/flock_*.vtp")):
        t, p = frame(path)
        c = tuple(sum(q[k] for q in p) / len(p) for k in range(3))
        if start is None:
            start = c
        nxt = len(reached)
        if prev is not None and nxt < len(targets):
            # Between frames the centroid flies straight: its closest approach on that path.
            (t0, c0), (centre, radius) = prev, targets[nxt]
            e = [c[k] - c0[k] for k in range(3)]
            ee = sum(x * x for x in e) or 1.0
            s = max(0.0, min(1.0, sum((centre[k] - c0[k]) * e[k] for k in range(3)) / ee))
            if math.dist([c0[k] + s * e[k] for k in range(3)], centre) <= radius:
                reached[nxt] = t0 + s * (t - t0)
        prev = (t, c)
        k = min(len(reached), len(targets) - 1)
        a = start if k == 0 else targets[k - 1][0]
        largest, nearest = clusters_and_nearest(p)
        finite = [x for x in nearest if x != math.inf]
        # Past the last target the flock flies on along the last leg (docs/MODEL.md "Flocking").
        rows.append((t, largest, across(c, a, targets[k][0], len(reached) == len(targets)),
                     statistics.median(finite) if finite else math.nan, len(p)))
    return rows, reached


def svg(series, path):
    w, h, left, right, top, gap, ph = 900, 520, 70, 20, 20, 60, 200
    tmax = max(r[0] for rows in series.values() for r in rows) or 1.0
    off_max = max(10.0, max(r[2] for rows in series.values() for r in rows))
    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           '<rect width="100%" height="100%" fill="white"/>']

    def panel(y0, label, value, vmax, ticks):
        out.append(f'<rect x="{left}" y="{y0}" width="{w - left - right}" height="{ph}" fill="none" stroke="#888"/>')
        out.append(f'<text x="12" y="{y0 + ph / 2}" transform="rotate(-90 12 {y0 + ph / 2})" text-anchor="middle">{label}</text>')
        for v in ticks:
            y = y0 + ph - v / vmax * ph
            out.append(f'<line x1="{left}" x2="{w - right}" y1="{y:.1f}" y2="{y:.1f}" stroke="#eee"/>')
            out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{v:g}</text>')
        for n, (name, rows) in enumerate(series.items()):
            pts = " ".join(f"{left + r[0] / tmax * (w - left - right):.1f},{y0 + ph - value(r) / vmax * ph:.1f}" for r in rows)
            out.append(f'<polyline fill="none" stroke="{colours[n % 4]}" stroke-width="1.5" points="{pts}"/>')

    panel(top, "largest cluster", lambda r: r[1], 1.0, [0.0, 0.25, 0.5, 0.75, 0.95])
    step = 25 if off_max <= 150 else 50 if off_max <= 300 else 100
    panel(top + ph + gap, "off the line (m)", lambda r: r[2], off_max,
          [v for v in range(0, int(off_max) + 1, step)])
    y = top + 2 * ph + gap
    for s in range(0, int(tmax) + 1, 1000):
        x = left + s / tmax * (w - left - right)
        out.append(f'<text x="{x:.1f}" y="{y + 16}" text-anchor="middle">{s}</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{y + 34}" text-anchor="middle">simulated time (s)</text>')
    for n, name in enumerate(series):
        out.append(f'<text x="{left + 10}" y="{top + ph + 20 + 16 * n}" fill="{colours[n % 4]}">{name}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario")
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--svg")
    ap.add_argument("--csv")
    a = ap.parse_args()
    with open(a.scenario, "rb") as f:
        sc = tomllib.load(f)
    if sc.get("units", {}).get("length") != "m":
        sys.exit(f"{a.scenario}: expected [units] length = \"m\"")
    by_name = {t["name"]: (tuple(t["centre"]), t.get("radius", 2.0)) for t in sc.get("targets", [])}
    route = {r["name"]: r["targets"] for r in sc.get("routes", [])}[sc["flocks"][0]["route"]]
    targets = [by_name[n] for n in route]
    series = {}
    csv = ["export,time_s,largest_cluster,off_line_m,median_nearest_m,birds"]
    for d in a.dirs:
        rows, reached = leg(d, targets)
        series[f"{rows[0][4]} birds"] = rows
        csv += [f"{d},{r[0]:.2f},{r[1]:.4f},{r[2]:.2f},{r[3]:.3f},{r[4]}" for r in rows]
        end = reached.get(len(targets) - 1, math.inf)
        leg_rows = [r for r in rows if 0 < r[0] <= end]
        print(f"{d}: {rows[0][4]} birds; reached " +
              ", ".join(f"{route[k]} at {reached[k]:.0f} s" if k in reached else f"{route[k]} never"
                        for k in range(len(targets))))
        if leg_rows:
            print(f"  to the last target, {len(leg_rows)} frames: largest cluster >= {min(r[1] for r in leg_rows):.4f}, "
                  f"off the line <= {max(r[2] for r in leg_rows):.1f} m, median nearest "
                  f"{min(r[3] for r in leg_rows):.2f}-{max(r[3] for r in leg_rows):.2f} m")
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("\n".join(csv) + "\n")
    if a.svg:
        svg(series, a.svg)


if __name__ == "__main__":
    main()
