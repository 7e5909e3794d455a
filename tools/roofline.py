#!/usr/bin/env python3
"""Counts the arithmetic of one bird-step in the step shader (docs/roofline.md).

Compiles shaders/compute/step.comp as the build does (glslangValidator, with line information),
inlines and optimises it (spirv-opt -O: what is not read is gone, constants folded) and counts, per
lane, the instructions of the stepping loop's body: every block, both sides of every branch (a CPU
device such as lavapipe runs a divergent branch's both sides under a mask, a GPU's warp the same),
the loop over the four wing points four times, the landing curve's search loop once. A vector
instruction counts each component; a fused multiply-add 2 floating-point operations. Each
instruction is put to the GLSL function its source line is in: "flight" leaves out those only a
landing, perching, standing or taking-off bird runs, the path of a flock in the air.

usage: tools/roofline.py [--json FILE]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Floating-point operations per component of the result.
FLOP = {"OpFAdd": 1, "OpFSub": 1, "OpFMul": 1, "OpFDiv": 1, "OpFNegate": 1, "OpFMod": 2, "OpFRem": 2,
        "OpVectorTimesScalar": 1}
# GLSL.std.450 instructions: floating-point operations per component of the result (or, for those
# that reduce a vector, of the operand: marked with a tuple).
EXT_FLOP = {"Fma": 2, "FAbs": 1, "FMin": 1, "FMax": 1, "FClamp": 2, "Round": 1, "Floor": 1, "Ceil": 1,
            "Fract": 1, "FSign": 1, "Sqrt": 1, "InverseSqrt": 1, "Cross": 3, "Normalize": ("n", 3),
            "Length": ("n", 2), "Distance": ("n", 3), "Pow": 1, "Log": 1, "Exp": 1, "Sin": 1, "Cos": 1}
COMPARE = re.compile(r"Op(FOrd|FUnord|Logical|Select|IEqual|INotEqual|ULess|UGreater|SLess|SGreater|Any|All)")
INTEGER = re.compile(r"Op(IAdd|ISub|IMul|UDiv|UMod|SDiv|Bitwise|ShiftLeft|ShiftRight|Convert|Bitcast)")


# Run only by birds that land, perch, stand or take off.
NOT_IN_FLIGHT = {"landing_goal", "landing_progress", "landing_curve", "landing_point", "landing_gate", "place_curve",
                 "perch", "perch_point", "come_to_rest", "stand_on_legs", "flown_past", "sunk_under", "into_wind",
                 "facing", "level_attitude", "flare_share", "flare_pitch", "perch_airspeed", "heeds_wind",
                 "approach_branch", "way_to_perch", "braking_due"}
FUNCTION = re.compile(r"^(?:[A-Za-z_]\w*\s+)+([A-Za-z_]\w*)\s*\(")


def compile_step(tmp):
    spv, opt, dis = (os.path.join(tmp, n) for n in ("step.spv", "step_o.spv", "step_o.txt"))
    subprocess.run(["glslangValidator", "--target-env", "vulkan1.2", "-V", "--quiet", "-g",
                    "-I" + os.path.join(ROOT, "shaders/compute"), "-I" + os.path.join(ROOT, "engine"),
                    os.path.join(ROOT, "shaders/compute/step.comp"), "-o", spv], check=True)
    subprocess.run(["spirv-opt", "-O", spv, "-o", opt], check=True)
    subprocess.run(["spirv-dis", "--raw-id", opt, "-o", dis], check=True)
    with open(dis) as f:
        return f.read().splitlines()


def source_functions(path):
    """For each line of a GLSL file, the function it is in (None outside any)."""
    owner, current = [None], None
    with open(path) as f:
        for line in f:
            m = FUNCTION.match(line)
            if m and not line.rstrip().endswith(";"):
                current = m.group(1)
            elif line.startswith("}"):
                owner.append(current)
                current = None
                continue
            owner.append(current)
    return owner


def parse(lines):
    """Instructions as (result, opcode, operands, function), each result's component count."""
    comps, types_of, strings, owners, out = {}, {}, {}, {}, []
    where = None
    for line in lines:
        m = re.match(r"\s*(?:(%\w+) = )?(Op\w+)(.*)", line)
        if not m:
            continue
        res, op, rest = m.group(1), m.group(2), m.group(3).split()
        if op == "OpString":
            strings[res] = m.group(3).strip().strip('"')
        elif op == "OpLine":
            path = strings.get(rest[0], "")
            if path not in owners:
                owners[path] = source_functions(path) if path.endswith(".glsl") or path.endswith(".comp") else []
            line_no = int(rest[1])
            where = owners[path][line_no] if line_no < len(owners[path]) else None
        elif op == "OpNoLine":
            where = None
        if op in ("OpTypeFloat", "OpTypeInt", "OpTypeBool"):
            comps[res] = 1
        elif op == "OpTypeVector":
            comps[res] = int(rest[1])
        if res and rest and rest[0] in comps:
            types_of[res] = comps[rest[0]]
        out.append((res, op, rest, where))
    return out, types_of


