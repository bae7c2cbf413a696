#!/usr/bin/env bash
# The Python package's test: builds it from source into a fresh virtualenv exactly as the
# README says (`pip install ./python`), runs its pytest suite against this checkout's
# command line, and runs the example study (examples/python) headless.
#
# Needs what `make test` needs (Rust, the HDF5 library) plus Python ≥ 3.9 with venv and
# PyPI for numpy, scipy, pytest, h5py, pandas, matplotlib and the maturin build backend.
# On Debian/Ubuntu a missing venv module (python3-venv) is installed with apt-get.
set -euo pipefail
cd "$(dirname "$0")/.."

python=${PYTHON:-python3}
if ! command -v "$python" >/dev/null 2>&1 || ! "$python" -c 'import ensurepip, venv' >/dev/null 2>&1; then
    # shellcheck source=SCRIPTDIR/lib/apt-install.sh
    source scripts/lib/apt-install.sh
    apt_install "Python 3 with venv" python3 python3-venv
fi
"$python" -c 'import sys; sys.exit(sys.version_info < (3, 9))' || {
    echo "test-python: $("$python" --version) is too old; the package needs Python 3.9 or later" >&2
    exit 1
}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
venv="$work/venv"
start=$SECONDS
"$python" -m venv "$venv"
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q numpy scipy pytest h5py pandas matplotlib
echo "test-python: virtualenv with numpy, scipy, pytest, h5py, pandas, matplotlib ($((SECONDS - start)) s)"

# The command line the tests compare every number with.
cargo build --release --bin beamflow

start=$SECONDS
"$venv/bin/python" -m pip install -q ./python
echo "test-python: pip install ./python ($((SECONDS - start)) s)"

# Run from outside the source tree, so that the installed package is what is imported.
start=$SECONDS
(cd "$work" && BEAMFLOW_CLI="$OLDPWD/target/release/beamflow" "$venv/bin/python" -m pytest -q -p no:cacheprovider "$OLDPWD/python/tests")
echo "test-python: pytest ($((SECONDS - start)) s)"

out=out/python
rm -f "$out/placement_study.png"
MPLBACKEND=Agg "$venv/bin/python" examples/python/placement_study.py --out "$out"
test -s "$out/placement_study.png" || { echo "test-python: the example wrote no figure" >&2; exit 1; }
