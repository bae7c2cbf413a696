#!/usr/bin/env bash
# The run report (report.html) in a real browser: runs a shipped case, opens its report in
# headless Chromium (installed with apt-get when missing, as ensure-hdf5.sh does for HDF5)
# offline, and fails on any console message (the page has no script, so any message is an
# error: a resource it could not load, a parse error) or when the rendered page holds fewer
# <svg> figures than the run wrote SVG files. Keeps the DOM and a screenshot when
# KEEP_REPORT=<dir> is set.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bin=${BEAMFLOW:-target/release/beamflow}
case_file=${REPORT_CASE:-cases/beam-frame-12V-60Hz.toml}
[ -x "$bin" ] || cargo build --release --quiet

browser=""
for b in chromium chromium-browser; do
    command -v "$b" >/dev/null 2>&1 && browser=$b && break
done
if [ -z "$browser" ]; then
    # shellcheck source=SCRIPTDIR/lib/apt-install.sh
    source scripts/lib/apt-install.sh
    apt_install "Chromium (headless browser for the report test)" chromium
    browser=chromium
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" --quiet run "$case_file" --out "$tmp/run"
report="$tmp/run/report.html"
[ -s "$report" ] || { echo "test-report: $report was not written" >&2; exit 1; }

# Self-contained: nothing loaded from another file, and no script.
if grep -Eiq '<(img|script|link|iframe|object|embed)[ >]| src=' "$report"; then
    echo "test-report: the report loads something from outside itself or holds a script:" >&2
    grep -Eio '<(img|script|link|iframe|object|embed)[ >][^>]*|src="[^"]*"' "$report" | head >&2
    exit 1
fi
# Offline: no address the page could fetch (the SVG namespace is a name, not a fetch).
if grep -Eo '(src|href)="[a-z]+://[^"]*"|url\([^)]*://' "$report" | grep -q .; then
    echo "test-report: the report refers to an external resource:" >&2
    grep -Eo '(src|href)="[a-z]+://[^"]*"|url\([^)]*://' "$report" >&2
    exit 1
fi

flags=(--headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking
    --disable-extensions --disable-sync --user-data-dir="$tmp/profile" --enable-logging=stderr --v=0)
timeout 120 "$browser" "${flags[@]}" --dump-dom "file://$report" >"$tmp/dom.html" 2>"$tmp/console.log" || {
    echo "test-report: $browser failed; its log:" >&2
    tail -n 30 "$tmp/console.log" >&2
    exit 1
}
timeout 120 "$browser" "${flags[@]}" --window-size=1280,2400 --screenshot="$tmp/shot.png" \
    "file://$report" >/dev/null 2>>"$tmp/console.log" || true

# Console messages (errors, failed loads) of the page.
if grep -E 'CONSOLE|Uncaught|Failed to load' "$tmp/console.log" | grep -q .; then
    echo "test-report: console messages while loading the report:" >&2
    grep -E 'CONSOLE|Uncaught|Failed to load' "$tmp/console.log" >&2
    exit 1
fi

figures=$(find "$tmp/run" -maxdepth 1 -name '*.svg' | wc -l)
shown=$(grep -o '<svg' "$tmp/dom.html" | wc -l)
title=$(grep -o '<h1>[^<]*' "$tmp/dom.html" | head -n 1 | sed 's/<h1>//')
if [ "$figures" -eq 0 ] || [ "$shown" -ne "$figures" ]; then
    echo "test-report: the rendered report shows $shown figures, the run wrote $figures SVG files" >&2
    exit 1
fi
[ -s "$tmp/shot.png" ] || { echo "test-report: no screenshot was taken" >&2; exit 1; }
if [ -n "${KEEP_REPORT:-}" ]; then
    mkdir -p "$KEEP_REPORT"
    cp "$report" "$tmp/dom.html" "$tmp/shot.png" "$tmp/console.log" "$KEEP_REPORT/"
fi
echo "test-report: '$title' renders in $browser with $shown figures and no console messages"
