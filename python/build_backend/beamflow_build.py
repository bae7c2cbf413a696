"""The build backend of ``pip install ./python``: maturin's, after checking that the Rust
toolchain the build needs is there.

Without this check, maturin's backend quietly downloads a Rust toolchain (about 1 GB) into
a temporary directory when ``cargo`` is not on PATH. A source build is for people who have
Rust; everyone else wants a wheel (docs/python.md), and is told so at once.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from typing import Any, List, Mapping, Optional

# The crate's rust-version (Cargo.toml): AVX-512 intrinsics.
RUST = (1, 89)

os.environ["MATURIN_NO_INSTALL_RUST"] = "1"


def _rustc_version() -> Optional[tuple]:
    if shutil.which("cargo") is None or shutil.which("rustc") is None:
        return None
    try:
        out = subprocess.run(["rustc", "--version"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    m = re.match(r"rustc (\d+)\.(\d+)", out)
    return (int(m.group(1)), int(m.group(2))) if m else None


def check_rust() -> None:
    """Stops the build with what to do when cargo and rustc ≥ 1.89 are not on PATH."""
    have = _rustc_version()
    if have is not None and have >= RUST:
        return
    found = "no Rust toolchain (cargo and rustc) on PATH" if have is None else f"rustc {have[0]}.{have[1]} on PATH"
    sys.stderr.write(
        f"\nbeamflow: building from source needs Rust >= {RUST[0]}.{RUST[1]} (cargo and rustc on PATH), "
        f"and found {found}.\n"
        "  * To install without Rust, install a wheel: pip install beamflow-<version>-<tags>.whl\n"
        "    (built by `bash scripts/test-python.sh`, or `maturin build --release --features static-hdf5`).\n"
        "  * To build from source, install Rust (https://rustup.rs, then `rustup update`) and the HDF5\n"
        "    C library with its headers (Debian/Ubuntu: apt-get install libhdf5-dev pkg-config).\n"
        "No toolchain is downloaded behind your back.\n\n"
    )
    sys.exit(1)


def _maturin() -> Any:
    import maturin

    return maturin


def get_requires_for_build_wheel(config_settings: Optional[Mapping[str, Any]] = None) -> List[str]:
    return _maturin().get_requires_for_build_wheel(config_settings)


def get_requires_for_build_sdist(config_settings: Optional[Mapping[str, Any]] = None) -> List[str]:
    return _maturin().get_requires_for_build_sdist(config_settings)


get_requires_for_build_editable = get_requires_for_build_wheel


def prepare_metadata_for_build_wheel(metadata_directory: str, config_settings: Optional[Mapping[str, Any]] = None) -> str:
    check_rust()
    return _maturin().prepare_metadata_for_build_wheel(metadata_directory, config_settings)


def build_wheel(
    wheel_directory: str, config_settings: Optional[Mapping[str, Any]] = None, metadata_directory: Optional[str] = None
) -> str:
    check_rust()
    return _maturin().build_wheel(wheel_directory, config_settings, metadata_directory)


def build_editable(
    wheel_directory: str, config_settings: Optional[Mapping[str, Any]] = None, metadata_directory: Optional[str] = None
) -> str:
    check_rust()
    return _maturin().build_editable(wheel_directory, config_settings, metadata_directory)


def build_sdist(sdist_directory: str, config_settings: Optional[Mapping[str, Any]] = None) -> str:
    check_rust()
    return _maturin().build_sdist(sdist_directory, config_settings)


prepare_metadata_for_build_editable = prepare_metadata_for_build_wheel
