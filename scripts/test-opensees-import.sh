#!/usr/bin/env bash
# Imports a model OpenSees exports and checks it against OpenSees' own eigen and against
# beamflow's native beam (scripts/opensees_import.py says what and how close). Installs
# openseespy, numpy and scipy in a virtualenv under target/, and the system BLAS and LAPACK
# the openseespy wheel links (Debian's libblas3, liblapack3) with apt-get when missing; fails
# with the reason when it cannot: the test never passes without running.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=scripts/lib/apt-install.sh
source scripts/lib/apt-install.sh

fail() {
    echo "OpenSees import test FAILED: $*" >&2
    exit 1
}

cargo build --release --quiet
beamflow="$(pwd)/${CARGO_TARGET_DIR:-target}/release/beamflow"
venv="${CARGO_TARGET_DIR:-target}/opensees-venv"
if ! ldconfig -p | grep -q 'libblas.so.3' || ! ldconfig -p | grep -q 'liblapack.so.3'; then
    apt_install "BLAS and LAPACK (for openseespy)" libblas3 liblapack3 || fail "no system BLAS/LAPACK"
fi
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv" || fail "cannot create a virtualenv (Debian: apt-get install python3-venv)"
fi
"$venv/bin/pip" install --quiet --disable-pip-version-check openseespy==3.7.1.2 numpy scipy ||
    fail "cannot install openseespy, numpy and scipy from PyPI"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$venv/bin/python" scripts/opensees_import.py "$beamflow" "$work" || fail "see the table above"
