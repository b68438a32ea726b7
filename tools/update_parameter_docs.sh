#!/usr/bin/env bash
# Writes docs/parameters/*.md from the option tables: runs the print_parameter_docs program of every
# package that builds one (its CMakeLists.txt gives a target that OUTPUT_NAME). A package whose program is not
# built is skipped with a note. With --check, compares the pages instead of writing them and exits
# non-zero when one is out of date.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
check=()
done_what=written
if [[ "${1:-}" == "--check" ]]; then
  check=(--check)
  done_what=checked
elif [[ $# -gt 0 ]]; then
  echo "usage: $0 [--check]" >&2
  exit 2
fi
out=docs/parameters
mkdir -p "$out"
status=0
for cmake in minibot3d_*/CMakeLists.txt; do
  grep -q 'OUTPUT_NAME print_parameter_docs' "$cmake" || continue
  package=$(dirname "$cmake")
  program=devel/lib/$package/print_parameter_docs
  if [[ ! -x "$program" ]]; then
    echo "note: $program is not built (tools/build.sh); $package's pages skipped" >&2
    continue
  fi
  if "$program" "${check[@]}" "$out"; then
    echo "$package: pages $done_what in $out/"
  else
    status=1
  fi
done
exit "$status"
