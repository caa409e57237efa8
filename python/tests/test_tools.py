"""diff, check and compare from Python: the CLI's figures, as data."""

from __future__ import annotations

import numpy as np
import pytest

import shadelab


def test_diff_gives_the_figures_and_the_heat_map(device, small):
    phong = device.render(None, "phong", **small)
    gouraud = device.render(None, "gouraud", **small)
    same = shadelab.diff(phong, phong)
    assert same["passed"] and same["figures"]["stats"]["rmse"] == 0.0
    apart = shadelab.diff(phong, gouraud)
    assert not apart["passed"]
    assert apart["failures"]
    assert apart["figures"]["stats"]["max_abs"] > 0
    assert apart["heatmap"].shape == (48, 64, 3)
    assert apart["heatmap"].dtype == np.float32
    # Arrays and files are images too.
    assert shadelab.diff(phong.array, gouraud.array)["figures"] == apart["figures"]
    loose = shadelab.diff(phong, gouraud, thresholds={"max_abs": 10, "p99_abs": 10, "rmse": 10, "flip_mean": 10})
    assert loose["passed"]


def test_diff_refuses_images_of_two_sizes(device):
    with pytest.raises(ValueError, match="cannot be compared"):
        shadelab.diff(device.render(None, "flat", width=8, height=8), np.zeros((9, 8, 3), np.float32))


def test_check_passes_the_gpu_against_the_reference(device):
    records = shadelab.check(None, ["flat", "phong"], device=device, width=64, height=48)
    assert [r["shading"] for r in records] == ["flat", "phong"]
    assert all(r["passed"] for r in records), records
    assert records[1]["figures"]["interior"]["max_abs"] < 1e-3


def test_compare_gives_records_a_dataframe_takes(device, tmp_path):
    records = shadelab.compare(
        None, ["phong", "gouraud:segments=8"], out=tmp_path, runs=1, device=device
    )
    assert [r["name"] for r in records] == ["phong", "gouraud:segments=8"]
    for r in records:
        # Flat: every value a number, a string, a bool or None.
        assert all(not isinstance(v, dict) for v in r.values()), r
        assert isinstance(r["pareto"], bool)
        assert r["timing.gpu_ms"] > 0
        assert r["model_error.rmse"] >= 0
    assert (tmp_path / "reference.png").is_file()
