# Type information for the railfem package (PEP 561): the signatures of __init__.py and the
# shapes of what the built-in cases return. tests/test_stubs.py keeps the signatures equal
# to the runtime's.
from os import PathLike
from typing import Any, Dict, Iterator, List, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

from ._railfem import SolverError as SolverError

_Path = Union[str, PathLike[str]]
_Array = npt.NDArray[np.float64]
Geometry = Literal["linear", "nonlinear"]

__all__ = [
    "Model",
    "Recording",
    "Result",
    "SolverError",
    "critical_radius",
    "curve",
    "elements",
    "load_plugin",
    "train_bridge",
]

class Recording:
    """One recorder's history: ``time`` (n,), ``values`` (n, len(columns))."""

    file: str
    columns: List[str]
    time: _Array
    values: _Array
    def __init__(self, raw: Dict[str, Any]) -> None: ...
    def __getitem__(self, name: str) -> _Array: ...
    def __contains__(self, name: object) -> bool: ...
    def __len__(self) -> int: ...
    def as_dict(self) -> Dict[str, _Array]: ...

class RunStats(TypedDict):
    """``Result.stats``: counts and wall-clock seconds of a run."""

    steps: int
    iterations: int
    cuts: int
    factorizations: int
    symbolic: int
    equations: int
    wall: float
    timings: Dict[str, float]

class Result:
    """What ``Model.run`` returns."""

    recorders: Dict[str, Recording]
    energy: Optional[Recording]
    energy_summary: Optional[str]
    energy_relative_error: Optional[float]
    stats: RunStats
    size: str
    warnings: List[str]
    out: Optional[str]
    def __init__(self, raw: Dict[str, Any]) -> None: ...
    def __getitem__(self, file: str) -> Recording: ...

class CheckReport(TypedDict):
    """``Model.check()``: the model's size as ``railfem check`` prints it, and warnings."""

    size: str
    warnings: List[str]

class Model:
    """A railfem model: ``Model.from_file(path)`` or ``Model.from_dict(d)``."""

    @classmethod
    def from_file(cls, path: _Path) -> Model: ...
    @classmethod
    def from_dict(
        cls, data: Dict[str, Any], name: str = "model", base: Optional[_Path] = None
    ) -> Model: ...
    @property
    def name(self) -> str: ...
    def check(self) -> CheckReport: ...
    def run(self, out: Optional[_Path] = None) -> Result: ...

class CurveWheels(TypedDict):
    """Per wheel quantity, (steps, wheels), named as curve.csv's columns (N, m, rad)."""

    station: _Array
    radius: _Array
    cant: _Array
    Q_fe: _Array
    Y_fe: _Array
    n_contact: _Array
    n_slide: _Array
    Q_statics: _Array
    Q_printed: _Array
    Y_theory: _Array
    Q_lean: _Array

class CurveMetrics(TypedDict):
    """The numbers ``railfem curve`` prints: relative differences FE vs theory on the arc."""

    max_rel_normal_statics: float
    max_rel_shear: float
    max_rel_shear_wheel: float
    max_rel_normal_printed: float
    max_rel_normal_lean: float
    arc_mean_normal_inner: float
    arc_mean_normal_outer: float
    contact_spacing: float
    first_slide: Optional[float]
    first_separation: Optional[float]

class CaseStats(TypedDict):
    """Steps, Newton iterations and wall-clock seconds of a built-in case."""

    steps: int
    iterations: int
    wall: float

class CurveResult(TypedDict):
    """What ``curve()`` returns."""

    time: _Array
    station: _Array
    wheel_names: List[str]
    inner: List[bool]
    wheels: CurveWheels
    metrics: CurveMetrics
    stats: CaseStats
    energy_summary: Optional[str]
    case: Dict[str, Any]

def curve(
    *,
    speed: Optional[float] = None,
    radius: Optional[float] = None,
    ct: Optional[float] = None,
    mu: Optional[float] = None,
    dt: Optional[float] = None,
    penalty: Optional[float] = None,
    duration: Optional[float] = None,
    lengths: Optional[Sequence[float]] = None,
    quick: bool = False,
    geometry: Geometry = "linear",
    anti_roll: Optional[float] = None,
    out: Optional[_Path] = None,
) -> CurveResult: ...

class TrainWheels(TypedDict):
    """Per wheel extremes of ``train_bridge()`` (N, -, s)."""

    max_yq: _Array
    t_max_yq: _Array
    max_dqq: _Array
    t_max_dqq: _Array
    min_q: _Array
    t_min_q: _Array
    mean_q: _Array

class TrainBridgeResult(TypedDict):
    """What ``train_bridge()`` returns."""

    dofs: int
    elements: int
    nodes: int
    element_length: float
    build_seconds: List[float]
    wheel_names: List[str]
    q_static: _Array
    wheels: TrainWheels
    midspan: Dict[int, Recording]
    stats: CaseStats

def train_bridge(
    *,
    cars: Optional[int] = None,
    spans: Optional[int] = None,
    span: Optional[float] = None,
    element_length: Optional[float] = None,
    dof: Optional[int] = None,
    speed: Optional[float] = None,
    radius: Optional[float] = None,
    ct: Optional[float] = None,
    duration: Optional[float] = None,
    dt: Optional[float] = None,
    record_every: Optional[int] = None,
    pier_height: Optional[float] = None,
    midspans: Optional[Sequence[int]] = None,
    quake: Optional[_Path] = None,
    seed: int = 1,
    pga: float = 0.3,
    quake_duration: float = 30.0,
    geometry: Geometry = "linear",
    steps: Optional[int] = None,
    out: Optional[_Path] = None,
) -> TrainBridgeResult: ...

def critical_radius(
    *,
    criterion: Literal["sliding", "separation"] = "sliding",
    speed: float = 120.0,
    ct: float = 200.0,
    mu: float = 0.3,
    clothoid: float = 2000.0,
    dt: float = 0.01,
    geometry: Geometry = "linear",
    out: Optional[_Path] = None,
) -> Dict[str, Any]: ...

class ParamDoc(TypedDict):
    """One model-file key of an element kind: ``default`` is ``None`` for a required key."""

    key: str
    unit: str
    default: Any
    doc: str

class ElementKindDoc(TypedDict):
    """One registered element kind, as ``railfem elements`` lists it."""

    name: str
    description: str
    params: List[ParamDoc]

def elements() -> List[ElementKindDoc]: ...
def load_plugin(path: _Path) -> List[str]: ...
