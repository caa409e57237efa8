"""The default scene's key light moved around a circle, one Phong frame
per step, on one device.

    python moving_light.py [STEPS [OUT_DIR]]

Reads the built-in default scene once, moves its first light around a
circle of the light's own radius about the vertical axis in ``STEPS``
steps (default 8) with ``scene.with_light`` (no scene read again a
frame), renders each frame in Phong at 160 x 120 and prints the frame's
mean brightness (the mean of its linear RGB values). Given ``OUT_DIR``,
it saves the frames there too, ``frame-001.png`` and on. The device and
its Phong pipeline are kept between frames.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional

import shadelab


def main(argv: List[str]) -> int:
    steps = int(argv[1]) if len(argv) > 1 else 8
    if steps < 1:
        print("STEPS is a count of frames, 1 or more", file=sys.stderr)
        return 2
    out: Optional[Path] = Path(argv[2]) if len(argv) > 2 else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    device = shadelab.Device()
    scene = shadelab.Scene.default()
    # Where the light is, from the scene's dict (the TOML files' schema).
    light: Dict[str, Any] = scene.to_dict()["lights"][0]
    x, y, z = (float(v) for v in light["position"])
    radius = math.hypot(x, z)
    start = math.atan2(z, x)
    for step in range(steps):
        angle = start + 2.0 * math.pi * step / steps
        moved = scene.with_light(0, position=[radius * math.cos(angle), y, radius * math.sin(angle)])
        image = device.render(moved, "phong", width=160, height=120)
        mean = float(image.array.mean())
        if out is not None:
            image.save(out / f"frame-{step + 1:03}.png")
        degrees = math.degrees(angle - start)
        print(f"frame {step + 1:3}/{steps}: light at {degrees:6.1f} deg, mean brightness {mean:.5f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
