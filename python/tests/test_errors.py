"""Every exception class, raised where its failure happens, with the
CLI's one-line message; none is a Rust panic."""

from __future__ import annotations

import pytest

import shadelab


def test_a_refused_setting_is_a_value_error_with_the_cli_message(device, small):
    with pytest.raises(shadelab.RefusalError) as caught:
        device.render(None, "phong", width=0)
    assert isinstance(caught.value, ValueError)
    assert str(caught.value) == "--width 0 is out of range; expected 1 to 16384 pixels"
    with pytest.raises(ValueError, match="stops one render"):
        device.render(None, "phong", time=1.0, **small)
    with pytest.raises(ValueError, match="shading"):
        device.render(None, "no-such-mode", **small)
    with pytest.raises(ValueError, match="--samples 5000 is out of range"):
        device.render(None, "raytrace", samples=5000, **small)


def test_a_device_that_does_not_exist_is_a_runtime_error():
    with pytest.raises(shadelab.DeviceError) as caught:
        shadelab.Device("no-such-device")
    assert isinstance(caught.value, RuntimeError)
    assert "no Vulkan device matches `no-such-device`" in str(caught.value)


def test_a_render_over_the_memory_limit_is_a_memory_error(device, monkeypatch):
    monkeypatch.setenv("SHADELAB_MAX_MEMORY", "1M")
    with pytest.raises(shadelab.MemoryLimitError) as caught:
        device.render(None, "phong", width=2048, height=2048)
    assert isinstance(caught.value, MemoryError)
    assert "over the memory limit of 1.0 MiB" in str(caught.value)
    monkeypatch.delenv("SHADELAB_MAX_MEMORY")
    assert device.render(None, "phong", width=8, height=8).array.shape == (8, 8, 3)


def test_an_image_that_cannot_be_written_is_an_os_error(device, small, tmp_path):
    image = device.render(None, "phong", **small)
    with pytest.raises(shadelab.OutputError) as caught:
        image.save(tmp_path / "image.bmp")
    assert isinstance(caught.value, OSError)
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(OSError):
        image.save(blocker / "image.png")


def test_a_lighting_hook_that_does_not_compile_is_refused_not_crashed(device, small):
    with pytest.raises(ValueError, match="lighting hook"):
        device.render(None, "phong", lighting="vec3 shade_light(vec3 N) { return nonsense; }", **small)
    with pytest.raises(ValueError, match="CPU reference always evaluates the built-in formula"):
        shadelab.Device(backend="cpu").render(None, "phong", lighting="vec3 f() { return vec3(0); }", **small)


def test_every_class_is_a_shadelab_error_and_the_builtin_kind():
    kinds = {
        shadelab.SceneError: ValueError,
        shadelab.RefusalError: ValueError,
        shadelab.DeviceError: RuntimeError,
        shadelab.MemoryLimitError: MemoryError,
        shadelab.OutputError: OSError,
        shadelab.InternalError: RuntimeError,
    }
    for cls, builtin in kinds.items():
        assert issubclass(cls, shadelab.ShadelabError) and issubclass(cls, builtin)


def test_a_panic_comes_out_as_internal_error_not_a_base_exception():
    # Every call into the library runs in one guard; a panic there (a
    # bug) is an InternalError, which `except Exception` catches: pyo3's
    # own PanicException derives from BaseException.
    from shadelab import _shadelab

    with pytest.raises(shadelab.InternalError, match="this is a bug"):
        _shadelab._panic_at_the_border()
    # The process goes on.
    assert shadelab.Device(backend="cpu").render(None, "flat", width=8, height=8).array.shape == (8, 8, 3)
