"""The built-in default scene in the four classic modes, on one device.

    python four_modes.py [OUT_DIR]

Renders flat, Gouraud, Phong and (Whitted) ray tracing at 320 x 240,
saves ``OUT_DIR/default-MODE.png`` (default folder: ``out``) and prints
each mode's render time. One ``Device`` serves every render: the Vulkan
context is opened once and each mode's pipeline is built at its first use.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import List, Literal, Sequence

import shadelab

Mode = Literal["flat", "gouraud", "phong", "raytrace"]
MODES: Sequence[Mode] = ("flat", "gouraud", "phong", "raytrace")


def main(argv: List[str]) -> int:
    out = Path(argv[1] if len(argv) > 1 else "out")
    out.mkdir(parents=True, exist_ok=True)
    device = shadelab.Device()
    scene = shadelab.Scene.default()
    print(f"device: {device.name}")
    for mode in MODES:
        image = device.render(scene, mode, width=320, height=240)
        path = out / f"default-{mode}.png"
        image.save(path)
        total_ms = image.timings["total_ms"]
        took = f"{total_ms:8.1f} ms" if total_ms is not None else "       ? ms"
        print(f"{mode:>8}: {took}  {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
