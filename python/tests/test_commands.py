"""The command line's other commands from Python — optimize, sweep into a table with shards
and resume, merge, paper, identify, synth — equal the command line's outputs bit for bit,
and their bad arguments raise errors that name the Python argument."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List

import numpy as np
import pytest

import beamflow
from conftest import bits, run_cli

SWEEP = "cases/placement-inertial.sweep.toml"
IDENT = Path("cases/identification")

ONE_OBJECTIVE = """
base = "{base}"
harmonics = 5
[search]
seed = 3
starts = 2
evaluations = 30
top = 3
[[variable]]
path = "actuator[0].x_e"
min = 0.1
max = 0.6
[[objective]]
quantity = "net_power"
goal = "maximize"
"""

TWO_OBJECTIVES = ONE_OBJECTIVE.replace("top = 3", "top = 3\npareto_points = 4") + """
[[objective]]
quantity = "dissipation"
goal = "minimize"
"""


def spec_file(tmp_path: Path, text: str) -> Path:
    base = (Path.cwd() / "cases" / "placement-frame.toml").resolve()
    p = tmp_path / "study.opt.toml"
    p.write_text(text.format(base=base), encoding="utf-8")
    return p


def csv_numbers(path: Path) -> Dict[str, np.ndarray]:
    """A CSV table of the command line read with numpy's own parser (not the package's)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    header = [h.strip('"') for h in lines[0].split(",")]
    rows = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    return {h: rows[:, k] for k, h in enumerate(header)}


def assert_frame_equals_csv(frame: Any, path: Path) -> None:
    expected = csv_numbers(path)
    assert list(frame.columns) == list(expected)
    for name, col in expected.items():
        got = np.asarray(frame[name], dtype=np.float64)
        assert np.array_equal(bits(got), bits(col)), name


@pytest.mark.parametrize("text", [ONE_OBJECTIVE, TWO_OBJECTIVES], ids=["one objective", "pareto"])
def test_optimize_equals_the_cli(cli: Path, tmp_path: Path, text: str) -> None:
    spec = spec_file(tmp_path, text)
    run_cli(cli, "optimize", str(spec), "--out", str(tmp_path / "cli"), "--no-plots")
    events: List[Dict[str, Any]] = []
    r = beamflow.optimize(spec, out=tmp_path / "py", plots=False, threads=2, progress=events.append)
    names = ["best.toml", "history.csv", "optima.csv"] + (["pareto.csv"] if "pareto" in text else [])
    for name in names:
        cli_text = (tmp_path / "cli" / name).read_text(encoding="utf-8")
        assert (tmp_path / "py" / name).read_text(encoding="utf-8") == cli_text, name
        assert r.texts[name] == cli_text, name
    assert sorted(p.name for p in r.files) == sorted(names + ["summary.json", "report.html"])
    cli_summary = json.loads((tmp_path / "cli" / "summary.json").read_text(encoding="utf-8"))
    for s in (cli_summary, r.summary):
        s.pop("seconds")
    assert r.summary == cli_summary
    assert_frame_equals_csv(r.history, tmp_path / "cli" / "history.csv")
    assert_frame_equals_csv(r.optima, tmp_path / "cli" / "optima.csv")
    if "pareto" in text:
        assert_frame_equals_csv(r.pareto, tmp_path / "cli" / "pareto.csv")
    else:
        assert r.pareto is None
    # The best case is the command line's best.toml, its paths resolving from the base
    # case's folder.
    best = beamflow.Case.from_file(tmp_path / "cli" / "best.toml")
    assert r.best.to_dict() == best.to_dict()
    assert r.best.base_dir.resolve() == (Path.cwd() / "cases").resolve()
    assert r.best["actuator[0].x_e"] == r.summary["best"]["variables"]["actuator[0].x_e"]
    assert events[-1]["task"] == "optimize" and events[-1]["done"] == r.evaluations
    assert events[-1]["unit"] == "evaluations"


def test_optimize_without_out_or_pandas(tmp_path: Path) -> None:
    spec = spec_file(tmp_path, ONE_OBJECTIVE)
    r = beamflow.optimize(spec, as_frame=False)
    assert r.files == [] and not list(tmp_path.glob("out*"))
    assert isinstance(r.history, dict) and r.history["evaluation"].dtype == np.int64
    assert len(r.history["evaluation"]) == r.evaluations
    # A dict with a Case as its base gives the same optimisation.
    d = {
        "base": beamflow.Case.from_file("cases/placement-frame.toml"),
        "harmonics": 5,
        "search": {"seed": 3, "starts": 2, "evaluations": 30, "top": 3},
        "variable": [{"path": "actuator[0].x_e", "min": 0.1, "max": 0.6}],
        "objective": [{"quantity": "net_power", "goal": "maximize"}],
    }
    assert beamflow.optimize(d, as_frame=False).texts["optima.csv"] == r.texts["optima.csv"]


