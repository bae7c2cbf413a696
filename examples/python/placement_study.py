"""Where on the beam should the actuator go?  A placement study from Python.

Net power that a frame-type and an inertial-type actuator push into the paper's
clamped–clamped beam (12 V, 60 Hz), against the stack position x_E along the beam, and
the power per harmonic at the best position. Run from the repository root:

    python examples/python/placement_study.py [--out DIR]

It writes placement_study.png (and prints the best positions). Cells are marked `# %%`
so that it also runs cell by cell in an editor or notebook.
"""

# %% Setup
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files, not windows: runs the same on a desktop and in CI
import matplotlib.pyplot as plt
import numpy as np

import beamflow

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", type=Path, default=Path("out/python"), help="output directory")
parser.add_argument("--points", type=int, default=64, help="positions along the beam")
args = parser.parse_args()
args.out.mkdir(parents=True, exist_ok=True)

# %% The two actuators: the shipped placement cases, read as Python objects
cases = {
    "frame": beamflow.Case.from_file("cases/placement-frame.toml"),
    "inertial": beamflow.Case.from_file("cases/placement-inertial.toml"),
}
length = cases["frame"]["beam.length"]  # a default, read like any field
print(f"beam length {length} m; drive {cases['frame']['actuator[0].voltage.frequency']} Hz")

# %% Sweep the stack position x_E with the library's parallel sweep (one row per position)
tables = {}
for name, case in cases.items():
    tables[name] = beamflow.sweep(
        {
            "title": f"{name} actuator along the beam",
            "base": case,  # a Case (changed or not) or a case file
            "parameter": [{"path": "actuator[0].x_e", "start": 0.05, "stop": 0.68, "count": args.points}],
        },
        as_frame=False,  # numpy columns; with pandas installed the default is a DataFrame
    )

best = {}
for name, t in tables.items():
    x = t["actuator[0].x_e"]
    p = t[f"net_power[{name}]"]
    i = int(np.argmax(p))
    best[name] = float(x[i])
    print(f"{name:8s}: best x_E = {x[i]:.3f} {x.unit}, net power {p[i] * 1e6:.2f} µ{p.unit} "
          f"(energy balance error ≤ {np.max(t['balance_error']):.1e})")

# %% One full run at each best position: power per harmonic at the stack foot
spectra = {}
for name, case in cases.items():
    c = case.copy()
    c["actuator[0].x_e"] = best[name]
    ss = c.run().analysis("steady_state")
    link = f"{name}_stack"
    spectra[name] = (ss.spectra[link]["frequency"], ss.point_power(link))
    # The sweep's fast path (cached stack forces) and the full run agree to round-off.
    swept = float(np.max(tables[name][f"net_power[{name}]"]))
    assert abs(ss.net_power[name] - swept) <= 1e-8 * abs(swept), (ss.net_power[name], swept)

# %% Figure
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
for name, t in tables.items():
    x, p = t["actuator[0].x_e"], t[f"net_power[{name}]"]
    ax1.plot(1e3 * x, 1e6 * p, marker="o", ms=3, label=f"{name} (best {1e3 * best[name]:.0f} mm)")
    ax1.axvline(1e3 * best[name], color=ax1.lines[-1].get_color(), lw=0.8, ls=":")
# The inertial actuator puts in orders of magnitude less at 60 Hz: a logarithmic axis
# (linear around zero if some position takes power out of the beam).
if min(float(np.min(t[f"net_power[{n}]"])) for n, t in tables.items()) > 0:
    ax1.set_yscale("log")
else:
    ax1.set_yscale("symlog", linthresh=1e-3)
    ax1.axhline(0.0, color="0.6", lw=0.8)
ax1.set_xlabel("stack position $x_E$ (mm)")
ax1.set_ylabel("net power into the beam (µW)")
ax1.set_title("Net power against position, 12 V, 60 Hz")
ax1.legend()

width = 0.4
for k, (name, (f, p)) in enumerate(spectra.items()):
    h = np.arange(len(f))
    ax2.bar(h[1:] + (k - 0.5) * width, 1e6 * np.abs(p[1:]), width, label=f"{name} at {1e3 * best[name]:.0f} mm")
ax2.set_yscale("log")
ax2.set_xticks(np.arange(1, len(f)))
ax2.set_xlabel("harmonic of 60 Hz")
ax2.set_ylabel("|power| at the stack foot (µW)")
ax2.set_title("Power per harmonic at the best position")
ax2.legend()

png = args.out / "placement_study.png"
fig.savefig(png, dpi=120)
print(f"wrote {png}")
