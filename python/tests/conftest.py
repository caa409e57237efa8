"""Shared fixtures of the package's tests: the repository's assets, the
CLI binary the tests compare with, one device for the session."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterator

import pytest

import shadelab

pytest_plugins = ["pytester"]

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def assets() -> Path:
    return ROOT / "assets"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `shadelab` binary built from this checkout (`cargo build
    --release`, which the test command runs first)."""
    binary = Path(os.environ.get("SHADELAB_BIN", ROOT / "target" / "release" / "shadelab"))
    if not binary.is_file():
        pytest.fail(f"{binary} is missing: build it with `cargo build --release` first")
    return binary


@pytest.fixture(scope="session")
def device() -> Iterator[shadelab.Device]:
    yield shadelab.Device()


@pytest.fixture
def small() -> dict:
    """Settings that keep a render in milliseconds."""
    return {"width": 64, "height": 48}