def test_optimize_stops_when_the_progress_callback_raises(tmp_path: Path) -> None:
    text = ONE_OBJECTIVE.replace("evaluations = 30", "evaluations = 3000")
    spec = spec_file(tmp_path, text)
    seen: List[int] = []

    class Stop(Exception):
        pass

    def stop(e: Dict[str, Any]) -> None:
        seen.append(e["done"])
        if e["done"] > 0:
            raise Stop

    with pytest.raises(Stop):
        beamflow.optimize(spec, progress=stop, threads=1)
    assert seen and seen[-1] > 0


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"max_steps": 3}, "search.evaluations"),
        ({"max_memory": "-1"}, "max_memory"),
        ({"max_steps": "many"}, "max_steps"),
        ({"threads": 0}, "threads"),
        ({"max_memory": [1]}, "max_memory"),
    ],
)
def test_optimize_bad_arguments_name_the_argument(tmp_path: Path, kwargs: Dict[str, Any], field: str) -> None:
    spec = spec_file(tmp_path, ONE_OBJECTIVE)
    with pytest.raises(beamflow.InputError) as e:
        beamflow.optimize(spec, **kwargs)
    assert e.value.field == field
    assert "--" not in str(e.value), "the message names a command-line flag"


def table_bits(t: beamflow.SweepTable) -> Dict[str, np.ndarray]:
    return {k: bits(np.asarray(c, dtype=np.float64)) for k, c in t.items()}


def assert_tables_equal(a: beamflow.SweepTable, b: beamflow.SweepTable) -> None:
    assert list(a) == list(b)
    for k, col in table_bits(a).items():
        assert np.array_equal(col, table_bits(b)[k]), k


def test_sweep_shards_and_merge_equal_the_cli(cli: Path, tmp_path: Path) -> None:
    c, p = tmp_path / "cli", tmp_path / "py"
    for k in (1, 2):
        run_cli(cli, "sweep", SWEEP, "--out", str(c / f"s{k}.h5"), "--shard", f"{k}/2", "--no-plots")
        t = beamflow.sweep(SWEEP, out=p / f"s{k}.h5", shard=f"{k}/2", plots=False, as_frame=False)
        assert_tables_equal(t, beamflow.read_sweep_table(c / f"s{k}.h5", as_frame=False))
    run_cli(cli, "merge", str(c / "s1.h5"), str(c / "s2.h5"), "--out", str(c / "all.h5"), "--csv")
    files = beamflow.merge([p / "s1.h5", p / "s2.h5"], p / "all.h5", csv=True)
    assert "all.csv" in {f.name for f in files} and any(f.suffix == ".html" for f in files)
    assert all(f.exists() for f in files)
    assert sorted(f.name for f in files) == sorted(f.name for f in c.iterdir() if f.name not in ("s1.h5", "s2.h5", "all.h5"))
    assert (p / "all.csv").read_text(encoding="utf-8") == (c / "all.csv").read_text(encoding="utf-8")
    merged = beamflow.read_sweep_table(p / "all.h5", as_frame=False)
    assert_tables_equal(merged, beamflow.read_sweep_table(c / "all.h5", as_frame=False))
    assert_tables_equal(merged, beamflow.sweep(SWEEP, as_frame=False))


def test_sweep_into_a_table_resumes_after_an_interrupt(tmp_path: Path) -> None:
    out = tmp_path / "table.h5"

    class Stop(Exception):
        pass

    def stop(e: Dict[str, Any]) -> None:
        if e["done"] > 0:
            raise Stop

    with pytest.raises(Stop):
        beamflow.sweep(SWEEP, out=out, plots=False, threads=1, progress=stop)
    assert not out.exists()
    t = beamflow.sweep(SWEEP, out=out, plots=False, as_frame=False)
    assert_tables_equal(t, beamflow.sweep(SWEEP, as_frame=False))
    assert not Path(f"{out}.parts").exists()


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"shard": "3/2"}, "shard"),
        ({"shard": "1/2"}, "shard"),
        ({"csv": True, "out": "table.csv"}, "out"),
        ({"max_steps": 2, "out": "t.h5"}, "parameter"),
    ],
)
def test_sweep_bad_arguments_name_the_argument(tmp_path: Path, kwargs: Dict[str, Any], field: str) -> None:
    if "out" in kwargs:
        kwargs["out"] = tmp_path / kwargs["out"]
    with pytest.raises(beamflow.InputError) as e:
        beamflow.sweep(SWEEP, plots=False, **kwargs)
    assert e.value.field == field, e.value
    assert "--" not in str(e.value), "the message names a command-line flag"


