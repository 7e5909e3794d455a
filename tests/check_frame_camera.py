#!/usr/bin/python3
"""tools/paraview/run_files.frame_camera on flocks of many shapes, sizes and places (the short
run whose camera once flew off to 5e8 cm among them): every point must come out inside the
picture, and the camera must stand in front of them all. (frame_camera aims at a region that
leaves room for the legend and the title; near points may reach a little into it.) Exits 0 or 1 with the cases."""
import math
import os
import random
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools", "paraview"))
from run_files import frame_camera  # noqa: E402

def project(camera, p, aspect):
    focal, position, up, angle = camera
    back = [position[i] - focal[i] for i in range(3)]
    n = math.sqrt(sum(b * b for b in back))
    back = [b / n for b in back]
    right = [up[1] * back[2] - up[2] * back[1], up[2] * back[0] - up[0] * back[2], up[0] * back[1] - up[1] * back[0]]
    n = math.sqrt(sum(r * r for r in right))
    right = [r / n for r in right]
    true_up = [back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
               back[0] * right[1] - back[1] * right[0]]
    d = [p[i] - position[i] for i in range(3)]
    depth = -sum(d[i] * back[i] for i in range(3))
    tan_v = math.tan(math.radians(angle) / 2)
    x = sum(d[i] * right[i] for i in range(3)) / (depth * tan_v * aspect)
    y = sum(d[i] * true_up[i] for i in range(3)) / (depth * tan_v)
    return x, y, depth


def main():
    rng = random.Random(1)
    failures = []
    cases = 0
    for scale in (1.0, 30.0, 1000.0, 30000.0):  # cm: one bird, a flock, a murmuration, a route
        for _ in range(40):
            centre = [rng.uniform(-1e4, 1e4), rng.uniform(0, 1e4), rng.uniform(-1e4, 1e4)]
            size = [scale * rng.uniform(0.1, 3.0) for _ in range(3)]
            points = [[centre[i] + size[i] * rng.uniform(-1, 1) for i in range(3)] for _ in range(rng.choice((1, 2, 50)))]
            for azimuth, elevation in ((35.0, 25.0), (0.0, 80.0), (200.0, 5.0)):
                cases += 1
                camera = frame_camera(points, azimuth, elevation, 16 / 9)
                for p in points:
                    x, y, depth = project(camera, p, 16 / 9)
                    inside = -1.0 <= x <= 1.0 and -1.0 <= y <= 1.0
                    if depth <= 0 or not inside:
                        failures.append(f"scale {scale} az {azimuth} el {elevation}: point {p} at ({x:.2f}, {y:.2f}), depth {depth:.0f}")
                        break
    if failures:
        print(f"{len(failures)} of {cases} cases frame badly:\n" + "\n".join(failures[:10]))
        return 1
    print(f"ok: {cases} flocks framed, every point inside the picture, in front of the camera")
    return 0


if __name__ == "__main__":
    sys.exit(main())
