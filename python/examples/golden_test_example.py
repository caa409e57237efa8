"""An example golden image test with the ``shadelab_golden`` fixture.

The fixture comes with the package (its pytest plugin is registered on
install). Copy this file into your tests as ``test_golden.py`` (pytest
collects only ``test_*.py`` files by default, so it is not collected
here) and run it:

    pytest test_golden.py --shadelab-create   # first run: make the references
    pytest test_golden.py                     # every later run: judge against them
    pytest test_golden.py --shadelab-bless    # a change you accept: rewrite them

The references go to ``references/`` under pytest's rootdir (the ini
value ``shadelab_references`` or ``--shadelab-references DIR`` sets
another folder), named ``NAME-MODE.png`` as ``shadelab golden`` names
them, so one folder serves both.
"""

from __future__ import annotations

from typing import Any, Dict

import pytest

import shadelab
from shadelab.pytest_plugin import GoldenCheck

SIZE: Dict[str, Any] = {"width": 160, "height": 120}


@pytest.mark.parametrize("mode", ["flat", "gouraud", "phong", "raytrace"])
def test_default_scene(shadelab_golden: GoldenCheck, mode: str) -> None:
    # `name` is the reference's stem: references/default-MODE.png. Left
    # out, a scene file gives its stem; the default scene, a dict or TOML
    # text give the test's name.
    record = shadelab_golden(shadelab.Scene.default(), mode, name="default", **SIZE)
    assert record["status"] in ("pass", "created", "updated")


def test_brighter_key_light(shadelab_golden: GoldenCheck) -> None:
    # A scene changed as a dict: the reference is named by `name`.
    scene = shadelab.Scene.default().to_dict()
    scene["lights"][0]["intensity"] = [12.0, 10.5, 8.5]
    shadelab_golden(shadelab.Scene.from_dict(scene), "phong", name="bright-key", **SIZE)


def test_diffuse_only_hook(shadelab_golden: GoldenCheck) -> None:
    # Your own lighting (docs/lighting-hooks.md): GLSL source, or the
    # path of a .glsl file. This one is diffuse only, no highlight.
    hook = (
        "vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {\n"
        "    vec3 light = USE_ATTENUATION ? intensity / (INVERSE_SQUARE ? d * d : d + k) : intensity;\n"
        "    return light * m.kd * m.color * dot(N, L);\n"
        "}\n"
    )
    shadelab_golden(shadelab.Scene.default(), "phong", name="hooked", lighting=hook, **SIZE)
