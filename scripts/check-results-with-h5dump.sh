#!/usr/bin/env bash
# Runs a small case and reads its HDF5 result with h5dump, an independent reader, to prove
# beamflow writes standard HDF5 (units as attributes, complex as compound {r, i}).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cargo run --release --quiet -- run cases/paper-beam.toml --out "$dir" --no-plots >/dev/null
f="$dir/paper-beam.h5"
h5dump -a /analysis_0_modes/frequencies_hz/unit "$f" | grep -q '"Hz"'
h5dump -d /analysis_0_modes/frequencies_hz "$f" | grep -q '49.88'
h5dump -H -d /analysis_1_harmonic/mobility "$f" | grep -q 'H5T_COMPOUND'
h5dump -d /case/toml "$f" | grep -q 'clamped'
echo "h5dump check: 4 passed, 0 failed"
