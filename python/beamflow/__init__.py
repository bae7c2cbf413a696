"""beamflow from Python: vibrational power flow from piezoelectric force actuators into
beams, with numpy arrays in and out.

This package is the beamflow Rust library itself (through PyO3), not a second
implementation: a case run here gives the numbers of ``beamflow run`` bit for bit.

    >>> import beamflow
    >>> case = beamflow.Case.from_file("cases/beam-frame-12V-60Hz.toml")
    >>> case["actuator[0].x_e"] = 0.2                 # the dotted paths of sweeps
    >>> res = case.run()
    >>> ss = res.analysis("steady_state")
    >>> ss.net_power                                  # W, per actuator
    >>> ss.point_power("frame_stack")                 # W per harmonic (a Quantity)
    >>> res.to_hdf5("frame.h5")
    >>> table = beamflow.sweep("cases/placement-frame.sweep.toml")   # DataFrame with pandas
    >>> opt = beamflow.optimize("cases/two_frames.opt.toml")         # opt.best, opt.history

Errors are :mod:`beamflow.errors` exceptions carrying the file, field and reason.
"""

from . import errors, identify
from ._commands import OptimizeResult, merge, optimize, paper, synth
from ._case import Case
from ._imported import imported
from ._native import __version__
from ._progress import ProgressArg
from ._results import Analysis, Group, Quantity, Results, read_results
from ._sweep import SweepTable, read_sweep_table, sweep
from ._system import DofMap, Modes, System
from .errors import *  # noqa: F401,F403  (the exception classes, listed in errors.__all__)

__all__ = [
    "__version__",
    "Case",
    "imported",
    "Results",
    "Analysis",
    "Group",
    "Quantity",
    "read_results",
    "sweep",
    "read_sweep_table",
    "SweepTable",
    "optimize",
    "OptimizeResult",
    "merge",
    "paper",
    "synth",
    "identify",
    "System",
    "DofMap",
    "Modes",
    "errors",
    "ProgressArg",
    *errors.__all__,
]
