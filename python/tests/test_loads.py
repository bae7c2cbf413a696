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


def test_a_step_load_gives_a_record_not_harmonics() -> None:
    case = CASE.replace('kind = "sine"\namplitude = 1.0\nfrequency = 60.0', 'kind = "step"\ntime = 0.0\nfrom = 0.0\nto = 1.0\nrise_time = 0.05')
    case = case.replace('type = "steady_state"', 'type = "transient"\ndt = 1e-4\nduration = 0.2')
    res = beamflow.Case.from_toml(case).run()
    a = res.analysis(0)
    s = res.summary["analyses"][0]
    # A record has no period: none of a periodic run's keys.
    assert "harmonics" not in s and "mean_power_w" not in s
    rec = a.record
    assert rec is not None
    assert rec["points/shaker"].attrs["energy_J"] == s["record"]["energy_j"]["shaker"]
