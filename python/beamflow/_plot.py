"""A run's figures as matplotlib figures: the plots the command line writes (the library
describes each one — titles, axes, series, bars — and matplotlib draws it), so the same
plots with the same numbers, to restyle, annotate or show in a notebook."""

from __future__ import annotations

import math
import re
from typing import Any, Dict, Iterator, List, Optional

import numpy as np

__all__ = ["Plots"]

_MARKERS = ["o", "s", "^", "D", "v"]
_SUBSCRIPT = re.compile(r"_\{([^}]*)\}")


def _matplotlib() -> Any:
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise ImportError("results.plot needs matplotlib, an optional dependency of beamflow: pip install matplotlib") from None
    return Figure


def _text(s: str) -> str:
    """The renderer's ``F_{p}`` subscripts as matplotlib's mathtext."""
    return _SUBSCRIPT.sub(lambda m: f"$_{{{m.group(1)}}}$", s)


def _gaps(s: Dict[str, Any]) -> tuple:
    """x, y with NaN where the line must not join: before each break, and where an angle
    wraps (a jump of more than half its period)."""
    x, y = np.asarray(s["x"], dtype=float), np.asarray(s["y"], dtype=float)
    cut = set(s["breaks"])
    if s["wrap"]:
        cut |= {i + 1 for i in np.flatnonzero(np.abs(np.diff(y)) > s["wrap"] / 2)}
    if not cut:
        return x, y
    at = sorted(i for i in cut if 0 < i < len(x))
    return np.insert(x, at, np.nan), np.insert(y, at, np.nan)


def _notes(ax: Any, notes: List[str]) -> None:
    if notes:
        ax.text(0.99, 0.01, "\n".join(_text(n) for n in notes), transform=ax.transAxes, ha="right", va="bottom",
                fontsize="small")


def _lines(ax: Any, p: Dict[str, Any]) -> None:
    stems = []
    for i, s in enumerate(p["series"]):
        color = f"C{i % 10}"
        marker = dict(marker=_MARKERS[i % len(_MARKERS)], markerfacecolor="none" if i > 0 else color)
        label = _text(s["label"]) or None
        x, y = _gaps(s)
        style = s["style"]
        if style == "stems":
            ax.plot(x, y, ls="none", color=color, label=label, **marker)
            stems.append((x, y, color))
        elif style == "markers":
            ax.plot(x, y, ls="none", color=color, label=label, **marker)
        elif style == "line_markers":
            ax.plot(x, y, color=color, label=label, **marker)
        else:
            ax.plot(x, y, ls="--" if style == "dashed" else "-", color=color, label=label)
    if p["log_x"]:
        ax.set_xscale("log")
    if p["symlog_y"] is not None:
        ax.set_yscale("symlog", linthresh=p["symlog_y"])
    elif p["log_y"]:
        ax.set_yscale("log")
    if p["x_range"]:
        ax.set_xlim(*p["x_range"])
    if p["y_range"]:
        ax.set_ylim(*p["y_range"])
    if stems:
        lo, hi = ax.get_ylim()
        base = p["stem_base"]
        base = lo if (not math.isfinite(base) or (p["log_y"] and p["symlog_y"] is None)) else min(max(base, lo), hi)
        for x, y, color in stems:
            ax.vlines(x, base, y, color=color)
        ax.set_ylim(lo, hi)
    ax.set_title(_text(p["title"]))
    ax.set_xlabel(_text(p["x_label"]))
    ax.set_ylabel(_text(p["y_label"]))
    ax.grid(True, alpha=0.3)
    if any(s["label"] for s in p["series"]):
        ax.legend(fontsize="small")
    _notes(ax, p["notes"])


def _bars(ax: Any, b: Dict[str, Any]) -> None:
    n, groups = len(b["categories"]), b["groups"]
    width = 0.8 / max(len(groups), 1)
    for k, (name, values) in enumerate(groups):
        x = np.arange(n) + (k - (len(groups) - 1) / 2) * width
        bars = ax.bar(x, values, width, label=name or None, color=f"C{k % 10}")
        if b["show_values"]:
            ax.bar_label(bars, fmt="%.4g", fontsize="small")
    ax.set_xticks(np.arange(n), [_text(c) for c in b["categories"]])
    ax.axhline(0.0, color="black", lw=0.8)
    if b["log_y"]:
        ax.set_yscale("log")
    ax.set_title(_text(b["title"]))
    ax.set_xlabel(_text(b["x_label"]))
    ax.set_ylabel(_text(b["y_label"]))
    if any(name for name, _ in groups):
        ax.legend(fontsize="small")
    _notes(ax, b["notes"])


def _map(ax: Any, m: Dict[str, Any]) -> None:
    z = np.asarray(m["z"])
    if m["diverging"]:
        lim = float(np.abs(z).max()) or 1.0
        kw = dict(cmap="RdBu_r", vmin=-lim, vmax=lim)
    else:
        kw = dict(cmap="viridis")
    mesh = ax.pcolormesh(m["x"], m["y"], z, shading="nearest", **kw)
    if m["z_label"]:
        ax.figure.colorbar(mesh, ax=ax, label=_text(m["z_label"]))
    for line in m["lines"]:
        xs, ys = zip(*line)
        ax.plot(xs, ys, color="black", lw=1.2)
    for x, y, label in m["marks"]:
        ax.plot([x], [y], marker="^", color="black", ls="none")
        if label:
            ax.annotate(_text(label), (x, y), xytext=(6, 6), textcoords="offset points", fontsize="small")
    ax.set_aspect("equal")
    ax.set_title(_text(m["title"]))
    ax.set_xlabel(_text(m["x_label"]))
    ax.set_ylabel(_text(m["y_label"]))


