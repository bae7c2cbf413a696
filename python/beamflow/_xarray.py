"""An analysis's results as an xarray Dataset: the same arrays (no copy of a number is
changed), laid out on named dimensions with coordinates, each variable with its ``units``
and ``long_name`` (the description of the HDF5 dataset)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

import numpy as np

if TYPE_CHECKING:
    from ._results import Analysis, Group, Quantity

__all__ = ["to_dataset"]


def _xarray() -> Any:
    try:
        import xarray
    except ImportError:
        raise ImportError(
            "Analysis.to_xarray() needs xarray, an optional dependency of beamflow: pip install xarray"
        ) from None
    return xarray


def _var(dims: Tuple[str, ...], q: "Quantity") -> Tuple[Tuple[str, ...], np.ndarray, Dict[str, str]]:
    return dims, np.asarray(q).view(np.ndarray), {"units": q.unit, "long_name": q.description}


def _stack(dim: str, qs: List["Quantity"], inner: Tuple[str, ...]) -> Tuple[Tuple[str, ...], np.ndarray, Dict[str, str]]:
    """Per-member arrays of one quantity (a link's power, a sensor's w) along ``dim``."""
    return (dim, *inner), np.stack([np.asarray(q).view(np.ndarray) for q in qs]), {
        "units": qs[0].unit,
        "long_name": qs[0].description,
    }


def _members(
    members: Dict[str, "Group"],
    names: List[str],
    dim: str,
    prefix: str,
    sizes: Dict[str, Tuple[str, int]],
    out: Dict[str, Any],
) -> None:
    """Every dataset the members of a group share (``links/<link>/power``, …) as one
    variable ``<prefix><name>`` over ``dim`` (in the order of ``names``, its coordinate)
    and the dimension its length names."""
    if not members:
        return
    first = members[names[0]]
    for key, q in first.datasets.items():
        if not isinstance(q, np.ndarray) or q.ndim != 1:
            continue
        inner = [d for d, n in sizes.values() if n == len(q)]
        qs = [members[m].datasets.get(key) for m in names]
        if len(inner) != 1 or any(not isinstance(x, np.ndarray) or x.shape != q.shape for x in qs):
            continue
        out[f"{prefix}{key}"] = _stack(dim, qs, (inner[0],))  # type: ignore[arg-type]


def _periodic(a: "Analysis") -> Any:
    xr = _xarray()
    data: Dict[str, Any] = {}
    # A rigid base has no beam, and so no mean powers in link order: its links by name.
    links = a.link_names if "link_names" in a.datasets else sorted(a.links)
    coords: Dict[str, Any] = {"t": _var(("t",), a.t), "link": links, "actuator": a.actuators}
    spectra = a.spectra
    harmonics = len(spectra[links[0]]["frequency"]) if spectra else 0
    coords["harmonic"] = np.arange(harmonics)
    if spectra:
        # Every link's spectrum is at the same multiples of the drive frequency.
        coords["frequency"] = _var(("harmonic",), spectra[links[0]]["frequency"])
    sizes = {"t": ("t", len(a.t)), "harmonic": ("harmonic", harmonics)}
    for key, dim in (("net_power", "actuator"), ("mean_power", "link")):
        if key in a.datasets:
            data[key] = _var((dim,), a.datasets[key])  # type: ignore[arg-type]
    _members(a.links, links, "link", "", sizes, data)
    _members(spectra, links, "link", "spectrum_", sizes, data)
    data.pop("spectrum_frequency", None)
    for group, dim in (("drives", "drive"), ("sensors", "sensor"), ("loads", "load")):
        members = a._members(group)
        if members:
            coords[dim] = list(members)
            _members(members, coords[dim], dim, f"{dim}_", sizes, data)
    for body, g in a.bodies.items():
        for key, q in g.datasets.items():
            data[f"{body}_{key}"] = _var(("t",), q)  # type: ignore[arg-type]
    modal = a.modal
    if modal is not None:
        _modal(modal, a, coords, data)
    if "beam_dissipation_per_harmonic" in a.datasets:
        data["beam_dissipation_per_harmonic"] = _var(("harmonic",), a.datasets["beam_dissipation_per_harmonic"])  # type: ignore[arg-type]
    return xr.Dataset(data, coords=coords, attrs=_attrs(a))


def _modal(modal: "Group", a: "Analysis", coords: Dict[str, Any], data: Dict[str, Any]) -> None:
    """A steady state's mode-resolved tables over ``mode`` (and ``harmonic``, ``link``)."""
    f = modal.datasets["mode_frequency_hz"]
    coords["mode"] = np.arange(1, len(f) + 1)  # type: ignore[arg-type]
    coords["mode_frequency"] = _var(("mode",), f)  # type: ignore[arg-type]
    dims = {"harmonic": len(coords["harmonic"]), "mode": len(f), "link": len(coords["link"])}  # type: ignore[arg-type]
    for key, q in modal.datasets.items():
        if key in ("mode_frequency_hz", "frequency") or not isinstance(q, np.ndarray):
            continue
        shape = tuple(q.shape)
        for pair in (("harmonic", "mode"), ("link", "mode"), ("mode",), ("link",)):
            if shape == tuple(dims[d] for d in pair):
                data[f"modal_{key}"] = _var(pair, q)  # type: ignore[arg-type]
                break


