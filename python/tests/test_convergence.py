"""A transient that runs out of periods before it settles warns (`ConvergenceWarning`, a
`RuntimeWarning`) and says so on its results, where the command line prints "NOT settled";
its numbers are still the command line's, bit for bit."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import beamflow
from conftest import REPO, bits, run_cli


def frame_transient(max_periods: int) -> beamflow.Case:
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    case["analysis"] = [{"type": "transient", "max_periods": max_periods}]
    return case


def test_a_transient_that_did_not_settle_warns_and_says_so(cli: Path, tmp_path: Path) -> None:
    case = frame_transient(4)
    with pytest.warns(beamflow.ConvergenceWarning, match=r"NOT settled after 4 periods.*max_periods") as seen:
        res = case.run()
    assert issubclass(beamflow.ConvergenceWarning, RuntimeWarning)
    assert len(seen) == 1
    tr = res.analysis("transient")
    assert tr.settled is False
    assert res.warnings and "NOT settled" in res.warnings[0]
    assert "NOT settled" in res._repr_html_()

    # The command line says the same of the same case, and gives the same (unsettled) power.
    path = tmp_path / "unsettled.toml"
    path.write_text(case.to_toml())
    stdout = run_cli(cli, "run", str(path), "--out", str(tmp_path / "out"), "--no-plots")
    assert "NOT settled after 4 periods" in stdout
    summary = json.loads((tmp_path / "out" / "unsettled.json").read_text())
    cli_power = [summary["analyses"][0]["net_power_w"][name] for name in summary["actuators"]]
    assert np.array_equal(bits(np.array(cli_power)), bits(np.asarray(tr["net_power"])))


def test_a_settled_transient_does_not_warn() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error", beamflow.ConvergenceWarning)
        res = frame_transient(400).run()
    assert res.analysis("transient").settled is True
    assert res.warnings == []


def test_a_fixed_number_of_periods_has_nothing_to_settle() -> None:
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    case["analysis"] = [{"type": "transient", "periods": 3, "steady_state": False}, {"type": "steady_state"}]
    with warnings.catch_warnings():
        warnings.simplefilter("error", beamflow.ConvergenceWarning)
        res = case.run()
    assert [a.settled for a in res.analyses] == [None, None]
