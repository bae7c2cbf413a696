"""Results of a run: the HDF5 layout of ``docs/results-format.md``, held in memory.

A :class:`Results` is a tree of :class:`Group` objects whose datasets are
:class:`Quantity` arrays (numpy arrays with ``unit`` and ``description``), text, or lists
of text — the same names, shapes, dtypes and bits as the ``.h5`` file the command line
writes for the same case. On top of the tree, :class:`Analysis` offers the numbers a study
usually wants: net and point powers, power per harmonic, time histories, energy balance.
"""

from __future__ import annotations

import html
import json
import os
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, Mapping, Optional, Tuple, Union

import numpy as np

from . import _native

__all__ = ["Quantity", "Group", "Results", "Analysis", "read_results"]


class Quantity(np.ndarray):
    """A numpy array with a physical ``unit`` (SI, ``"1"`` if dimensionless) and a
    ``description``.

    Slicing keeps the unit (a slice is part of the same quantity); arithmetic returns a plain
    ``numpy.ndarray``, because beamflow does not track units through operations::

        >>> f = results.analysis("steady_state").spectra["frame_stack"]["frequency"]
        >>> f.unit, f.dtype, f.shape
        ('Hz', dtype('float64'), (10,))
    """

    unit: str
    description: str

    def __new__(cls, data: Any, unit: str = "", description: str = "") -> "Quantity":
        obj = np.asarray(data).view(cls)
        obj.unit = unit
        obj.description = description
        return obj

    def __array_finalize__(self, obj: Any) -> None:
        self.unit = getattr(obj, "unit", "")
        self.description = getattr(obj, "description", "")

    def __array_wrap__(self, arr: Any, context: Any = None, return_scalar: bool = False) -> Any:
        plain = np.asarray(arr).view(np.ndarray)
        return plain[()] if return_scalar else plain

    def __reduce__(self) -> Any:
        rebuild, args, state = super().__reduce__()  # type: ignore[misc]
        return rebuild, args, (state, self.unit, self.description)

    def __setstate__(self, state: Any) -> None:
        base, self.unit, self.description = state
        super().__setstate__(base)  # type: ignore[misc]

    def __repr__(self) -> str:
        body = np.array2string(self.view(np.ndarray), threshold=8, edgeitems=3)
        return f"Quantity({body}, unit={self.unit!r})"


Item = Union["Group", Quantity, str, List[str]]


class Group(Mapping[str, Item]):
    """A group of the results tree: a read-only mapping of names to subgroups and datasets.

    ``group["a/b/c"]`` walks subgroups; ``group.attrs`` holds the group's attributes (HDF5
    attributes: numbers and text); ``group.groups`` and ``group.datasets`` list the two kinds
    of members.
    """

    def __init__(self, raw: Dict[str, Any], path: str = "/") -> None:
        self.path = path
        self.attrs: Dict[str, Union[float, int, str]] = dict(raw["attrs"])
        base = path.rstrip("/")
        self.groups: Dict[str, Group] = {
            k: self._child(v, f"{base}/{k}") for k, v in raw["groups"].items()
        }
        self.datasets: Dict[str, Union[Quantity, str, List[str]]] = {}
        for k, d in raw["datasets"].items():
            data = d["data"]
            if isinstance(data, np.ndarray):
                data = Quantity(data, d["unit"], d["description"])
            self.datasets[k] = data

    def _child(self, raw: Dict[str, Any], path: str) -> "Group":
        return Group(raw, path)

    def __getitem__(self, key: str) -> Item:
        node: Any = self
        parts = [p for p in key.split("/") if p]
        for i, part in enumerate(parts):
            if not isinstance(node, Group):
                break
            if part in node.groups:
                node = node.groups[part]
            elif part in node.datasets and i == len(parts) - 1:
                return node.datasets[part]
            else:
                break
        else:
            return node
        raise KeyError(f"{self.path}: no group or dataset `{key}` (members: {', '.join(self)})")

    def __iter__(self) -> Iterator[str]:
        return iter(sorted([*self.groups, *self.datasets]))

    def __len__(self) -> int:
        return len(self.groups) + len(self.datasets)

    def walk(self) -> Iterator[tuple]:
        """Every dataset below this group: ``(path, value)`` in sorted order."""
        base = self.path.rstrip("/")
        for k in sorted(self.datasets):
            yield f"{base}/{k}", self.datasets[k]
        for k in sorted(self.groups):
            yield from self.groups[k].walk()

    def __repr__(self) -> str:
        lines = [f"<{type(self).__name__} {self.path}>"]
        for k, v in sorted(self.attrs.items()):
            lines.append(f"  @{k} = {v!r}")
        for k in sorted(self.groups):
            lines.append(f"  {k}/")
        for k, d in sorted(self.datasets.items()):
            if isinstance(d, Quantity):
                lines.append(f"  {k}: {d.dtype} {d.shape} [{d.unit}] {d.description}")
            else:
                lines.append(f"  {k}: text")
        return "\n".join(lines)


