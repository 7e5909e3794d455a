#!/usr/bin/env bash
# Checks that the C++ and GLSL sources are as clang-format 14 (Debian 12's, which
# tools/install-deps.sh installs) writes them under .clang-format (shaders/.clang-format keeps
# their includes in order). `tools/check_format.sh --fix` formats them in place instead.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
format=${CLANG_FORMAT:-clang-format}
if ! "$format" --version | grep -q 'version 14\.'; then
  echo "check_format: needs clang-format 14 (Debian 12's), found: $("$format" --version)" >&2
  exit 1
fi
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.glsl' '*.comp' '*.vert' '*.frag')
else
  mapfile -t files < <(find engine tools tests shaders -name '*.cpp' -o -name '*.h' -o -name '*.glsl' \
                         -o -name '*.comp' -o -name '*.vert' -o -name '*.frag' | sort)
fi
if [ "${1:-}" = --fix ]; then
  "$format" -i "${files[@]}"
else
  "$format" --dry-run --Werror "${files[@]}"
  echo "check_format: ${#files[@]} files as clang-format writes them"
fi
