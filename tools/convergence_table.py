#!/usr/bin/env python3
"""The convergence study's tables in Markdown (docs/convergence.md), from `aeroflock converge --json`
and the behaviours' gtest JSON at each step (tools/convergence-study.sh).

usage: tools/convergence_table.py CONVERGENCE.json BEHAVIOURS_DIR
"""
import glob
import json
import os
import sys


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


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
