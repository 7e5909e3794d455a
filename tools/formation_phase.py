#!/usr/bin/python3
"""A formation's wingbeat phase against the streamwise distance, as Portugal et al. 2014 (Nature
505:399, Fig. 3) plotted the ibises': from `aeroflock run ... --vtk DIR` exports, an SVG.

    /usr/bin/python3 tools/formation_phase.py OUT.svg LABEL DIR SUMMARY [LABEL DIR SUMMARY ...]

For each export DIR and its run's summary (`--summary`, the run measured with `--structure-from`:
it gives the span and the optimum lateral offset) one panel: each follower of each exported frame
(a bird with another at least 0.25 spans ahead along its flight through the air within 10 spans;
the nearest such is the bird it follows, measured in the frame of that bird's flight through the
air, the export's `air_velocity`, as docs/MODEL.md "Formation flying" has it) gives a point: its
streamwise distance dx behind that bird (m) and the phase lag of its wingbeat, the leader's phase
less its own, in [0, 2 pi). Blue: in a V place (30-60 degrees behind the wing, the lateral offset
within 10 % of the summary's optimum); red: directly behind (its centre within a quarter span of
the leader's line of flight); grey: elsewhere (at most 1,200 points drawn a panel, every k-th).
The line is the wingtip path's lag 2 pi f dx / U (f and U, the airspeed, the mean over the
followers), the dashed one half a beat from it (spatial anti-phase). Portugal's ibises in V places
lie along the line, those directly behind along the dashed one. It needs VTK's
Python module (Debian's python3-vtk9) and nothing else.
"""
import json
import math
import os
import sys

from formation_followers import directly_behind, followers, in_v_place

try:
    import vtk
except ImportError as e:
    print(f"SKIPPED: cannot import VTK's Python module (vtk): {e}")
    sys.exit(77)

W, H, M = 460, 360, 56  # a panel's size and margin, px
DX_MAX = 4.0  # m
MOST_POINTS = 1200  # drawn in a panel


def frame(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    d = r.GetOutput()
    pd = d.GetPointData()
    n = d.GetNumberOfPoints()
    return [{"p": d.GetPoints().GetPoint(i), "v": pd.GetArray("air_velocity").GetTuple3(i),
             "phase": pd.GetArray("wingbeat_phase").GetTuple1(i),
             "f": pd.GetArray("frequency").GetTuple1(i)} for i in range(n)]


def points(vtk_dir, span, optimum):  # cm, as the export
    out, fs, us = [], [], []
    for name in sorted(os.listdir(os.path.join(vtk_dir, "frames"))):
        birds = frame(os.path.join(vtk_dir, "frames", name))
        for i, lead, dx, dy, speed in followers(birds, span):
            if in_v_place(dx, dy, optimum):
                kind = "v"
            elif directly_behind(dy, span):
                kind = "behind"
            else:
                kind = "other"
            out.append((dx / 100.0, (lead["phase"] - birds[i]["phase"]) % (2 * math.pi), kind))
            fs.append(lead["f"])
            us.append(speed / 100.0)
    return out, sum(fs) / len(fs), sum(us) / len(us)


def panel(x0, label, pts, f, u):
    sx = lambda dx: x0 + M + (W - 2 * M) * dx / DX_MAX
    sy = lambda lag: M + (H - 2 * M) * (1 - lag / (2 * math.pi))
    s = [f'<rect x="{x0 + M}" y="{M}" width="{W - 2 * M}" height="{H - 2 * M}" fill="none" '
         f'stroke="black"/>',
         f'<text x="{x0 + W / 2}" y="{M - 14}" text-anchor="middle" font-size="15">{label}</text>',
         f'<text x="{x0 + W / 2}" y="{H - 14}" text-anchor="middle">streamwise distance behind '
         f'the bird followed (m)</text>',
         f'<text transform="translate({x0 + 16},{H / 2}) rotate(-90)" text-anchor="middle">'
         f'phase lag (leader less follower)</text>']
    for k in range(int(DX_MAX) + 1):
        s.append(f'<text x="{sx(k)}" y="{H - M + 16}" text-anchor="middle">{k}</text>')
    for k, t in enumerate(["0", "π/2", "π", "3π/2", "2π"]):
        s.append(f'<text x="{x0 + M - 6}" y="{sy(k * math.pi / 2) + 4}" '
                 f'text-anchor="end">{t}</text>')
    colour = {"other": "#b0b0b0", "v": "#1f5fd0", "behind": "#d02020"}
    step = max(1, len(pts) // MOST_POINTS)  # every step-th point drawn, all counted
    for kind in ("other", "v", "behind"):
        for dx, lag, k in pts[::step]:
            if k == kind and 0 <= dx <= DX_MAX:
                s.append(f'<circle class="{k}" cx="{sx(dx):.1f}" cy="{sy(lag):.1f}" r="1.6"/>')
    # The wingtip path's lag and half a beat from it, wrapped into [0, 2 pi).
    for shift, dash in ((0.0, ""), (math.pi, ' stroke-dasharray="6,4"')):
        seg, prev = [], None
        for i in range(401):
            dx = DX_MAX * i / 400
            lag = (2 * math.pi * f * dx / u + shift) % (2 * math.pi)
            if prev is not None and abs(lag - prev) > math.pi:
                s.append(f'<polyline points="{" ".join(seg)}" fill="none" stroke="black"{dash}/>')
                seg = []
            seg.append(f"{sx(dx):.1f},{sy(lag):.1f}")
            prev = lag
        s.append(f'<polyline points="{" ".join(seg)}" fill="none" stroke="black"{dash}/>')
    n = {k: sum(1 for p in pts if p[2] == k) for k in colour}
    s.append(f'<text x="{x0 + W - M}" y="{H - M - 8}" text-anchor="end" font-size="11">'
             f'<tspan fill="{colour["v"]}">V place {n["v"]}</tspan>  '
             f'<tspan fill="{colour["behind"]}">directly behind {n["behind"]}</tspan>  '
             f'<tspan fill="#808080">elsewhere {n["other"]}</tspan></text>')
    return s


def main():
    if len(sys.argv) < 5 or (len(sys.argv) - 2) % 3:
        print(__doc__)
        return 2
    out, runs = sys.argv[1], sys.argv[2:]
    n = len(runs) // 3
    body = []
    for k in range(n):
        label, vtk_dir, summary = runs[3 * k:3 * k + 3]
        flock = json.load(open(summary))["structure"][0]
        pts, f, u = points(vtk_dir, flock["wingspan"], flock["formation"]["optimum_lateral"])
        if not pts:
            print(f"{label}: no follower in {vtk_dir}")
            return 1
        count = {kind: sum(1 for p in pts if p[2] == kind) for kind in ("v", "behind", "other")}
        print(f"{label}: {len(pts)} follower-frames (in V places {count['v']}, directly behind "
              f"{count['behind']}, elsewhere {count['other']}), f {f:.2f} Hz, U {u:.2f} m/s")
        body += panel(k * W, label, pts, f, u)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{n * W}" height="{H}" '
           f'font-family="sans-serif" font-size="12">',
           "<style>circle { fill-opacity: 0.5 } .other { fill: #b0b0b0 } "
           ".v { fill: #1f5fd0 } .behind { fill: #d02020 }</style>",
           f'<rect width="{n * W}" height="{H}" fill="white"/>'] + body + ["</svg>"]
    with open(out + ".part", "w") as f:
        f.write("\n".join(svg) + "\n")
    os.replace(out + ".part", out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
