#!/bin/bash
# The time step's convergence study (docs/convergence.md), as its tables were made:
#   1. aeroflock converge: every built-in scenario and the envelope's sample at 0.1 to 10 ms, on the
#      CPU reference, against the 0.1 ms step (convergence.json, convergence.txt);
#   2. docs/MODEL.md's behaviours (tests/test_behaviours.cpp, the CPU reference) flown at each step;
#   3. the tables, in Markdown, on stdout, and the plot (tools/convergence_table.py: convergence.png).
# usage: tools/convergence-study.sh [BUILD_DIR] [OUT_DIR]     (defaults: build/release, docs)
# About 40 minutes on 2 cores.
set -euo pipefail
build=${1:-build/release}
out=${2:-docs}
steps_ms="0.1 0.3 0.5 1 2 3 5 10"
mkdir -p "$out"
"$build/aeroflock" converge --dts "${steps_ms// /,}" --json "$out/convergence.json" > "$out/convergence.txt"
behaviours="$out/convergence-behaviours"
mkdir -p "$behaviours"
for ms in $steps_ms; do
  dt=$(awk "BEGIN { print $ms / 1000 }")
  # A failing behaviour is a finding of the study, not an error of the script.
  AEROFLOCK_TEST_DT=$dt "$build/tests/test_behaviours" --gtest_brief=1 \
    --gtest_output="json:$behaviours/dt_${ms}_ms.json" > /dev/null || true
done
"$(dirname "$0")/convergence_table.py" "$out/convergence.json" "$behaviours" "$out/convergence.png"
