"""Arrays of `Results` have the shapes, dtypes and units that docs/python.md documents:
the table there is checked against real runs in both directions (every documented row
is met, every dataset is documented)."""

from __future__ import annotations

import re
from typing import Dict, List, Tuple

import numpy as np
import pytest

import beamflow
from conftest import REPO

Row = Tuple[List[str], str, str, str, str]


def documented() -> List[Row]:
    text = (REPO / "docs" / "python.md").read_text()
    table = text.split("<!-- shapes-table -->")[1].split("<!-- /shapes-table -->")[0]
    rows = []
    for line in table.strip().splitlines()[2:]:
        kinds, name, shape, dtype, unit = [c.strip() for c in line.strip("|").split("|")]
        rows.append(([k.strip() for k in kinds.split(",")], name.strip("`"), shape, dtype, unit))
    assert len(rows) > 50
    return rows


def pattern(name: str) -> "re.Pattern[str]":
    parts = re.split(r"(<[a-z]+>)", name)
    return re.compile("^" + "".join("[^/]+" if p.startswith("<") else re.escape(p) for p in parts) + "$")


def runs() -> List[beamflow.Results]:
    frame = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml").to_dict()
    frame["sensor"] = [{"name": "midspan", "x": 0.365}]
    return [
        beamflow.Case.from_dict(frame, name="frame+sensor", base_dir="cases").run(),
        beamflow.Case.from_file("cases/beam-inertial-12V-60Hz.toml").run(),
        beamflow.Case.from_file("cases/paper-beam.toml").run(),
    ]


def symbols(res: beamflow.Results, a: beamflow.Group, kind: str) -> Dict[str, int]:
    spec = beamflow.Case.from_toml(res.case_toml).to_dict(defaults=True)
    s = {"N": len(res["model/node_x"])}  # type: ignore[arg-type]
    if kind == "model":
        return s
    entry = spec["analysis"][a.index]  # type: ignore[attr-defined]
    if kind == "modes":
        s["m"] = entry["count"]
    elif kind == "harmonic":
        s.update(F=len(a["frequency_hz"]), P=len(a["point_x"]), Q=len(entry["force"]))
    else:
        s.update(n_t=len(a["t"]), H=int(a.attrs["harmonics"]) + 1, L=len(a["link_names"]), A=len(res.actuators))
        if "modal" in a.groups:
            s["R"] = len(a["modal/mode_frequency_hz"])
            assert 1 <= s["R"] <= 30
    return s


def shape_of(expr: str, s: Dict[str, int]) -> Tuple[int, ...]:
    dims = [d.strip() for d in expr.strip("()").split(",") if d.strip()]
    return tuple(int(np.prod([s[f] for f in d.split("·")])) for d in dims)


def test_documented_shapes_dtypes_and_units() -> None:
    rows = documented()
    met = [0] * len(rows)
    checked = 0
    for res in runs():
        groups = [("model", res.groups["model"])] + [(a.kind, a) for a in res.analyses]
        for kind, g in groups:
            s = symbols(res, g, kind)
            base = g.path.rstrip("/") + "/"
            for path, value in g.walk():
                # `model/parameters/` holds the resolved case fields one by one (provenance,
                # docs/results-format.md), not arrays of results.
                skipped = path.startswith(base + "reduction/") or path.startswith(base + "parameters/")
                if not isinstance(value, beamflow.Quantity) or skipped:
                    continue
                rel = path[len(base):]
                found = [i for i, r in enumerate(rows) if kind in r[0] and pattern(r[1]).match(rel)]
                assert found, f"{path} ({kind}) is not documented in docs/python.md"
                _, name, shape, dtype, unit = rows[found[0]]
                assert value.dtype == np.dtype(dtype), (path, value.dtype, dtype)
                assert value.unit == unit, (path, value.unit, unit)
                assert value.shape == shape_of(shape, s), (path, value.shape, shape, s)
                assert value.description, path
                met[found[0]] += 1
                checked += 1
    unmet = [rows[i][1] for i, n in enumerate(met) if n == 0]
    assert not unmet, f"documented but never met: {unmet}"
    assert checked > 200


def test_quantities_keep_units_on_slices_not_through_arithmetic() -> None:
    res = beamflow.Case.from_file("cases/paper-beam.toml").run()
    f = res["analysis_0_modes/frequencies_hz"]
    assert isinstance(f, beamflow.Quantity) and f.unit == "Hz" and isinstance(f, np.ndarray)
    assert f[:3].unit == "Hz" and f[:3].description == f.description
    assert type(2 * np.pi * f) is np.ndarray and type(f.sum()) in (float, np.float64)
    assert float(f[0]) == res.summary["analyses"][0]["frequencies_hz"][0]
    import pickle

    g = pickle.loads(pickle.dumps(f))
    assert g.unit == "Hz" and np.array_equal(g, f)


def test_analysis_accessors_agree_with_the_tree(frame_results: beamflow.Results) -> None:
    ss = frame_results.analysis("steady_state")
    assert ss is frame_results.analysis(0) and ss.kind == "steady_state"
    assert list(ss.net_power) == frame_results.actuators == ["frame"]
    assert list(ss.net_power.values()) == list(ss["net_power"])  # type: ignore[arg-type]
    assert list(ss.mean_power) == ss.link_names == ["frame_stack", "frame_left_leg", "frame_right_leg"]
    p = ss.point_power("frame_stack")
    assert p.unit == "W" and p.shape == (int(ss.attrs["harmonics"]) + 1,)
    # The mean power is the sum of the power per harmonic (the spectra are independent of it).
    assert ss.mean_power["frame_stack"] == pytest.approx(float(np.sum(p)), rel=1e-9)
    # Net power per actuator: the sum over its links.
    assert ss.net_power["frame"] == pytest.approx(sum(ss.mean_power.values()), rel=1e-12)
    assert ss.balance["balance_error"] < 1e-6
    tr = frame_results.analysis("transient")
    assert set(tr.balance) >= {"energy_run.beam", "energy_run.system", "final_change"}
    assert tr.modal is None and ss.modal is not None and ss.reduction is None
    with pytest.raises(KeyError, match="no analysis"):
        frame_results.analysis("harmonic")
    modes = beamflow.Case.from_file("cases/paper-beam.toml").run().analysis("modes")
    with pytest.raises(AttributeError, match="modes analysis"):
        modes.net_power
