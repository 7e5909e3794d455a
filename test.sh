#!/usr/bin/env bash
# ./test.sh          installs what is missing, builds, and runs the quick tiers: the unit and
#                    integration tests (ctest --preset quick), minutes on two cores.
# ./test.sh --full   then the validate tier (whole flights, the flight envelope's grids, the flock
#                    criteria), the sanitizers' subset (the asan preset) and the scenario loader's
#                    fuzzer for 90 s (the fuzz preset). CI runs this (.ci/run).
# docs/TESTING.md says what each tier holds and what it may take.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

full=false
case "${1:-}" in
  "") ;;
  --full) full=true ;;
  *) echo "usage: ./test.sh [--full]" >&2; exit 2 ;;
esac

# Each stage's wall time, from the start, on stderr: what docs/TESTING.md's budgets are held to.
start=$SECONDS
stage() {
  "$@"
  local t=$((SECONDS - start))
  printf '[test.sh] %-40s done at %d:%02d\n' "$*" $((t / 60)) $((t % 60)) >&2
}

stage tools/install-deps.sh
stage cmake --preset release
stage cmake --build --preset release
stage ctest --preset quick -j 2
$full || exit 0

stage ctest --preset validate -j 2

stage cmake --preset asan
stage cmake --build --preset asan
stage ctest --preset asan -j 2

stage cmake --preset fuzz
stage cmake --build --preset fuzz
stage ctest --preset fuzz
