"""Sweeps through Python equal the command line's sweep table, bit for bit."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import beamflow
from conftest import bits, run_cli

SWEEP = "cases/placement-inertial.sweep.toml"


@pytest.fixture(scope="module")
def cli_table(cli: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("sweep") / "table.h5"
    run_cli(cli, "sweep", SWEEP, "--out", str(out), "--no-plots")
    return out


def cli_columns(path: Path) -> dict:
    """The command line's table read with h5py, named as the Python columns."""
    with h5py.File(path, "r") as f:
        t = f["table"]
        acts = list(t["actuators"].asstr()[()])
        links = list(t["links"].asstr()[()])
        params = list(t["parameters"].asstr()[()])
        cols = {"case": (t["case_index"][()], "1")}
        for name in params:
            ds = next(d for d in t["inputs"].values() if d.attrs["description"].endswith(f"`{name}`"))
            cols[name] = (ds[()], ds.attrs["unit"])
        for i, a in enumerate(acts):
            cols[f"net_power[{a}]"] = (t["net_power"][:, i], "W")
        for key, unit in (("mean_power", "W"), ("force_amplitude", "N")):
            for i, l in enumerate(links):
                cols[f"{key}[{l}]"] = (t[key][:, i], unit)
        cols["beam_dissipation"] = (t["beam_dissipation"][()], "W")
        cols["balance_error"] = (t["balance_error"][()], "1")
    return cols


def assert_table_equals(table: beamflow.SweepTable, expected: dict) -> None:
    assert list(table) == list(expected)
    for name, (values, unit) in expected.items():
        col = table[name]
        assert col.unit == unit, name
        assert col.dtype == values.dtype and col.shape == values.shape, name
        assert np.array_equal(bits(np.asarray(col)), bits(values)), f"column {name} differs"


def test_python_sweep_equals_the_cli_table(cli_table: Path) -> None:
    table = beamflow.sweep(SWEEP, as_frame=False)
    assert isinstance(table, beamflow.SweepTable)
    expected = cli_columns(cli_table)
    assert table.rows > 100
    assert_table_equals(table, expected)
    # One thread gives the same bits.
    assert_table_equals(beamflow.sweep(SWEEP, as_frame=False, threads=1), expected)
    # And the command line's file read back.
    assert_table_equals(beamflow.read_sweep_table(cli_table, as_frame=False), expected)


def test_a_sweep_given_as_a_dict(cli_table: Path) -> None:
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+; the package itself needs 3.9

    spec = tomllib.loads(Path(SWEEP).read_text())
    spec["base"] = "placement-inertial.toml"
    table = beamflow.sweep(spec, base_dir="cases", as_frame=False)
    assert_table_equals(table, cli_columns(cli_table))


def test_dataframe_with_units() -> None:
    pd = pytest.importorskip("pandas")
    df = beamflow.sweep(
        {
            "base": "cases/placement-frame.toml",
            "parameter": [{"path": "actuator[0].x_e", "values": [0.1, 0.2, 0.3]}],
        }
    )
    assert isinstance(df, pd.DataFrame) and df.index.name == "case" and list(df.index) == [0, 1, 2]
    assert list(df["actuator[0].x_e"]) == [0.1, 0.2, 0.3]
    assert df.attrs["units"]["net_power[frame]"] == "W" and df.attrs["units"]["actuator[0].x_e"] == "m"
    # Each row equals a case run with the same value (the sweep's fast path vs run_case).
    case = beamflow.Case.from_file("cases/placement-frame.toml")
    case["actuator[0].x_e"] = 0.2
    one = case.run().analysis("steady_state").net_power["frame"]
    assert df["net_power[frame]"][1] == pytest.approx(one, rel=1e-9)


