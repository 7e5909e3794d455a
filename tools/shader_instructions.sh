#!/bin/bash
# Instructions lavapipe runs in each compiled shader over a short run, counted by callgrind:
# the same from run to run, where timings on a shared machine drift by 20-30 % within minutes
# (docs/BENCHMARK.md, "Counting instructions"). A shader is a JIT function without a name; the
# largest of a flocking run is the step, the next the perception (their counts follow the changes
# made to each). Takes minutes: valgrind runs the program some 50 times slower.
#   tools/shader_instructions.sh [AEROFLOCK] [run arguments...]
# default: build/release/aeroflock, run tools/shader_instructions.toml --seconds 0.3 --backend
# vulkan: the default scenario's 1,000 starlings spawned over the span of a flown flock (a
# spawned flock, compact, meets few of the costs of one that has flown for a while).
set -euo pipefail
aeroflock=${1:-build/release/aeroflock}
shift || true
args=("$@")
[ ${#args[@]} -gt 0 ] || args=("$(dirname "$0")/shader_instructions.toml" --seconds 0.3)
command -v valgrind > /dev/null || { echo "needs valgrind (apt-get install valgrind)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# One worker thread: each shader's instructions in one thread's profile.
LP_NUM_THREADS=1 valgrind --tool=callgrind --separate-threads=yes \
  --callgrind-out-file="$out/cg.%p" "$aeroflock" run "${args[@]}" --backend vulkan > "$out/log" 2>&1 ||
  { tail -20 "$out/log" >&2; exit 1; }
# The JIT code has no file: callgrind names it ???:0xADDRESS [???].
for f in "$out"/cg.*-*; do
  callgrind_annotate --threshold=100 "$f" 2> /dev/null | grep '???:0x.*\[???\]' || true
done | awk '{gsub(",", "", $1); if ($1 > 1000000) printf "%15.0f instructions  %s\n", $1, $(NF - 1)}' | sort -rn