def _names(listing: List[str]) -> List[str]:
    """Actuator names from ``model/actuators`` entries ``"name (kind)"``."""
    return [s.rsplit(" (", 1)[0] for s in listing]


class Analysis(Group):
    """One analysis of a run (group ``analysis_<i>_<kind>``), with accessors.

    ``kind`` is ``modes``, ``harmonic``, ``transient`` or ``steady_state``; ``index`` its
    place in the case's ``[[analysis]]`` list. Transient and steady-state analyses have
    time histories (``t``, ``links``, ``bodies``, ``drives``, ``sensors``, ``loads``), spectra per link,
    mean and net powers; the steady state also its mode-resolved tables (``modal``).
    """

    def __init__(
        self, raw: Dict[str, Any], path: str, actuators: List[str], tables: Callable[[], Dict[str, Any]]
    ) -> None:
        super().__init__(raw, path)
        name = path.strip("/")
        _, index, kind = name.split("_", 2)
        self.index = int(index)
        self.kind = kind
        self.actuators = actuators
        self._all_tables = tables

    def tables(self) -> Dict[str, Any]:
        """This analysis's tidy tables as pandas DataFrames, by name (``point_power``,
        ``net_power``, ``spectra``, ``series``, ``modal_point_power``, ``harmonic``, …):
        the tables of ``beamflow run --csv``, column names with their unit in brackets
        (``mean power [W]``), the same numbers bit for bit (docs/results-format.md)."""
        prefix = self.path.strip("/") + "_"
        return {k[len(prefix):]: v for k, v in self._all_tables().items() if k.startswith(prefix)}

    def table(self, name: str) -> Any:
        """One of :attr:`tables` (e.g. ``"point_power"``, ``"spectra"``) as a DataFrame."""
        tables = self.tables()
        if name not in tables:
            raise KeyError(f"{self.path}: no table {name!r} (there are {', '.join(tables) or 'none'})")
        return tables[name]

    def to_xarray(self) -> Any:
        """This analysis as an xarray Dataset (xarray is an optional dependency): the same
        numbers on named dimensions, each variable with ``units`` and ``long_name``.

        Steady state and transient: dimensions ``t``, ``link``, ``actuator``, ``harmonic``
        (coordinate ``frequency``, Hz), ``drive``, ``sensor``, ``load`` and, for the modal
        tables, ``mode`` (coordinate ``mode_frequency``); variables ``net_power``
        (actuator), ``mean_power`` (link), the links' time histories by their dataset name
        (``power``, ``transmitted``, … over link × t), their spectra as ``spectrum_<name>``
        (link × harmonic), ``drive_<name>``, ``sensor_<name>``, ``load_<name>``,
        ``<body>_q`` and ``modal_<name>``. Harmonic: ``mobility`` (frequency × point ×
        force_point), ``velocity``, ``input_power`` and the balance. Modes: ``frequency``
        and ``shape_w`` (mode × node, coordinate ``x``)."""
        from ._xarray import to_dataset

        return to_dataset(self)

    @property
    def settled(self) -> Optional[bool]:
        """Whether a transient that was to run until its start-up transient died away did
        (False: it ran out of periods, and its powers may be far off). None where nothing
        was to settle (other analyses, a fixed number of periods, a record)."""
        if self.kind != "transient" or "settling_estimate" not in self.attrs:
            return None
        return bool(self.attrs["converged"])

    def _not_settled(self) -> Optional[str]:
        """What the command line says of a transient that did not settle, else None."""
        if self.settled is not False:
            return None
        left, periods = float(self.attrs["settling_estimate"]), int(self.attrs["periods_run"])
        needed = self.attrs.get("periods_needed")
        about = f" (the decay over the last periods asks for about {int(needed)} in all)" if needed is not None else ""
        return (
            f"analysis {self.index} (transient) NOT settled after {periods} periods: start-up transient left "
            f"{left:.1e} (relative), so its powers are not the steady state's; raise `max_periods`{about}"
        )

    def _members(self, name: str) -> Dict[str, Group]:
        """The subgroups of group ``name`` (empty if the analysis has none)."""
        g = self.groups.get(name)
        return dict(g.groups) if g else {}

    def _need(self, *kinds: str) -> None:
        if self.kind not in kinds:
            raise AttributeError(f"{self.path}: a {self.kind} analysis has no such result (only {', '.join(kinds)})")

    @property
    def link_names(self) -> List[str]:
        """Links (``<actuator>_<link>``) in the order of ``mean_power`` and ``modal/point_power``."""
        self._need("transient", "steady_state")
        return list(self.datasets["link_names"])  # type: ignore[arg-type]

    @property
    def net_power(self) -> Dict[str, float]:
        """Net mean power into the base per actuator (W), by actuator name."""
        self._need("transient", "steady_state")
        q = self.datasets["net_power"]
        return {a: float(p) for a, p in zip(self.actuators, q)}  # type: ignore[arg-type]

    @property
    def mean_power(self) -> Dict[str, float]:
        """Time-averaged power into the base at each link's foot (W), by link name."""
        self._need("transient", "steady_state")
        q = self.datasets["mean_power"]
        return {n: float(p) for n, p in zip(self.link_names, q)}  # type: ignore[arg-type]

    @property
    def spectra(self) -> Dict[str, Group]:
        """Per link: ``frequency`` (Hz), complex ``transmitted``/``interface`` force (N),
        ``velocity`` (m/s), ``acceleration`` (m/s²) amplitudes and ``power`` per harmonic (W)."""
        self._need("transient", "steady_state")
        return self._members("spectra")

    def point_power(self, link: str) -> Quantity:
        """Power into the base per harmonic (W) at one link's foot; frequencies in
        ``spectra[link]["frequency"]``."""
        return self.spectra[link].datasets["power"]  # type: ignore[return-value]

    @property
    def t(self) -> Quantity:
        """Sample times of the recorded window (s)."""
        self._need("transient", "steady_state")
        return self.datasets["t"]  # type: ignore[return-value]

    @property
    def links(self) -> Dict[str, Group]:
        """Time histories per link: stretch, forces, base motion and instantaneous power."""
        self._need("transient", "steady_state")
        return self._members("links")

    @property
    def sensors(self) -> Dict[str, Group]:
        """Time histories per sensor: ``w`` (m), ``v`` (m/s), ``a`` (m/s²)."""
        return self._members("sensors")

    @property
    def loads(self) -> Dict[str, Group]:
        """Per point load (``[[load]]``): ``force`` (N), ``w``/``v``/``a`` at its point, its
        ``power_per_harmonic`` (W), attributes ``x_m`` and ``mean_power_W``."""
        return self._members("loads")

    @property
    def load_power(self) -> Dict[str, float]:
        """Mean power each point load puts into the beam (W), by load name."""
        self._need("transient", "steady_state")
        return {n: float(g.attrs["mean_power_W"]) for n, g in self.loads.items()}

    @property
    def drives(self) -> Dict[str, Group]:
        """Per actuator: voltage (V), hysteretic displacement h (m), stroke (m), force f_p (N)."""
        return self._members("drives")

    @property
    def bodies(self) -> Dict[str, Group]:
        """Per actuator body DOF: ``q``, ``q_dot``, ``q_ddot``."""
        return self._members("bodies")

    @property
    def modal(self) -> Optional[Group]:
        """Mode-resolved tables of a steady state (``point_power`` per link and mode,
        ``power_participation``, modal ``dissipation``, …), or None."""
        return self.groups.get("modal")

    @property
    def record(self) -> Optional[Group]:
        """A non-periodic transient's record analysis (energies, PSDs, H1 FRFs per point,
        ``points/<name>``), or None for a periodic run."""
        return self.groups.get("record")

    @property
    def reduction(self) -> Optional[Group]:
        """The modal reduction used and its error estimate, or None for a full model."""
        return self.groups.get("reduction")

    @property
    def mesh_estimate(self) -> Optional[Group]:
        """A plate's grid error estimate (``relative_error`` per link against a grid of
        half the elements each way, ``max_relative_error``), a ``not_estimated`` reason,
        or None where the analysis has no plate point powers."""
        return self.groups.get("mesh_estimate")

    @property
    def balance(self) -> Dict[str, float]:
        """Energy-balance and accuracy estimates (relative errors, dimensionless).

        Steady state: ``balance_error`` (net input vs beam dissipation). Transient: the beam's
        and the system's balance over the run and the last period, and ``final_change`` (the
        last period-to-period change of the powers that decided settling). Harmonic: the
        largest ``balance_error`` over the frequencies. A reduced run adds
        ``reduction_max_relative_error``; a plate's grid estimate, ``mesh_max_relative_error``.
        """
        out: Dict[str, float] = {}
        if self.kind == "steady_state":
            out["balance_error"] = float(self.attrs["balance_error"])
        elif self.kind == "transient":
            # A record (non-periodic drive) has no last period and no settling.
            periodic = self.record is None
            for span in ("energy_run", "energy_last_period") if periodic else ("energy_run",):
                for part in ("beam", "system"):
                    g = self[f"{span}/{part}"]
                    out[f"{span}.{part}"] = float(g.attrs["relative_error"])  # type: ignore[union-attr]
            if periodic:
                out["final_change"] = float(self.attrs["final_change"])
        elif self.kind == "harmonic":
            out["balance_error"] = float(np.max(self.datasets["balance_error"]))  # type: ignore[arg-type]
        red = self.reduction
        if red is not None and "max_relative_error" in red.attrs:
            out["reduction_max_relative_error"] = float(red.attrs["max_relative_error"])
        mesh = self.mesh_estimate
        if mesh is not None and "max_relative_error" in mesh.attrs:
            out["mesh_max_relative_error"] = float(mesh.attrs["max_relative_error"])
        return out


