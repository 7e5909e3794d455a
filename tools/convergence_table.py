#!/usr/bin/env python3
"""The convergence study's tables in Markdown (docs/convergence.md) from `aeroflock converge --json`
and the behaviours' gtest JSON at each step (tools/convergence-study.sh), and its plot (gnuplot).

usage: tools/convergence_table.py CONVERGENCE.json BEHAVIOURS_DIR [PLOT.png]
"""
import glob
import json
import os
import subprocess
import sys
import tempfile


def percent(x):
    return "0" if x == 0 else (f"{100 * x:.2g} %" if x < 1e-3 else f"{100 * x:.2f} %")


def behaviours(directory):
    """dt (s): (passed, total, the names of those that failed)."""
    found = {}
    for path in glob.glob(os.path.join(directory, "dt_*_ms.json")):
        ms = float(os.path.basename(path)[3:-8])
        with open(path) as f:
            d = json.load(f)
        failed = [f"{s['name']}.{t['name']}" for s in d["testsuites"] for t in s["testsuite"]
                  if t.get("failures") or t.get("result") == "ERRORED"]
        found[round(ms / 1000, 7)] = (d["tests"] - len(failed), d["tests"], failed)
    return found


def main(convergence, behaviour_dir):
    with open(convergence) as f:
        c = json.load(f)
    seen = behaviours(behaviour_dir)
    dts = [r["dt"] for r in c["scenarios"][0]["runs"]]
    singles = [s for s in c["scenarios"] if not s["flocking"]]
    flocks = [s for s in c["scenarios"] if s["flocking"]]
    env = {e["species"]: e for e in c["envelope"]}

    print(f"Position error after {c['seconds']:g} s (or where the route ends, if sooner) relative to the "
          f"distance flown, against the {c['reference_dt'] * 1e3:g} ms step; the worst bird of each scenario.\n")
    head = ["dt (ms)"] + [s["name"] for s in singles]
    print("| " + " | ".join(head) + " |")
    print("|" + " --- |" * len(head))
    for k, dt in enumerate(dts):
        cells = [f"{dt * 1e3:g}"] + [percent(s["runs"][k]["error_max"]) for s in singles]
        print("| " + " | ".join(cells) + " |")

    print("\nThe flocks: their centroid's error (single flocking birds part whatever the step: any rounding "
          "changes who is nearest), the median single bird's, and what no longer holds.\n")
    head = ["dt (ms)"] + [f"{s['name']} ({s['birds']:,} birds)" for s in flocks]
    print("| " + " | ".join(head) + " |")
    print("|" + " --- |" * len(head))
    for k, dt in enumerate(dts):
        cells = [f"{dt * 1e3:g}"]
        for s in flocks:
            r = s["runs"][k]
            cell = f"{percent(r['centroid_error'])} (median bird {percent(r['error_median'])})"
            if not r["holds"]:
                cell += f"; **{r['failed']}**"
            cells.append(cell)
        print("| " + " | ".join(cells) + " |")

    print("\nEverything else that must hold, and the speed (bird-seconds flown per wall second on the CPU "
          "reference, the default scenario's flock).\n")
    head = ["dt (ms)", "scenarios that hold", "behaviours pass"] + \
           [f"envelope {name} ({e['rows'][0]['cases']} cases)" for name, e in env.items()] + ["speed"]
    print("| " + " | ".join(head) + " |")
    print("|" + " --- |" * len(head))
    default = next((s for s in c["scenarios"] if s["name"] == "default"), c["scenarios"][0])
    for k, dt in enumerate(dts):
        hold = sum(s["runs"][k]["holds"] for s in c["scenarios"])
        broken = [s["name"] for s in c["scenarios"] if not s["runs"][k]["holds"]]
        cells = [f"{dt * 1e3:g}", f"{hold} of {len(c['scenarios'])}" + (f" (not {', '.join(broken)})" if broken else "")]
        b = seen.get(round(dt, 7))
        cells.append("not run" if b is None else f"{b[0]} of {b[1]}" + (f" (failed: {', '.join(b[2])})" if b[2] else ""))
        for name, e in env.items():
            row = e["rows"][k]
            fails = ", ".join(f"{v} {o}" for o, v in row["failures"].items())
            cells.append(f"{row['reached']}" + (f" ({fails})" if fails else ""))
        cells.append(f"{default['runs'][k]['bird_seconds_per_second']:,.0f}")
        print("| " + " | ".join(cells) + " |")
    largest = c.get("largest_dt")
    print(f"\nLargest step at which everything holds within {100 * c['tolerance']:g} %: "
          f"{'none' if largest is None else f'{largest * 1e3:g} ms'} (aeroflock converge).")


