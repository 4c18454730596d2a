#!/usr/bin/env bash
# Checks that every C++ source in the repository is as clang-format (.clang-format) writes it.
# Run with --fix to apply the formatter instead.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/setup.sh
symdyn_require_command clang-format-14 clang-format-14

# Left out: the docs' quotation of an emitted header, laid out as the generator writes it.
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' ':!tests/docs/fixtures/emitted_interface.hpp')
if [ "${1:-}" = "--fix" ]; then
  clang-format-14 -i "${files[@]}"
  exit 0
fi
if ! clang-format-14 --dry-run --Werror "${files[@]}" 2>/tmp/symdyn-format.$$; then
  grep -o '^[^:]*' /tmp/symdyn-format.$$ | sort -u | sed 's/^/not formatted: /' >&2
  rm -f /tmp/symdyn-format.$$
  echo "error: run ./scripts/check_format.sh --fix (clang-format-14, .clang-format)" >&2
  exit 1
fi
rm -f /tmp/symdyn-format.$$
echo "format: ${#files[@]} files as clang-format writes them"
