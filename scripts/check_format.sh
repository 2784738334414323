#!/usr/bin/env bash
# Fails (exit 1) and names every tracked .cpp/.h file that clang-format (.clang-format) would change.
# Fix with: git ls-files '*.cpp' '*.h' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "check_format: clang-format is not installed" >&2; exit 2; }
bad=()
while IFS= read -r f; do
  [ -f "$f" ] || continue
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done < <(git ls-files '*.cpp' '*.h')
if [ ${#bad[@]} -gt 0 ]; then
  echo "check_format: ${#bad[@]} file(s) not formatted: ${bad[*]}" >&2
  echo "check_format: run  clang-format -i ${bad[*]}" >&2
  exit 1
fi
echo "check_format: every tracked .cpp/.h file is formatted"
