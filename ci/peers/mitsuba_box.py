"""Peer for shadelab's two estimators of secondary illumination: Mitsuba 3 rendering a
shadelab scene of planes and boxes (assets/diffuse-box.toml: diffuse materials, one point
light, falloff "inverse-square") with its backward path tracer (`path`) or its particle
tracer (`ptracer`, light paths from the emitters splatted to the camera), the twins of
`--shading raytrace --bounces B` and `--shading forward --bounces B`.

    mitsuba_box.py VARIANT INTEGRATOR SCENE.toml BOUNCES SPP OUT.exr

The scene is read from shadelab's TOML (its planes as rectangles, its boxes as cubes turned
about Y, its camera, light and kd * color), so that both render the same thing. shadelab's
image is pi times radiance (docs/lighting-model.md, "Secondary illumination") where
Mitsuba's is radiance: the image written is Mitsuba's times pi, in shadelab's units.
`BOUNCES` diffuse bounces are Mitsuba's max_depth = BOUNCES + 2 (the eye's hit and its
direct light are two vertices). For `ptracer`, SPP is light paths per pixel of the image
(Mitsuba's convention). One warm-up render (the JIT's compilation), then one timed: prints
one JSON line with its time. VARIANT: llvm_ad_rgb or scalar_rgb; llvm_ad_rgb needs a libLLVM
that lowers Dr.Jit's intrinsics (LLVM 15 cannot: "Cannot select: fminimum"): the newest
libLLVM found is used, unless DRJIT_LIBLLVM_PATH names one.
"""
import math
import os
import sys
import time
import tomllib

from peer_common import emit, use_newest_libllvm


def usage():
    sys.exit("usage: mitsuba_box.py llvm_ad_rgb|scalar_rgb path|ptracer SCENE.toml BOUNCES SPP OUT.exr")


if len(sys.argv) != 7 or not sys.argv[4].isdigit() or not sys.argv[5].isdigit():
    usage()
VARIANT, INTEGRATOR, SCENE, BOUNCES, SPP, OUT = (
    sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]), sys.argv[6])
if VARIANT not in ("llvm_ad_rgb", "scalar_rgb") or INTEGRATOR not in ("path", "ptracer") or SPP < 1:
    usage()
if VARIANT.startswith("llvm"):
    use_newest_libllvm()

import numpy as np  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant(VARIANT)
T = mi.ScalarTransform4f


def v3(x):
    return [float(x)] * 3 if isinstance(x, (int, float)) else [float(c) for c in x]


def shapes(scene):
    """shadelab's planes and boxes as Mitsuba rectangles and cubes."""
    materials = scene.get("materials", {})
    out = {}
    for k, o in enumerate(scene["objects"]):
        m = materials[o["material"]]
        albedo = [float(m.get("kd", 1.0)) * c for c in v3(m.get("color", 1.0))]
        bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}}
        c = v3(o["center"])
        if o["shape"] == "plane":
            n = v3(o["normal"])
            up = [0, 0, 1] if abs(n[1]) > 0.9 else [0, 1, 0]
            half = float(o["size"]) / 2
            to_world = T().look_at(origin=c, target=[c[i] + n[i] for i in range(3)], up=up) @ T().scale([half, half, 1])
            out[f"plane{k}"] = {"type": "rectangle", "to_world": to_world, "bsdf": bsdf}
        elif o["shape"] == "box":
            rx, ry, rz = v3(o.get("rotate_deg", 0.0))
            if rx or rz:
                sys.exit("mitsuba_box.py: boxes turned about Y only")
            half = [s / 2 for s in v3(o["size"])]
            to_world = T().translate(c) @ T().rotate([0, 1, 0], ry) @ T().scale(half)
            out[f"box{k}"] = {"type": "cube", "to_world": to_world, "bsdf": bsdf}
        else:
            sys.exit(f"mitsuba_box.py: a {o['shape']} is not a plane or a box")
    return out


with open(SCENE, "rb") as f:
    scene = tomllib.load(f)
if scene.get("lighting", {}).get("falloff") != "inverse-square":
    sys.exit("mitsuba_box.py: the scene's lights must fall off as inverse-square, as Mitsuba's do")
cam, img = scene["camera"], scene["image"]
light = scene["lights"][0]
width, height = int(img["width"]), int(img["height"])
description = {
    "type": "scene",
    "integrator": {"type": INTEGRATOR, "max_depth": BOUNCES + 2},
    "sensor": {"type": "perspective", "fov": float(cam["fov_y"]), "fov_axis": "y",
               "to_world": T().look_at(origin=v3(cam["position"]), target=v3(cam["look_at"]), up=[0, 1, 0]),
               "film": {"type": "hdrfilm", "width": width, "height": height, "pixel_format": "rgb",
                        "rfilter": {"type": "box"}},
               "sampler": {"type": "independent", "sample_count": SPP}},
    "light": {"type": "point", "position": v3(light["position"]),
              "intensity": {"type": "rgb", "value": v3(light["intensity"])}},
}
description.update(shapes(scene))
loaded = mi.load_dict(description)
np.array(mi.render(loaded, spp=SPP, seed=1))  # warm-up: the JIT's kernels
started = time.perf_counter()
image = np.array(mi.render(loaded, spp=SPP, seed=2))
seconds = time.perf_counter() - started
mi.Bitmap(image * math.pi).write(OUT)
emit(dict(peer="mitsuba", variant=VARIANT, integrator=INTEGRATOR, scene=os.path.basename(SCENE),
          width=width, height=height, bounces=BOUNCES, spp=SPP, ms=round(seconds * 1e3, 3),
          mitsuba=getattr(mi, "__version__", getattr(mi, "MI_VERSION", "?")),
          libllvm=os.environ.get("DRJIT_LIBLLVM_PATH", "") if VARIANT.startswith("llvm") else ""))
