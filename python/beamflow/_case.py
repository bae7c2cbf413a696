"""Cases: read, change by dotted path, check and run."""

from __future__ import annotations

import html
import os
import warnings
from pathlib import Path
from typing import Any, Dict, Iterable, Mapping, Optional, Tuple, Union

from . import _native
from ._arguments import Size, as_arguments, budget_text
from ._progress import ProgressArg, callback
from ._results import Results
from ._system import Modes, System, _modes, _system
from .errors import ConvergenceWarning

__all__ = ["Case"]

PathLike = Union[str, "os.PathLike[str]"]
_MISSING = object()


class Case:
    """A beamflow case (the TOML file of ``docs/case-format.md``), always valid.

    Fields are read and changed by the dotted paths of sweeps; every change is checked at
    once, and a bad path or value raises :class:`beamflow.InputError` naming the field::

        >>> case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
        >>> case["actuator[0].x_e"]
        0.15
        >>> case["actuator[0].x_e"] = 0.2
        >>> case["damping.zeta"]          # not written in the file: the default
        0.01
        >>> results = case.run()
        >>> results.analysis("steady_state").net_power
        {'frame': 9.347781076581875e-06}

    Several fields that only make sense together change in one step with :meth:`update`.
    """

    __slots__ = ("_native",)

    def __init__(self, native: "_native.NativeCase") -> None:
        self._native = native

    # -- construction -------------------------------------------------------------------

    @classmethod
    def from_file(cls, path: PathLike) -> "Case":
        """Reads and checks a case file; its relative paths resolve next to it."""
        return cls(_native.NativeCase.from_file(Path(path)))

    @classmethod
    def from_toml(cls, text: str, *, name: str = "<toml>", base_dir: Optional[PathLike] = None) -> "Case":
        """A case from TOML text. ``name`` labels it in messages; relative paths in it
        resolve against ``base_dir`` (default: the working directory)."""
        return cls(_native.NativeCase.from_toml(text, name, Path(base_dir or ".")))

    @classmethod
    def from_dict(cls, value: Mapping[str, Any], *, name: str = "<dict>", base_dir: Optional[PathLike] = None) -> "Case":
        """A case from a dict shaped like the TOML file (tables are dicts, arrays of tables
        are lists of dicts)::

            Case.from_dict({"actuator": [{"type": "inertial", "x_e": 0.15,
                                          "voltage": {"kind": "sine", "amplitude": 12.0, "frequency": 60.0}}],
                            "analysis": [{"type": "steady_state"}]})
        """
        return cls(_native.NativeCase.from_value(value, name, Path(base_dir or ".")))

    # -- fields -------------------------------------------------------------------------

    @property
    def file(self) -> str:
        """The file (or label) messages and results name the case by."""
        return self._native.file

    @property
    def base_dir(self) -> Path:
        """Where relative paths in the case resolve."""
        return Path(self._native.dir)

    def __getitem__(self, path: str) -> Any:
        """The value at a dotted path (``"actuator[0].voltage.frequency"``): as written in
        the case, else the default it gets. Tables come back as dicts, arrays as lists.
        Raises :class:`beamflow.FieldNotFound` (a ``KeyError``) for a path that is no field."""
        return self._native.get(path)

    def __setitem__(self, path: str, value: Any) -> None:
        """Sets a field by dotted path and checks the case; on error nothing changes."""
        self._native.set(path, value)

    def __contains__(self, path: object) -> bool:
        try:
            self._native.get(str(path))
            return True
        except KeyError:
            return False

    def get(self, path: str, default: Any = None) -> Any:
        """The value at ``path``, or ``default`` if there is no such field."""
        try:
            return self._native.get(path)
        except KeyError:
            return default

    def update(self, values: Union[Mapping[str, Any], Iterable[Tuple[str, Any]]] = ()) -> None:
        """Sets several dotted paths and checks the case once, after all of them (for
        changes that are only valid together, e.g. a shorter beam and an actuator on it)."""
        items = list(values.items()) if isinstance(values, Mapping) else list(values)
        self._native.update(items)

    def copy(self) -> "Case":
        """An independent copy (changes to it leave this case alone)."""
        return Case(self._native.copy())

    __copy__ = copy

    def to_toml(self) -> str:
        """The case as TOML text (the file as read while unchanged)."""
        return self._native.to_toml()

    def to_dict(self, *, defaults: bool = False) -> Dict[str, Any]:
        """The case as a dict; with ``defaults=True`` every field, defaults filled in."""
        return self._native.to_dict(defaults)

    def __repr__(self) -> str:
        return f"<beamflow.Case {self.file}>"

    def __eq__(self, other: object) -> bool:
        """Two cases are equal when they describe the same model and analyses: every field
        alike, defaults filled in, and relative paths resolving in the same directory (how
        they were written, or the label messages give them, does not count)."""
        if not isinstance(other, Case):
            return NotImplemented
        return (
            self.to_dict(defaults=True) == other.to_dict(defaults=True)
            and self.base_dir.resolve() == other.base_dir.resolve()
        )

    __hash__ = None  # type: ignore[assignment]  (a case changes: not a dict key)

    def __reduce__(self) -> Tuple[Any, Tuple[str, str, str]]:
        """Pickles as its TOML text, label and directory (for multiprocessing, joblib,
        Dask); unpickling checks the case again, its files relative to the same directory."""
        return (_unpickle, (self.to_toml(), self.file, str(self.base_dir)))

    def _repr_html_(self) -> str:
        """A notebook's view: the title, the actuators and analyses, the TOML on demand."""
        d = self.to_dict(defaults=True)
        rows = [("file", self.file), ("title", d.get("title") or "")]
        for i, a in enumerate(d.get("actuator", [])):
            v = a.get("voltage", {})
            drive = ", ".join(f"{k} {v[k]}" for k in ("kind", "amplitude", "frequency") if k in v)
            rows.append((f"actuator[{i}]", f"{a.get('name', '')} ({a.get('type')}) at x_e = {a.get('x_e')} m; {drive}"))
        for i, a in enumerate(d.get("analysis", [])):
            rows.append((f"analysis[{i}]", a.get("type", "")))
        body = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th><td style='text-align:left'>{html.escape(str(v))}</td></tr>" for k, v in rows)
        toml = html.escape(self.to_toml())
        return f"<b>beamflow.Case</b><table>{body}</table><details><summary>TOML</summary><pre>{toml}</pre></details>"

    # -- running ------------------------------------------------------------------------

    def check(self, *, max_memory: Optional[Size] = None, max_steps: Optional[Size] = None) -> Dict[str, Any]:
        """Builds the model and assembles the system, like ``beamflow check``: returns
        ``elements``, ``dofs``, ``actuators``, ``links`` and ``modal_damping``; raises on
        any problem (naming the file, the field and the reason), also an analysis that
        would take more than ``max_memory`` (e.g. ``"8G"``; default: half the memory
        available) or ``max_steps`` time steps (default 1e9)."""
        with as_arguments():
            return self._native.check(budget_text(max_memory, "max_memory"), budget_text(max_steps, "max_steps"))

    def run(
        self, *, progress: ProgressArg = None, max_memory: Optional[Size] = None, max_steps: Optional[Size] = None
    ) -> Results:
        """Runs every analysis of the case and returns its :class:`Results` (the same
        numbers, bit for bit, as ``beamflow run``'s HDF5 and JSON).

        The solve runs with the GIL released, so other Python threads (another case) run
        at the same time. Ctrl-C raises ``KeyboardInterrupt`` at once and stops the solve
        at its next step (period, harmonic, frequency), so no core stays busy with it.

        ``progress=True`` shows bars (tqdm's if installed); a callable is called with each
        task's progress (see :data:`beamflow.ProgressArg`). A transient that did not settle
        warns with :class:`beamflow.ConvergenceWarning` and says so on its analysis
        (:attr:`Analysis.settled`).

        An analysis that would take more than ``max_memory`` (bytes, or e.g. ``"8G"``;
        default: half the memory available) or ``max_steps`` time steps (default 1e9) is
        refused before it starts, as ``beamflow run --max-memory/--max-steps`` refuses it.
        """
        budget = (budget_text(max_memory, "max_memory"), budget_text(max_steps, "max_steps"))
        cb, close = callback(progress)
        try:
            with as_arguments():
                run = self._native.run(cb, *budget)
        finally:
            close()
        results = Results(run.tree(), run)
        for note in results.warnings:
            warnings.warn(note, ConvergenceWarning, stacklevel=2)
        return results

    def system(self) -> System:
        """The assembled M, C, K (``scipy.sparse.csr_matrix``) and the DOF map of the full
        model (beam, supports removed, plus actuator bodies)."""
        return _system(self._native.system())

    def modes(self, count: int = 10) -> Modes:
        """The bare beam's natural modes (what ``beamflow modes`` prints), with closed-form
        references where they exist; shapes as ``w`` at every node."""
        return _modes(self._native.modes(count), coupled=False)

    def coupled_modes(self, count: int = 10) -> Modes:
        """The undamped modes of the beam with its actuators attached (the assembled K, M
        over every DOF); shapes over the global DOFs (see :attr:`Modes.dofs`)."""
        return _modes(self._native.coupled_modes(count), coupled=True)


def _unpickle(text: str, name: str, base_dir: str) -> Case:
    return Case.from_toml(text, name=name, base_dir=base_dir)
