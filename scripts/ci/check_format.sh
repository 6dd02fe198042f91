#!/usr/bin/env bash
# Checks that every tracked C++ file is formatted by the repository's .clang-format
# (clang-format 14, the version scripts/install_deps.sh installs). Prints one summary line:
#   [check_format] PASS: 123 C++ files formatted
#   [check_format] FAIL: 2 of 123 C++ files need clang-format -i: a.cpp b.hpp
# Exit status 1 on findings. Fix with:
#   git ls-files '*.cpp' '*.hpp' '*.h' | xargs clang-format-14 -i
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

CF="$(command -v clang-format-14 || command -v clang-format || true)"
if [ -z "$CF" ]; then
  echo "[check_format] FAIL: clang-format not found (scripts/install_deps.sh installs it)"
  exit 1
fi

# Tracked files when this is a git checkout, else every C++ file of the source folders.
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
  mapfile -t files < <(find src include toolbox test -name '*.cpp' -o -name '*.hpp' -o -name '*.h' | sort)
fi

bad=()
for f in "${files[@]}"; do
  # --dry-run --Werror: exit != 0 and a diagnostic per change clang-format would make.
  if ! "$CF" --style=file --dry-run --Werror "$f" >/dev/null 2>&1; then bad+=("$f"); fi
done

if [ ${#bad[@]} -ne 0 ]; then
  echo "[check_format] FAIL: ${#bad[@]} of ${#files[@]} C++ files need clang-format -i: ${bad[*]}"
  exit 1
fi
echo "[check_format] PASS: ${#files[@]} C++ files formatted ($("$CF" --version | grep -o 'version [0-9.]*'))"
