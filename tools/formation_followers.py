"""Who follows whom in a snapshot of a formation, as docs/MODEL.md "Formation flying" measures it
(engine/model/formation_figures.h), in plain Python for the scripts that read a run's VTK export
(tools/formation_phase.py, tests/check_formation.py).

A bird is a dict with "p" (position) and "v" (its velocity through the air, the export's
`air_velocity`), in the same length unit as `span`.
"""
import math


def _dot(a, b):
    return sum(a[k] * b[k] for k in range(3))


def followers(birds, span):
    """(i, lead, dx, dy, speed) for each follower i of `birds`: a bird with another at least 0.25
    spans ahead of it along its flight, within 10 spans, the nearest such its `lead`; dx its
    distance behind the lead along the lead's flight, dy its distance across it (level), speed the
    lead's airspeed."""
    out = []
    for i, b in enumerate(birds):
        own = math.sqrt(_dot(b["v"], b["v"]))
        lead, nearest = None, 10.0 * span
        for j, o in enumerate(birds):
            offset = [o["p"][k] - b["p"][k] for k in range(3)]
            d = math.sqrt(_dot(offset, offset))
            if j != i and _dot(offset, b["v"]) / own >= 0.25 * span and d <= nearest:
                lead, nearest = o, d
        if lead is None:
            continue
        speed = math.sqrt(_dot(lead["v"], lead["v"]))
        ahead = [x / speed for x in lead["v"]]
        level = math.hypot(ahead[0], ahead[2])
        side = [-ahead[2] / level, 0.0, ahead[0] / level]  # ahead x up, normalised
        offset = [b["p"][k] - lead["p"][k] for k in range(3)]
        out.append((i, lead, -_dot(offset, ahead), abs(_dot(offset, side)), speed))
    return out


def directly_behind(dy, span):
    """Within a quarter span of the lead's track, across its flight: in the downwash between its
    tip vortices."""
    return dy < 0.25 * span


def in_v_place(dx, dy, optimum):
    """30-60 degrees behind the lead's wing, the lateral offset within 10 % of `optimum`."""
    bearing = math.atan2(dx, dy)
    return math.pi / 6 <= bearing <= math.pi / 3 and abs(dy - optimum) <= 0.1 * optimum
