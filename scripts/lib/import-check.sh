# shellcheck shell=bash
# What the scripts that check an imported model against the code that built it share.
# Source this file from the repository's root, with WHAT set (the test's name in messages).
#
# fail REASON...: says the test failed and why, and exits 1.
# import_venv NAME PACKAGE...: builds beamflow (release) into $beamflow, and a virtualenv
#   target/NAME holding the PyPI packages into $python; fails when it cannot, so the test
#   never passes without running.
fail() {
    echo "$WHAT test FAILED: $*" >&2
    exit 1
}

import_venv() {
    local venv="${CARGO_TARGET_DIR:-target}/$1"
    shift
    cargo build --release --quiet
    beamflow="$(pwd)/${CARGO_TARGET_DIR:-target}/release/beamflow"
    if [ ! -x "$venv/bin/python" ]; then
        python3 -m venv "$venv" || fail "cannot create a virtualenv (Debian: apt-get install python3-venv)"
    fi
    "$venv/bin/pip" install --quiet --disable-pip-version-check "$@" || fail "cannot install $* from PyPI"
    python="$venv/bin/python"
}