class Results(Group):
    """Everything a case run produced, in the layout of the HDF5 results file.

    ``results.analyses`` lists the analyses in case order; ``results.analysis("transient")``
    (or an index) picks one. ``to_hdf5`` writes the file the command line would write;
    ``summary`` holds the command line's JSON headline numbers; ``write_figures`` draws its
    figures (results of :meth:`Case.run` only).
    """

    def __init__(
        self, tree: "_native.NativeTree", run: Optional["_native.NativeRun"] = None, summary: Optional[str] = None
    ) -> None:
        self._tree = tree
        self._run = run
        self._summary = summary if summary is not None or run is None else run.summary_json()
        self._tables: Optional[Dict[str, Any]] = None
        raw = tree.to_python()
        model = raw["groups"].get("model")
        listing = model["datasets"].get("actuators") if model else None
        self._actuators = _names(listing["data"] if listing else [])
        super().__init__(raw, "/")

    def _child(self, raw: Dict[str, Any], path: str) -> Group:
        name = path.strip("/")
        if name.startswith("analysis_"):
            return Analysis(raw, path, self._actuators, self.tables)
        return Group(raw, path)

    def tables(self) -> Dict[str, Any]:
        """Every tidy table of ``beamflow run --csv`` as a pandas DataFrame, by the name
        its file has after the case's stem (``analysis_1_steady_state_point_power``);
        column names carry their unit in brackets. :meth:`Analysis.tables` has one
        analysis's."""
        if self._tables is None:
            import pandas as pd

            self._tables = {
                name: pd.DataFrame({header: column for header, column in columns})
                for name, columns in self._tree.tables().items()
            }
        return dict(self._tables)

    def to_xarray(self) -> Dict[str, Any]:
        """Every analysis as an xarray Dataset (:meth:`Analysis.to_xarray`), by group name
        (``analysis_0_steady_state``, …)."""
        return {a.path.strip("/"): a.to_xarray() for a in self.analyses}

    @property
    def warnings(self) -> List[str]:
        """What the results say of their own accuracy that should not pass unseen: each
        transient that did not settle (also warned of as :class:`ConvergenceWarning` by
        :meth:`Case.run`)."""
        return [n for n in (a._not_settled() for a in self.analyses) if n]

    def __reduce__(self) -> Tuple[Any, Tuple[bytes, Optional[str]]]:
        """Pickles as the HDF5 file :meth:`to_hdf5` writes (every number bit for bit) and
        the summary; unpickled results have no figures (:meth:`write_figures`)."""
        with tempfile.TemporaryDirectory(prefix="beamflow-pickle-") as d:
            path = Path(d) / "results.h5"
            self._tree.write_hdf5(path)
            data = path.read_bytes()
        return (_unpickle, (data, self._summary))

    def _repr_html_(self) -> str:
        """A notebook's view: title, case, and per analysis its headline numbers and state."""
        rows = []
        for a in self.analyses:
            if a.kind in ("transient", "steady_state") and "net_power" in a.datasets:
                numbers = ", ".join(f"{k}: {v:.4g} W" for k, v in a.net_power.items())
            else:
                numbers = ""
            state = {True: "settled", False: "<b>NOT settled</b>", None: ""}[a.settled]
            rows.append(f"<tr><td>{a.index}</td><td>{a.kind}</td><td>{html.escape(numbers)}</td><td>{state}</td></tr>")
        head = "<tr><th>analysis</th><th>kind</th><th>net power</th><th>state</th></tr>"
        title = html.escape(f"{self.title} ({self.case_file})")
        return f"<b>beamflow.Results</b> {title}<table>{head}{''.join(rows)}</table>"

    @property
    def title(self) -> str:
        return str(self.attrs.get("title", ""))

    @property
    def case_file(self) -> str:
        """The case file (or label) the run came from."""
        return str(self.attrs.get("case_file", ""))

    @property
    def case_toml(self) -> str:
        """The case that ran, as TOML text."""
        return self["case/toml"]  # type: ignore[return-value]

    @property
    def actuators(self) -> List[str]:
        """Actuator names, in case order (the order of ``net_power``)."""
        return list(self._actuators)

    @property
    def analyses(self) -> List[Analysis]:
        """The analyses, in the order of the case's ``[[analysis]]`` entries."""
        found = [g for g in self.groups.values() if isinstance(g, Analysis)]
        return sorted(found, key=lambda a: a.index)

    def analysis(self, which: Union[int, str]) -> Analysis:
        """An analysis by index in the case, or the first of a kind (``"steady_state"``, …)."""
        for a in self.analyses:
            if a.index == which or a.kind == which:
                return a
        kinds = ", ".join(f"{a.index}: {a.kind}" for a in self.analyses)
        raise KeyError(f"no analysis {which!r} in these results (there are {kinds or 'none'})")

    @property
    def summary(self) -> Dict[str, Any]:
        """The headline numbers, exactly as the command line's ``<case>.json``."""
        if self._summary is None:
            raise AttributeError("results read from a file have no summary; it is written next to it as <case>.json")
        return json.loads(self._summary)

    def to_hdf5(self, path: Union[str, "os.PathLike[str]"]) -> Path:
        """Writes these results as an HDF5 file (atomically); returns its path."""
        p = Path(path)
        self._tree.write_hdf5(p)
        return p

    @property
    def plot(self) -> Any:
        """The figures :meth:`write_figures` draws, as matplotlib figures (a
        :class:`beamflow._plot.Plots`: ``res.plot.time()``, ``res.plot.spectrum(actuator=…)``,
        ``res.plot["steady_state_frame_loop"]``, ``res.plot.names``)."""
        if self._run is None:
            raise AttributeError("figures are drawn from a run (Case.run()), not from a results file")
        from ._plot import Plots

        if getattr(self, "_plots", None) is None:
            self._plots = Plots(self._run)
        return self._plots

    def write_figures(self, directory: Union[str, "os.PathLike[str]"], stem: Optional[str] = None) -> List[Path]:
        """Draws the command line's figures of this run (PNG and SVG) into ``directory``;
        ``stem`` prefixes the file names (default: the case file's stem)."""
        if self._run is None:
            raise AttributeError("figures are drawn from a run (Case.run()), not from a results file")
        stem = stem or (Path(self.case_file).stem or "case")
        return [Path(p) for p in self._run.write_figures(Path(directory), stem)]


def read_results(path: Union[str, "os.PathLike[str]"]) -> Results:
    """Reads an HDF5 results file written by ``beamflow run`` (or :meth:`Results.to_hdf5`).

    Sweep tables (``beamflow sweep --out``) read too; :func:`beamflow.read_sweep_table`
    gives them as columns.
    """
    return Results(_native.read_results(Path(path)))


def _unpickle(data: bytes, summary: Optional[str]) -> Results:
    with tempfile.TemporaryDirectory(prefix="beamflow-pickle-") as d:
        path = Path(d) / "results.h5"
        path.write_bytes(data)
        return Results(_native.read_results(path), summary=summary)
