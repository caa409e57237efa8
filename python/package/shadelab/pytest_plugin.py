"""Golden image tests in pytest, judged as ``shadelab golden`` judges them.

The ``shadelab_golden`` fixture renders a scene and compares it with its
stored reference: ``REFERENCES/KEY/NAME-MODE.png`` (this driver's, looked
for first) or ``REFERENCES/NAME-MODE.png`` (shared), the same files and
limits as the CLI's, so one folder serves both::

    def test_spheres(shadelab_golden):
        shadelab_golden("assets/spheres.toml", "phong", width=160, height=120)

``--shadelab-create`` makes the missing references, ``--shadelab-bless``
(or ``SHADELAB_BLESS=1``) accepts renders that changed. A failure names
the figures over their limits and where the render and its heat map were
written. Each pytest-xdist worker opens its own device; every case writes
only its own files, each atomically.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, Optional

import pytest

import shadelab
from shadelab import _shadelab


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("shadelab", "golden image tests (shadelab)")
    group.addoption(
        "--shadelab-create",
        action="store_true",
        help="make the golden references that are missing from this run's renders",
    )
    group.addoption(
        "--shadelab-bless",
        action="store_true",
        help="accept this run's renders: rewrite every reference over its limits, make the missing ones",
    )
    group.addoption(
        "--shadelab-references",
        metavar="DIR",
        help="the folder of stored references (default: the ini value shadelab_references)",
    )
    group.addoption(
        "--shadelab-out",
        metavar="DIR",
        help="where a failing case's render and heat map go (default: the ini value shadelab_out)",
    )
    parser.addini(
        "shadelab_references",
        "the folder of golden references, from the rootdir",
        default="references",
    )
    parser.addini("shadelab_out", "where failing cases' pictures go, from the rootdir", default="golden-out")
    parser.addini(
        "shadelab_preset",
        "the limits: stored-reference (one 8-bit step) or gpu-vs-reference",
        default="stored-reference",
    )


def _folder(config: pytest.Config, option: str, ini: str) -> Path:
    given = config.getoption(option) or config.getini(ini)
    path = Path(given)
    return path if path.is_absolute() else Path(config.rootpath) / path


class GoldenCheck:
    """Renders a scene and judges it against its stored reference; fails
    the test where it is over its limits or has no reference."""

    def __init__(self, config: pytest.Config, device: shadelab.Device, test_name: str) -> None:
        self.device = device
        self.references = _folder(config, "--shadelab-references", "shadelab_references")
        self.out = _folder(config, "--shadelab-out", "shadelab_out")
        self.create = bool(config.getoption("--shadelab-create"))
        self.bless = bool(config.getoption("--shadelab-bless")) or os.environ.get("SHADELAB_BLESS") == "1"
        self.preset = str(config.getini("shadelab_preset"))
        self.test_name = test_name

    def __call__(
        self,
        scene: Any,
        shading: str = "phong",
        *,
        name: Optional[str] = None,
        thresholds: Optional[Dict[str, float]] = None,
        preset: Optional[str] = None,
        **render: Any,
    ) -> Dict[str, Any]:
        """Judges ``scene`` in ``shading``; ``name`` is the reference's
        ``{name}-{mode}.png`` (default: the scene file's stem, or the
        test's name for a dict or text scene). Returns the case's record."""
        if name is None and not isinstance(scene, (str, os.PathLike)):
            scene_name = getattr(scene, "name", "scene")
            name = self.test_name if scene_name in ("scene", "default") else scene_name
        record: Dict[str, Any] = _shadelab.golden_case(
            self.device,
            scene,
            shading,
            str(self.references),
            name=name,
            preset=preset or self.preset,
            thresholds=thresholds,
            create=self.create,
            bless=self.bless,
            out=str(self.out),
            **render,
        )
        status = record["status"]
        if status in ("pass", "created", "updated"):
            return record
        pytest.fail(_failure(record, self.references), pytrace=False)
        return record  # pragma: no cover (pytest.fail raises)


def _failure(record: Dict[str, Any], references: Path) -> str:
    """What a person needs of a case that did not pass, as the CLI says it."""
    file = record["file"]
    status = record["status"]
    lines = []
    if status == "missing":
        lines.append(
            f"golden {file}: no reference in {references} (this driver's folder is {record['key']}/); "
            "run pytest with --shadelab-create to make it from this render"
        )
    elif status == "error":
        lines.append(f"golden {file}: {record.get('error')}")
    else:
        reference = record.get("reference")
        lines.append(f"golden {file}: over its limits against {reference} ({record['preset']}):")
        lines.extend(f"  {f}" for f in record.get("failures") or [])
        figures = record.get("figures") or {}
        stats = figures.get("stats") or {}
        flip = figures.get("flip") or {}
        if stats:
            lines.append(
                "  figures: max_abs {:.4g}, p99_abs {:.4g}, rmse {:.4g}, flip_mean {:.4g}".format(
                    stats.get("max_abs", float("nan")),
                    stats.get("p99_abs", float("nan")),
                    stats.get("rmse", float("nan")),
                    flip.get("mean", float("nan")),
                )
            )
        if record.get("hint"):
            lines.append(f"  {record['hint']}")
        lines.append("  accept the render with --shadelab-bless")
    for written in record.get("written") or []:
        what = "heat map" if "-diff." in str(written) else "render" if "-actual." in str(written) else "picture"
        lines.append(f"  {what}: {written}")
    return "\n".join(lines)


@pytest.fixture(scope="session")
def shadelab_device() -> shadelab.Device:
    """One device for the session (for each pytest-xdist worker: its own)."""
    return shadelab.Device()


@pytest.fixture
def shadelab_golden(request: pytest.FixtureRequest, shadelab_device: shadelab.Device) -> GoldenCheck:
    """Judges renders against stored references: ``shadelab_golden(scene,
    shading, **render settings)``."""
    safe = "".join(c if c.isalnum() or c in "-_" else "-" for c in request.node.name)
    return GoldenCheck(request.config, shadelab_device, safe)
