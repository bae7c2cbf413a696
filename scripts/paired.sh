#!/bin/bash
# Alternates two builds of a timing example and reports the median of the per-pair ratios,
# which both halves of a pair measure in the same state of a drifting shared machine.
#
#   scripts/paired.sh OLD_BINARY NEW_BINARY [args...]     (N=12 pairs by default)
#
# Each binary must print "best <number>" (e.g. examples/step_cost.rs). Build the two from
# two commits, e.g. `cargo build --release --example step_cost` and copy
# target/release/examples/step_cost aside before checking out the other commit.
set -euo pipefail
old=$1; new=$2; shift 2
for _ in $(seq 1 "${N:-12}"); do
  a=$("$old" "$@" | grep -o "best [0-9.]*" | cut -d' ' -f2)
  b=$("$new" "$@" | grep -o "best [0-9.]*" | cut -d' ' -f2)
  echo "$a $b"
done | python3 -c '
import statistics, sys
pairs = [tuple(map(float, line.split())) for line in sys.stdin]
r = sorted(b / a for a, b in pairs)
print("old: best %.3f, median %.3f" % (min(a for a, _ in pairs), statistics.median(a for a, _ in pairs)))
print("new: best %.3f, median %.3f" % (min(b for _, b in pairs), statistics.median(b for _, b in pairs)))
print("new/old per pair: median %.3f, quartiles %.3f-%.3f" % (statistics.median(r), r[len(r) // 4], r[3 * len(r) // 4]))
'
