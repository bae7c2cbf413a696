"""The `beamflow` command installed with the package runs the command line's own main:
the same files, output and exit status as the binary."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import List

import pytest

from conftest import REPO, assert_same, h5_contents, load_json

CASE = "cases/beam-frame-12V-60Hz.toml"


def commands() -> List[List[str]]:
    """`python -m beamflow`, and the console script when the package is installed (a
    development tree has none)."""
    found = [[sys.executable, "-m", "beamflow"]]
    script = Path(sys.executable).parent / "beamflow"
    if os.environ.get("BEAMFLOW_INSTALLED"):
        assert script.exists(), f"the installed package has no console script at {script}"
    if script.exists():
        found.append([str(script)])
    return found


def run(cmd: List[str], *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([*cmd, *args], cwd=REPO, capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("cmd", commands(), ids=lambda c: Path(c[-1]).name)
def test_run_writes_the_binarys_files(cmd: List[str], cli: Path, tmp_path: Path) -> None:
    outs = {}
    for name, prog in (("binary", [str(cli)]), ("python", cmd)):
        d = tmp_path / name
        done = run(prog, "run", CASE, "--out", str(d), "--no-plots")
        assert done.returncode == 0, done.stderr
        outs[name] = (done.stdout.replace(str(d), "OUT"), d / "beam-frame-12V-60Hz.h5", d / "beam-frame-12V-60Hz.json")
    (text_b, h5_b, js_b), (text_p, h5_p, js_p) = outs["binary"], outs["python"]
    assert text_p == text_b
    assert load_json(js_p) == load_json(js_b)
    assert_same(h5_contents(h5_b), h5_contents(h5_p), ignore=("/@created",)) > 100


@pytest.mark.parametrize("cmd", commands(), ids=lambda c: Path(c[-1]).name)
@pytest.mark.parametrize(
    "args",
    [["--version"], ["check", CASE], ["check", "cases/no-such-case.toml"], ["run"], ["no-such-command"]],
    ids=["version", "check", "missing-file", "missing-argument", "unknown-command"],
)
def test_output_and_exit_status_are_the_binarys(cmd: List[str], args: List[str], cli: Path) -> None:
    want, got = run([str(cli)], *args), run(cmd, *args)
    assert (got.returncode, got.stdout, got.stderr) == (want.returncode, want.stdout, want.stderr)
