"""Imported models from matrices in memory (spec §17): scipy.sparse (or dense numpy) M, K,
optionally C, and a DOF table, written in the format ``[imported]`` reads."""

import atexit
import csv
import shutil
import tempfile
from pathlib import Path
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

_COLUMNS = ("row", "node", "x_m", "y_m", "z_m", "component")
_folders = []


@atexit.register
def _remove_folders() -> None:
    for f in _folders:
        shutil.rmtree(f, ignore_errors=True)


def imported(
    mass: Any,
    stiffness: Any,
    dofs: Any,
    *,
    damping: Any = None,
    fixed: Sequence[int] = (),
    folder: Optional[Union[str, Path]] = None,
) -> dict:
    """The ``imported`` table of a case for a model given in memory::

        table = beamflow.imported(M, K, dofs)          # scipy.sparse or numpy arrays
        case = beamflow.Case.from_dict({"imported": table, "damping": {"kind": "none"},
                                        "actuator": [{"type": "inertial", "node": 12,
                                                      "component": "uz", "voltage": {...}}],
                                        "analysis": [{"type": "modes", "count": 6}]})

    ``dofs`` names each matrix row: a pandas DataFrame with columns ``row, node, x_m, y_m,
    z_m, component`` (``row`` 1-based), a dict of such columns, or a sequence of
    ``(row, node, x, y, z, component)`` rows. ``damping`` is C (use it with
    ``damping.kind = "given"``), ``fixed`` 1-based rows held at zero. The matrices are
    written as Matrix Market files (exact values) into ``folder``, by default a temporary
    folder removed when Python exits; the model is checked when a case using it runs, as a
    case file's would be (:class:`beamflow.InputError` naming the file and row).
    """
    out = Path(folder) if folder is not None else Path(tempfile.mkdtemp(prefix="beamflow-imported-"))
    if folder is None:
        _folders.append(out)
    out.mkdir(parents=True, exist_ok=True)
    table = {"mass": str(out / "M.mtx"), "stiffness": str(out / "K.mtx"), "dofs": str(out / "dofs.csv")}
    _write_matrix(out / "M.mtx", mass)
    _write_matrix(out / "K.mtx", stiffness)
    if damping is not None:
        _write_matrix(out / "C.mtx", damping)
        table["damping"] = str(out / "C.mtx")
    _write_dofs(out / "dofs.csv", dofs)
    if len(fixed):
        table["fixed"] = [int(r) for r in fixed]
    return table


def _write_matrix(path: Path, a: Any) -> None:
    """Matrix Market coordinate real, general storage, values in shortest round-trip form
    (beamflow checks the symmetry itself and names the entry that breaks it)."""
    import scipy.sparse

    coo = scipy.sparse.coo_matrix(a)
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real general\n")
        f.write(f"{coo.shape[0]} {coo.shape[1]} {coo.nnz}\n")
        for i, j, v in zip(coo.row, coo.col, coo.data):
            f.write(f"{i + 1} {j + 1} {float(v)!r}\n")


def _rows(dofs: Any) -> Iterable[Sequence[Any]]:
    if hasattr(dofs, "to_dict") and hasattr(dofs, "columns"):  # a pandas DataFrame
        dofs = {c: list(dofs[c]) for c in dofs.columns}
    if isinstance(dofs, Mapping):
        missing = [c for c in _COLUMNS if c not in dofs]
        if missing:
            raise ValueError(f"dofs: missing column(s) {', '.join(missing)} (need {', '.join(_COLUMNS)})")
        return zip(*(dofs[c] for c in _COLUMNS))
    return dofs


def _write_dofs(path: Path, dofs: Any) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(_COLUMNS)
        for k, r in enumerate(_rows(dofs)):
            r = list(r)
            if len(r) != 6:
                raise ValueError(f"dofs: row {k} has {len(r)} values, not (row, node, x, y, z, component)")
            w.writerow([int(r[0]), int(r[1]), *(repr(float(v)) for v in r[2:5]), str(r[5])])
