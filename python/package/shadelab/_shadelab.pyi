"""Type stubs of the Rust half of the package (``shadelab._shadelab``)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Literal, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

StrPath = Union[str, "PathLike[str]"]
Shading = Literal["flat", "gouraud", "phong", "raytrace", "forward"]
SceneLike = Union["Scene", StrPath, Dict[str, Any], None]
Progress = Union[Callable[[int, int], Any], bool, None]

class Scene:
    @staticmethod
    def load(path: StrPath) -> Scene: ...
    @staticmethod
    def from_dict(d: Dict[str, Any], base_dir: Optional[StrPath] = None) -> Scene: ...
    @staticmethod
    def from_toml(text: str, base_dir: Optional[StrPath] = None) -> Scene: ...
    @staticmethod
    def default() -> Scene: ...
    def with_light(
        self,
        index: int,
        *,
        position: Optional[Sequence[float]] = None,
        intensity: Union[float, Sequence[float], None] = None,
    ) -> Scene: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def path(self) -> Optional[str]: ...
    @property
    def warnings(self) -> List[str]: ...

class Image:
    @property
    def array(self) -> npt.NDArray[np.float32]: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def timings(self) -> Dict[str, Optional[float]]: ...
    @property
    def stats(self) -> Optional[Dict[str, Any]]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    def save(self, path: StrPath) -> None: ...
    def _repr_png_(self) -> bytes: ...
    def __array__(self, dtype: Any = None, copy: Optional[bool] = None) -> npt.NDArray[Any]: ...

class Device:
    def __init__(
        self,
        name_or_index: Union[str, int, None] = None,
        backend: Literal["gpu", "cpu", "auto"] = "gpu",
    ) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def driver(self) -> Optional[str]: ...
    @property
    def backend(self) -> str: ...
    def render(
        self,
        scene: SceneLike = None,
        shading: Shading = "phong",
        *,
        width: Optional[int] = None,
        height: Optional[int] = None,
        msaa: Union[int, str, None] = None,
        samples: Optional[int] = None,
        depth: Optional[int] = None,
        bounces: Optional[int] = None,
        photons: Optional[int] = None,
        caustics: Optional[int] = None,
        caustic_passes: Optional[int] = None,
        lighting: Optional[str] = None,
        traversal: Optional[Literal["bvh", "query", "auto"]] = None,
        watchdog: Optional[float] = None,
        shadows: Optional[bool] = None,
        time: Optional[float] = None,
        error: Optional[float] = None,
        stats: bool = False,
        progress: Progress = None,
    ) -> Image: ...

ImageLike = Union[Image, npt.NDArray[Any], StrPath]

def diff(
    expected: ImageLike,
    actual: ImageLike,
    *,
    preset: Literal["gpu-vs-reference", "stored-reference"] = "gpu-vs-reference",
    thresholds: Optional[Dict[str, float]] = None,
) -> Dict[str, Any]: ...
def check(
    scene: SceneLike = None,
    shading: Optional[Sequence[Shading]] = None,
    *,
    device: Optional[Device] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
) -> List[Dict[str, Any]]: ...
def compare(
    scene: SceneLike = None,
    variants: Optional[Sequence[str]] = None,
    *,
    out: Optional[StrPath] = None,
    runs: int = 3,
    device: Optional[Device] = None,
) -> List[Dict[str, Any]]: ...
def golden_case(
    device: Device,
    scene: SceneLike,
    shading: str,
    references: StrPath,
    *,
    name: Optional[str] = None,
    preset: str = "stored-reference",
    thresholds: Optional[Dict[str, float]] = None,
    create: bool = False,
    bless: bool = False,
    per_driver: bool = False,
    out: Optional[StrPath] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    msaa: Union[int, str, None] = None,
    lighting: Optional[str] = None,
) -> Dict[str, Any]: ...
def driver_key(device: Device) -> str: ...
def read_image(path: StrPath) -> npt.NDArray[np.float32]: ...
