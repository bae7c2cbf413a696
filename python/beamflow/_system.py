"""The assembled system and modes, for custom studies with numpy and scipy."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from ._results import Quantity

__all__ = ["System", "DofMap", "Modes"]


@dataclass(frozen=True)
class DofMap:
    """What each global DOF is, as columns of length ``n``.

    ``node``: the structure's node (its index; −1 for an actuator body DOF); ``x``, ``y``,
    ``z``: the node's position (m; NaN for a body DOF and where the structure has no such
    coordinate: ``y`` on a beam, ``z`` on a beam and a plate); ``node_id``: the source
    model's node number on an imported model (−1 elsewhere); ``kind``: ``"w"`` (m),
    ``"theta"`` (rad), a plate's ``"w_x"``, ``"w_y"``, ``"w_xy"``, an imported model's
    component (``"uz"``, ``"rx"``, …), or the body DOF's name (``"z_t"`` of an inertial
    actuator, ``"y"``, ``"phi"`` of a frame); ``actuator``: the actuator a body DOF belongs
    to (empty for the structure). DOFs fixed by supports have no index.
    """

    index: np.ndarray
    node: np.ndarray
    x: Quantity
    kind: List[str]
    actuator: List[str]
    y: Optional[Quantity] = None
    z: Optional[Quantity] = None
    node_id: Optional[np.ndarray] = None

    def __len__(self) -> int:
        return len(self.index)

    def where(self, kind: str, actuator: str = "") -> np.ndarray:
        """Global indices of the DOFs of one kind (``"w"``, ``"theta"``, ``"phi"``, …),
        optionally of one actuator."""
        return np.array(
            [i for i, k, a in zip(self.index, self.kind, self.actuator) if k == kind and (not actuator or a == actuator)],
            dtype=np.int64,
        )

    def to_frame(self) -> Any:
        """The map as a pandas DataFrame (needs pandas)."""
        import pandas as pd

        columns = {"node": self.node, "x": np.asarray(self.x)}
        for name in ("y", "z"):
            if getattr(self, name) is not None:
                columns[name] = np.asarray(getattr(self, name))
        if self.node_id is not None:
            columns["node_id"] = self.node_id
        columns.update({"kind": self.kind, "actuator": self.actuator})
        return pd.DataFrame(columns, index=pd.Index(self.index, name="dof"))


def _dofmap(raw: Dict[str, Any]) -> DofMap:
    """The map, with ``y``, ``z`` and ``node_id`` only where the structure has them."""
    has = lambda c: bool(np.any(~np.isnan(raw[c])))  # noqa: E731
    y = Quantity(raw["y"], "m", "node y of the DOF") if has("y") else None
    z = Quantity(raw["z"], "m", "node z of the DOF") if has("z") else None
    ids = raw["node_id"] if np.any(raw["node_id"] >= 0) else None
    x = Quantity(raw["x"], "m", "node x of the DOF")
    return DofMap(raw["index"], raw["node"], x, list(raw["kind"]), list(raw["actuator"]), y, z, ids)


@dataclass(frozen=True)
class System:
    """The assembled second-order system M·q̈ + C·q̇ + K·q = f of a case.

    ``K`` (N/m, N/rad, …), ``M`` (kg, kg·m²) and ``C`` (N·s/m) are ``scipy.sparse``
    CSR matrices over the free DOFs described by ``dofs``. ``C`` holds the Rayleigh
    damping ``a0·M + a1·K`` of the beam (``rayleigh``) and the actuators' dashpots; with
    modal damping (``modal_damping``: the ratios) the beam's damping is not a matrix in
    these coordinates and ``C`` holds the dashpots only.
    """

    K: Any
    M: Any
    C: Any
    dofs: DofMap
    rayleigh: Tuple[float, float]
    modal_damping: Optional[List[float]]

    @property
    def n(self) -> int:
        """Number of free DOFs."""
        return int(self.K.shape[0])


def _system(raw: Dict[str, Any]) -> System:
    import scipy.sparse as sp

    mats = {k: sp.csr_matrix(tuple(raw[k][:3]), shape=raw[k][3]) for k in ("K", "M", "C")}
    return System(mats["K"], mats["M"], mats["C"], _dofmap(raw["dofs"]), tuple(raw["rayleigh"]), raw["modal_damping"])


@dataclass(frozen=True)
class Modes:
    """Natural modes, ascending.

    ``frequencies_hz`` (Hz). Bare beam (:meth:`Case.modes`): ``analytic_hz`` and
    ``relative_error`` against the closed form where one exists (else empty),
    ``roundoff_bound`` per mode, ``node_x`` (m) and ``shapes`` with one row per mode: w at
    each node (m/√kg, mass-normalised). On a plate also ``node_y`` (m); on an imported
    model ``node_y``, ``node_z`` (m) and ``node_id`` (the model's own node numbers);
    ``None`` on a beam. Coupled (:meth:`Case.coupled_modes`): ``shapes``
    with one row per mode over the global DOFs of ``dofs`` (mass-normalised).
    """

    frequencies_hz: Quantity
    shapes: Quantity
    coupled: bool
    node_x: Optional[Quantity] = None
    node_y: Optional[Quantity] = None
    node_z: Optional[Quantity] = None
    node_id: Optional[np.ndarray] = None
    analytic_hz: Optional[Quantity] = None
    relative_error: Optional[Quantity] = None
    roundoff_bound: Optional[Quantity] = None
    reference: str = ""
    dofs: Optional[DofMap] = None


def _modes(raw: Dict[str, Any], coupled: bool) -> Modes:
    f = Quantity(raw["frequencies_hz"], "Hz", "natural frequencies")
    if coupled:
        shapes = Quantity(raw["shapes"], "1/sqrt(kg)", "mass-normalised mode shapes over the global DOFs, one row per mode")
        return Modes(f, shapes, True, dofs=_dofmap(raw["dofs"]))
    return Modes(
        f,
        Quantity(raw["shapes_w"], "m/sqrt(kg)", "mass-normalised mode shapes: w at each node, one row per mode"),
        False,
        node_x=Quantity(raw["node_x"], "m", "node coordinates"),
        node_y=Quantity(raw["node_y"], "m", "node y coordinates") if "node_y" in raw else None,
        node_z=Quantity(raw["node_z"], "m", "node z coordinates") if "node_z" in raw else None,
        node_id=np.asarray(raw["node_id"]) if "node_id" in raw else None,
        analytic_hz=Quantity(raw["analytic_hz"], "Hz", "closed-form natural frequencies"),
        relative_error=Quantity(raw["relative_error"], "1", "(f - f_analytic)/f_analytic"),
        roundoff_bound=Quantity(raw["roundoff_bound"], "1", "bound on each frequency's relative round-off error"),
        reference=raw["reference"],
    )
