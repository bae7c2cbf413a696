#!/usr/bin/env bash
# Make sure the HDF5 C library (headers + pkg-config file) and the `h5dump` tool are
# present, because:
#   * the `hdf5` crate (hdf5-metno) links the system libhdf5 and finds it via pkg-config;
#   * the results-file tests use `h5dump` as an independent reader to prove the files are
#     standard HDF5.
# Quiet when everything is already there. On Debian/Ubuntu it installs what is missing
# (as root, or through sudo); elsewhere it prints the install command and exits 1.
set -euo pipefail

have_lib() { command -v pkg-config >/dev/null 2>&1 && pkg-config --exists hdf5; }
have_dump() { command -v h5dump >/dev/null 2>&1; }

if have_lib && have_dump; then
    exit 0
fi

missing=()
have_lib || missing+=("HDF5 development files (pkg-config hdf5)")
have_dump || missing+=("h5dump")
list="$(printf '%s, ' "${missing[@]}")"
list="${list%, }"

# shellcheck source=SCRIPTDIR/lib/apt-install.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/apt-install.sh"
if command -v apt-get >/dev/null 2>&1 && apt_install "$list" libhdf5-dev pkg-config hdf5-tools; then
    if have_lib && have_dump; then
        exit 0
    fi
    echo "ensure-hdf5: apt-get finished but HDF5 is still not found" >&2
    exit 1
fi

cat >&2 <<MSG
ensure-hdf5: missing: ${list}
Install the HDF5 library, headers, pkg-config and tools, then retry:
  Debian/Ubuntu:  sudo apt-get update && sudo apt-get install -y libhdf5-dev pkg-config hdf5-tools
  Fedora/RHEL:    sudo dnf install -y hdf5-devel pkgconf-pkg-config hdf5
  macOS (Homebrew): brew install hdf5 pkg-config
    (and, if needed: export PKG_CONFIG_PATH="\$(brew --prefix hdf5)/lib/pkgconfig")
MSG
exit 1