def test_merge_bad_arguments_name_the_argument(tmp_path: Path) -> None:
    with pytest.raises(beamflow.InputError) as e:
        beamflow.merge([], tmp_path / "all.h5")
    assert e.value.field == "shards"
    with pytest.raises(beamflow.InputError) as e:
        beamflow.merge(str(tmp_path / "a.h5"), tmp_path / "all.h5")  # type: ignore[arg-type]
    assert e.value.field == "shards"


def test_paper_equals_the_cli(cli: Path, tmp_path: Path) -> None:
    run_cli(cli, "paper", "--out", str(tmp_path / "cli"))
    summary = beamflow.paper(tmp_path / "py")
    assert summary == json.loads((tmp_path / "cli" / "summary.json").read_text(encoding="utf-8"))
    assert sorted(f.name for f in (tmp_path / "py").iterdir()) == sorted(f.name for f in (tmp_path / "cli").iterdir())
    with pytest.raises(beamflow.InputError) as e:
        beamflow.paper(tmp_path / "small", max_steps=10)
    assert "max_steps" in str(e.value) and "--" not in str(e.value)


def read_columns(path: Path) -> Dict[str, np.ndarray]:
    """A measurement CSV as arrays by quantity name (the header's units are SI)."""
    lines = [l for l in path.read_text(encoding="utf-8").splitlines() if not l.startswith("#")]
    names = [h.split(" (")[0] for h in lines[0].split(",")]
    rows = np.array([[float(x) for x in l.split(",")] for l in lines[1:]])
    return {n: rows[:, k] for k, n in enumerate(names)}


