"""The command line's other commands from Python: optimisation, the paper's experiments,
merging sweep shards and synthetic measurements. Each calls the library function the
command line calls, so the numbers and files are the command line's, bit for bit."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import tempfile
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._arguments import Size, as_arguments, budget_text, check_numbers
from ._case import Case
from ._progress import ProgressArg, callback
from .errors import InputError, IoError

__all__ = ["OptimizeResult", "optimize", "merge", "paper", "synth"]

PathLike = Union[str, "os.PathLike[str]"]


def spec_text(spec: Union[PathLike, Mapping[str, Any]], base_dir: Optional[PathLike], field: str = "base") -> Any:
    """``(text, name, directory, cleanup)`` of a study given as a file or a dict; a dict's
    ``base`` may be a :class:`Case` (written to a temporary folder that ``cleanup`` removes)."""
    if isinstance(spec, Mapping):
        spec = dict(spec)
        tmp = None
        if isinstance(spec.get(field), Case):
            tmp = tempfile.TemporaryDirectory(prefix="beamflow-")
            spec[field] = str(standalone(spec[field], Path(tmp.name)))
        cleanup = tmp.cleanup if tmp is not None else (lambda: None)
        return _native.toml_dumps(spec), "<dict>", Path(base_dir or "."), cleanup
    path = Path(spec)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise IoError(str(path), e.strerror or str(e), e.errno) from None
    return text, str(path), Path(base_dir) if base_dir is not None else path.parent, lambda: None


def standalone(case: Case, directory: Path) -> Path:
    """Writes ``case`` as ``directory/base.toml`` for a study to read, with the files it
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


def _csv_columns(text: str) -> Dict[str, np.ndarray]:
    """A numeric CSV table of the command line as columns. Its numbers are written in
    their shortest exact form, so ``float`` reads them back bit for bit."""
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], rows[1:]
    cols: Dict[str, np.ndarray] = {}
    for k, name in enumerate(header):
        values = [r[k] for r in body]
        if name in ("evaluation", "rank", "feasible"):
            cols[name] = np.array([int(v) for v in values], dtype=np.int64)
        else:
            cols[name] = np.array([float(v) for v in values], dtype=np.float64)
    return cols


def _frame(cols: Dict[str, np.ndarray], as_frame: Optional[bool]) -> Any:
    if as_frame is False:
        return cols
    try:
        import pandas as pd
    except ImportError:
        if as_frame:
            raise
        return cols
    return pd.DataFrame(cols)


class OptimizeResult:
    """What :func:`optimize` found, as the command line's output set.

    ``best`` is the best case (a :class:`Case`, runnable as it is: the best values set and a
    steady-state analysis added if the base case had none); ``history`` every evaluation in
    order (``evaluation``, ``feasible``, ``best so far [<unit>]``, each objective and
    variable with its unit), ``optima`` the distinct local optima, best first, and
    ``pareto`` the Pareto front of a two-objective run (None with one objective): pandas
    DataFrames when pandas is installed, else dicts of numpy columns, the numbers of
    ``history.csv``, ``optima.csv`` and ``pareto.csv`` bit for bit. ``summary`` is
    ``summary.json`` (the best candidate's variables with their typed values, the
    objectives, the seed), ``texts`` every text file of the set by name and ``files`` the
    files written (with ``out=``).
    """

    def __init__(self, raw: Dict[str, Any], as_frame: Optional[bool]) -> None:
        self.texts: Dict[str, str] = dict(raw["texts"])
        self.files: List[Path] = [Path(p) for p in raw["files"]]
        self.evaluations: int = raw["evaluations"]
        self.seconds: float = raw["seconds"]
        self.summary: Dict[str, Any] = json.loads(self.texts["summary.json"])
        self.best = Case.from_toml(self.texts["best.toml"], name="best.toml", base_dir=raw["base_dir"] or ".")
        self.history = _frame(_csv_columns(self.texts["history.csv"]), as_frame)
        self.optima = _frame(_csv_columns(self.texts["optima.csv"]), as_frame)
        pareto = self.texts.get("pareto.csv")
        self.pareto = None if pareto is None else _frame(_csv_columns(pareto), as_frame)

    def __repr__(self) -> str:
        objectives = ", ".join(f"{k} = {v:.6g}" for k, v in self.summary["best"]["objectives"].items())
        return f"<beamflow.OptimizeResult {self.evaluations} evaluations: best {objectives}>"


