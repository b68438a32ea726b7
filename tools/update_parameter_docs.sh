#!/usr/bin/env bash
# Writes docs/parameters/*.md from the option tables: runs every package's print_parameter_docs
# (devel/lib/<package>/print_parameter_docs, built by tools/build.sh). Each package's
# parameter_docs_test fails until the pages it owns are written again after a table changed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mkdir -p docs/parameters
found=0
for tool in devel/lib/*/print_parameter_docs; do
  [ -x "$tool" ] || continue
  "$tool" docs/parameters
  echo "update_parameter_docs: $tool -> docs/parameters/"
  found=1
done
if [ "$found" = 0 ]; then
  echo "update_parameter_docs: no devel/lib/*/print_parameter_docs; build first (tools/build.sh)" >&2
  exit 1
fi