def draw(d: Dict[str, Any]) -> Any:
    """A matplotlib Figure of a drawing the library describes."""
    Figure = _matplotlib()
    if d["kind"] == "maps":
        n, cols = len(d["panels"]), d["columns"]
        rows = math.ceil(n / cols)
        fig = Figure(figsize=(6 * cols, 4.2 * rows), layout="constrained")
        axes = fig.subplots(rows, cols, squeeze=False).ravel()
        for ax, p in zip(axes, d["panels"]):
            _map(ax, p)
        for ax in axes[n:]:
            ax.set_visible(False)
        fig.suptitle(_text(d["title"]))
        return fig
    if d["kind"] == "map":
        w, h = d["size"]
        fig = Figure(figsize=(w / 100, h / 100), layout="constrained")
        _map(fig.subplots(), d)
        return fig
    if d["kind"] == "panels":
        n, cols = len(d["panels"]), d["columns"]
        rows = math.ceil(n / cols)
        w, h = d["size"] or ((1000 if cols == 1 else 700 * cols), 320 * rows)
        fig = Figure(figsize=(w / 100, h / 100), layout="constrained")
        axes = fig.subplots(rows, cols, squeeze=False).ravel()
        for ax, p in zip(axes, d["panels"]):
            _lines(ax, p)
        for ax in axes[n:]:
            ax.set_visible(False)
        if d["title"]:
            fig.suptitle(_text(d["title"]))
        return fig
    w, h = d["size"]
    fig = Figure(figsize=(w / 100, h / 100), layout="constrained")
    (_lines if d["kind"] == "lines" else _bars)(fig.subplots(), d)
    return fig


class Plots:
    """``results.plot``: the figures ``beamflow run`` writes, as matplotlib figures.

    Each figure has the name of its file without the case's stem
    (``steady_state_frame_time``, ``modes``, ``harmonic_transfer``, …): ``plot.names``
    lists them, ``plot[name]`` draws one. The methods pick by kind, narrowed by
    ``analysis`` (``"steady_state"``, ``"transient_2"``, …) and ``actuator`` where a
    run has several: ``time`` (transmitted forces, the stack force's components,
    instantaneous power), ``spectrum`` (transmitted-force levels per harmonic),
    ``power_spectrum`` (power per harmonic), ``power_points`` (mean power per interface
    point), ``loop`` (the stack's hysteresis loop), ``power_by_mode``, ``modes``,
    ``harmonic``, ``transfer`` and ``coupled``.
    """

    def __init__(self, run: Any) -> None:
        self._run = run
        self._drawings: Optional[Dict[str, Dict[str, Any]]] = None

    def _all(self) -> Dict[str, Dict[str, Any]]:
        if self._drawings is None:
            self._drawings = dict(self._run.drawings())
        return self._drawings

    @property
    def names(self) -> List[str]:
        return list(self._all())

    def __getitem__(self, name: str) -> Any:
        drawings = self._all()
        if name not in drawings:
            raise KeyError(f"no figure {name!r}; the run's figures are {', '.join(drawings)}")
        return draw(drawings[name])

    def __iter__(self) -> Iterator[str]:
        return iter(self._all())

    def __len__(self) -> int:
        return len(self._all())

    def all(self) -> Dict[str, Any]:
        """Every figure, by name."""
        return {name: draw(d) for name, d in self._all().items()}

    def pick(self, kind: str, analysis: Optional[str] = None, actuator: Optional[str] = None) -> Any:
        """The one figure of ``kind`` (the end of its name) of ``analysis`` and ``actuator``."""
        whole = kind in ("modes", "harmonic")
        found = [
            n for n in self._all()
            if (re.fullmatch(rf"{kind}(_\d+)?", n) if whole else n.endswith(f"_{kind}"))
            and (analysis is None or n == analysis or n.startswith(f"{analysis}_"))
            and (actuator is None or f"_{actuator}_" in f"_{n}_")
        ]
        if len(found) == 1:
            return self[found[0]]
        if not found:
            raise KeyError(f"no {kind} figure here (analysis={analysis!r}, actuator={actuator!r}); the run's figures are "
                           f"{', '.join(self._all())}")
        raise ValueError(f"{len(found)} {kind} figures ({', '.join(found)}): pick one with analysis= or actuator=")

    def time(self, analysis: Optional[str] = None, actuator: Optional[str] = None) -> Any:
        return self.pick("time", analysis, actuator)

    def spectrum(self, analysis: Optional[str] = None, actuator: Optional[str] = None) -> Any:
        return self.pick("spectrum", analysis, actuator)

    def power_spectrum(self, analysis: Optional[str] = None, actuator: Optional[str] = None) -> Any:
        return self.pick("power_spectrum", analysis, actuator)

    def power_points(self, analysis: Optional[str] = None, actuator: Optional[str] = None) -> Any:
        return self.pick("power_points", analysis, actuator)

    def loop(self, analysis: Optional[str] = None, actuator: Optional[str] = None) -> Any:
        return self.pick("loop", analysis, actuator)

    def power_by_mode(self, analysis: Optional[str] = None) -> Any:
        return self.pick("power_by_mode", analysis)

    def modes(self, analysis: Optional[str] = None) -> Any:
        return self.pick("modes", analysis)

    def harmonic(self, analysis: Optional[str] = None) -> Any:
        return self.pick("harmonic", analysis)

    def transfer(self, analysis: Optional[str] = None) -> Any:
        return self.pick("transfer", analysis)

    def coupled(self, analysis: Optional[str] = None) -> Any:
        return self.pick("coupled", analysis)

    def __repr__(self) -> str:
        return f"<beamflow plots: {', '.join(self._all())}>"