def test_bad_sweeps_raise_with_the_field() -> None:
    with pytest.raises(beamflow.InputError) as e:
        beamflow.sweep({"base": "cases/placement-frame.toml", "parameter": [{"path": "actuator[0].x_e", "values": [0.1, 0.9]}]})
    assert (e.value.file, e.value.field) == ("<dict>", "parameter[0].values")
    with pytest.raises(beamflow.InputError) as e:
        beamflow.sweep({"base": "cases/placement-frame.toml", "parameter": [{"path": "actuator[0].x_ee", "values": [0.1]}]})
    assert e.value.field == "parameter[0].path" and "x_ee" in e.value.reason
    with pytest.raises(beamflow.InputError, match="base"):
        beamflow.sweep({"base": "nowhere.toml", "parameter": [{"path": "actuator[0].x_e", "values": [0.1]}]})
    with pytest.raises(beamflow.IoError):
        beamflow.sweep("cases/absent.sweep.toml")


def test_a_case_object_as_the_base(tmp_path: Path) -> None:
    """A case changed in Python is swept as it stands; files it names still resolve."""
    case = beamflow.Case.from_file("cases/placement-inertial.toml")
    case["actuator[0].voltage.amplitude"] = 6.0
    params = [{"path": "actuator[0].x_e", "values": [0.1, 0.3]}]
    table = beamflow.sweep({"base": case, "parameter": params}, as_frame=False)
    # The same sweep from a file holding the changed case.
    (tmp_path / "changed.toml").write_text(case.to_toml())
    expected = beamflow.sweep({"base": str(tmp_path / "changed.toml"), "parameter": params}, as_frame=False)
    for name in expected:
        assert np.array_equal(bits(np.asarray(table[name])), bits(np.asarray(expected[name]))), name
    full = beamflow.sweep({"base": "cases/placement-inertial.toml", "parameter": params}, as_frame=False)
    # 6 V instead of 12 V: a quarter of the power, up to the stack's hysteresis.
    ratio = table["net_power[inertial]"] / full["net_power[inertial]"]
    assert np.all((ratio > 0.2) & (ratio < 0.3)), ratio
    # A voltage series named relative to the case file.
    (tmp_path / "cases").mkdir()
    t = np.arange(0, 0.5, 1e-4)
    np.savetxt(tmp_path / "cases" / "drive.csv", np.c_[t, 12 * np.sin(2 * np.pi * 60 * t)], delimiter=",", header="t,u", comments="")
    d = case.to_dict()
    d["actuator"][0]["voltage"] = {"kind": "series", "file": "drive.csv", "time_column": "t", "voltage_column": "u"}
    series = beamflow.Case.from_dict(d, name="series", base_dir=tmp_path / "cases")
    assert series["actuator[0].voltage.file"] == "drive.csv"
    from beamflow._commands import standalone

    written = beamflow.Case.from_file(standalone(series, tmp_path))
    assert written["actuator[0].voltage.file"] == str((tmp_path / "cases" / "drive.csv").resolve())
    # The series was found and read from the temporary base; the sweep then refuses it for
    # the reason a series has, not for a missing file.
    with pytest.raises(beamflow.InputError, match="non-periodic drive"):
        beamflow.sweep({"base": series, "parameter": params}, as_frame=False)


def test_pandas_is_optional(monkeypatch: pytest.MonkeyPatch) -> None:
    import subprocess
    import sys

    code = "import sys, beamflow; bad = {'pandas', 'matplotlib'} & set(sys.modules); assert not bad, bad"
    subprocess.run([sys.executable, "-c", code], check=True)
    import beamflow._sweep as sweep_module

    monkeypatch.setattr(sweep_module, "_have_pandas", lambda: False)
    table = beamflow.sweep({"base": "cases/placement-frame.toml", "parameter": [{"path": "actuator[0].x_e", "values": [0.2]}]})
    assert isinstance(table, beamflow.SweepTable) and table["net_power[frame]"].unit == "W"
    assert table.units["actuator[0].x_e"] == "m" and table.rows == 1
