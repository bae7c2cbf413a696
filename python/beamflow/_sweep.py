"""Parameter sweeps through the library's parallel sweep runner."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, Iterator, Mapping, Optional, Union

import numpy as np

from . import _native
from ._progress import ProgressArg, callback
from ._results import Quantity
from ._arguments import Size, as_arguments, budget_text, check_numbers
from ._commands import spec_text
from .errors import InputError, SweepInterrupted

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
    out: Optional[PathLike] = None,
    shard: Optional[str] = None,
    csv: bool = False,
    plots: bool = True,
    max_memory: Optional[Size] = None,
    max_steps: Optional[Size] = None,
    client: Any = None,
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

    With ``out`` (an HDF5 table, ``FILE.h5``) it runs as ``beamflow sweep --out``: finished
    cases are kept in ``FILE.h5.parts/`` until the table is written, so a sweep stopped (by
    Ctrl-C, or a crash) resumes where it stopped when called again; ``shard="k/N"`` runs
    only cases i with i mod N = k − 1 (join the shards with :func:`merge`); ``csv`` also
    writes the tidy CSV (``FILE.csv``) and ``plots`` the figure, best-case table and
    report.html beside the table. ``max_memory`` (e.g. ``"8G"``) and ``max_steps`` bound
    what one case may take and how many cases there may be.

    With a Dask ``client`` (``distributed.Client``) the cases are spread over its workers:
    the sweep is cut into shards, each run by the library on a worker, and the shard tables
    joined by the library's merge, so the table is the one a single process gives, bit for
    bit (with ``out``, written there; ``threads`` is then per worker). The case files the
    sweep names must be readable by the workers at the same paths.

    ``progress=True`` shows a bar of the cases done (tqdm's if installed); a callable is
    called with each change. Ctrl-C stops the cases being solved at their next step and
    raises :class:`beamflow.SweepInterrupted` (a ``KeyboardInterrupt``) whose ``table``
    holds the cases finished (with ``out``: a ``KeyboardInterrupt``, the finished cases
    being in the checkpoints).
    """
    check_numbers(whole={"threads": threads})
    text, name, directory, cleanup = spec_text(spec, base_dir)
    budget = (budget_text(max_memory, "max_memory"), budget_text(max_steps, "max_steps"))
    cb, close = callback(progress)
    try:
        with as_arguments():
            if client is not None:
                if shard is not None:
                    raise InputError("<arguments>", "shard", "a sweep on a Dask `client` makes its own shards")
                from ._dask import sweep_on

                table = SweepTable(sweep_on(client, text, name, directory, threads, budget, cb,
                                            None if out is None else Path(out), csv, plots))
                return _result(table, as_frame)
            if out is None:
                if shard is not None or csv:
                    field = "shard" if shard is not None else "csv"
                    raise InputError("<arguments>", field, f"`{field}` needs `out`, the table to write")
                raw, stopped = _native.run_sweep(text, name, directory, threads, *budget, cb)
            else:
                _native.sweep_into(text, name, directory, Path(out), shard, threads, csv, plots, *budget, cb)
                return read_sweep_table(out, as_frame=as_frame)
    finally:
        close()
        cleanup()
    table = SweepTable(raw)
    if isinstance(stopped, KeyboardInterrupt):
        raise SweepInterrupted(_result(table, as_frame), table.rows, int(table.meta["total_cases"])) from stopped
    if stopped is not None:
        raise stopped
    return _result(table, as_frame)


def read_sweep_table(path: PathLike, *, as_frame: Optional[bool] = None) -> Any:
    """Reads a sweep table written by ``beamflow sweep``/``merge`` (same columns as
    :func:`sweep`; a DataFrame when pandas is installed unless ``as_frame=False``)."""
    return _result(SweepTable(_native.read_sweep_table(Path(path))), as_frame)
