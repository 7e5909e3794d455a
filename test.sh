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

tools/install-deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset quick -j 2
$full || exit 0

ctest --preset validate -j 2

cmake --preset asan
cmake --build --preset asan
ctest --preset asan -j 2

cmake --preset fuzz
cmake --build --preset fuzz
ctest --preset fuzz
