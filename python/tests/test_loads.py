"""Point loads from Python: the accessors read what the command line reports."""

from __future__ import annotations

import beamflow

CASE = """
[[load]]
name = "shaker"
x = 0.2
[load.force]
kind = "sine"
amplitude = 1.0
frequency = 60.0
[[analysis]]
type = "steady_state"
[output]
plots = false
"""


def test_load_power_equals_the_summary_and_the_series() -> None:
    res = beamflow.Case.from_toml(CASE).run()
    a = res.analysis(0)
    p = a.load_power["shaker"]
    assert p == res.summary["analyses"][0]["load_power_w"]["shaker"]
    g = a.loads["shaker"]
    f, v = g["force"], g["v"]
    direct = sum(x * y for x, y in zip(f, v)) / len(f)
    assert abs(direct - p) < 1e-9 * p
    assert p > 0
