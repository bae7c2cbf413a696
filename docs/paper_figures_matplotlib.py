#!/usr/bin/env python3
"""The paper's Figs. 8-16 drawn with matplotlib from beamflow's own CSV tables, to set
beside beamflow's figures (docs/report.md, "beamflow beside matplotlib").

    beamflow paper --out out/paper --csv
    python docs/paper_figures_matplotlib.py out/paper docs/img

Reads only the CSV files (numpy and matplotlib needed) and writes mpl-fig08.png ...
mpl-fig16.png into the second folder. Same quantities, windows and units as beamflow's
figures; one colour per point as beamflow's palette (stack foot, left leg, right leg,
inertial stack).
"""

import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

COLOUR = {
    "frame_stack": "#1f77b4",
    "frame_left_leg": "#ff7f0e",
    "frame_right_leg": "#2ca02c",
    "inertial_stack": "#d62728",
}
LABEL = {
    "frame_stack": "stack foot",
    "frame_left_leg": "left leg",
    "frame_right_leg": "right leg",
    "inertial_stack": "stack foot",
}
FRAME = ["frame_stack", "frame_left_leg", "frame_right_leg"]
DPI = 100
LARGEST = 150_000  # bytes per PNG


class Series:
    """A time-series table: columns by their name without the unit."""

    def __init__(self, path):
        with open(path) as f:
            header = next(csv.reader(f))
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
        self.columns = {h.split(" [")[0]: data[:, i] for i, h in enumerate(header)}
        # Time from the start of the stored window, in ms, as beamflow draws it.
        self.ms = (self.columns["t"] - self.columns["t"][0]) * 1e3

    def __getitem__(self, name):
        return self.columns[name]


class Spectra:
    """A spectra table: per link, the harmonics' frequency, complex amplitudes and power."""

    def __init__(self, path):
        self.rows = {}
        with open(path) as f:
            for row in csv.DictReader(f):
                self.rows.setdefault(row["link"], []).append(row)

    def column(self, link, name):
        return np.array([float(r[name]) for r in self.rows[link]])

    def complex(self, link, name):
        return self.column(link, f"{name} re [N]") + 1j * self.column(link, f"{name} im [N]")


def table(folder, run, analysis, kind):
    return os.path.join(folder, f"{run}_analysis_{analysis}_{kind}.csv")


def finish(fig, out, name):
    path = os.path.join(out, name)
    dpi = DPI
    fig.savefig(path, dpi=dpi)
    # Kept small for the docs: a slightly lower resolution for the busiest figures.
    while os.path.getsize(path) > LARGEST and dpi > 60:
        dpi -= 10
        fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print(f"wrote {path} ({os.path.getsize(path) // 1024} KB)")


def legend(ax):
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9)


def dress(ax, title, xlabel, ylabel):
    """Title, axis names with units, a light grid, and the legend right of the plot."""
    ax.set(title=title, xlabel=xlabel, ylabel=ylabel)
    ax.grid(alpha=0.3)
    legend(ax)


def figure(title, rows=2, cols=1, size=(10, 6.84)):
    fig, axes = plt.subplots(rows, cols, figsize=size, layout="constrained")
    fig.suptitle(title)
    return fig, axes


def fig08(s, out):
    fig, (a, b) = figure("Fig. 8 — transmitted forces on a rigid base, 48 V, 30 Hz")
    a.plot(s.ms, s["links/inertial_stack/transmitted"] * 1e3, color=COLOUR["inertial_stack"], label="stack foot")
    dress(a, "inertial-type: $F_T$", "time (ms)", "transmitted force (mN)")
    for link in FRAME:
        b.plot(s.ms, s[f"links/{link}/transmitted"], color=COLOUR[link], label=LABEL[link])
    dress(b, "frame-type: $F_E$, $F_L$, $F_R$", "time (ms)", "transmitted force (N)")
    finish(fig, out, "mpl-fig08.png")


def fig09(s, out):
    fig, axes = figure("Fig. 9 — components of the stack-foot force and their sum", 2, 2, (14, 6.84))
    for col, (link, kind, name, scale, unit) in enumerate(
        [("inertial_stack", "inertial-type", "F_T", 1e3, "mN"), ("frame_stack", "frame-type", "F_E", 1.0, "N")]
    ):
        top, bottom = axes[0, col], axes[1, col]
        p = f"links/{link}/"
        top.plot(s.ms, s[p + "f_stiffness"], color="#17becf", label=r"stiffness $k\,u$")
        top.plot(s.ms, s[p + "f_damping"], color="#bcbd22", ls="--", label=r"damping $c\,\dot u$")
        top.plot(s.ms, s[p + "f_pzt"], color="#e377c2", label=r"PZT $-F_p$")
        dress(top, f"{kind}: components of ${name}$", "time (ms)", "force (N)")
        total = s[p + "transmitted"]
        largest = max(np.max(np.abs(s[p + c])) for c in ("f_stiffness", "f_damping", "f_pzt"))
        share = np.max(np.abs(total)) / largest * 100
        bottom.plot(s.ms, total * scale, color=COLOUR[link], label=f"total ${name}$")
        dress(bottom, f"{kind}: total ${name}$, {share:.2g} % of the largest component", "time (ms)", f"force ({unit})")
    finish(fig, out, "mpl-fig09.png")


