"""Parameter sweeps through the library's parallel sweep runner."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, Iterator, List, Mapping, Optional, Union

from . import _native
from ._results import Quantity

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

        data = {k: c.view(type(c).__base__) for k, c in self.columns.items() if k != "case"}
        df = pd.DataFrame(data, index=pd.Index(self.columns["case"].view(type(self.columns["case"]).__base__), name="case"))
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
) -> Any:
    """Runs a parameter sweep (``docs/sweeps.md``) on the library's parallel runner.

    ``spec`` is a sweep file or the same content as a dict; a dict's ``base`` case path
    resolves against ``base_dir`` (default: the working directory)::

        table = beamflow.sweep({
            "base": "cases/placement-frame.toml",
            "parameter": [{"path": "actuator[0].x_e", "start": 0.1, "stop": 0.6, "count": 26}],
        })

    Returns a pandas DataFrame when pandas is installed (``as_frame=None``, the default),
    else a :class:`SweepTable` of numpy columns; ``as_frame=False`` always gives the
    :class:`SweepTable`. The numbers are those of ``beamflow sweep``, bit for bit, whatever
    ``threads`` (default: one per core). Ctrl-C stops the sweep between cases.
    """
    if isinstance(spec, Mapping):
        text = _native.toml_dumps(spec)
        name = "<dict>"
        directory = Path(base_dir or ".")
    else:
        path = Path(spec)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as e:
            from .errors import IoError

            raise IoError(str(path), e.strerror or str(e), e.errno) from None
        name = str(path)
        directory = Path(base_dir) if base_dir is not None else path.parent
    return _result(SweepTable(_native.run_sweep(text, name, directory, threads)), as_frame)


def read_sweep_table(path: PathLike, *, as_frame: Optional[bool] = None) -> Any:
    """Reads a sweep table written by ``beamflow sweep``/``merge`` (same columns as
    :func:`sweep`; a DataFrame when pandas is installed unless ``as_frame=False``)."""
    return _result(SweepTable(_native.read_sweep_table(Path(path))), as_frame)
