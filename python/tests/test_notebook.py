"""What a notebook and a process pool need: `Case` and `Results` pickle and come back
equal, cases compare by content, both show as HTML, and results come as pandas DataFrames
equal to the command line's CSV tables bit for bit (units in the column names)."""

from __future__ import annotations

import csv
import pickle
from pathlib import Path

import numpy as np
import pytest

import beamflow
from conftest import assert_same, bits, run_cli, tree_contents

CASE = "cases/beam-frame-12V-60Hz.toml"


def test_a_case_pickles_and_comes_back_equal() -> None:
    case = beamflow.Case.from_file(CASE)
    case["actuator[0].x_e"] = 0.2
    back = pickle.loads(pickle.dumps(case))
    assert back == case and back is not case
    assert back.to_toml() == case.to_toml()
    assert (back.file, back.base_dir) == (case.file, case.base_dir)
    assert back["actuator[0].x_e"] == 0.2


def test_cases_are_equal_by_content() -> None:
    a = beamflow.Case.from_file(CASE)
    b = beamflow.Case.from_toml(Path(CASE).read_text(), name="other label", base_dir="cases")
    assert a == b
    b["damping.zeta"] = 0.01  # the default, now written: the same case
    assert a == b
    b["actuator[0].x_e"] = 0.2
    assert a != b
    assert a != beamflow.Case.from_toml(Path(CASE).read_text(), base_dir="/")  # files resolve elsewhere
    assert a != "a case"
    with pytest.raises(TypeError):
        hash(a)


def test_results_pickle_and_come_back_equal_bit_for_bit(frame_results: beamflow.Results) -> None:
    back = pickle.loads(pickle.dumps(frame_results))
    assert assert_same(tree_contents(frame_results), tree_contents(back)) > 100
    assert back.summary == frame_results.summary
    assert [a.kind for a in back.analyses] == [a.kind for a in frame_results.analyses]


def test_html_views(frame_results: beamflow.Results) -> None:
    case = beamflow.Case.from_file(CASE)
    page = case._repr_html_()
    assert "beamflow.Case" in page and "frame" in page and "steady_state" in page and "<pre>" in page
    page = frame_results._repr_html_()
    assert "beamflow.Results" in page and "steady_state" in page and "settled" in page
    net = frame_results.analysis("steady_state").net_power["frame"]
    assert f"{net:.4g} W" in page


def test_tables_are_the_cli_csv_bit_for_bit(frame_results: beamflow.Results, cli: Path, tmp_path: Path) -> None:
    pytest.importorskip("pandas")
    run_cli(cli, "run", CASE, "--out", str(tmp_path), "--no-plots", "--csv")
    files = {p.name[len("beam-frame-12V-60Hz_"):-len(".csv")]: p for p in tmp_path.glob("*.csv")}
    tables = frame_results.tables()
    assert sorted(tables) == sorted(files)
    for name, path in files.items():
        # Read with the csv module: float() reads the shortest round-trip text back exactly.
        with open(path, newline="") as f:
            header, *rows = list(csv.reader(f))
        got = tables[name]
        assert list(got.columns) == header, name
        for j, col in enumerate(header):
            cells, g = [r[j] for r in rows], got[col].to_numpy()
            if g.dtype.kind == "f":
                assert np.array_equal(bits(np.array([float(c) for c in cells])), bits(g)), (name, col)
            elif g.dtype.kind in "iu":
                assert [int(c) for c in cells] == g.tolist(), (name, col)
            else:
                assert cells == [str(x) for x in g], (name, col)
    ss = frame_results.analysis("steady_state")
    points = ss.table("point_power")
    assert any(c.endswith("[W]") for c in points.columns), list(points.columns)
    assert set(ss.tables()) >= {"point_power", "net_power", "spectra", "series"}
    with pytest.raises(KeyError, match="no table"):
        ss.table("nothing")
