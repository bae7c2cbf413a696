"""Imported models from matrices in memory: scipy.sparse M and K and a DOF table give the
closed-form modes of a spring–mass chain, the command line's numbers bit for bit on the
same files, and a bad matrix raises naming the file and the entry."""

from __future__ import annotations

import json
import subprocess
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse

import beamflow
from conftest import run_cli

M_KG, K_NM = 2.0, 8.0e4
DOFS = [(1, 10, 0.0, 0.0, 0.0, "uz"), (2, 11, 1.0, 0.0, 0.0, "uz")]


def chain(tmp_path: Path, k12: float = -K_NM) -> dict:
    """Two masses on springs, ground–m–m: ω² = (k/m)·(3 ∓ √5)/2."""
    m = scipy.sparse.diags([M_KG, M_KG]).tocsr()
    k = scipy.sparse.csr_matrix(np.array([[2 * K_NM, k12], [-K_NM, K_NM]]))
    return beamflow.imported(m, k, DOFS, folder=tmp_path / "model")


def case_dict(table: dict) -> dict:
    return {
        "imported": table,
        "damping": {"kind": "rayleigh", "a0": 2.0, "a1": 1e-5},
        "actuator": [{"type": "inertial", "node": 11, "component": "uz", "stack": {"hysteresis": False},
                      "voltage": {"kind": "sine", "amplitude": 1.0, "frequency": 10.0}}],
        "analysis": [{"type": "modes", "count": 2}, {"type": "steady_state"}],
    }


def test_a_chain_from_scipy_sparse_has_its_closed_form_modes(tmp_path: Path) -> None:
    res = beamflow.Case.from_dict(case_dict(chain(tmp_path))).run()
    f = np.asarray(res.analysis("modes")["frequencies_hz"])
    exact = [math.sqrt(K_NM / M_KG * (3 + s * math.sqrt(5)) / 2) / (2 * math.pi) for s in (-1, 1)]
    assert np.allclose(f, exact, rtol=1e-12, atol=0), (f, exact)


def test_python_and_the_command_line_agree_bit_for_bit(tmp_path: Path, cli: Path) -> None:
    case = case_dict(chain(tmp_path))
    toml = tmp_path / "chain.toml"
    model = case["imported"]
    lines = ["[imported]"] + [f'{k} = "{v}"' for k, v in model.items()]
    lines += ["[damping]", 'kind = "rayleigh"', "a0 = 2.0", "a1 = 1e-5",
              "[[actuator]]", 'type = "inertial"', "node = 11", 'component = "uz"',
              "[actuator.stack]", "hysteresis = false",
              "[actuator.voltage]", 'kind = "sine"', "amplitude = 1.0", "frequency = 10.0",
              "[[analysis]]", 'type = "modes"', "count = 2", "[[analysis]]", 'type = "steady_state"']
    toml.write_text("\n".join(lines) + "\n")
    run_cli(cli, "run", str(toml), "--out", str(tmp_path / "out"), "--no-plots")
    cli_json = json.loads((tmp_path / "out" / "chain.json").read_text())
    res = beamflow.Case.from_dict(case).run()
    assert res.analysis("steady_state").mean_power["inertial_stack"] == cli_json["analyses"][1]["mean_power_w"]["inertial_stack"]
    assert list(res.analysis("modes")["frequencies_hz"]) == cli_json["analyses"][0]["frequencies_hz"]


def test_a_non_symmetric_stiffness_raises_naming_the_file(tmp_path: Path) -> None:
    case = case_dict(chain(tmp_path, k12=-1.5 * K_NM))
    with pytest.raises(beamflow.InputError, match=r"K\.mtx.*not symmetric"):
        beamflow.Case.from_dict(case).run()


def test_a_dof_table_with_a_missing_column_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="missing column"):
        beamflow.imported(np.eye(1), np.eye(1), {"row": [1], "node": [1]}, folder=tmp_path)


PORTAL = "cases/portal-frame/portal-frame.toml"


