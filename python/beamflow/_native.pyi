# Type stubs of the compiled extension module (python/src). The documented API is the
# Python package around it; these are its building blocks.
from os import PathLike
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

__version__: str

Progress = Callable[[Dict[str, Any]], Any]

class NativeCase:
    @staticmethod
    def from_file(path: PathLike[str]) -> NativeCase: ...
    @staticmethod
    def from_toml(text: str, name: str, dir: PathLike[str]) -> NativeCase: ...
    @staticmethod
    def from_value(value: Mapping[str, Any], name: str, dir: PathLike[str]) -> NativeCase: ...
    @property
    def file(self) -> str: ...
    @property
    def dir(self) -> Path: ...
    def get(self, path: str) -> Any: ...
    def set(self, path: str, value: Any) -> None: ...
    def update(self, items: Sequence[Tuple[str, Any]]) -> None: ...
    def to_toml(self) -> str: ...
    def to_dict(self, full: bool) -> Dict[str, Any]: ...
    def copy(self) -> NativeCase: ...
    def check(self) -> Dict[str, Any]: ...
    def run(self, progress: Optional[Progress] = None) -> NativeRun: ...
    def system(self) -> Dict[str, Any]: ...
    def modes(self, count: int) -> Dict[str, Any]: ...
    def coupled_modes(self, count: int) -> Dict[str, Any]: ...

class NativeTree:
    def to_python(self) -> Dict[str, Any]: ...
    def write_hdf5(self, path: PathLike[str]) -> None: ...
    def tables(self) -> Dict[str, List[Tuple[str, Any]]]: ...

class NativeEvaluator:
    def __init__(self, text: str, name: str, dir: PathLike[str]) -> None: ...
    def evaluate(self, u: List[float]) -> Any: ...

class NativeRun:
    @property
    def case_file(self) -> str: ...
    def tree(self) -> NativeTree: ...
    def summary_json(self) -> str: ...
    def write_figures(self, dir: PathLike[str], stem: str) -> List[Path]: ...
    def drawings(self) -> List[Tuple[str, Dict[str, Any]]]: ...

def read_results(path: PathLike[str]) -> NativeTree: ...
def toml_dumps(value: Mapping[str, Any]) -> str: ...
def run_sweep(
    text: str,
    name: str,
    dir: PathLike[str],
    threads: Optional[int] = None,
    max_memory: Optional[str] = None,
    max_steps: Optional[str] = None,
    progress: Optional[Progress] = None,
) -> Tuple[Dict[str, Any], Optional[BaseException]]: ...
def sweep_into(
    text: str,
    name: str,
    dir: PathLike[str],
    out: PathLike[str],
    shard: Optional[str] = None,
    threads: Optional[int] = None,
    csv: bool = False,
    plots: bool = True,
    max_memory: Optional[str] = None,
    max_steps: Optional[str] = None,
    progress: Optional[Progress] = None,
) -> Dict[str, Any]: ...
def run_optimize(
    text: str,
    name: str,
    dir: PathLike[str],
    out: Optional[PathLike[str]] = None,
    threads: Optional[int] = None,
    plots: bool = True,
    max_memory: Optional[str] = None,
    max_steps: Optional[str] = None,
    progress: Optional[Progress] = None,
    remote: Optional[Callable[[List[float]], Any]] = None,
) -> Dict[str, Any]: ...
def merge(shards: Sequence[PathLike[str]], out: PathLike[str], csv: bool = False, plots: bool = True) -> List[str]: ...
def paper(
    out: PathLike[str],
    csv: bool = False,
    max_memory: Optional[str] = None,
    max_steps: Optional[str] = None,
    progress: Optional[Progress] = None,
) -> None: ...
def identify_dp(
    first: PathLike[str],
    second: PathLike[str],
    k_p: Optional[float] = None,
    offset_tolerance: Optional[float] = None,
    align: bool = True,
    out: Optional[PathLike[str]] = None,
    plots: bool = True,
    uniform_tolerance: Optional[float] = None,
) -> Dict[str, Any]: ...
def identify_bouc_wen(
    file: PathLike[str],
    d_p: float,
    target: Optional[str] = None,
    k_p: Optional[float] = None,
    seeds: Optional[Sequence[int]] = None,
    period: Optional[float] = None,
    cycles: Optional[int] = None,
    particles: Optional[int] = None,
    max_iterations: Optional[int] = None,
    out: Optional[PathLike[str]] = None,
    plots: bool = True,
    uniform_tolerance: Optional[float] = None,
    max_memory: Optional[str] = None,
    max_steps: Optional[str] = None,
) -> Dict[str, Any]: ...
def identify_modal(
    file: PathLike[str],
    mass: float,
    modes: Optional[int] = None,
    band: Optional[Tuple[float, float]] = None,
    element: Optional[str] = None,
    use_mode: Optional[int] = None,
    segment: Optional[int] = None,
    exp_window: Optional[float] = None,
    force_window: Optional[float] = None,
    min_coherence: Optional[float] = None,
    out: Optional[PathLike[str]] = None,
    plots: bool = True,
    uniform_tolerance: Optional[float] = None,
) -> Dict[str, Any]: ...
def synth(
    case: PathLike[str],
    out: PathLike[str],
    kind: Optional[str] = None,
    noise: Optional[float] = None,
    voltage_noise: Optional[float] = None,
    seed: Optional[int] = None,
    actuator: Optional[str] = None,
    periods: Optional[int] = None,
    samples_per_period: Optional[int] = None,
    offset: Optional[float] = None,
    element: Optional[str] = None,
    mass: Optional[float] = None,
    hits: Optional[int] = None,
    digits: Optional[int] = 7,
    max_memory: Optional[str] = None,
    max_steps: Optional[str] = None,
) -> Dict[str, Any]: ...
def read_sweep_table(path: PathLike[str]) -> Dict[str, Any]: ...
def cli_main(argv: List[str]) -> int: ...
