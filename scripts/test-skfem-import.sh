#!/usr/bin/env bash
# Imports a Morley plate scikit-fem assembles and checks it against scikit-fem's own eigen,
# Navier's closed form and beamflow's native plate (scripts/skfem_import.py says what and
# how close). Installs scikit-fem, numpy and scipy in a virtualenv under target/ (wheels
# only: nothing from apt-get); fails with the reason when it cannot: the test never passes
# without running.
set -euo pipefail
cd "$(dirname "$0")/.."
WHAT="scikit-fem import"
# shellcheck source=scripts/lib/import-check.sh
source scripts/lib/import-check.sh

import_venv skfem-venv "scikit-fem==12.*" numpy scipy
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" scripts/skfem_import.py "$beamflow" "$work" || fail "see the table above"