def test_an_unknown_node_is_refused_at_once_as_beamflow_check_refuses_it(tmp_path: Path, cli: Path) -> None:
    text = Path(PORTAL).read_text().replace('at = [0.45, 1.0, 0.0]', "node = 9999", 1)
    bad = Path("cases/portal-frame") / f"nonode-{tmp_path.name}.toml"
    bad.write_text(text)
    try:
        cli_says = subprocess.run([str(cli), "check", str(bad)], capture_output=True, text=True)
        assert cli_says.returncode != 0 and "9999" in cli_says.stderr
        with pytest.raises(beamflow.InputError) as e:
            beamflow.Case.from_file(str(bad))
        assert str(e.value).strip() in cli_says.stderr, (str(e.value), cli_says.stderr)
    finally:
        bad.unlink()
    case = beamflow.Case.from_file(PORTAL)
    with pytest.raises(beamflow.InputError, match="9999"):
        case["actuator[0].node"] = 9999
    assert "node" not in case.to_dict()["actuator"][0], "a refused change changes nothing"
    actuator = {k: v for k, v in case.to_dict()["actuator"][0].items() if k != "at"}
    with pytest.raises(beamflow.InputError, match="9999"):
        beamflow.Case.from_dict({**case.to_dict(), "actuator": [{**actuator, "node": 9999}]}, base_dir="cases/portal-frame")


def test_modes_of_a_plate_and_an_imported_model_place_their_nodes() -> None:
    plate = beamflow.Case.from_file("cases/plate-frame.toml").modes(3)
    assert plate.node_y is not None and len(plate.node_y) == len(plate.node_x) == plate.shapes.shape[1]
    assert plate.node_z is None
    portal = beamflow.Case.from_file(PORTAL).modes(3)
    assert len(portal.node_z) == len(portal.node_y) == len(portal.node_id) == len(portal.node_x)
    assert beamflow.Case.from_file("cases/paper-beam.toml").modes(3).node_y is None


def test_dof_maps_of_a_plate_and_an_imported_model_place_their_rows() -> None:
    plate = beamflow.Case.from_file("cases/plate-frame.toml").system()
    d = plate.dofs
    w = d.where("w")
    assert len(w) > 0 and d.y is not None and d.z is None and d.node_id is None
    # Every row of one node sits at that node's (x, y); a body row has no position.
    by_node = {n: (x, y) for n, x, y in zip(d.node[w], np.asarray(d.x)[w], np.asarray(d.y)[w])}
    for kind in ("w_x", "w_y", "w_xy"):
        rows = [i for i in d.where(kind) if d.node[i] in by_node]  # nodes whose w is free
        assert rows, kind
        for i in rows:
            assert by_node[d.node[i]] == (float(d.x[i]), float(d.y[i])), (kind, i)
    body = [i for i, a in enumerate(d.actuator) if a]
    assert body and np.isnan(np.asarray(d.y)[body]).all()
    assert 0 <= np.nanmin(d.x) and 0 <= np.nanmin(d.y) and np.nanmax(d.y) > 0
    portal = beamflow.Case.from_file(PORTAL).system()
    p = portal.dofs
    assert p.z is not None and p.node_id is not None and p.y is not None
    structure = [i for i, a in enumerate(p.actuator) if not a]
    assert (p.node_id[structure] >= 0).all() and (p.node_id[[i for i in range(len(p)) if i not in structure]] == -1).all()
    # The source model's DOF map places its nodes where beamflow's rows say they are.
    folder = Path(PORTAL).parent
    table = {int(r[1]): (float(r[2]), float(r[3]), float(r[4])) for r in (l.split(",") for l in (folder / "portal_dofs.csv").read_text().splitlines()[1:] if l)}
    for i in structure:
        assert table[int(p.node_id[i])] == (float(p.x[i]), float(p.y[i]), float(p.z[i]))


def test_a_plates_steady_state_states_its_grids_error_as_the_command_line_does(cli_runs: dict) -> None:
    """The grid's error estimate (against half the elements each way) is in the results
    and the summary, and is the command line's to the last bit."""
    results = beamflow.Case.from_file("cases/plate-frame.toml").run()
    ss = results.analysis("steady_state")
    mesh = ss.mesh_estimate
    assert mesh is not None and list(mesh["coarse_elements"]) == [10, 8]
    relative = np.asarray(mesh["relative_error"])
    assert relative.shape == (3,) and (relative > 0).all()
    assert ss.balance["mesh_max_relative_error"] == float(mesh.attrs["max_relative_error"]) >= relative.max()
    _, js = cli_runs["cases/plate-frame.toml"]
    cli = json.loads(Path(js).read_text())["analyses"][0]["mesh_estimate"]
    assert cli["max_relative_error"] == ss.balance["mesh_max_relative_error"]
    assert results.summary["analyses"][0]["mesh_estimate"] == cli
    assert beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml").run().analysis("steady_state").mesh_estimate is None
