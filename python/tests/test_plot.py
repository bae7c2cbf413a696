"""``results.plot``: the command line's figures as matplotlib figures — the same set of
plots, drawing the library's numbers."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import beamflow
from conftest import bits, run_cli

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

CASES = ["cases/beam-frame-12V-60Hz.toml", "cases/paper-beam.toml", "cases/two-frames.toml"]


@pytest.mark.parametrize("case", CASES)
def test_the_same_figures_as_the_cli(cli: Path, tmp_path: Path, case: str) -> None:
    run_cli(cli, "run", case, "--out", str(tmp_path))
    stem = Path(case).stem
    cli_names = sorted(p.stem[len(stem) + 1:] for p in tmp_path.glob("*.svg"))
    res = beamflow.Case.from_file(case).run()
    assert sorted(res.plot.names) == cli_names
    for name, fig in res.plot.all().items():
        assert fig.axes, name
        assert all(ax.get_title() or not ax.get_visible() for ax in fig.axes), name
        fig.canvas.draw()  # every figure renders


def test_lines_are_the_results_numbers(frame_results: beamflow.Results) -> None:
    ss = frame_results.analysis("steady_state")
    fig = frame_results.plot.time(analysis="steady_state")
    forces = fig.axes[0]
    assert forces.get_title() == "frame: transmitted forces"
    ys = [np.asarray(line.get_ydata()) for line in forces.get_lines()]
    stack = np.asarray(ss.links["frame_stack"]["transmitted"])
    assert any(y.shape == stack.shape and np.array_equal(bits(y), bits(stack)) for y in ys)
    bars = frame_results.plot.power_points(analysis="steady_state")
    heights = sorted(p.get_height() for p in bars.axes[0].patches)
    assert heights == sorted(ss.mean_power.values())


def test_picking_a_figure(frame_results: beamflow.Results) -> None:
    with pytest.raises(ValueError, match="analysis="):
        frame_results.plot.time()  # a steady state and a transient
    with pytest.raises(KeyError, match="no modes figure"):
        frame_results.plot.modes()
    name = frame_results.plot.names[0]
    assert frame_results.plot[name].axes
    with pytest.raises(KeyError, match="no figure"):
        frame_results.plot["nothing"]


def test_a_results_file_has_no_figures(tmp_path: Path, frame_results: beamflow.Results) -> None:
    read = beamflow.read_results(frame_results.to_hdf5(tmp_path / "r.h5"))
    with pytest.raises(AttributeError, match="from a run"):
        read.plot


def test_without_matplotlib_the_error_says_what_to_install(
    frame_results: beamflow.Results, monkeypatch: pytest.MonkeyPatch
) -> None:
    name = frame_results.plot.names[0]
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    with pytest.raises(ImportError, match="pip install matplotlib"):
        frame_results.plot[name]
