"""Sweeps and optimisations spread over a Dask cluster.

A sweep is cut into shards (``beamflow sweep --shard k/N``), each run on a worker by the
library's sweep runner, and the shard tables joined by the library's merge (``beamflow
merge``). An optimisation runs its search here and sends each candidate to a worker,
where the library's evaluator solves it. Either way the numbers are those of a single
process, bit for bit."""

from __future__ import annotations

import functools
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple

from . import _native

__all__ = ["sweep_on", "evaluator_on", "cluster_threads"]

#: Shards per worker thread: small enough shards that a slow one does not hold the end.
SHARDS_PER_THREAD = 4


def run_shard(text: str, name: str, directory: str, shard: str, threads: Optional[int], budget: Tuple[Any, Any]) -> bytes:
    """On a worker: one shard of the sweep, as the bytes of its HDF5 table."""
    with tempfile.TemporaryDirectory(prefix="beamflow-shard-") as d:
        out = Path(d) / "shard.h5"
        _native.sweep_into(text, name, Path(directory), out, shard, threads, False, False, *budget, None)
        return out.read_bytes()


@functools.lru_cache(maxsize=4)
def _evaluator(text: str, name: str, directory: str) -> Any:
    """On a worker: the optimisation loaded once for all its candidates there."""
    return _native.NativeEvaluator(text, name, Path(directory))


def evaluate_candidate(text: str, name: str, directory: str, u: List[float]) -> Any:
    """On a worker: one candidate's evaluation, as plain values."""
    return _evaluator(text, name, directory).evaluate(u)


def evaluator_on(client: Any, text: str, name: str, directory: Path) -> Callable[[List[float]], Any]:
    """What the library calls for each candidate: its evaluation on ``client``'s workers."""
    where = str(directory.resolve())

    def evaluate(u: List[float]) -> Any:
        return client.submit(evaluate_candidate, text, name, where, u, pure=False).result()

    return evaluate


def cluster_threads(client: Any) -> int:
    """The worker threads of ``client``'s cluster."""
    return _threads(client)


def _threads(client: Any) -> int:
    workers = client.scheduler_info().get("workers", {})
    return max(1, sum(int(w.get("nthreads", 1)) for w in workers.values()))


def sweep_on(
    client: Any,
    text: str,
    name: str,
    directory: Path,
    threads: Optional[int],
    budget: Tuple[Any, Any],
    progress: Optional[Callable[[Dict[str, Any]], Any]],
    out: Optional[Path] = None,
    csv: bool = False,
    plots: bool = True,
) -> Dict[str, Any]:
    """Runs the sweep on ``client``'s workers; returns the raw table of the whole sweep,
    also written to ``out`` (with the files beside it) if given."""
    from distributed import as_completed

    n = SHARDS_PER_THREAD * _threads(client)
    futures = [
        client.submit(run_shard, text, name, str(directory.resolve()), f"{k}/{n}", threads, budget, pure=False)
        for k in range(1, n + 1)
    ]
    tables: List[Optional[bytes]] = [None] * n
    index = {f.key: k for k, f in enumerate(futures)}
    try:
        for done, f in enumerate(as_completed(futures), start=1):
            tables[index[f.key]] = f.result()
            if progress is not None:
                progress({"task": "sweep", "done": done, "total": n, "unit": "shards", "message": ""})
    except BaseException:
        client.cancel(futures)
        raise
    with tempfile.TemporaryDirectory(prefix="beamflow-merge-") as d:
        paths = []
        for k, data in enumerate(tables, start=1):
            p = Path(d) / f"shard-{k}.h5"
            p.write_bytes(data)  # type: ignore[arg-type]
            paths.append(p)
        if out is None:
            out, csv, plots = Path(d) / "sweep.h5", False, False
        _native.merge(paths, out, csv, plots)
        return _native.read_sweep_table(out)
