#!/usr/bin/env bash
# The reports in a real browser: runs a shipped case, a small sweep and the paper's
# experiments, opens each report in headless Chromium (installed with apt-get when missing,
# as ensure-hdf5.sh does for HDF5) offline, and fails on any console message (the pages
# have no script, so any message is an error: a resource it could not load, a parse error)
# or when a rendered page holds another number of <svg> figures than its run wrote figure
# files. Then shoots one figure's SVG standalone and compares it with beamflow's PNG of it
# (scripts/figure_pixels.py). Keeps each DOM and a screenshot when KEEP_REPORT=<dir> is set.
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
flags=(--headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking
    --disable-extensions --disable-sync --user-data-dir="$tmp/profile" --enable-logging=stderr --v=0)

# check_report NAME REPORT FIGURES: REPORT must be self-contained, load in the browser with
# no console message and show FIGURES <svg> figures.
check_report() {
    local name=$1 report=$2 figures=$3 work="$tmp/$1"
    mkdir -p "$work"
    [ -s "$report" ] || { echo "test-report: $report was not written" >&2; exit 1; }
    # Self-contained: nothing loaded from another file, and no script.
    if grep -Eiq '<(img|script|link|iframe|object|embed)[ >]| src=' "$report"; then
        echo "test-report: $name loads something from outside itself or holds a script:" >&2
        grep -Eio '<(img|script|link|iframe|object|embed)[ >][^>]*|src="[^"]*"' "$report" | head >&2
        exit 1
    fi
    # Offline: no address the page could fetch (the SVG namespace is a name, not a fetch).
    if grep -Eo '(src|href)="[a-z]+://[^"]*"|url\([^)]*://' "$report" | grep -q .; then
        echo "test-report: $name refers to an external resource:" >&2
        grep -Eo '(src|href)="[a-z]+://[^"]*"|url\([^)]*://' "$report" >&2
        exit 1
    fi
    timeout 120 "$browser" "${flags[@]}" --dump-dom "file://$report" >"$work/dom.html" 2>"$work/console.log" || {
        echo "test-report: $browser failed on $name; its log:" >&2
        tail -n 30 "$work/console.log" >&2
        exit 1
    }
    timeout 120 "$browser" "${flags[@]}" --window-size=1280,2400 --screenshot="$work/shot.png" \
        "file://$report" >/dev/null 2>>"$work/console.log" || true
    # Console messages (errors, failed loads) of the page.
    if grep -E 'CONSOLE|Uncaught|Failed to load' "$work/console.log" | grep -q .; then
        echo "test-report: console messages while loading $name:" >&2
        grep -E 'CONSOLE|Uncaught|Failed to load' "$work/console.log" >&2
        exit 1
    fi
    local shown title
    shown=$(grep -o '<svg' "$work/dom.html" | wc -l)
    title=$(grep -o '<h1>[^<]*' "$work/dom.html" | head -n 1 | sed 's/<h1>//')
    if [ "$figures" -eq 0 ] || [ "$shown" -ne "$figures" ]; then
        echo "test-report: the rendered $name report shows $shown figures, expected $figures" >&2
        exit 1
    fi
    [ -s "$work/shot.png" ] || { echo "test-report: no screenshot of $name was taken" >&2; exit 1; }
    if [ -n "${KEEP_REPORT:-}" ]; then
        mkdir -p "$KEEP_REPORT/$name"
        cp "$report" "$work/dom.html" "$work/shot.png" "$work/console.log" "$KEEP_REPORT/$name/"
    fi
    echo "test-report: $name: '$title' renders in $browser with $shown figures and no console messages"
}

count() { find "$1" -maxdepth 1 -name "$2" | wc -l; }

# A case run: one inline figure per SVG file the run wrote.
"$bin" --quiet run "$case_file" --out "$tmp/run"
check_report run "$tmp/run/report.html" "$(count "$tmp/run" '*.svg')"

# A small sweep (the shipped placement study's base case, 4 × 3 positions and
# frequencies): its figure, written as PNG, inline as SVG.
cp cases/placement-frame.toml "$tmp/"
cat >"$tmp/small.sweep.toml" <<'SWEEP'
title = "Placement sweep, 4 positions x 3 frequencies"
base = "placement-frame.toml"
analysis = "steady_state"
harmonics = 3
[[parameter]]
path = "actuator[0].x_e"
start = 0.1
stop = 0.6
count = 4
[[parameter]]
path = "actuator[0].voltage.frequency"
start = 40.0
stop = 80.0
count = 3
SWEEP
"$bin" --quiet sweep "$tmp/small.sweep.toml" --out "$tmp/sweep/small.h5" >/dev/null
check_report sweep "$tmp/sweep/small.report.html" "$(count "$tmp/sweep" '*.png')"

# The paper's experiments (Figs. 8-16), unless REPORT_PAPER=0 skips them.
if [ "${REPORT_PAPER:-1}" != 0 ]; then
    "$bin" --quiet paper --out "$tmp/paper" >/dev/null
    check_report paper "$tmp/paper/report.html" "$(count "$tmp/paper" '*.svg')"
fi

# One figure's SVG shot in the browser at the size of beamflow's PNG of it: text and lines in
# the same places, and the PNG's line edges anti-aliased (scripts/figure_pixels.py says how
# and with which thresholds); its self-test shows both checks fail on a spoiled PNG.
if ! command -v python3 >/dev/null 2>&1; then
    # shellcheck source=SCRIPTDIR/lib/apt-install.sh
    source scripts/lib/apt-install.sh
    apt_install "Python 3 (figure pixel checks)" python3
fi
figures=$tmp/figures
if [ ! -s "$tmp/paper/fig08_transmitted_forces.svg" ]; then
    "$bin" --quiet paper --out "$figures" >/dev/null
else
    figures=$tmp/paper
fi
svg=$figures/fig08_transmitted_forces.svg png=${svg%.svg}.png
read -r width height < <(python3 scripts/figure_pixels.py size "$png")
{
    printf '<!DOCTYPE html><html><head><style>'
    printf 'html,body{margin:0;padding:0;overflow:hidden;background:#fff}svg{display:block}'
    printf '</style></head><body>\n'
    cat "$svg"
    printf '</body></html>\n'
} >"$tmp/figure.html"
timeout 120 "$browser" "${flags[@]}" --hide-scrollbars --force-device-scale-factor=1 \
    --window-size="$width,$height" --screenshot="$tmp/figure-shot.png" \
    "file://$tmp/figure.html" >/dev/null 2>>"$tmp/figure-console.log" || true
[ -s "$tmp/figure-shot.png" ] || { echo "test-report: no screenshot of $svg was taken" >&2; exit 1; }
python3 scripts/figure_pixels.py same "$tmp/figure-shot.png" "$png"
python3 scripts/figure_pixels.py antialiased "$png"
python3 scripts/figure_pixels.py self-test "$tmp/figure-shot.png" "$png"
[ -z "${KEEP_REPORT:-}" ] || cp "$tmp/figure-shot.png" "$png" "$KEEP_REPORT/"
