"""A source build (`pip install ./python`) without the Rust it needs stops at once with
what to do, instead of maturin's silent download of a toolchain."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import REPO

HOOK = f"""
import sys
sys.path.insert(0, {str(REPO / "python" / "build_backend")!r})
import beamflow_build
beamflow_build.prepare_metadata_for_build_wheel(sys.argv[1])
"""


def backend(path: str, tmp_path: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("CARGO", "RUSTUP"))}
    env["PATH"] = path
    t = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", HOOK, str(tmp_path)], env=env, capture_output=True, text=True, timeout=60)
    assert time.perf_counter() - t < 10, "the check took long enough to have downloaded something"
    return done


def test_without_rust_the_build_says_what_to_do(tmp_path: Path) -> None:
    empty = tmp_path / "bin"
    empty.mkdir()
    done = backend(str(empty), tmp_path)
    assert done.returncode == 1
    for words in ("Rust >= 1.89", "no Rust toolchain", "wheel", "rustup", "libhdf5-dev", "No toolchain is downloaded"):
        assert words in done.stderr, (words, done.stderr)
    assert os.listdir(tmp_path) == ["bin"], "nothing is written"


@pytest.mark.skipif(sys.platform == "win32", reason="shell scripts stand in for the toolchain")
def test_an_old_rust_is_named(tmp_path: Path) -> None:
    fake = tmp_path / "bin"
    fake.mkdir()
    for tool, out in (("cargo", "cargo 1.80.0"), ("rustc", "rustc 1.80.1 (3f5fd8dd4 2024-08-06)")):
        (fake / tool).write_text(f"#!/bin/sh\necho '{out}'\n")
        (fake / tool).chmod(0o755)
    done = backend(str(fake), tmp_path)
    assert done.returncode == 1
    assert "found rustc 1.80 on PATH" in done.stderr, done.stderr
