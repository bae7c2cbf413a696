"""Results as xarray Datasets hold the command line's numbers bit for bit, on the named
dimensions docs/python.md gives, with their units."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Dict, Tuple

import h5py
import numpy as np
import pytest

import beamflow
from conftest import bits

xr = pytest.importorskip("xarray")


def same(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(bits(a), bits(b))


def check_periodic(ds: "xr.Dataset", g: h5py.Group) -> int:
    checked = 0
    links = list(g["link_names"].asstr()[()]) if "link_names" in g else sorted(g["links"])
    assert list(ds["link"].values) == links
    assert same(ds["t"].values, g["t"][()])
    for key in ("mean_power", "net_power"):
        assert (key in ds) == (key in g)
        if key in g:
            assert same(ds[key].values, g[key][()])
    for link in links:
        for key, h in g["links"][link].items():
            v = ds[key].sel(link=link)
            assert same(v.values, h[()]), (link, key)
            assert ds[key].attrs["units"] == h.attrs["unit"]
            checked += 1
        for key, h in g["spectra"][link].items():
            if key == "frequency":
                assert same(ds["frequency"].values, h[()]), link
            else:
                assert same(ds[f"spectrum_{key}"].sel(link=link).values, h[()]), (link, key)
                checked += 1
    for group, dim in (("drives", "drive"), ("sensors", "sensor")):
        for name, members in g.get(group, {}).items():
            for key, h in members.items():
                if h.shape == g["t"].shape:
                    assert same(ds[f"{dim}_{key}"].sel({dim: name}).values, h[()]), (name, key)
                    checked += 1
    for body, members in g.get("bodies", {}).items():
        for key, h in members.items():
            assert same(ds[f"{body}_{key}"].values, h[()])
            assert ds[f"{body}_{key}"].attrs["units"] == h.attrs["unit"]
            checked += 1
    if "modal" in g:
        assert same(ds["mode_frequency"].values, g["modal/mode_frequency_hz"][()])
        assert same(ds["modal_point_power"].transpose("link", "mode").values, g["modal/point_power"][()])
        assert same(ds["modal_eta_abs"].transpose("harmonic", "mode").values, g["modal/eta_abs"][()])
        checked += 2
    return checked


def check_harmonic(ds: "xr.Dataset", g: h5py.Group) -> int:
    mobility = g["mobility"][()]
    n_forces = g["input_power"].shape[1]
    assert same(ds["frequency"].values, g["frequency_hz"][()])
    for i in range(ds.sizes["point"]):
        for j in range(n_forces):
            assert same(ds["mobility"].values[:, i, j], mobility[:, i * n_forces + j])
    assert same(ds["velocity"].values, g["velocity"][()])
    assert same(ds["input_power"].values, g["input_power"][()])
    assert ds["mobility"].attrs["units"] == g["mobility"].attrs["unit"]
    return 3


def check_modes(ds: "xr.Dataset", g: h5py.Group) -> int:
    assert same(ds["frequency"].values, g["frequencies_hz"][()])
    assert same(ds["shape_w"].values, g["shapes_w"][()])
    assert same(ds["x"].values, g["node_x"][()])
    return 2


def test_datasets_hold_the_cli_numbers(cli_runs: Dict[str, Tuple[Path, Path]]) -> None:
    kinds = set()
    for case, (h5, _) in cli_runs.items():
        res = beamflow.read_results(h5)
        datasets = res.to_xarray()
        assert list(datasets) == [a.path.strip("/") for a in res.analyses]
        with h5py.File(h5, "r") as f:
            for a in res.analyses:
                ds, g = datasets[a.path.strip("/")], f[a.path.strip("/")]
                check = {"steady_state": check_periodic, "transient": check_periodic, "harmonic": check_harmonic,
                         "modes": check_modes}[a.kind]
                assert check(ds, g) > 0, (case, a.path)
                assert ds.attrs["kind"] == a.kind
                kinds.add(a.kind)
    assert kinds == {"steady_state", "transient", "harmonic", "modes"}


def test_spectra_select_by_frequency(frame_results: beamflow.Results) -> None:
    ds = frame_results.analysis("steady_state").to_xarray()
    drive = ds["spectrum_power"].swap_dims(harmonic="frequency").sel(frequency=60.0)
    assert same(drive.sel(link="frame_stack").values, frame_results.analysis("steady_state").point_power("frame_stack")[1])


def test_without_xarray_the_error_says_what_to_install(
    frame_results: beamflow.Results, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ImportError, match="pip install xarray"):
        frame_results.analysis("steady_state").to_xarray()