def test_identify_dp_equals_the_cli_on_files_and_arrays(cli: Path, tmp_path: Path) -> None:
    a, b = str(IDENT / "dp-pair_1.csv"), str(IDENT / "dp-pair_2.csv")
    run_cli(cli, "identify", "dp", a, b, "--out", str(tmp_path / "cli"), "--no-plots")
    r = beamflow.identify.dp(a, b, out=tmp_path / "py", plots=False)
    for name in ("dp.json", "dp.toml"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert r.values == json.loads((tmp_path / "cli" / "dp.json").read_text(encoding="utf-8"))
    assert r.fragment == (tmp_path / "cli" / "dp.toml").read_text(encoding="utf-8")
    arrays = beamflow.identify.dp(read_columns(IDENT / "dp-pair_1.csv"), read_columns(IDENT / "dp-pair_2.csv"))
    for key in ("d_p", "delta_v", "std_error", "residual_rms", "shift"):
        assert arrays[key] == r[key], key


def test_identify_bouc_wen_equals_the_cli(cli: Path, tmp_path: Path) -> None:
    f = str(IDENT / "stroke.csv")
    flags = ["--d-p", "1.3e-7", "--seeds", "1,2", "--particles", "8", "--max-iterations", "15"]
    run_cli(cli, "identify", "bouc-wen", f, *flags, "--out", str(tmp_path / "cli"), "--no-plots")
    r = beamflow.identify.bouc_wen(f, d_p=1.3e-7, seeds=[1, 2], particles=8, max_iterations=15, out=tmp_path / "py", plots=False)
    for name in ("bouc-wen.json", "bouc-wen.toml"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert r.values == json.loads((tmp_path / "cli" / "bouc-wen.json").read_text(encoding="utf-8"))


def test_identify_modal_equals_the_cli(cli: Path, tmp_path: Path) -> None:
    f = str(IDENT / "impact-stack.csv")
    run_cli(cli, "identify", "modal", f, "--mass", "0.315", "--out", str(tmp_path / "cli"), "--no-plots")
    r = beamflow.identify.modal(f, mass=0.315, out=tmp_path / "py", plots=False)
    for name in ("modal.json", "modal.toml"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert r.values == json.loads((tmp_path / "cli" / "modal.json").read_text(encoding="utf-8"))
    assert r.report.startswith("impact test")


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: beamflow.identify.dp(IDENT / "dp-pair_1.csv", IDENT / "dp-pair_2.csv", offset_tolerance=-1), "offset_tolerance"),
        (lambda: beamflow.identify.dp(IDENT / "dp-pair_1.csv", IDENT / "dp-pair_2.csv", k_p=0.0), "k_p"),
        (lambda: beamflow.identify.dp(IDENT / "dp-pair_1.csv", IDENT / "dp-pair_2.csv", uniform_tolerance=2), "uniform_tolerance"),
        (lambda: beamflow.identify.dp({"time": [0, 1], "volts": [1, 2]}, IDENT / "dp-pair_2.csv"), "first"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=1.3e-7, target="force"), "k_p"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=1.3e-7, target="strain"), "target"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=1.3e-7, particles=1), "particles"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=1.3e-7, cycles=-1), "cycles"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=1.3e-7, seeds=[-2]), "seeds[0]"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=-1.0), "d_p"),
        (lambda: beamflow.identify.modal(IDENT / "impact-stack.csv", mass=0.315, element="arm"), "element"),
        (lambda: beamflow.identify.modal(IDENT / "impact-stack.csv", mass=0.315, band=(1.0,)), "band"),
        (lambda: beamflow.identify.modal(IDENT / "impact-stack.csv", mass=-1.0), "mass"),
        (lambda: beamflow.identify.modal(IDENT / "impact-stack.csv", mass=0.3, band=(10.0, "x")), "band[1]"),
        (lambda: beamflow.identify.dp(IDENT / "dp-pair_1.csv", IDENT / "dp-pair_2.csv", k_p="x"), "k_p"),
        (lambda: beamflow.identify.bouc_wen(IDENT / "stroke.csv", d_p=1.3e-7, max_iterations=2.5), "max_iterations"),
        (lambda: beamflow.sweep(SWEEP, threads=-1), "threads"),
        (lambda: beamflow.optimize("cases/two_frames.opt.toml", threads=-2), "threads"),
        (lambda: beamflow.synth("cases/rigid-base-48V-30Hz.toml", "x.csv", kind="sine"), "kind"),
        (lambda: beamflow.synth("cases/rigid-base-48V-30Hz.toml", "x.csv", seed=-1), "seed"),
        (lambda: beamflow.synth("cases/rigid-base-48V-30Hz.toml", "x.h5"), "out"),
    ],
)
def test_identify_and_synth_bad_arguments_name_the_argument(call: Any, field: str) -> None:
    with pytest.raises(beamflow.InputError) as e:
        call()
    assert e.value.field == field, e.value
    assert "--" not in str(e.value), "the message names a command-line flag"


@pytest.mark.parametrize("kind", ["stroke", "dp_pair", "impact"])
def test_synth_equals_the_cli(cli: Path, tmp_path: Path, kind: str) -> None:
    case = "cases/rigid-base-48V-30Hz.toml"
    run_cli(cli, "synth", case, "--out", str(tmp_path / "cli" / "m.csv"), "--kind", kind.replace("_", "-"), "--seed", "5")
    r = beamflow.synth(case, tmp_path / "py" / "m.csv", kind=kind, seed=5)
    assert r["files"] and len(r["files"]) == len(r["samples"])
    for f in r["files"]:
        assert f.read_bytes() == (tmp_path / "cli" / f.name).read_bytes()
    assert r["truth"]
    # A Case object is measured alike.
    again = beamflow.synth(beamflow.Case.from_file(case), tmp_path / "case" / "m.csv", kind=kind, seed=5)
    for f, g in zip(r["files"], again["files"]):
        data = lambda p: [l for l in p.read_text(encoding="utf-8").splitlines() if not l.startswith("#")]
        assert data(f) == data(g)


def test_a_case_runs_and_checks_within_a_budget() -> None:
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    for call in (lambda: case.run(max_steps=10), lambda: case.check(max_steps=10)):
        with pytest.raises(beamflow.InputError) as e:
            call()
        assert "max_steps" in e.value.reason and "--" not in str(e.value), e.value
    with pytest.raises(beamflow.InputError) as e:
        case.run(max_memory="lots")
    assert e.value.field == "max_memory"
    assert case.check(max_memory="64G", max_steps=1e12)["dofs"] > 0
