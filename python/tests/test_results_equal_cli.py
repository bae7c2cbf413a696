"""Every number of `Case.run()` equals the command line's HDF5 and JSON for the shipped
cases, bit for bit; so do `read_results` of the command line's file and `to_hdf5`."""

from __future__ import annotations

from pathlib import Path
from typing import Dict, Tuple

import pytest

import beamflow
from conftest import CASES, REPO, assert_same, h5_contents, load_json, tree_contents

CASE_NAMES = [str(c.relative_to(REPO)) for c in CASES]
CREATED = ("/@created",)


@pytest.fixture(scope="module")
def python_runs() -> Dict[str, beamflow.Results]:
    import os

    os.chdir(REPO)
    return {name: beamflow.Case.from_file(name).run() for name in CASE_NAMES}


def test_the_shipped_cases_are_all_there() -> None:
    assert len(CASE_NAMES) >= 6 and "cases/beam-frame-12V-60Hz.toml" in CASE_NAMES


@pytest.mark.parametrize("name", CASE_NAMES)
def test_results_equal_the_cli_hdf5_bit_for_bit(
    name: str, python_runs: Dict[str, beamflow.Results], cli_runs: Dict[str, Tuple[Path, Path]]
) -> None:
    h5, _ = cli_runs[name]
    numbers = assert_same(h5_contents(h5), tree_contents(python_runs[name]), ignore=CREATED)
    assert numbers > 100


@pytest.mark.parametrize("name", CASE_NAMES)
def test_summary_equals_the_cli_json(
    name: str, python_runs: Dict[str, beamflow.Results], cli_runs: Dict[str, Tuple[Path, Path]]
) -> None:
    _, js = cli_runs[name]
    # JSON floats are written shortest-round-trip, so equality here is equality of bits.
    assert python_runs[name].summary == load_json(js)


@pytest.mark.parametrize("name", CASE_NAMES)
def test_read_results_of_the_cli_file_equals_the_run(
    name: str, python_runs: Dict[str, beamflow.Results], cli_runs: Dict[str, Tuple[Path, Path]]
) -> None:
    h5, _ = cli_runs[name]
    read = beamflow.read_results(h5)
    assert_same(tree_contents(python_runs[name]), tree_contents(read), ignore=CREATED)
    with pytest.raises(AttributeError, match="summary"):
        read.summary


@pytest.mark.parametrize("name", CASE_NAMES)
def test_to_hdf5_writes_the_cli_file(
    name: str, python_runs: Dict[str, beamflow.Results], cli_runs: Dict[str, Tuple[Path, Path]], tmp_path: Path
) -> None:
    h5, _ = cli_runs[name]
    mine = python_runs[name].to_hdf5(tmp_path / "mine.h5")
    assert_same(h5_contents(h5), h5_contents(mine), ignore=CREATED)
    assert h5_contents(mine)["/@"]["created"] == python_runs[name].attrs["created"]


def test_a_changed_value_is_seen_by_the_comparison(
    python_runs: Dict[str, beamflow.Results], cli_runs: Dict[str, Tuple[Path, Path]]
) -> None:
    """The comparison itself can fail: one ulp in one number is found."""
    import numpy as np

    name = "cases/beam-frame-12V-60Hz.toml"
    got = tree_contents(python_runs[name])
    key = "/analysis_0_steady_state/net_power"
    value, attrs = got[key]
    got[key] = (np.nextafter(value, np.inf), attrs)
    with pytest.raises(AssertionError, match="values differ"):
        assert_same(h5_contents(cli_runs[name][0]), got, ignore=CREATED)


def test_figures_are_the_cli_figures(cli: Path, tmp_path: Path) -> None:
    from conftest import run_cli

    name = "cases/beam-frame-12V-60Hz.toml"
    run_cli(cli, "run", name, "--out", str(tmp_path / "cli"))
    cli_figs = sorted(p.name for p in (tmp_path / "cli").iterdir() if p.suffix in (".png", ".svg"))
    mine = beamflow.Case.from_file(name).run().write_figures(tmp_path / "py")
    assert sorted(p.name for p in mine) == cli_figs and len(cli_figs) >= 10
    for p in mine:
        head = p.read_bytes()[:8]
        assert head == b"\x89PNG\r\n\x1a\n" if p.suffix == ".png" else head.startswith(b"<svg") or b"<svg" in p.read_bytes()[:200]
    with pytest.raises(AttributeError, match="figures"):
        beamflow.read_results(cli_runs_file(tmp_path / "cli")).write_figures(tmp_path / "none")


def cli_runs_file(directory: Path) -> Path:
    return next(directory.glob("*.h5"))
