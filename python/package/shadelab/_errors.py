"""The exceptions shadelab raises, each with the CLI's one-line message.

Each is also the built-in exception a caller would catch for its kind of
failure: a bad scene or a refused setting is a ``ValueError``, a device that
cannot be opened or fails a ``RuntimeError``, a render over the memory limit
a ``MemoryError``, a file that cannot be written an ``OSError``.
"""

from __future__ import annotations

from typing import Optional


class ShadelabError(Exception):
    """Base of every shadelab exception."""


class SceneError(ShadelabError, ValueError):
    """A scene that cannot be loaded: ``path`` and ``line`` for a file or
    text, ``key`` (``"objects[2].radius"``) for a dict."""

    path: Optional[str] = None
    line: Optional[int] = None
    key: Optional[str] = None


class RefusalError(ShadelabError, ValueError):
    """A setting or a request the renderer refuses (out of range, or not
    for this mode or backend), before any work is done."""


class DeviceError(ShadelabError, RuntimeError):
    """No Vulkan device to open, or one that failed."""


class MemoryLimitError(ShadelabError, MemoryError):
    """A render or a scene over the memory limit (``SHADELAB_MAX_MEMORY``),
    refused before anything large is allocated."""


class OutputError(ShadelabError, OSError):
    """An image that cannot be written."""


class InternalError(ShadelabError, RuntimeError):
    """A bug in shadelab (a panic caught at the border): please report it."""
