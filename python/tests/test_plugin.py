"""The pytest plugin: references made, passed, failed with figures and a
heat map, blessed, and the same under pytest-xdist; one folder serves
the CLI's `shadelab golden` too."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

ASSETS = Path(__file__).resolve().parents[2] / "assets"

TEST_FILE = f"""
import shadelab

def scene(intensity):
    d = shadelab.Scene.load({str(ASSETS / 'spheres.toml')!r}).to_dict()
    d["lights"][0]["intensity"] = intensity
    return shadelab.Scene.from_dict(d)

def test_spheres(shadelab_golden):
    shadelab_golden(scene(INTENSITY), "phong", name="spheres", width=64, height=48)

def test_spheres_flat(shadelab_golden):
    shadelab_golden(scene(INTENSITY), "flat", name="spheres", width=64, height=48)
"""


def write_test(pytester: pytest.Pytester, intensity: float) -> None:
    pytester.makepyfile(test_golden=TEST_FILE.replace("INTENSITY", repr(intensity)))
    pytester.makeini("[pytest]\nshadelab_references = refs\n")


def test_create_pass_fail_bless(pytester: pytest.Pytester):
    write_test(pytester, 8.0)
    # No reference: each case fails, saying how to make one.
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider")
    result.assert_outcomes(failed=2)
    result.stdout.fnmatch_lines(["*no reference in*--shadelab-create*"])
    # Made, then passed.
    pytester.runpytest_subprocess("--shadelab-create").assert_outcomes(passed=2)
    refs = pytester.path / "refs"
    assert (refs / "spheres-phong.png").is_file() and (refs / "spheres-flat.png").is_file()
    pytester.runpytest_subprocess().assert_outcomes(passed=2)
    # The light changed: over the limits, the figures and the pictures named.
    write_test(pytester, 12.0)
    result = pytester.runpytest_subprocess()
    result.assert_outcomes(failed=2)
    result.stdout.fnmatch_lines(
        [
            "*golden spheres-phong.png: over its limits against*stored-reference*",
            "*max_abs*",
            "*figures: max_abs*",
            "*render: *spheres-phong-actual.png*",
            "*heat map: *spheres-phong-diff.png*",
        ]
    )
    assert (pytester.path / "golden-out" / "spheres-phong-diff.png").is_file()
    before = (refs / "spheres-phong.png").read_bytes()
    # Blessed: rewritten, and passing after.
    pytester.runpytest_subprocess("--shadelab-bless").assert_outcomes(passed=2)
    assert (refs / "spheres-phong.png").read_bytes() != before
    pytester.runpytest_subprocess().assert_outcomes(passed=2)


def test_under_xdist_each_worker_judges_its_own_cases(pytester: pytest.Pytester):
    write_test(pytester, 8.0)
    pytester.runpytest_subprocess("-n", "2", "--shadelab-create").assert_outcomes(passed=2)
    pytester.runpytest_subprocess("-n", "2").assert_outcomes(passed=2)
    write_test(pytester, 12.0)
    pytester.runpytest_subprocess("-n", "2").assert_outcomes(failed=2)


def test_the_cli_judges_the_references_the_plugin_made(pytester: pytest.Pytester, cli, tmp_path):
    # One folder serves both: the plugin's references pass `shadelab
    # golden` with the same scene, size and mode.
    scene = tmp_path / "spheres.toml"
    scene.write_text((ASSETS / "spheres.toml").read_text())
    pytester.makepyfile(
        test_one=f"""
def test_one(shadelab_golden):
    shadelab_golden({str(scene)!r}, "phong", width=64, height=48)
"""
    )
    pytester.makeini("[pytest]\nshadelab_references = refs\n")
    pytester.runpytest_subprocess("--shadelab-create").assert_outcomes(passed=1)
    run = subprocess.run(
        [cli, "golden", scene, "--shading", "phong", "--width", "64", "--height", "48",
         "--references", pytester.path / "refs", "--out", tmp_path / "out"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "PASS" in run.stdout
