# The two commands of the README. Both make sure the HDF5 C library is installed first
# (scripts/ensure-hdf5.sh installs it with apt-get on Debian/Ubuntu, or says how).
.PHONY: paper test test-report test-slurm test-python deps

# The main job: every experiment of the paper, figures, HDF5 files and a summary in out/paper.
paper: deps
	cargo run --release -- paper --out out/paper

# The whole test suite in release mode (the physics tests run long time integrations),
# then the report.html of a run, of a small sweep and of the paper's experiments are
# rendered in headless Chromium (installed with apt-get if missing) and must load with no
# console message and show every figure, then an outside
# HDF5 reader (h5dump) checks that a result file is standard HDF5, then the
# model OpenSees exports is imported and checked against OpenSees' eigen and the native
# beam (scripts/test-opensees-import.sh; openseespy from PyPI in a virtualenv), a Morley
# plate scikit-fem assembles against scikit-fem's eigen, Navier's closed form and the native
# plate (scripts/test-skfem-import.sh; scikit-fem from PyPI in a virtualenv), then the
# Slurm job array of docs/sweeps.md runs on a one-node cluster on localhost (slurm-wlm and
# munge are installed with apt-get if missing; needs root or passwordless sudo), the
# Python package is built as a manylinux wheel with HDF5 inside, installed into a fresh
# virtualenv without Rust and tested (scripts/test-python.sh), and
# every command of the README runs as written in a fresh clone (scripts/test-readme.sh), and
# each fuzz target runs for a minute (scripts/test-fuzz.sh, docs/testing.md).
test: deps
	cargo test --release
	bash scripts/test-report.sh
	bash scripts/check-results-with-h5dump.sh
	bash scripts/test-opensees-import.sh
	bash scripts/test-skfem-import.sh
	bash scripts/test-readme.sh
	bash scripts/test-slurm.sh
	bash scripts/test-python.sh
	bash scripts/test-fuzz.sh

# The Python package's build, tests and example alone.
test-python: deps
	bash scripts/test-python.sh

# The report's browser test alone.
test-report: deps
	bash scripts/test-report.sh

# The Slurm test alone.
test-slurm: deps
	bash scripts/test-slurm.sh

deps:
	@bash scripts/ensure-hdf5.sh
