#!/usr/bin/env bash
# Runs every example with two fibrane binaries and compares their history.csv files column by column
# (scripts/compare_histories.py, default tolerance 1e-10 of each column's scale).
#   scripts/compare_examples.sh REFERENCE_BINARY NEW_BINARY [OUTDIR] [-- compare_histories options]
# One thread each: threaded sums are added in an order fixed for a given thread count but not across
# counts (and, in binaries before the ordered sums, not across runs either), which Newton's tolerance then
# lets through to ~1e-9 of the reactions; with one thread a refactoring that keeps the arithmetic gives
# equal bits.
set -euo pipefail
cd "$(dirname "$0")/.."
reference=${1:?reference binary}; new=${2:?new binary}; out=${3:-out/compare-examples}
shift $(( $# < 3 ? $# : 3 )); [ "${1:-}" = "--" ] && shift
mkdir -p "$out"
status=0
for case_file in examples/*.yaml; do
  name=$(basename "$case_file" .yaml)
  for which in reference new; do
    binary=$reference; [ "$which" = new ] && binary=$new
    "$binary" run "$case_file" -o "$out/$which/$name" --quiet --threads 1 > "$out/$which-$name.log" 2>&1 || true
  done
  /usr/bin/python3 scripts/compare_histories.py "$out/reference/$name" "$out/new/$name" "$@" | tail -n 1 || status=1
done
exit $status