def optimize(
    spec: Union[PathLike, Mapping[str, Any]],
    *,
    base_dir: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    threads: Optional[int] = None,
    plots: bool = True,
    max_memory: Optional[Size] = None,
    max_steps: Optional[Size] = None,
    as_frame: Optional[bool] = None,
    progress: ProgressArg = None,
    client: Any = None,
) -> OptimizeResult:
    """Runs an optimisation (``docs/optimize.md``), as ``beamflow optimize`` does.

    ``spec`` is an optimisation file or the same content as a dict (its ``base`` a case
    file, resolved against ``base_dir``, or a :class:`Case`). With ``out`` the command
    line's output set is written there too (``best.toml``, the CSV tables,
    ``summary.json`` and, with ``plots``, the figures). ``max_memory`` (e.g. ``"8G"``) and
    ``max_steps`` bound what it may take, as the command line's ``--max-memory`` and
    ``--max-steps``. The result does not depend on ``threads``.

    With a Dask ``client`` (``distributed.Client``) the search runs here and every
    candidate is solved on a worker of its cluster by the library's evaluator: the same
    optimisation, bit for bit; ``threads`` (default: the cluster's worker threads) is then
    how many candidates are out at once. The files the optimisation names must be readable
    by the workers at the same paths.

    ``progress=True`` shows a bar of the evaluations; a callable gets each change. Ctrl-C
    (or an exception from the callable) stops the candidates being solved at their next
    step and raises ``KeyboardInterrupt``.
    """
    check_numbers(whole={"threads": threads})
    text, name, directory, cleanup = spec_text(spec, base_dir)
    remote = None
    if client is not None:
        from ._dask import cluster_threads, evaluator_on

        remote = evaluator_on(client, text, name, directory)
        threads = threads or cluster_threads(client)
    cb, close = callback(progress)
    try:
        with as_arguments():
            raw = _native.run_optimize(
                text,
                name,
                directory,
                None if out is None else Path(out),
                threads,
                plots,
                budget_text(max_memory, "max_memory"),
                budget_text(max_steps, "max_steps"),
                cb,
                remote,
            )
    finally:
        close()
        cleanup()
    return OptimizeResult(raw, as_frame)


def merge(shards: Sequence[PathLike], out: PathLike, *, csv: bool = False, plots: bool = True) -> List[Path]:
    """Joins the shard tables of ``beamflow.sweep(..., shard=)`` (or ``beamflow sweep
    --shard``) into the table ``out``, as ``beamflow merge`` does, and writes beside it the
    tidy CSV (with ``csv``; ``out`` must then end in ``.h5``) and, with ``plots``, the
    figure, the best-case table and report.html. Returns the files written beside the
    table; :func:`read_sweep_table` reads the table."""
    if isinstance(shards, (str, os.PathLike)):
        raise InputError("<arguments>", "shards", "give a list of shard files, not one path")
    with as_arguments():
        return [Path(p) for p in _native.merge([Path(s) for s in shards], Path(out), csv, plots)]


def paper(
    out: PathLike = "out/paper",
    *,
    csv: bool = False,
    max_memory: Optional[Size] = None,
    max_steps: Optional[Size] = None,
    progress: ProgressArg = None,
) -> Dict[str, Any]:
    """Reproduces the paper's experiments into ``out``, as ``beamflow paper`` does
    (figures, HDF5, with ``csv`` the tidy CSV tables); returns its ``summary.json``."""
    cb, close = callback(progress)
    try:
        with as_arguments():
            _native.paper(Path(out), csv, budget_text(max_memory, "max_memory"), budget_text(max_steps, "max_steps"), cb)
    finally:
        close()
    return json.loads((Path(out) / "summary.json").read_text(encoding="utf-8"))


def synth(
    case: Union[PathLike, Case],
    out: PathLike,
    *,
    kind: str = "stroke",
    noise: Optional[float] = None,
    voltage_noise: Optional[float] = None,
    seed: Optional[int] = None,
    actuator: Optional[str] = None,
    periods: Optional[int] = None,
    samples_per_period: Optional[int] = None,
    offset: Optional[float] = None,
    element: str = "stack",
    mass: Optional[float] = None,
    hits: Optional[int] = None,
    digits: int = 7,
    max_memory: Optional[Size] = None,
    max_steps: Optional[Size] = None,
) -> Dict[str, Any]:
    """Synthetic measurements of ``case``'s actuator, written as CSV to ``out``, as
    ``beamflow synth`` does (a ``"dp_pair"`` writes ``STEM_1.csv`` and ``STEM_2.csv``).

    ``kind``: ``"stroke"``, ``"blocked_force"``, ``"impact"`` or ``"dp_pair"``; the other
    arguments are the command line's flags (``None``: its default). Returns ``files``,
    ``samples`` (per file), ``truth`` (the parameters the records were made with) and
    ``report`` (what the command line prints).
    """
    check_numbers(
        whole={"seed": seed, "periods": periods, "samples_per_period": samples_per_period, "hits": hits, "digits": digits},
        real={"noise": noise, "voltage_noise": voltage_noise, "offset": offset, "mass": mass},
    )
    with contextlib.ExitStack() as stack:
        if isinstance(case, Case):
            tmp = stack.enter_context(tempfile.TemporaryDirectory(prefix="beamflow-synth-"))
            case = standalone(case, Path(tmp))
        with as_arguments():
            raw = _native.synth(
                Path(case), Path(out), kind, noise, voltage_noise, seed, actuator, periods, samples_per_period,
                offset, element, mass, hits, digits,
                budget_text(max_memory, "max_memory"), budget_text(max_steps, "max_steps"),
            )
    raw["files"] = [Path(p) for p in raw["files"]]
    raw["truth"] = json.loads(raw["truth"])
    return raw
