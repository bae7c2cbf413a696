"""The matplotlib rendering of the paper's figures (docs/paper_figures_matplotlib.py, set
beside beamflow's in docs/report.md) still reads the CSV tables `beamflow paper --csv`
writes: every figure drawn, none empty."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO, run_cli

pytest.importorskip("matplotlib")


def test_the_matplotlib_script_draws_every_paper_figure_from_the_csv(cli: Path, tmp_path: Path) -> None:
    run_cli(cli, "paper", "--out", str(tmp_path / "paper"), "--csv")
    script = REPO / "docs" / "paper_figures_matplotlib.py"
    done = subprocess.run([sys.executable, str(script), str(tmp_path / "paper"), str(tmp_path / "img")],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    drawn = sorted(p.name for p in (tmp_path / "img").glob("mpl-fig*.png"))
    assert drawn == [f"mpl-fig{n:02d}.png" for n in range(8, 17)], drawn
    for name in drawn:
        # A figure with axes, lines and text: tens of kB. An empty canvas is a few kB.
        assert (tmp_path / "img" / name).stat().st_size > 15_000, name
