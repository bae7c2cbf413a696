"""Parameter identification from measurements, as ``beamflow identify`` does: ``d_p`` from a
pair of stroke records (:func:`dp`), the Bouc–Wen hysteresis α, β, γ (:func:`bouc_wen`)
and a stiffness and damping from an impact test (:func:`modal`).

A measurement is a file (CSV with time and the quantities' columns, units in the header,
or a results file ``FILE.h5[:ACTUATOR]``) or a dict of numpy arrays in SI units keyed by
column name (``time``, ``voltage``, ``displacement``, ``force``, ``acceleration``). Each
function returns an :class:`Identification`: the numbers the command line writes as JSON
(bit for bit), the case fragment and, with ``out``, the files written there.
"""

from __future__ import annotations

import contextlib
import json
import tempfile
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._arguments import Size, as_arguments, budget_text, check_numbers
from ._commands import PathLike
from .errors import InputError

__all__ = ["Identification", "Measurement", "dp", "bouc_wen", "modal"]

#: A measurement file, or columns of numbers by name (SI units).
Measurement = Union[PathLike, Mapping[str, Any]]

_UNITS = {"time": "s", "voltage": "V", "displacement": "m", "force": "N", "acceleration": "m/s^2"}


class Identification:
    """The result of an identification: ``values`` (the JSON the command line writes:
    ``dp.json``, ``bouc-wen.json``, ``modal.json``), ``fragment`` (the case fragment, TOML
    text), ``files`` (written with ``out``) and ``report`` (what the command line prints)."""

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.values: Dict[str, Any] = json.loads(raw["json"])
        self.fragment: str = raw["fragment"]
        self.files: List[Path] = [Path(p) for p in raw["files"]]
        self.report: str = raw["report"]

    def __getitem__(self, key: str) -> Any:
        return self.values[key]

    def __repr__(self) -> str:
        return f"<beamflow.identify.Identification\n{self.fragment}>"


