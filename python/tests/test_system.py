"""The assembled matrices and the modes, checked with scipy (an independent eigensolver)
against `beamflow modes`."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import beamflow
from conftest import run_cli


def eigsh_hz(k: sp.csr_matrix, m: sp.csr_matrix, count: int) -> np.ndarray:
    lam = spla.eigsh(k, k=count, M=m, sigma=0.0, which="LM", return_eigenvectors=False)
    return np.sqrt(np.sort(lam)) / (2 * np.pi)


def test_scipy_eigsh_on_k_and_m_gives_the_cli_modes(cli: Path, tmp_path: Path) -> None:
    run_cli(cli, "modes", "cases/paper-beam.toml", "--count", "6", "--json", str(tmp_path / "m.json"))
    expected = np.array(json.loads((tmp_path / "m.json").read_text())["frequencies_hz"])
    s = beamflow.Case.from_file("cases/paper-beam.toml").system()
    assert sp.isspmatrix_csr(s.K) and s.K.dtype == np.float64 and s.K.shape == (s.n, s.n)
    for name in ("K", "M", "C"):
        a = getattr(s, name)
        assert (a - a.T).count_nonzero() == 0, f"{name} is not symmetric"
    f = eigsh_hz(s.K, s.M, 6)
    np.testing.assert_allclose(f, expected, rtol=1e-8, atol=0)
    # The Python call of the same modes is the command line's, number for number.
    m = beamflow.Case.from_file("cases/paper-beam.toml").modes(6)
    assert list(m.frequencies_hz) == list(expected) and m.frequencies_hz.unit == "Hz"
    assert m.shapes.shape == (6, len(m.node_x)) and m.relative_error.max() < 1e-6


def test_rayleigh_damping_is_a0_m_plus_a1_k() -> None:
    s = beamflow.Case.from_file("cases/paper-beam.toml").system()
    a0, a1 = s.rayleigh
    assert a0 > 0 and a1 > 0 and s.modal_damping is None
    diff = s.C - (a0 * s.M + a1 * s.K)
    assert abs(diff).max() <= 1e-12 * abs(s.C).max()


def test_dof_map_describes_every_dof() -> None:
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    s = case.system()
    d = s.dofs
    assert len(d) == s.n and list(d.index) == list(range(s.n))
    n_nodes = case.check()["elements"] + 1
    w, theta = d.where("w"), d.where("theta")
    assert len(w) == len(theta) == n_nodes - 2  # both ends clamped
    assert np.all(np.diff(d.x[w]) > 0) and d.x.unit == "m"
    body = [i for i, a in enumerate(d.actuator) if a]
    assert sorted(d.kind[i] for i in body) == ["phi", "y"] and all(d.node[i] == -1 for i in body)
    assert np.isnan(d.x[body]).all()
    # The frame's body mass sits on its own DOFs: unit acceleration of y needs its mass.
    y = d.where("y", "frame")[0]
    assert s.M[y, y] > 0
    pd = pytest.importorskip("pandas")
    frame = d.to_frame()
    assert isinstance(frame, pd.DataFrame) and len(frame) == s.n


def test_coupled_modes_equal_a_dense_scipy_solve() -> None:
    case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    s = case.system()
    # Shift-invert Lanczos (another algorithm). Not scipy.linalg.eigh(K, M): reducing with
    # M's Cholesky factor computes the lowest eigenvalue to ε·λ_max absolute, and the
    # stiff stack makes λ_max/λ_1 large enough to cost mode 1 its 8th digit (1e-7 here).
    expected = eigsh_hz(s.K, s.M, 6)
    m = case.coupled_modes(6)
    np.testing.assert_allclose(m.frequencies_hz, expected, rtol=1e-8)
    # Mass-normalised shapes over the global DOFs: Φᵀ M Φ = I.
    phi = np.asarray(m.shapes).T
    np.testing.assert_allclose(phi.T @ (s.M @ phi), np.eye(6), atol=1e-9)
    # The actuator changes the beam's modes: the coupled first mode is below the bare one.
    assert m.frequencies_hz[0] < case.modes(1).frequencies_hz[0]
