"""Checks the shape of `aeroflock bench --json` output (not its figures):
python3 check_bench_json.py FILE [AFTER_SECONDS]."""
import json
import math
import sys

FIELDS = ("name", "backend", "variant", "birds", "iterations", "real_time", "p10", "p90", "time_unit",
          "bird_steps_per_second")


def main(path):
    with open(path) as f:
        d = json.load(f)
    ctx = d["context"]
    for key in ("date", "cpu_model", "num_cpus", "omp_threads", "git_revision", "build_type", "dt",
                "steps_per_frame", "budget_ms", "repetitions", "quick", "devices", "after_seconds"):
        assert key in ctx, f"context lacks {key}"
    assert ctx["after_seconds"] == (float(sys.argv[2]) if len(sys.argv) > 2 else 0.0), ctx
    bench = d["benchmarks"]
    assert bench, "no benchmarks"
    backends = set()
    for b in bench:
        for field in FIELDS:
            assert field in b, f"{b.get('name')}: lacks {field}"
        assert b["time_unit"] == "ms"
        assert b["name"] == f"{b['backend']}/{b['variant']}/birds:{b['birds']}", b["name"]
        assert b["iterations"] > 0 and b["birds"] > 0
        assert b["p10"] <= b["real_time"] <= b["p90"], b["name"]
        backends.add(b["backend"])
        # A Vulkan flock alone (headless, solo, realtime-*) has its passes timed on the device
        # (lavapipe and GPUs write timestamps); without flocking it has no grid and no perception.
        passes = b["device_passes_ms"]
        alone = b["variant"] in ("headless", "solo") or b["variant"].startswith("realtime-")
        if b["backend"].startswith("vulkan") and alone:
            assert passes is not None, f"{b['name']}: no device passes"
            assert passes["steps"] > 0 and passes["grid"] >= 0 and passes["perception"] >= 0, b
            assert (b["variant"] == "solo") == (passes["grid"] == passes["perception"] == 0), b
            # The grid's cell: a power of two of cm where the flock flocks, none solo.
            cell = b["grid_cell_cm"]
            if b["variant"] == "solo":
                assert cell is None, b
            else:
                assert cell is not None and cell >= 64 and math.log2(cell).is_integer(), b
        else:
            assert passes is None, b
    for backend in backends:
        key = f"{backend}/headless"
        assert key in d["birds_per_frame"], f"birds_per_frame lacks {key}"
        assert isinstance(d["birds_per_frame"][key], int)
        assert key in d["scaling_exponent"], f"scaling_exponent lacks {key}"
        # The exponent is fitted over the sizes it names, each of them measured.
        measured = {b["birds"] for b in bench if b["backend"] == backend and b["variant"] == "headless"}
        fitted = d["scaling_exponent_sizes"][key]
        assert (d["scaling_exponent"][key] is None) == (len(fitted) < 2), (key, fitted)
        assert set(fitted) <= measured, f"{key}: fitted over {fitted}, measured {sorted(measured)}"
    assert isinstance(d["ratios"], list)
    # Flocking's cost, frames alternated: one entry for each size both headless and solo measured.
    cost = d["flocking_cost"]
    for backend in backends:
        sizes = [{b["birds"] for b in bench if b["backend"] == backend and b["variant"] == v}
                 for v in ("headless", "solo")]
        paired = {c["birds"] for c in cost if c["backend"] == backend}
        # Every size both measured, but those a pair would take too long for (the smallest never).
        assert paired <= sizes[0] & sizes[1], f"{backend}: flocking's cost at {paired}, measured {sizes}"
        assert not (sizes[0] & sizes[1]) or min(sizes[0] & sizes[1]) in paired, f"{backend}: {paired}"
    for c in cost:
        assert c["iterations"] > 0 and c["with_flocking_ms"] > 0 and c["without_flocking_ms"] > 0, c
        assert abs(c["flocking_keeps"] - c["without_flocking_ms"] / c["with_flocking_ms"]) < 1e-9, c
    # Birds in real time: each realtime series measured has its step, its budget (the frame's
    # flight) and the flock its search found, no larger than the largest size measured.
    real_time = d["birds_in_real_time"]
    for b in bench:
        if b["variant"].startswith("realtime-"):
            key = f"{b['backend']}/{b['variant']}"
            assert key in real_time, f"birds_in_real_time lacks {key}"
    for key, r in real_time.items():
        assert r["dt"] > 0 and r["budget_ms"] > 0 and isinstance(r["birds"], int), (key, r)
        assert key.endswith("realtime-paper") == (r["dt"] == 0.0003), (key, r)
        measured = [b for b in bench if f"{b['backend']}/{b['variant']}" == key]
        fitted = [b["birds"] for b in measured if b["real_time"] <= r["budget_ms"]]
        assert r["birds"] == 0 or r["birds"] >= max(fitted, default=0), (key, r, fitted)
    print(f"{path}: {len(bench)} benchmarks, birds per frame {d['birds_per_frame']}, "
          f"flocking's cost at {len(cost)} sizes")


if __name__ == "__main__":
    main(sys.argv[1])