def fig10(s, out):
    fig, axes = figure("Fig. 10 — top displacements on a rigid base", 3, 1, (10, 10.04))
    panels = [
        ("inertial-type: top mass $z_t$", "bodies/inertial_z_t/q", "$z_t$", r"$z_t$ (µm)"),
        ("frame-type: top beam $y$", "bodies/frame_y/q", "$y$", r"$y$ (µm)"),
        ("frame-type: top beam rotation $\\varphi$", "bodies/frame_phi/q", r"rotation $\varphi$", r"rotation $\varphi$ (µrad)"),
    ]
    for ax, (title, column, label, ylabel) in zip(axes, panels):
        ax.plot(s.ms, s[column] * 1e6, color="#1f77b4", label=label)
        dress(ax, title, "time (ms)", ylabel)
    finish(fig, out, "mpl-fig10.png")


def fig11(folder, out):
    fig, ax = figure("Fig. 11 — inertial-type $F_T$ against top mass (rigid base, 48 V, 30 Hz)", 1, 1, (10, 6))
    for m_t, colour in zip(["0.1", "0.3", "0.5", "1"], ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728"]):
        s = Series(table(folder, f"rigid-inertial-mt-{m_t}", 0, "transient_series"))
        ax.plot(s.ms, s["links/inertial_stack/transmitted"] * 1e3, color=colour, lw=1.2, label=f"$m_t$ = {m_t} kg")
    dress(ax, None, "time (ms)", "transmitted force $F_T$ (mN)")
    finish(fig, out, "mpl-fig11.png")


def stems(ax, f, y, colour, marker, label, bottom):
    """Stems at their true frequencies from the axis floor, markers hollow so they overlap visibly."""
    ax.vlines(f, bottom, y, color=colour, lw=1.5)
    face = colour if marker == "o" else "none"
    ax.plot(f, y, marker, ls="none", color=colour, mfc=face, ms=7, label=label)


def fig12(sp, out):
    fig, axes = figure("Fig. 12 — transmitted-force spectra: the drive and its odd harmonics")
    panels = [
        ("inertial-type $F_T$", [("inertial_stack", "o", "$F_T$")]),
        ("frame-type", [("frame_stack", "o", "$F_E$"), ("frame_left_leg", "s", "$F_L$"), ("frame_right_leg", "^", "$F_R$")]),
    ]
    for ax, (title, links) in zip(axes, panels):
        levels = []
        for link, _, _ in links:
            h = sp.column(link, "harmonic")
            odd = h % 2 == 1
            levels.append((sp.column(link, "frequency [Hz]")[odd], 20 * np.log10(np.abs(sp.complex(link, "transmitted")[odd]))))
        bottom = min(np.min(l) for _, l in levels) - 5
        for (link, marker, label), (f, level) in zip(links, levels):
            stems(ax, f, level, COLOUR[link], marker, label, bottom)
        ax.set_ylim(bottom=bottom)
        dress(ax, title, "frequency (Hz)", "force level (dB re 1 N)")
    finish(fig, out, "mpl-fig12.png")


def fig13(s, out):
    fig, (a, b) = figure("Fig. 13 — inertial-type on the beam at 0.150 m, 12 V, 60 Hz")
    a.plot(s.ms, s["links/inertial_stack/interface"] * 1e3, color=COLOUR["inertial_stack"], label="$F_T$ at the interface")
    dress(a, "interface force", "time (ms)", "force (mN)")
    b.plot(s.ms, s["links/inertial_stack/base_acceleration"] * 1e3, color="#1f77b4", label=r"$\ddot w(x_E)$")
    dress(b, "beam acceleration at the interface", "time (ms)", "acceleration (mm/s²)")
    finish(fig, out, "mpl-fig13.png")


def fig14(sp, out):
    fig, ax = figure("Fig. 14 — inertial-type: power-flow spectrum, 12 V, 60 Hz", 1, 1, (10, 6))
    link = "inertial_stack"
    f = sp.column(link, "frequency [Hz]")
    p, pa = sp.column(link, "power [W]"), sp.column(link, "power_from_acceleration [W]")
    # The drive's odd harmonics; the mean and the even lines are zero to rounding.
    shown = (sp.column(link, "harmonic") % 2 == 1) & (p > 0)
    bottom = 10 ** np.floor(np.log10(p[shown].min()))
    stems(ax, f[shown], p[shown], COLOUR[link], "o", "from $F$ and $v$", bottom)
    ax.plot(f[shown], pa[shown], "s", ls="none", color="#ff7f0e", mfc="none", ms=10, label="from $F$ and $a$")
    ax.set_yscale("log")
    ax.set_ylim(bottom=bottom)
    ax.set_xlim(0, f.max() + 60)
    dress(ax, None, "frequency (Hz)", "power into the beam (W)")
    ax.grid(alpha=0.3, which="both")
    finish(fig, out, "mpl-fig14.png")


def fig15(s, sp, out):
    fig, (a, b) = figure("Fig. 15 — frame-type on the beam: power at the stack foot and at both legs, 12 V, 60 Hz")
    for link in FRAME:
        a.plot(s.ms, s[f"links/{link}/power"] * 1e3, color=COLOUR[link], label=LABEL[link])
    dress(a, "instantaneous power", "time (ms)", "power (mW)")
    # Signed lines spanning six decades: a symmetric log axis, linear within ±1 pW.
    for link, marker in zip(FRAME, ["o", "s", "^"]):
        f, p = sp.column(link, "frequency [Hz]"), sp.column(link, "power [W]")
        odd = sp.column(link, "harmonic") % 2 == 1
        stems(b, f[odd], p[odd], COLOUR[link], marker, LABEL[link], 0.0)
    b.set_yscale("symlog", linthresh=1e-12)
    b.set_yticks([s * 10.0**e for s in (-1, 1) for e in (-5, -8, -11)] + [0])
    b.axhline(0, color="0.3", lw=0.8)
    dress(b, "power per harmonic", "frequency (Hz)", "power into the beam (W)")
    finish(fig, out, "mpl-fig15.png")


def fig16(folder, out):
    def net(run):
        with open(table(folder, run, 0, "steady_state_net_power")) as f:
            return sum(float(r["net_power [W]"]) for r in csv.DictReader(f))

    def at_drive(run):
        sp = Spectra(table(folder, run, 0, "steady_state_spectra"))
        return sum(sp.column(link, "power [W]")[1] for link in sp.rows)

    runs = ["beam-inertial-12V-60Hz", "beam-frame-12V-60Hz"]
    nets, drives = [net(r) for r in runs], [at_drive(r) for r in runs]
    fig, ax = figure("Fig. 16 — net power into the beam, 12 V, 60 Hz drive", 1, 1, (10, 6))
    x = np.arange(2)
    for offset, values, colour, label in [
        (-0.2, nets, "#1f77b4", "net power (all harmonics)"),
        (0.2, drives, "#ff7f0e", "at the drive frequency"),
    ]:
        bars = ax.bar(x + offset, values, 0.38, color=colour, label=label)
        ax.bar_label(bars, [f"{v * 1e9:.1f} nW" if v < 1e-6 else f"{v * 1e6:.2f} µW" for v in values], fontsize=9)
    ax.set_yscale("log")
    ax.set_ylim(1e-8, 1e-5)
    ax.set_xticks(x, ["inertial-type", "frame-type"])
    ax.set(xlabel="actuator", ylabel="net power (W)")
    ax.grid(alpha=0.3, axis="y", which="both")
    ax.text(
        1.01,
        0.8,
        f"frame / inertial:\nnet power {nets[1] / nets[0]:.0f}×\nat 60 Hz {drives[1] / drives[0]:.0f}×",
        transform=ax.transAxes,
        va="top",
        fontsize=9,
    )
    legend(ax)
    finish(fig, out, "mpl-fig16.png")


def main(folder, out):
    os.makedirs(out, exist_ok=True)
    rigid = Series(table(folder, "rigid-base-48V-30Hz", 0, "transient_series"))
    fig08(rigid, out)
    fig09(rigid, out)
    fig10(rigid, out)
    fig11(folder, out)
    fig12(Spectra(table(folder, "rigid-base-48V-30Hz", 0, "transient_spectra")), out)
    inertial = Series(table(folder, "beam-inertial-12V-60Hz", 1, "transient_series"))
    fig13(inertial, out)
    fig14(Spectra(table(folder, "beam-inertial-12V-60Hz", 1, "transient_spectra")), out)
    frame = Series(table(folder, "beam-frame-12V-60Hz", 1, "transient_series"))
    fig15(frame, Spectra(table(folder, "beam-frame-12V-60Hz", 0, "steady_state_spectra")), out)
    fig16(folder, out)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
