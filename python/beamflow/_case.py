"""Cases: read, change by dotted path, check and run."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, Iterable, Mapping, Optional, Tuple, Union

from . import _native
from ._results import Results
from ._system import Modes, System, _modes, _system

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

    # -- running ------------------------------------------------------------------------

    def check(self) -> Dict[str, Any]:
        """Builds the model and assembles the system, like ``beamflow check``: returns
        ``elements``, ``dofs``, ``actuators``, ``links`` and ``modal_damping``; raises on
        any problem (naming the file, the field and the reason)."""
        return self._native.check()

    def run(self) -> Results:
        """Runs every analysis of the case and returns its :class:`Results` (the same
        numbers, bit for bit, as ``beamflow run``'s HDF5 and JSON).

        The solve runs with the GIL released, so other Python threads (another case) run
        at the same time. Ctrl-C raises ``KeyboardInterrupt`` at once; the abandoned solve
        then finishes in the background and its result is dropped (a case run has no
        cancellation point of its own; a sweep stops between cases).
        """
        run = self._native.run()
        return Results(run.tree(), run)

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
