"""Shared fixtures: the repository, the command-line binary the Python results are
compared with, and the command line's outputs for every shipped case."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import Any, Dict, Iterator, Tuple

import h5py
import numpy as np
import pytest

import beamflow

REPO = Path(__file__).resolve().parents[2]
# Case files only: sweep and optimisation specs sit beside them with their own suffixes.
CASES = sorted(
    p for p in (REPO / "cases").glob("*.toml") if not p.name.endswith((".sweep.toml", ".opt.toml"))
)


@pytest.fixture(autouse=True)
def in_repo(monkeypatch: pytest.MonkeyPatch) -> None:
    """Case paths are relative to the repository, as on the command line, so that the
    command line and Python name the case file alike (it is stored in the results)."""
    monkeypatch.chdir(REPO)


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `beamflow` binary of this checkout (BEAMFLOW_CLI, else target/release)."""
    path = Path(os.environ.get("BEAMFLOW_CLI", REPO / "target" / "release" / "beamflow"))
    if not path.exists():
        pytest.fail(f"the command-line binary {path} is missing: run `cargo build --release` (or set BEAMFLOW_CLI)")
    return path


def run_cli(cli: Path, *args: str) -> str:
    done = subprocess.run([str(cli), *args], cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 0, f"beamflow {' '.join(args)} failed:\n{done.stderr}"
    return done.stdout


@pytest.fixture(scope="session")
def cli_runs(cli: Path, tmp_path_factory: pytest.TempPathFactory) -> Dict[str, Tuple[Path, Path]]:
    """`beamflow run` of every shipped case: case path → (HDF5 file, JSON summary)."""
    out = tmp_path_factory.mktemp("cli")
    runs = {}
    for case in CASES:
        rel = str(case.relative_to(REPO))
        d = out / case.stem
        run_cli(cli, "run", rel, "--out", str(d), "--no-plots")
        runs[rel] = (d / f"{case.stem}.h5", d / f"{case.stem}.json")
    return runs


def h5_contents(path: Path) -> Dict[str, Any]:
    """Everything in an HDF5 file, read with h5py (not with beamflow): object path →
    attributes (for groups) or (value, attributes) for datasets."""
    out: Dict[str, Any] = {}
    with h5py.File(path, "r") as f:
        out["/@"] = {k: _attr(v) for k, v in f.attrs.items()}

        def visit(name: str, obj: Any) -> None:
            key = "/" + name
            attrs = {k: _attr(v) for k, v in obj.attrs.items()}
            if isinstance(obj, h5py.Group):
                out[key + "@"] = attrs
            elif obj.dtype.kind in "fciu" or obj.dtype.names:
                out[key] = (np.asarray(obj[()]), attrs)
            elif obj.shape == ():
                out[key] = (obj.asstr()[()], attrs)
            else:
                out[key] = (list(obj.asstr()[()]), attrs)

        f.visititems(visit)
    return out


def _attr(v: Any) -> Any:
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.generic):
        return v.item()
    return v


def tree_contents(g: beamflow.Group) -> Dict[str, Any]:
    """The same listing for a beamflow results tree."""
    out: Dict[str, Any] = {"/@": dict(g.attrs)}

    def visit(group: beamflow.Group) -> None:
        for name, sub in group.groups.items():
            out[sub.path + "@"] = dict(sub.attrs)
            visit(sub)
        base = group.path.rstrip("/")
        for name, d in group.datasets.items():
            if isinstance(d, beamflow.Quantity):
                out[f"{base}/{name}"] = (d, {"unit": d.unit, "description": d.description})
            else:
                out[f"{base}/{name}"] = (d, {})

    visit(g)
    return out


def bits(a: np.ndarray) -> np.ndarray:
    """The raw 64-bit words of a float or complex array (NaN payloads and −0 count)."""
    a = np.ascontiguousarray(a)
    return a.view(np.uint64) if a.dtype.kind in "fc" else a


def assert_same(expected: Dict[str, Any], got: Dict[str, Any], ignore: Tuple[str, ...] = ()) -> int:
    """Asserts two listings hold the same objects, attributes and values, bit for bit;
    returns the number of numbers compared."""
    assert sorted(expected) == sorted(got), (
        f"objects differ: only in expected {sorted(set(expected) - set(got))}, only in got {sorted(set(got) - set(expected))}"
    )
    numbers = 0
    for key, want in expected.items():
        have = got[key]
        if key.endswith("@"):
            want = {k: v for k, v in want.items() if f"{key}{k}" not in ignore}
            have = {k: v for k, v in have.items() if f"{key}{k}" not in ignore}
            assert want.keys() == have.keys(), key
            for k in want:
                assert type(want[k]) is type(have[k]) and (want[k] == have[k] or np.isnan(want[k]) and np.isnan(have[k])), (key, k, want[k], have[k])
            continue
        (wv, wa), (hv, ha) = want, have
        assert wa == ha, (key, wa, ha)
        if isinstance(wv, np.ndarray):
            assert isinstance(hv, np.ndarray), key
            assert (wv.dtype, wv.shape) == (hv.dtype, hv.shape), (key, wv.dtype, wv.shape, hv.dtype, hv.shape)
            assert np.array_equal(bits(wv), bits(hv)), f"{key}: values differ"
            numbers += wv.size
        else:
            assert wv == hv, key
    return numbers


def load_json(path: Path) -> Any:
    return json.loads(path.read_text())


@pytest.fixture(scope="session")
def frame_results() -> Iterator[beamflow.Results]:
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        yield beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml").run()
    finally:
        os.chdir(cwd)