def classify(op, rest, n, types_of):
    """(kind, lane operations) of one instruction."""
    if op in FLOP:
        return "flop", FLOP[op] * n
    if op == "OpDot":
        return "flop", 2 * types_of.get(rest[1], 3) - 1
    if op == "OpExtInst":
        cost = EXT_FLOP.get(rest[2])
        if cost is None:  # UMin and the like: integer, counted with those
            return "integer", n
        if isinstance(cost, tuple):
            return "flop", cost[1] * types_of.get(rest[3], 3)
        return "flop", cost * n
    if COMPARE.match(op):
        return "compare_select", n
    if INTEGER.match(op):
        return "integer", n
    return None, 0


def count(instructions, types_of):
    entry = next(rest[1] for _, op, rest, _ in instructions if op == "OpEntryPoint")
    main = next(i for i, (r, op, _, _) in enumerate(instructions) if op == "OpFunction" and r == entry)
    body = instructions[main:]
    label_at = {r: i for i, (r, op, _, _) in enumerate(body) if op == "OpLabel"}
    loops = [i for i, (_, op, _, _) in enumerate(body) if op == "OpLoopMerge"]
    end = label_at[body[loops[0]][2][0]]  # the stepping loop: its header to its merge block
    weights = [1] * len(body)
    nested = [(i, label_at[body[i][2][0]]) for i in loops[1:] if i < end]
    # The wing points' loops: one inside the other (i < 2, side < 2), twice each.
    for start, stop in nested:
        inner_or_outer = any(o != (start, stop) and (o[0] > start and o[1] <= stop or start > o[0] and stop <= o[1])
                             for o in nested)
        if inner_or_outer:
            for i in range(start, stop):
                weights[i] *= 2
    tally = {"flight": {}, "every_branch": {}}
    by_function = {}
    for i in range(loops[0], end):
        res, op, rest, where = body[i]
        kind, ops = classify(op, rest, types_of.get(res, 1), types_of)
        if not kind:
            continue
        ops *= weights[i]
        paths = ["every_branch"] + ([] if where in NOT_IN_FLIGHT else ["flight"])
        for path in paths:
            tally[path][kind] = tally[path].get(kind, 0) + ops
        if kind == "flop" and "flight" in paths:
            by_function[where or "?"] = by_function.get(where or "?", 0) + ops
    return tally, by_function


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", help="write the counts to FILE")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        instructions, types_of = parse(compile_step(tmp))
    tally, by_function = count(instructions, types_of)
    result = {}
    for path in ("flight", "every_branch"):
        t = tally[path]
        result[path] = {k: t.get(k, 0) for k in ("flop", "compare_select", "integer")}
        result[path]["lane_operations"] = sum(result[path].values())
    result["flight_flop_by_function"] = dict(sorted(by_function.items(), key=lambda kv: -kv[1]))
    print(f"{'per bird-step':16s} {'flop':>6s} {'compare':>8s} {'integer':>8s} {'all':>6s}")
    for path in ("flight", "every_branch"):
        r = result[path]
        print(f"{path:16s} {r['flop']:6d} {r['compare_select']:8d} {r['integer']:8d} {r['lane_operations']:6d}")
    print("\nflight flop by the function its source line is in (after inlining, exclusive):")
    for name, flop in list(result["flight_flop_by_function"].items())[:14]:
        print(f"  {name:22s} {flop:6d}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    sys.exit(main())
