#!/usr/bin/env bash
# Make sure `cargo fuzz` and the nightly toolchain it needs are present (the fuzz targets in
# fuzz/ build with libFuzzer and sanitizer flags only nightly Rust accepts). Quiet when both
# are there; installs cargo-fuzz with `cargo install --locked` when it is missing.
set -euo pipefail

if ! rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
    echo "ensure-fuzz: installing the nightly toolchain (rustup toolchain install nightly)" >&2
    rustup toolchain install nightly --profile minimal
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "ensure-fuzz: installing cargo-fuzz (cargo install cargo-fuzz --locked)" >&2
    cargo install cargo-fuzz --locked
fi
