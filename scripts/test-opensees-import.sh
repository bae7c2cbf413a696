#!/usr/bin/env bash
# Imports a model OpenSees exports and checks it against OpenSees' own eigen and against
# beamflow's native beam (scripts/opensees_import.py says what and how close). Installs
# openseespy, numpy and scipy in a virtualenv under target/, and the system BLAS and LAPACK
# the openseespy wheel links (Debian's libblas3, liblapack3) with apt-get when missing; fails
# with the reason when it cannot: the test never passes without running.
set -euo pipefail
cd "$(dirname "$0")/.."
WHAT="OpenSees import"
# shellcheck source=scripts/lib/apt-install.sh
source scripts/lib/apt-install.sh
# shellcheck source=scripts/lib/import-check.sh
source scripts/lib/import-check.sh

if ! ldconfig -p | grep -q 'libblas.so.3' || ! ldconfig -p | grep -q 'liblapack.so.3'; then
    apt_install "BLAS and LAPACK (for openseespy)" libblas3 liblapack3 || fail "no system BLAS/LAPACK"
fi
import_venv opensees-venv openseespy==3.7.1.2 numpy scipy
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" scripts/opensees_import.py "$beamflow" "$work" || fail "see the table above"
