#!/usr/bin/env bash
# Installs what is missing, builds and runs every test; then the sanitizers' subset of the tests
# (the asan preset) and the scenario loader's fuzzer for 90 s (the fuzz preset): docs/TESTING.md
# "Sanitizers and fuzzing".
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

tools/install-deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset release -j 2

cmake --preset asan
cmake --build --preset asan
ctest --preset asan -j 2

cmake --preset fuzz
cmake --build --preset fuzz
ctest --preset fuzz