def _harmonic(a: "Analysis") -> Any:
    xr = _xarray()
    d = a.datasets
    names = list(d["point_names"])  # type: ignore[arg-type]
    n_forces = d["input_power"].shape[1]  # type: ignore[union-attr]
    coords = {
        "frequency": _var(("frequency",), d["frequency_hz"]),  # type: ignore[arg-type]
        "point": names,
        "point_x": _var(("point",), d["point_x"]),  # type: ignore[arg-type]
        "force_point": names[:n_forces],
    }
    mobility = d["mobility"]
    n_f = len(d["frequency_hz"])  # type: ignore[arg-type]
    data = {
        # Column i·n_forces + j holds V_i / F_j.
        "mobility": (
            ("frequency", "point", "force_point"),
            np.asarray(mobility).view(np.ndarray).reshape(n_f, len(names), n_forces),
            {"units": mobility.unit, "long_name": mobility.description},  # type: ignore[union-attr]
        ),
        "velocity": _var(("frequency", "point"), d["velocity"]),  # type: ignore[arg-type]
        "input_power": _var(("frequency", "force_point"), d["input_power"]),  # type: ignore[arg-type]
    }
    for key in ("total_power", "dissipated_power", "balance_error"):
        data[key] = _var(("frequency",), d[key])  # type: ignore[arg-type]
    return xr.Dataset(data, coords=coords, attrs=_attrs(a))


def _modes(a: "Analysis") -> Any:
    xr = _xarray()
    d = a.datasets
    f = d["frequencies_hz"]
    coords = {"mode": np.arange(1, len(f) + 1), "x": _var(("node",), d["node_x"])}  # type: ignore[arg-type]
    data = {"frequency": _var(("mode",), f), "shape_w": _var(("mode", "node"), d["shapes_w"])}  # type: ignore[arg-type]
    for key in ("analytic_hz", "relative_error", "roundoff_bound"):
        if key in d:
            data[key] = _var(("mode",), d[key])  # type: ignore[arg-type]
    return xr.Dataset(data, coords=coords, attrs=_attrs(a))


def _attrs(a: "Analysis") -> Dict[str, Any]:
    plain = {k: v for k, v in a.attrs.items() if isinstance(v, (str, int, float, np.number))}
    return {"analysis": a.path.strip("/"), "kind": a.kind, **plain}


def to_dataset(a: "Analysis") -> Any:
    """``a`` as an xarray Dataset (see :meth:`Analysis.to_xarray`)."""
    build: Optional[Any] = {"transient": _periodic, "steady_state": _periodic, "harmonic": _harmonic, "modes": _modes}.get(a.kind)
    if build is None:
        raise ValueError(f"{a.path}: no Dataset layout for a {a.kind} analysis")
    return build(a)
