"""A sweep spread over a Dask cluster of two worker processes gives the table of one
process, bit for bit."""

from __future__ import annotations

import pickle
from pathlib import Path
from typing import Any, Dict, Iterator, List

import numpy as np
import pytest

import beamflow
from conftest import bits

distributed = pytest.importorskip("distributed")

SWEEP = "cases/placement-inertial.sweep.toml"


@pytest.fixture(scope="module")
def client() -> Iterator[Any]:
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as c:
            yield c


def assert_same_table(a: beamflow.SweepTable, b: beamflow.SweepTable) -> None:
    assert list(a) == list(b) and a.rows == b.rows
    for name in a:
        x, y = np.asarray(a[name], dtype=np.float64), np.asarray(b[name], dtype=np.float64)
        assert np.array_equal(bits(x), bits(y)), name
    assert a.meta == b.meta


def test_a_two_worker_cluster_gives_the_one_process_table(client: Any, tmp_path: Path) -> None:
    assert len(client.scheduler_info()["workers"]) == 2
    events: List[Dict[str, Any]] = []
    spread = beamflow.sweep(SWEEP, client=client, as_frame=False, progress=events.append)
    one = beamflow.sweep(SWEEP, as_frame=False, threads=1)
    assert_same_table(spread, one)
    assert events[-1]["done"] == events[-1]["total"] and events[-1]["unit"] == "shards"
    # Written to a table, with the files beside it, as `beamflow merge` writes them.
    written = beamflow.sweep(SWEEP, client=client, out=tmp_path / "t.h5", csv=True, plots=False, as_frame=False)
    assert_same_table(written, one)
    assert (tmp_path / "t.csv").exists()


def test_a_case_dict_and_a_frame_on_the_cluster(client: Any) -> None:
    pytest.importorskip("pandas")
    spec = {"base": "cases/placement-frame.toml", "parameter": [{"path": "actuator[0].x_e", "values": [0.1, 0.2, 0.3]}]}
    frame = beamflow.sweep(spec, client=client)
    assert frame.equals(beamflow.sweep(spec))


@pytest.mark.parametrize("objectives", [1, 2], ids=["one objective", "pareto"])
def test_an_optimisation_on_the_cluster_is_the_one_process_optimisation(client: Any, objectives: int) -> None:
    spec = {
        "base": "cases/placement-frame.toml",
        "harmonics": 5,
        "search": {"seed": 2, "starts": 2, "evaluations": 24, "top": 3, "pareto_points": 3},
        "variable": [{"path": "actuator[0].x_e", "min": 0.1, "max": 0.6}],
        "objective": [{"quantity": "net_power", "goal": "maximize"}, {"quantity": "dissipation", "goal": "minimize"}][
            :objectives
        ],
    }
    events: List[Dict[str, Any]] = []
    spread = beamflow.optimize(spec, client=client, as_frame=False, progress=events.append)
    one = beamflow.optimize(spec, as_frame=False, threads=1)
    assert spread.evaluations == one.evaluations
    for name, text in one.texts.items():
        if name != "summary.json":
            assert spread.texts[name] == text, name
    for s in (spread.summary, one.summary):
        s.pop("seconds")
    assert spread.summary == one.summary
    assert events[-1]["done"] == spread.evaluations


def test_errors_on_the_workers_arrive_whole(client: Any) -> None:
    with pytest.raises(beamflow.InputError) as e:
        beamflow.sweep(SWEEP, client=client, max_steps=2)
    assert e.value.field == "parameter" and "max_steps" in e.value.reason
    with pytest.raises(beamflow.InputError) as e:
        beamflow.sweep(SWEEP, client=client, shard="1/2")
    assert e.value.field == "shard"


def test_errors_pickle_with_their_fields() -> None:
    for err in (
        beamflow.InputError("a.toml", "x", "too big"),
        beamflow.FieldNotFound("a.toml", "y", "no such field"),
        beamflow.ParseError("a.toml", "line 1"),
        beamflow.IoError("a.h5", "gone", 2),
        beamflow.Hdf5Error("a.h5", "bad"),
        beamflow.NumericalError("singular"),
    ):
        back = pickle.loads(pickle.dumps(err))
        assert type(back) is type(err) and str(back) == str(err) and vars(back) == vars(err)
