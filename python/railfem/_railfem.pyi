# Type information for the compiled module (python/src/*.rs). The package's __init__.py
# wraps it; its stub carries the documented shapes.
from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Union

_Path = Union[str, PathLike[str]]

class SolverError(RuntimeError): ...

class Model:
    @staticmethod
    def from_file(path: str) -> Model: ...
    @staticmethod
    def from_dict(data: Dict[str, Any], name: str = "model", base: Optional[str] = None) -> Model: ...
    @property
    def name(self) -> str: ...
    def check(self) -> Dict[str, Any]: ...
    def run(self, out: Optional[str] = None) -> Dict[str, Any]: ...

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
    geometry: str = "linear",
    anti_roll: Optional[float] = None,
    out: Optional[_Path] = None,
) -> Dict[str, Any]: ...
def critical_radius(
    *,
    criterion: str = "sliding",
    speed: float = 120.0,
    ct: float = 200.0,
    mu: float = 0.3,
    clothoid: float = 2000.0,
    dt: float = 0.01,
    geometry: str = "linear",
    out: Optional[_Path] = None,
) -> Dict[str, Any]: ...
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
    geometry: str = "linear",
    steps: Optional[int] = None,
    out: Optional[_Path] = None,
) -> Dict[str, Any]: ...
def elements() -> List[Dict[str, Any]]: ...
def load_plugin(path: _Path) -> List[str]: ...
