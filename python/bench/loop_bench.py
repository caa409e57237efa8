"""The package's speed and memory where a user feels them: a loop of
renders of one scene with a moving light (the default scene's first light
around a circle, phong), three ways in interleaved rounds:

- python: one ``shadelab.Device``, each frame ``Scene.from_dict`` and
  ``device.render`` (the array read);
- rust: the library's own loop, ``cargo run --release --example
  render_loop`` (the same scene tables, the same device kept);
- cli: one ``shadelab render`` command per frame, each frame's scene a
  TOML file written beforehand (the commands' whole wall clock).

Then the resident size over 1000 renders through one device. Prints the
medians, the ratios the package is held to (cli / python at least 5,
python / rust at most 1.05) and the memory growth (at most 5 %).

    target/python-venv/bin/python python/bench/loop_bench.py [--frames 100] [--rounds 3]

Needs target/release/shadelab and target/release/examples/render_loop
(``cargo build --release --bin shadelab --example render_loop``) and the
package installed (``ci/python-tests.sh`` installs it).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Dict, List

import shadelab

ROOT = Path(__file__).resolve().parents[2]


def light_at(frame: int, frames: int) -> List[float]:
    angle = 2 * math.pi * frame / frames
    return [5 * math.cos(angle), 5.0, 5 * math.sin(angle)]


def python_loop(device: shadelab.Device, frames: int, width: int, height: int) -> float:
    table = shadelab.Scene.default().to_dict()
    started = time.perf_counter()
    for frame in range(frames):
        table["lights"][0]["position"] = light_at(frame, frames)
        image = device.render(shadelab.Scene.from_dict(table), "phong", width=width, height=height)
        image.array[..., 0].mean()
    return (time.perf_counter() - started) * 1e3


def rust_loop(frames: int, width: int, height: int) -> float:
    binary = ROOT / "target" / "release" / "examples" / "render_loop"
    out = subprocess.run([binary, str(frames), str(width), str(height)], check=True, capture_output=True, text=True)
    return float(json.loads(out.stdout)["wall_ms"])


def write_frames(folder: Path, frames: int) -> List[Path]:
    """Each frame's scene as a TOML file, for the CLI (not timed)."""
    import tomllib  # noqa: F401 (only to be sure the text below is TOML 1.0)

    base = (ROOT / "src" / "scene" / "default.toml").read_text()
    paths = []
    first = base.index("[[lights]]")
    position = base.index("position", first)
    line_end = base.index("\n", position)
    for frame in range(frames):
        x, y, z = light_at(frame, frames)
        text = base[:position] + f"position = [{x!r}, {y!r}, {z!r}]" + base[line_end:]
        path = folder / f"frame{frame:04}.toml"
        path.write_text(text)
        paths.append(path)
    return paths


def cli_loop(paths: List[Path], width: int, height: int, out: Path) -> float:
    binary = ROOT / "target" / "release" / "shadelab"
    started = time.perf_counter()
    for path in paths:
        subprocess.run(
            [binary, "render", path, "--shading", "phong", "--width", str(width), "--height", str(height),
             "--out", out / "frame.exr"],
            check=True,
            capture_output=True,
        )
    return (time.perf_counter() - started) * 1e3


def resident() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


def memory(device: shadelab.Device, renders: int) -> Dict[str, float]:
    scene = shadelab.Scene.default()
    for _ in range(100):
        device.render(scene, "phong", width=64, height=48)
    before = resident()
    for _ in range(renders):
        device.render(scene, "phong", width=64, height=48).array.sum()
    after = resident()
    return {"before_mib": before / 2**20, "after_mib": after / 2**20, "growth": after / before - 1}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--memory-renders", type=int, default=1000)
    parser.add_argument("--json", type=Path, help="also write the figures here")
    args = parser.parse_args()
    device = shadelab.Device()
    # Pipelines built and the driver's code generated before any timing,
    # for all three (the CLI's come from the same cache folder).
    python_loop(device, 2, args.width, args.height)
    times: Dict[str, List[float]] = {"python": [], "rust": [], "cli": []}
    with tempfile.TemporaryDirectory() as tmp:
        paths = write_frames(Path(tmp), args.frames)
        cli_loop(paths[:2], args.width, args.height, Path(tmp))
        for _ in range(args.rounds):
            times["python"].append(python_loop(device, args.frames, args.width, args.height))
            times["rust"].append(rust_loop(args.frames, args.width, args.height))
            times["cli"].append(cli_loop(paths, args.width, args.height, Path(tmp)))
    median = {k: statistics.median(v) for k, v in times.items()}
    figures: Dict[str, Any] = {
        "frames": args.frames,
        "size": f"{args.width}x{args.height}",
        "rounds": args.rounds,
        "device": device.name,
        "driver": device.driver,
        "ms": times,
        "median_ms": median,
        "cli_over_python": median["cli"] / median["python"],
        "python_over_rust": median["python"] / median["rust"],
        "memory": memory(device, args.memory_renders),
    }
    print(f"{args.frames} renders, phong {args.width}x{args.height}, moving light, median of {args.rounds} interleaved rounds on {device.name}:")
    for k in ("python", "rust", "cli"):
        spread = ", ".join(f"{t:.0f}" for t in times[k])
        print(f"  {k:6} {median[k]:8.0f} ms  ({spread})")
    print(f"  cli / python     {figures['cli_over_python']:.2f}x  (target: at least 5)")
    print(f"  python / rust    {figures['python_over_rust']:.3f}x  (target: at most 1.05)")
    m = figures["memory"]
    print(f"  resident size over {args.memory_renders} renders: {m['before_mib']:.1f} -> {m['after_mib']:.1f} MiB ({100 * m['growth']:+.2f} %; target: within 5 %)")
    if args.json:
        args.json.write_text(json.dumps(figures, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
