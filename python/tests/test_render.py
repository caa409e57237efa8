"""Rendering from Python: the array (its type, its orientation, its bits
against the CLI's EXR), what an image says of itself, saving, notebook
display and progress."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

import shadelab


def test_the_array_is_height_by_width_by_three_linear_float32(device, small):
    image = device.render(shadelab.Scene.default(), "phong", **small)
    assert image.array.dtype == np.float32
    assert image.array.shape == (48, 64, 3)
    assert (image.width, image.height) == (64, 48)
    # Linear, not sRGB-encoded: the default scene's background is
    # [0.05, 0.05, 0.08] in the file, which sRGB would make about 0.25.
    corner = image.array[0, 0]
    assert np.allclose(corner, [0.05, 0.05, 0.08], atol=1e-6), corner


def test_row_zero_is_the_top_of_the_image(device):
    # A white sphere above the view's centre, on a black background, lit
    # from the eye: its pixels are in the top half of the array.
    scene = shadelab.Scene.from_dict(
        {
            "camera": {"position": [0, 0, 6], "look_at": [0, 0, 0]},
            "image": {"width": 32, "height": 32, "background": [0, 0, 0]},
            "lights": [{"position": [0, 0, 6], "intensity": 1.0}],
            "materials": {"white": {"color": [1, 1, 1], "ka": 1.0}},
            "objects": [{"shape": "sphere", "center": [0, 1.2, 0], "radius": 0.5, "material": "white"}],
        }
    )
    a = device.render(scene, "flat").array
    lit_rows = np.nonzero(a.sum(axis=(1, 2)) > 0)[0]
    assert lit_rows.size > 0
    assert lit_rows.max() < 16, f"the sphere's rows {lit_rows} should be in the top half"


def test_the_array_holds_the_cli_exr_bit_for_bit(device, cli, assets, tmp_path):
    # The same render through the command line's EXR and through Python:
    # every float identical (compared as bits, so NaN and -0 count too).
    # The EXR is read by the `image` crate's decoder, not by the renderer.
    for scene, shading in [("spheres.toml", "phong"), ("rt-glass.toml", "raytrace"), ("spheres.toml", "gouraud")]:
        out = tmp_path / f"{shading}.exr"
        subprocess.run(
            [cli, "render", assets / scene, "--shading", shading, "--width", "96", "--height", "72", "--out", out],
            check=True,
            capture_output=True,
        )
        image = device.render(str(assets / scene), shading, width=96, height=72)
        from_cli = shadelab.read_image(out)
        assert from_cli.dtype == np.float32
        assert np.array_equal(image.array.view(np.uint32), from_cli.view(np.uint32)), (scene, shading)


def test_an_image_says_what_made_it_and_where_the_time_went(device, small):
    image = device.render(shadelab.Scene.default(), "raytrace", stats=True, **small)
    assert image.settings["shading"] == "raytrace"
    assert image.settings["width"] == 64
    assert image.settings["backend"] == "gpu"
    assert image.timings["total_ms"] > 0
    assert image.stats["rays"]["primary"] == 64 * 48
    assert image.stats["rays"]["shadow"] > 0


def test_saved_files_read_back_as_the_array(device, small, tmp_path):
    image = device.render(shadelab.Scene.default(), "phong", **small)
    image.save(tmp_path / "a.exr")
    assert np.array_equal(shadelab.read_image(tmp_path / "a.exr"), image.array)
    image.save(tmp_path / "a.png")
    png = shadelab.read_image(tmp_path / "a.png")
    # 8-bit sRGB of the clamped value: within half a step of it.
    assert np.abs(png - np.clip(image.array, 0, 1)).max() < 0.0046
    assert (tmp_path / "a.png").read_bytes().find(b"shadelab:settings") > 0


def test_a_notebook_shows_the_image_as_png(device, small):
    image = device.render(None, "phong", **small)
    data = image._repr_png_()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.asarray(image).shape == (48, 64, 3)


def test_progress_is_reported_to_a_callback(device, small):
    seen = []
    device.render(
        None, "forward", photons=40_000_000, progress=lambda done, total: seen.append((done, total)), **small
    )
    assert seen, "a long forward render reports its photons"
    assert all(total == 40_000_000 for _, total in seen)
    dones = [d for d, _ in seen]
    assert dones == sorted(dones) and 0 < dones[-1] <= 40_000_000


def test_renders_in_a_loop_see_their_own_settings(device):
    # One device, the light moved between renders: each image is its own
    # scene's (the pipelines kept, nothing of the last render kept).
    base = shadelab.Scene.default().to_dict()
    means = []
    for x in (-4.0, 0.0, 4.0):
        base["lights"][0]["position"][0] = x
        means.append(device.render(shadelab.Scene.from_dict(base), "phong", width=48, height=36).array.mean())
    assert len(set(means)) == 3


def test_the_default_device_serves_module_level_render(small):
    image = shadelab.render(None, "flat", **small)
    assert image.array.shape == (48, 64, 3)
    assert shadelab.default_device() is shadelab.default_device()


def test_the_cpu_backend_is_the_f64_reference(small):
    cpu = shadelab.Device(backend="cpu")
    image = cpu.render(None, "phong", **small)
    assert image.settings["backend"] == "cpu"
    gpu = shadelab.render(None, "phong", **small)
    # GPU against the reference: within check's limits, not equal.
    figures = shadelab.diff(image, gpu)
    assert figures["figures"]["stats"]["rmse"] < 1e-2


def test_scenes_are_given_as_paths_dicts_or_scenes(device, assets, small):
    by_path = device.render(str(assets / "spheres.toml"), "flat", **small)
    by_scene = device.render(shadelab.Scene.load(assets / "spheres.toml"), "flat", **small)
    by_dict = device.render(shadelab.Scene.load(assets / "spheres.toml").to_dict(), "flat", **small)
    assert np.array_equal(by_path.array, by_scene.array)
    assert np.array_equal(by_path.array, by_dict.array)


def test_a_path_relative_mesh_survives_to_dict(device, assets, small, tmp_path, monkeypatch):
    # The dict of a scene file names its meshes absolutely: given back
    # from another folder, it still finds them.
    d = shadelab.Scene.load(assets / "rt-mesh.toml").to_dict()
    monkeypatch.chdir(tmp_path)
    image = device.render(shadelab.Scene.from_dict(d), "flat", **small)
    assert image.array.max() > 0


def test_progress_true_draws_a_tqdm_bar(device, small, capsys):
    device.render(None, "forward", photons=40_000_000, progress=True, **small)
    err = capsys.readouterr().err
    # tqdm's bar in the render's own unit, run to the end.
    assert "photons" in err, err
    assert "40000000/40000000" in err, err


def test_an_exception_in_the_progress_callback_stops_the_render(device, small):
    calls = []

    def stop(done: int, total: int) -> None:
        calls.append(done)
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        device.render(None, "forward", photons=4_000_000_000, progress=stop, **small)
    assert len(calls) == 1
    assert device.render(None, "flat", **small).array.shape == (48, 64, 3)