def quoted(text):
    return "'" + text.replace("'", "''") + "'"


def plot(convergence, png):
    """Position error, speed and envelope cases against the step, three panels."""
    with open(convergence) as f:
        c = json.load(f)
    with tempfile.TemporaryDirectory() as tmp:
        errors, speed, cases, script = (os.path.join(tmp, n) for n in ("e.dat", "s.dat", "c.dat", "p.gp"))
        flocks = [s for s in c["scenarios"] if s["birds"] > 1]  # a single bird's run is too short to time
        with open(errors, "w") as e, open(speed, "w") as sp, open(cases, "w") as cs:
            # A bird perched on its branch at every step has no error: no point on a log scale.
            moved = [s for s in c["scenarios"] if any(r["criterion"] > 0 for r in s["runs"])]
            for s in moved:
                e.write("".join(f"{r['dt'] * 1e3} {r['criterion']}\n" for r in s["runs"][1:] if r["criterion"] > 0))
                e.write("\n\n")
            for s in flocks:
                sp.write("".join(f"{r['dt'] * 1e3} {r['bird_seconds_per_second']}\n" for r in s["runs"]) + "\n\n")
            for env in c["envelope"]:
                cs.write("".join(f"{r['dt'] * 1e3} {100 * r['reached'] / r['cases']}\n" for r in env["rows"]) + "\n\n")

        def series(path, titles):
            return ", ".join(f"{quoted(path)} index {i} using 1:2 with linespoints title {quoted(t)}"
                             for i, t in enumerate(titles))

        tol = c["tolerance"]
        with open(script, "w") as gp:
            gp.write(f"set terminal pngcairo size 1500,540 font 'sans,10'\nset output {quoted(png + '.tmp')}\n")
            gp.write("set multiplot layout 1,3 title 'aeroflock converge: the time step (CPU reference, "
                     f"{c['seconds']:g} s, against {c['reference_dt'] * 1e3:g} ms)'\n")
            gp.write("set grid\nset logscale x\nset xlabel 'dt (ms)'\nset key font ',8'\nset format y '%g'\n")
            gp.write("set logscale y\nset yrange [1e-5:0.1]\nset key bottom right\n"
                     "set ylabel 'position error / distance flown (flocks: their centroid)'\n")
            gp.write(f"plot {series(errors, [s['name'] for s in moved])}, {tol} with lines dashtype 2 "
                     f"lc rgb 'black' title '{100 * tol:g} %'\n")
            gp.write("set yrange [*:*]\nset key top left\nset ylabel 'bird-seconds flown per second'\n")
            gp.write(f"plot {series(speed, [s['name'] + ' (' + format(s['birds'], ',') + ')' for s in flocks])}\n")
            gp.write("unset logscale y\nset yrange [*:100.5]\nset key bottom left\n"
                     "set ylabel 'envelope cases reached (%)'\n")
            gp.write(f"plot {series(cases, [e['species'] for e in c['envelope']])}\nunset multiplot\n")
        subprocess.run(["gnuplot", script], check=True)
        os.replace(png + ".tmp", png)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
    if len(sys.argv) == 4:
        plot(sys.argv[1], sys.argv[3])