def _csv(name: str, columns: Mapping[str, Any], directory: Path) -> Path:
    """Columns given as arrays, written as the CSV the library reads; ``repr`` writes each
    number in its shortest exact form, so the library reads the same numbers."""
    unknown = [k for k in columns if k not in _UNITS]
    if unknown:
        raise InputError("<arguments>", name, f"unknown column {unknown[0]!r}: give some of {', '.join(_UNITS)}")
    data = []
    for k, v in columns.items():
        a = np.asarray(v, dtype=np.float64)
        if a.ndim != 1:
            raise InputError("<arguments>", f"{name}[{k!r}]", f"give a 1-D array, not one of shape {a.shape}")
        data.append(a)
    if len({len(a) for a in data}) > 1:
        raise InputError("<arguments>", name, f"the columns differ in length: {[len(a) for a in data]}")
    path = directory / f"{name}.csv"
    lines = [",".join(f"{k} ({_UNITS[k]})" for k in columns)]
    lines += [",".join(repr(float(x)) for x in row) for row in zip(*data)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@contextlib.contextmanager
def _sources(**measurements: Measurement) -> Any:
    """The measurements as files: arrays written to a temporary folder for the call."""
    with tempfile.TemporaryDirectory(prefix="beamflow-identify-") as tmp:
        files = {}
        for name, m in measurements.items():
            files[name] = _csv(name, m, Path(tmp)) if isinstance(m, Mapping) else Path(m)
        yield files


def dp(
    first: Measurement,
    second: Measurement,
    *,
    k_p: Optional[float] = None,
    offset_tolerance: Optional[float] = None,
    align: bool = True,
    out: Optional[PathLike] = None,
    plots: bool = True,
    uniform_tolerance: Optional[float] = None,
) -> Identification:
    """``d_p`` (m/V) from two records whose voltages differ by a constant offset
    (``beamflow identify dp``): ``values["d_p"]``, ``delta_v``, ``std_error``, …

    ``k_p`` (N/m): records with a blocked-force column instead of a stroke;
    ``offset_tolerance``: the largest accepted std(V₂ − V₁)/|ΔV| (default 0.1);
    ``align=False`` pairs samples by index. With ``out``, writes ``dp.toml``, ``dp.json``
    and (``plots``) the figure there.
    """
    check_numbers(real={"k_p": k_p, "offset_tolerance": offset_tolerance, "uniform_tolerance": uniform_tolerance})
    with _sources(first=first, second=second) as f, as_arguments():
        raw = _native.identify_dp(
            f["first"], f["second"], k_p, offset_tolerance, align, _out(out), plots, uniform_tolerance
        )
    return Identification(raw)


def bouc_wen(
    file: Measurement,
    *,
    d_p: float,
    target: str = "stroke",
    k_p: Optional[float] = None,
    seeds: Sequence[int] = (1, 2, 3),
    period: Optional[float] = None,
    cycles: Optional[int] = None,
    particles: Optional[int] = None,
    max_iterations: Optional[int] = None,
    out: Optional[PathLike] = None,
    plots: bool = True,
    uniform_tolerance: Optional[float] = None,
    max_memory: Optional[Size] = None,
    max_steps: Optional[Size] = None,
) -> Identification:
    """The Bouc–Wen α, β, γ by particle swarm against a stroke (``target="stroke"``) or
    blocked-force cycle (``target="force"`` with ``k_p``), ``d_p`` held fixed
    (``beamflow identify bouc-wen``). Each of ``seeds`` runs a swarm; the best fit is kept
    and the spread reported (``values["fit"]``). ``cycles`` whole periods (default 1) are
    fitted from the record's end; ``particles`` (30) and ``max_iterations`` (400) size the
    swarm.
    """
    seeds = list(seeds)
    check_numbers(
        whole={"cycles": cycles, "particles": particles, "max_iterations": max_iterations,
               **{f"seeds[{k}]": s for k, s in enumerate(seeds)}},
        real={"d_p": d_p, "k_p": k_p, "period": period, "uniform_tolerance": uniform_tolerance},
    )
    with _sources(file=file) as f, as_arguments():
        raw = _native.identify_bouc_wen(
            f["file"], d_p, target, k_p, seeds, period, cycles, particles, max_iterations, _out(out), plots,
            uniform_tolerance, budget_text(max_memory, "max_memory"), budget_text(max_steps, "max_steps"),
        )
    return Identification(raw)


def modal(
    file: Measurement,
    *,
    mass: float,
    modes: Optional[int] = None,
    band: Optional[Tuple[float, float]] = None,
    element: str = "stack",
    use_mode: Optional[int] = None,
    segment: Optional[int] = None,
    exp_window: Optional[float] = None,
    force_window: Optional[float] = None,
    min_coherence: Optional[float] = None,
    out: Optional[PathLike] = None,
    plots: bool = True,
    uniform_tolerance: Optional[float] = None,
) -> Identification:
    """A stiffness and damping from an impact test (time, force, acceleration): H1, modal
    fit, k = m·ω_n², c = 2ζ·m·ω_n (``beamflow identify modal``). ``mass`` (kg) is the
    known moving mass, ``element`` (``"stack"``, ``"leg"``, ``"leg_right"``) the fields
    of the fragment, ``band`` (F1, F2) in Hz the fits' band; the rest as the command line's
    flags. ``values["parameters"]`` holds k and c.
    """
    if band is not None:
        band = tuple(band)  # type: ignore[assignment]
        if len(band) != 2:
            raise InputError("<arguments>", "band", f"give two frequencies (F1, F2) in Hz, not {band!r}")
    check_numbers(
        whole={"modes": modes, "use_mode": use_mode, "segment": segment},
        real={"mass": mass, "exp_window": exp_window, "force_window": force_window, "min_coherence": min_coherence,
              "uniform_tolerance": uniform_tolerance, **{f"band[{k}]": f for k, f in enumerate(band or ())}},
    )
    with _sources(file=file) as f, as_arguments():
        raw = _native.identify_modal(
            f["file"], mass, modes, band, element, use_mode, segment, exp_window, force_window, min_coherence,
            _out(out), plots, uniform_tolerance,
        )
    return Identification(raw)


def _out(out: Optional[PathLike]) -> Optional[Path]:
    return None if out is None else Path(out)
