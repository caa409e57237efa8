"""shadelab: the classic shading models (flat, Gouraud, Phong, backward and
forward ray tracing) rendered headless on Vulkan (Mesa lavapipe), with a
double-precision CPU reference to check against.

>>> import shadelab
>>> image = shadelab.render(shadelab.Scene.default(), "phong", width=64, height=48)
>>> image.array.shape
(48, 64, 3)

``Device`` keeps the Vulkan context and its pipelines between renders;
``render`` uses one shared default device. ``diff``, ``check``, ``compare``
and ``golden`` are the CLI's commands of the same names. Everything is the
Rust library's (``shadelab._shadelab``); this file only gathers it.
"""

from __future__ import annotations

import os
import threading
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Union

from . import _shadelab
from ._errors import (
    DeviceError,
    InternalError,
    MemoryLimitError,
    OutputError,
    RefusalError,
    SceneError,
    ShadelabError,
)
from ._shadelab import Device, Image, Scene, check, compare, diff, driver_key, read_image

if TYPE_CHECKING:
    from ._shadelab import Shading

__version__: str = _shadelab.__version__

__all__ = [
    "Device",
    "DeviceError",
    "Image",
    "InternalError",
    "MemoryLimitError",
    "OutputError",
    "RefusalError",
    "Scene",
    "SceneError",
    "ShadelabError",
    "check",
    "compare",
    "default_device",
    "diff",
    "driver_key",
    "golden",
    "read_image",
    "render",
]

_default: Optional[Device] = None
_default_lock = threading.Lock()


def default_device() -> Device:
    """The device ``render`` uses, opened at its first use and kept."""
    global _default
    with _default_lock:
        if _default is None:
            _default = Device()
        return _default


def render(scene: Any = None, shading: Shading = "phong", **settings: Any) -> Image:
    """Renders on the default device: ``default_device().render(...)``."""
    return default_device().render(scene, shading, **settings)


def golden(
    scenes: Union[Any, Sequence[Any]],
    shading: Union[str, Sequence[str]] = ("flat", "gouraud", "phong", "raytrace"),
    references: Union[str, "os.PathLike[str]"] = "references",
    *,
    device: Optional[Device] = None,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Each scene in each mode judged against its stored reference, as
    ``shadelab golden`` judges it (``create=True`` makes the missing ones,
    ``bless=True`` accepts changed renders): the cases' records, as
    ``golden.json`` holds them. A case passed has ``status == "pass"``."""
    if isinstance(scenes, (str, os.PathLike, dict, Scene)):
        scenes = [scenes]
    modes = [shading] if isinstance(shading, str) else list(shading)
    device = device or default_device()
    return [
        _shadelab.golden_case(device, scene, mode, os.fspath(references), **options)
        for scene in scenes
        for mode in modes
    ]
