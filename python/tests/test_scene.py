"""Scenes from files, TOML text and dicts: one schema, one loader, errors
that say where."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import shadelab

DICT = {
    "camera": {"position": [0, 1, 6], "look_at": [0, 0, 0]},
    "image": {"width": 40, "height": 30},
    "lights": [{"position": [4, 6, 5], "intensity": 8.0}],
    "materials": {"plaster": {"color": [0.9, 0.85, 0.8]}},
    "objects": [
        {"shape": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": "plaster"},
        {"shape": "sphere", "center": [2, 0, 0], "radius": 0.5, "material": "plaster"},
    ],
}

TOML = """
[camera]
position = [0, 1, 6]
look_at = [0, 0, 0]

[image]
width = 40
height = 30

[[lights]]
position = [4, 6, 5]
intensity = 8.0

[materials.plaster]
color = [0.9, 0.85, 0.8]

[[objects]]
shape = "sphere"
center = [0, 0, 0]
radius = 1.0
material = "plaster"

[[objects]]
shape = "sphere"
center = [2, 0, 0]
radius = 0.5
material = "plaster"
"""


def test_a_dict_and_its_toml_text_are_one_scene(device):
    from_dict = device.render(shadelab.Scene.from_dict(DICT), "phong").array
    from_text = device.render(shadelab.Scene.from_toml(TOML), "phong").array
    assert np.array_equal(from_dict, from_text)


def test_to_dict_gives_back_what_from_dict_takes():
    scene = shadelab.Scene.from_toml(TOML)
    assert shadelab.Scene.from_dict(scene.to_dict()).to_dict() == scene.to_dict()
    assert scene.to_dict()["objects"][1]["radius"] == 0.5


def test_numpy_values_are_numbers():
    d = {**DICT, "lights": [{"position": np.array([4.0, 6.0, 5.0]), "intensity": np.float32(8.0)}]}
    assert shadelab.Scene.from_dict(d).width == 40


@pytest.mark.parametrize(
    "change, key, words",
    [
        (lambda d: d["objects"][1].update(radius="big"), "objects[1].radius", "number"),
        (lambda d: d["camera"].update(fov_y=200), "camera.fov_y", "fov"),
        (lambda d: d["materials"]["plaster"].update(color=[1, -1, 1]), "materials.plaster.color", ""),
        (lambda d: d["objects"][0].update(radius=float("nan")), "objects[0].radius", "finite"),
        (lambda d: d["objects"][0].update(colour=1), "objects[0].colour", "unknown key"),
        (lambda d: d["lights"][0].update(position=object()), "lights[0].position", "not object"),
    ],
)
def test_a_dict_error_names_its_key_path(change, key, words):
    import copy

    d = copy.deepcopy(DICT)
    change(d)
    with pytest.raises(shadelab.SceneError) as caught:
        shadelab.Scene.from_dict(d)
    error = caught.value
    assert isinstance(error, ValueError)
    assert error.key == key, str(error)
    assert str(error).startswith(key + ":"), str(error)
    assert words in str(error)
    assert error.path is None and error.line is None


def test_a_text_error_names_its_line():
    with pytest.raises(shadelab.SceneError) as caught:
        shadelab.Scene.from_toml(TOML.replace("radius = 0.5", "radius = -0.5"))
    assert caught.value.line == TOML.splitlines().index("radius = 0.5") + 1
    assert caught.value.key is None


def test_a_file_error_names_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[camera]\nposition = \"here\"\nlook_at = [0, 0, 0]\n")
    with pytest.raises(shadelab.SceneError) as caught:
        shadelab.Scene.load(bad)
    assert caught.value.path == str(bad)
    assert caught.value.line == 2
    with pytest.raises(shadelab.SceneError) as caught:
        shadelab.Scene.load(tmp_path / "missing.toml")
    assert "cannot read" in str(caught.value)


def test_a_gltf_scene_loads_and_has_no_dict(assets):
    scene = shadelab.Scene.load(assets / "models" / "cube.glb")
    assert scene.name == "cube"
    with pytest.raises(shadelab.RefusalError):
        scene.to_dict()


def test_a_corrupt_gltf_is_a_scene_error(tmp_path):
    broken = tmp_path / "broken.glb"
    broken.write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(shadelab.SceneError) as caught:
        shadelab.Scene.load(broken)
    assert caught.value.path == str(broken)


def test_with_light_moves_one_light_as_a_dict_would(device):
    base = shadelab.Scene.from_dict(DICT)
    moved = base.with_light(0, position=[-4.0, 6.0, 5.0])
    d = copy.deepcopy(DICT)
    d["lights"][0]["position"] = [-4.0, 6.0, 5.0]
    # The same image as the scene written with the light there, and its
    # dict says where the light is; the scene it came from is unchanged.
    assert np.array_equal(device.render(moved, "phong").array, device.render(shadelab.Scene.from_dict(d), "phong").array)
    assert moved.to_dict()["lights"][0]["position"] == [-4.0, 6.0, 5.0]
    assert base.to_dict()["lights"][0]["position"] == [4, 6, 5]
    brighter = base.with_light(0, intensity=16.0)
    assert brighter.to_dict()["lights"][0]["intensity"] == [16.0, 16.0, 16.0]
    assert device.render(brighter, "phong").array.mean() > device.render(base, "phong").array.mean()


@pytest.mark.parametrize(
    "index, settings, key",
    [
        (0, {"position": [float("nan"), 0, 0]}, "lights[0].position"),
        (0, {"intensity": -1.0}, "lights[0].intensity"),
        (0, {"intensity": "bright"}, "lights[0].intensity"),
        (3, {"position": [0, 0, 0]}, "lights[3]"),
    ],
)
def test_with_light_refuses_what_a_file_may_not_hold(index, settings, key):
    with pytest.raises(shadelab.SceneError) as caught:
        shadelab.Scene.from_dict(DICT).with_light(index, **settings)
    assert caught.value.key == key, str(caught.value)
