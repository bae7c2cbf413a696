#!/usr/bin/env bash
# Smoke run of the fuzz targets (fuzz/, cargo fuzz on nightly): each target runs for
# FUZZ_SECONDS (default 60) from the seed corpus — the shipped cases, meshes and CSV files,
# the bad-input table and every crash kept as a regression (tests/data/hostile/fuzz/) — so
# the regressions are replayed first. Exits non-zero on a crash, a hang (FUZZ_TIMEOUT s per
# input, default 10) or a memory blow-up (FUZZ_RSS_MB, default 2048), leaving the input in
# fuzz/artifacts/<target>/. A longer run: FUZZ_SECONDS=3600 bash scripts/test-fuzz.sh, or
# see docs/testing.md.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/ensure-fuzz.sh"
seconds="${FUZZ_SECONDS:-60}"
timeout_s="${FUZZ_TIMEOUT:-10}"
rss="${FUZZ_RSS_MB:-2048}"
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=(case csv mesh sweep optimize)
reg="$root/tests/data/hostile/fuzz"

cd "$root/fuzz"
cargo +nightly fuzz build -O
for t in "${targets[@]}"; do
    case "$t" in
        case) seeds=("$root/cases" "$root/tests/data/hostile/names" "$root/tests/data/hostile/paths" "$reg") ;;
        csv) seeds=("$root/fuzz/seeds/csv" "$root/tests/data" "$reg/csv") ;;
        mesh) seeds=("$root/meshes" "$reg/mesh") ;;
        # The shipped studies, copied apart from the cases they name as their base.
        sweep | optimize)
            ext=$([[ $t == sweep ]] && echo sweep || echo opt)
            mkdir -p "corpus/seeds-$t"
            cp "$root"/cases/*."$ext".toml "corpus/seeds-$t/"
            seeds=("$root/fuzz/corpus/seeds-$t" "$reg/$t") ;;
        *) echo "test-fuzz: unknown target $t (case, csv, mesh, sweep, optimize)" >&2; exit 2 ;;
    esac
    existing=()
    for s in "${seeds[@]}"; do [[ -d "$s" ]] && existing+=("$s"); done
    mkdir -p "corpus/$t"
    echo "test-fuzz: $t for ${seconds} s"
    if ! cargo +nightly fuzz run -O "$t" "corpus/$t" "${existing[@]}" -- \
        -max_total_time="$seconds" -timeout="$timeout_s" -rss_limit_mb="$rss" -max_len=8192 \
        -print_final_stats=1 2>"corpus/$t.log"; then
        tail -60 "corpus/$t.log" >&2
        echo "test-fuzz: target $t failed; the input is in fuzz/artifacts/$t/. Fix the cause and keep the" \
            "input as a regression in tests/data/hostile/fuzz/ (see docs/testing.md)." >&2
        exit 1
    fi
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "corpus/$t.log" | sed "s/^/  $t: /"
done
