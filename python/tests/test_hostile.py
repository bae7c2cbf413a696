"""Hostile values from Python end with an exception naming where they are, never with the
interpreter taken down; results are never written over the files they came from.

The conversions that could crash run in a child interpreter, so that a crash fails this
test instead of ending the test run."""

from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import beamflow
from conftest import REPO

FRAME = "cases/beam-frame-12V-60Hz.toml"


def run_child(code: str) -> subprocess.CompletedProcess:
    """Runs `code` in a fresh interpreter that imports the same beamflow."""
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=REPO,
    )


def expect_input_error(code: str, *words: str) -> None:
    """`code` must raise beamflow.InputError, caught in the child, whose text holds `words`."""
    wrapped = f"""
import beamflow
try:
{textwrap.indent(textwrap.dedent(code), "    ")}
except beamflow.InputError as e:
    print("RAISED", e.field, "|", e)
else:
    print("NO EXCEPTION")
"""
    done = run_child(wrapped)
    assert done.returncode == 0, f"the interpreter died ({done.returncode}): {done.stderr[-2000:]}"
    assert done.stdout.startswith("RAISED"), done.stdout + done.stderr
    for w in words:
        assert w in done.stdout, (w, done.stdout)


def test_a_dict_nested_20000_deep_raises_naming_where() -> None:
    expect_input_error(
        """
        d = {}
        inner = d
        for _ in range(20000):
            inner["beam"] = {}
            inner = inner["beam"]
        beamflow.Case.from_dict(d)
        """,
        "nests more than",
        "beam.beam.beam",
    )


def test_a_dict_that_contains_itself_raises_naming_where() -> None:
    expect_input_error(
        """
        d = {"title": "loop", "beam": {}}
        d["beam"]["again"] = d
        beamflow.Case.from_dict(d)
        """,
        "contains itself",
        "beam.again",
    )


def test_a_list_that_contains_itself_raises_on_set() -> None:
    expect_input_error(
        f"""
        case = beamflow.Case.from_file({FRAME!r})
        xs = [1.0]
        xs.append(xs)
        case["actuator[0].voltage.amplitude"] = xs
        """,
        "contains itself",
        "actuator[0].voltage.amplitude[1]",
    )


def test_ordinary_nesting_still_converts() -> None:
    drive = {"kind": "sine", "amplitude": 12.0, "frequency": 60.0}
    case = beamflow.Case.from_dict({"actuator": [{"type": "inertial", "x_e": 0.15, "voltage": drive}]})
    assert case["actuator[0].voltage.frequency"] == 60.0


def test_results_are_not_written_over_their_case_file(tmp_path: Path) -> None:
    case_file = tmp_path / "frame.toml"
    shutil.copy(REPO / FRAME, case_file)
    before = case_file.read_bytes()
    res = beamflow.Case.from_file(case_file).run()
    with pytest.raises(beamflow.InputError, match="must not replace an input") as e:
        res.to_hdf5(case_file)
    assert e.value.field == "path"
    assert case_file.read_bytes() == before
    written = res.to_hdf5(tmp_path / "frame.h5")
    again = beamflow.read_results(written)
    with pytest.raises(beamflow.InputError, match="must not replace an input"):
        again.to_hdf5(written)
