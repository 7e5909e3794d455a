#!/usr/bin/env bash
# Installs what is missing, builds, and runs the default scenario. Extra arguments go to
# `aeroflock run`, e.g. ./run.sh --seconds 5 --birds 200
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

tools/install-deps.sh
cmake --preset release
cmake --build --preset release
mkdir -p out/default  # aeroflock writes into directories that exist, it does not make them
build/release/aeroflock run default --summary out/default/summary.json \
  --png out/default/last_frame.png "$@"

echo
echo "outputs:"
echo "  program:  build/release/aeroflock (try: build/release/aeroflock scenarios)"
echo "  summary:  out/default/summary.json"
echo "  image:    out/default/last_frame.png (the last frame, rendered headless)"
echo "  watch it: build/release/aeroflock view   (under xvfb-run without a display)"
