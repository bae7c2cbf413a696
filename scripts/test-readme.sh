#!/usr/bin/env bash
# The README's examples, run as written from a fresh clone: every `beamflow …` and
# `cargo run …` line of the README's sh code blocks runs in a `git clone` of this
# repository's HEAD, in the clone's root, and must succeed. A command may write below
# out/ and the files it names itself (a redirect's target), and nothing else: no
# repository file changed, no stray output in the root.
#
# The clone reuses this checkout's release build: CARGO_TARGET_DIR points at this
# checkout's target/, and the clone's files are dated back so that cargo finds those
# artifacts fresh instead of rebuilding (the clone's sources are HEAD's; run on a clean
# checkout, as CI does, they are the sources of the build). `beamflow` itself resolves to
# the same binary.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$repo/target}
cargo build --release --bin beamflow
if [ -n "$(git status --porcelain --untracked-files=no)" ]; then
    echo "test-readme: note: uncommitted changes are not in the clone (it holds HEAD)" >&2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
clone="$work/beamflow"
git clone -q "$repo" "$clone"
find "$clone" -path "$clone/.git" -prune -o -exec touch -h -d @1 {} +
export PATH="$CARGO_TARGET_DIR/release:$PATH"

# Lines of ```sh / ```bash blocks whose command is beamflow or cargo run, with `\`
# continuations joined.
mapfile -t commands < <(awk '
    /^```(sh|bash|shell)[[:space:]]*$/ { inside = 1; next }
    /^```/ { inside = 0; next }
    inside {
        line = $0
        while (line ~ /\\$/ && (getline next_line) > 0) { sub(/\\$/, "", line); line = line next_line }
        sub(/^[[:space:]]+/, "", line)
        if (line ~ /^(beamflow|cargo run)([[:space:]]|$)/) print line
    }' "$clone/README.md")
if [ "${#commands[@]}" -eq 0 ]; then
    echo "test-readme: no beamflow or cargo run commands found in README.md" >&2
    exit 1
fi

# What is in the clone besides its committed files: changed tracked files and new files.
left() {
    git status --porcelain --untracked-files=all | sort
}

failed=0
cd "$clone"
for cmd in "${commands[@]}"; do
    start=$SECONDS
    before=$(left)
    if ! bash -c "$cmd" >"$work/stdout" 2>"$work/stderr"; then
        echo "test-readme: FAILED: $cmd" >&2
        tail -n 20 "$work/stderr" >&2
        failed=1
        continue
    fi
    # What this command left: changed tracked files, and new files outside out/ that the
    # command does not name.
    stray=$(comm -13 <(echo "$before") <(left) | while read -r status path; do
        if [ "$status" != "??" ]; then
            echo "$path (changed)"
        elif [[ $path != out/* ]] && [[ $cmd != *"$path"* ]]; then
            echo "$path"
        fi
    done)
    if [ -n "$stray" ]; then
        echo "test-readme: FAILED: $cmd wrote outside out/: $stray" >&2
        failed=1
        continue
    fi
    echo "test-readme: ok ($((SECONDS - start)) s): $cmd"
done
if [ "$failed" -ne 0 ]; then
    exit 1
fi
echo "test-readme: all ${#commands[@]} README commands ran from a fresh clone"
