"""Peer for shadelab's ray tracer at --depth 0: Mitsuba 3 rendering the peers' UV sphere (the
PLY that sphere_scene.py writes) at SIZExSIZE with one point light, a diffuse BSDF and the
`direct` integrator at 1 sample per pixel: a primary ray per pixel and a shadow ray per hit,
the rays shadelab traces at --depth 0.

    mitsuba_peer.py VARIANT PLY SIZE RUNS      (VARIANT: llvm_ad_rgb or scalar_rgb)

llvm_ad_rgb JIT-compiles and vectorises (Dr.Jit's LLVM backend; it needs a libLLVM: set
DRJIT_LIBLLVM_PATH, else the newest /usr/lib/*/libLLVM*.so* is used); scalar_rgb is plain C++.
One warm-up render (its time, kernel compilation included, is reported as first_ms; with the
scene's load before it, BVH included, as first_image_ms), then RUNS
timed ones: mi.render() and the conversion of the image to an array (which forces evaluation).
Rays: SIZE^2 primary plus one shadow ray per pixel whose alpha says it hit, so Mrays/s is an
approximation. Prints one JSON line.
"""
import os
import sys
import time

from peer_common import emit, summary, use_newest_libllvm


def usage():
    sys.exit("usage: mitsuba_peer.py llvm_ad_rgb|scalar_rgb PLY SIZE RUNS")


if len(sys.argv) != 5 or not sys.argv[3].isdigit() or not sys.argv[4].isdigit():
    usage()
VARIANT, PLY, SIZE, RUNS = sys.argv[1], os.path.abspath(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
if VARIANT not in ("llvm_ad_rgb", "scalar_rgb") or SIZE < 1 or RUNS < 1:
    usage()
if not os.path.isfile(PLY):
    sys.exit(f"mitsuba_peer.py: no such mesh: {PLY}")
if VARIANT.startswith("llvm"):
    use_newest_libllvm()

import numpy as np  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant(VARIANT)
started = time.perf_counter()
scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
    "sensor": {"type": "perspective", "fov": 40, "fov_axis": "y",
               "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0.5, 3], target=[0, 0, 0], up=[0, 1, 0]),
               "film": {"type": "hdrfilm", "width": SIZE, "height": SIZE, "pixel_format": "rgba",
                        "rfilter": {"type": "box"}},
               "sampler": {"type": "independent", "sample_count": 1}},
    "light": {"type": "point", "position": [4, 6, 5], "intensity": {"type": "rgb", "value": 50.0}},
    "mesh": {"type": "ply", "filename": PLY, "bsdf": {"type": "diffuse"}},
})
times = []
img = None
for i in range(RUNS + 1):
    t0 = time.perf_counter()
    img = np.array(mi.render(scene, spp=1, seed=i))
    times.append(time.perf_counter() - t0)
    if i == 0:
        first_image_ms = (time.perf_counter() - started) * 1e3
hits = int((img[..., 3] > 0).sum()) if img.ndim == 3 and img.shape[-1] >= 4 else SIZE * SIZE
rays = SIZE * SIZE + hits
s = summary(times[1:])
emit(dict(s, peer="mitsuba", variant=VARIANT, mitsuba=getattr(mi, "__version__", getattr(mi, "MI_VERSION", "?")),
          triangles=int(scene.shapes()[0].face_count()), width=SIZE, height=SIZE,
          first_ms=round(times[0] * 1e3, 3), first_image_ms=round(first_image_ms, 3), rays=rays, hits=hits,
          mrays_per_s=round(rays / (s["median_ms"] / 1e3) / 1e6, 3),
          libllvm=os.environ.get("DRJIT_LIBLLVM_PATH", "") if VARIANT.startswith("llvm") else ""))
