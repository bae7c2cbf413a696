"""Parameter sweeps through the library's parallel sweep runner."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any, Dict, Iterator, Mapping, Optional, Union

import numpy as np

from . import _native
from ._case import Case
from ._progress import ProgressArg, callback
from ._results import Quantity
from .errors import SweepInterrupted

__all__ = ["SweepTable", "sweep", "read_sweep_table"]

PathLike = Union[str, "os.PathLike[str]"]


class SweepTable(Mapping[str, Quantity]):
    """A sweep's table: one row per case, as named numpy columns (:class:`Quantity`, with
    ``unit`` and ``description``), in case order.

    Columns: ``case`` (index in the whole sweep), each swept field by its dotted path
    (e.g. ``actuator[0].x_e``), ``net_power[<actuator>]`` (W), ``mean_power[<link>]`` (W),
    ``force_amplitude[<link>]`` (N, transmitted force at the drive's fundamental),
    ``beam_dissipation`` (W) and ``balance_error`` (1). ``meta`` holds the sweep's
    description (title, analysis, harmonics, actuators, links, hash).
    """

    def __init__(self, raw: Dict[str, Any]) -> None:
        self.columns: Dict[str, Quantity] = {name: Quantity(data, unit, desc) for name, data, unit, desc in raw["columns"]}
        self.meta: Dict[str, Any] = dict(raw["meta"])

    def __getitem__(self, name: str) -> Quantity:
        return self.columns[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self.columns)

    def __len__(self) -> int:
        return len(self.columns)

    @property
    def units(self) -> Dict[str, str]:
        """The unit of every column."""
        return {k: c.unit for k, c in self.columns.items()}

    @property
    def rows(self) -> int:
        return len(self.columns["case"])

    def to_dict(self) -> Dict[str, Quantity]:
        """The columns as a plain dict."""
        return dict(self.columns)

    def to_frame(self) -> Any:
        """The table as a pandas DataFrame indexed by case; units and the sweep's
        description in ``df.attrs["units"]`` and ``df.attrs["sweep"]``."""
        import pandas as pd

        plain = {k: np.asarray(c).view(np.ndarray) for k, c in self.columns.items()}
        case = plain.pop("case")
        df = pd.DataFrame(plain, index=pd.Index(case, name="case"))
        df.attrs["units"] = self.units
        df.attrs["sweep"] = dict(self.meta)
        return df

    def __repr__(self) -> str:
        return f"<beamflow.SweepTable {self.meta.get('title') or self.meta.get('sweep_file')}: {self.rows} cases, columns {list(self.columns)}>"


def _have_pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def _result(table: SweepTable, as_frame: Optional[bool]) -> Any:
    if as_frame or (as_frame is None and _have_pandas()):
        return table.to_frame()
    return table


def sweep(
    spec: Union[PathLike, Mapping[str, Any]],
    *,
    base_dir: Optional[PathLike] = None,
    threads: Optional[int] = None,
    as_frame: Optional[bool] = None,
    progress: ProgressArg = None,
) -> Any:
    """Runs a parameter sweep (``docs/sweeps.md``) on the library's parallel runner.

    ``spec`` is a sweep file or the same content as a dict. A dict's ``base`` is a case file
    (resolved against ``base_dir``, default: the working directory) or a :class:`Case`::

        table = beamflow.sweep({
            "base": "cases/placement-frame.toml",
            "parameter": [{"path": "actuator[0].x_e", "start": 0.1, "stop": 0.6, "count": 26}],
        })
        case = beamflow.Case.from_file("cases/placement-frame.toml")
        case["actuator[0].voltage.amplitude"] = 24.0
        table = beamflow.sweep({"base": case, "parameter": [{"path": "actuator[0].x_e", "values": [0.1, 0.2]}]})

    Returns a pandas DataFrame when pandas is installed (``as_frame=None``, the default),
    else a :class:`SweepTable` of numpy columns; ``as_frame=False`` always gives the
    :class:`SweepTable`. The numbers are those of ``beamflow sweep``, bit for bit, whatever
    ``threads`` (default: one per core).

    ``progress=True`` shows a bar of the cases done (tqdm's if installed); a callable is
    called with each change. Ctrl-C stops the cases being solved at their next step and
    raises :class:`beamflow.SweepInterrupted` (a ``KeyboardInterrupt``) whose ``table``
    holds the cases finished.
    """
    if isinstance(spec, Mapping):
        spec = dict(spec)
        tmp = None
        if isinstance(spec.get("base"), Case):
            tmp = tempfile.TemporaryDirectory(prefix="beamflow-sweep-")
            spec["base"] = str(_standalone(spec["base"], Path(tmp.name)))
        try:
            text = _native.toml_dumps(spec)
            directory = Path(base_dir or ".")
            return _run(text, "<dict>", directory, threads, as_frame, progress)
        finally:
            if tmp is not None:
                tmp.cleanup()
    else:
        path = Path(spec)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as e:
            from .errors import IoError

            raise IoError(str(path), e.strerror or str(e), e.errno) from None
        directory = Path(base_dir) if base_dir is not None else path.parent
        return _run(text, str(path), directory, threads, as_frame, progress)


def _run(text: str, name: str, directory: Path, threads: Optional[int], as_frame: Optional[bool], progress: ProgressArg) -> Any:
    cb, close = callback(progress)
    try:
        raw, stopped = _native.run_sweep(text, name, directory, threads, cb)
    finally:
        close()
    table = SweepTable(raw)
    if isinstance(stopped, KeyboardInterrupt):
        raise SweepInterrupted(_result(table, as_frame), table.rows, int(table.meta["total_cases"])) from stopped
    if stopped is not None:
        raise stopped
    return _result(table, as_frame)


def _standalone(case: Case, directory: Path) -> Path:
    """Writes ``case`` as ``directory/base.toml`` for a sweep to read, with the files it
    names (a mesh, voltage series; relative to the case file) made absolute so that they
    still resolve from there."""
    case = case.copy()
    fields = ["beam.mesh.file"] + [f"actuator[{i}].voltage.file" for i in range(len(case.get("actuator", [])))]
    changes = {}
    for path in fields:
        value = case.get(path)
        if isinstance(value, str) and not Path(value).is_absolute():
            changes[path] = str((case.base_dir / value).resolve())
    if changes:
        case.update(changes)
    out = directory / "base.toml"
    out.write_text(case.to_toml(), encoding="utf-8")
    return out


def read_sweep_table(path: PathLike, *, as_frame: Optional[bool] = None) -> Any:
    """Reads a sweep table written by ``beamflow sweep``/``merge`` (same columns as
    :func:`sweep`; a DataFrame when pandas is installed unless ``as_frame=False``)."""
    return _result(SweepTable(_native.read_sweep_table(Path(path))), as_frame)
