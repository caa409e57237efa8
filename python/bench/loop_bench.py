"""The package's speed and memory where a user feels them: a loop of
renders of one scene with a moving light (the default scene's first light
around a circle, phong), three ways in interleaved rounds:

- python: one ``shadelab.Device``, each frame's scene made by
  ``Scene.from_dict`` (``--way table``, the default) or by
  ``scene.with_light`` (``--way light``), and ``device.render`` (the array
  read), in a process of its own as the Rust
  loop is, the pipeline built before the clock starts;
- rust: the library's own loop, ``cargo run --release --example
  render_loop`` (the same scene tables, the same device kept);
- cli: one ``shadelab render`` command per frame, each frame's scene a
  TOML file written beforehand (the commands' whole wall clock).

Python's and Rust's loops run back to back, each first in turn, and the
ratio is the median of each round's own. Then the resident size over
1000 renders through one device. Prints the
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
import os
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


def python_loop(device: shadelab.Device, frames: int, width: int, height: int, way: str) -> Dict[str, float]:
    """The loop's wall and CPU milliseconds (the process's CPU, every
    thread's: the driver's included, as the Rust loop counts it). `way`:
    each frame's scene made from the dict (`table`), or the scene read once
    and its light moved (`light`)."""
    table = shadelab.Scene.default().to_dict()
    base = shadelab.Scene.from_dict(table)
    # The pipeline built before the clock starts, as the Rust loop does.
    device.render(base, "phong", width=width, height=height).array.mean()
    # numpy's OpenBLAS threads spin for about 0.1 s once numpy has loaded
    # (84 ms of CPU over a second of `time.sleep` after `import numpy`, 6 ms
    # with OPENBLAS_NUM_THREADS=1), taking a core from the driver: a cost
    # of starting the interpreter, which the loop is not, so it is let pass.
    time.sleep(0.3)
    started, cpu_started = time.perf_counter(), time.process_time()
    for frame in range(frames):
        if way == "light":
            scene = base.with_light(0, position=light_at(frame, frames))
        else:
            table["lights"][0]["position"] = light_at(frame, frames)
            scene = shadelab.Scene.from_dict(table)
        image = device.render(scene, "phong", width=width, height=height)
        image.array[..., 0].mean()
    return {
        "wall_ms": (time.perf_counter() - started) * 1e3,
        "cpu_ms": (time.process_time() - cpu_started) * 1e3,
    }


def python_loop_alone(frames: int, width: int, height: int, way: str) -> Dict[str, float]:
    """``python_loop`` in a process of its own, as the Rust loop runs: a
    process that has forked (this one, for every command it times) pays
    page faults on its next writes to its memory, which the loop's
    renders are."""
    out = subprocess.run(
        [sys.executable, __file__, "--python-loop", str(frames), str(width), str(height), way],
        check=True,
        capture_output=True,
        text=True,
    )
    return {k: float(v) for k, v in json.loads(out.stdout).items()}


def rust_loop(frames: int, width: int, height: int, way: str) -> Dict[str, float]:
    binary = ROOT / "target" / "release" / "examples" / "render_loop"
    out = subprocess.run([binary, str(frames), str(width), str(height), way], check=True, capture_output=True, text=True)
    figures = json.loads(out.stdout)
    return {"wall_ms": float(figures["wall_ms"]), "cpu_ms": float(figures["cpu_ms"])}


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


def cli_loop(paths: List[Path], width: int, height: int, out: Path) -> Dict[str, float]:
    binary = ROOT / "target" / "release" / "shadelab"
    started = time.perf_counter()
    for path in paths:
        subprocess.run(
            [binary, "render", path, "--shading", "phong", "--width", str(width), "--height", str(height),
             "--out", out / "frame.exr"],
            check=True,
            capture_output=True,
        )
    return {"wall_ms": (time.perf_counter() - started) * 1e3}


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
    # The default scene's own size.
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--memory-renders", type=int, default=1000)
    parser.add_argument("--json", type=Path, help="also write the figures here")
    parser.add_argument("--way", choices=["table", "light"], default="table",
                        help="each frame's scene made from the dict (table), or read once and its light moved (light)")
    parser.add_argument("--python-loop", nargs=4, metavar=("FRAMES", "WIDTH", "HEIGHT", "WAY"),
                        help="(internal) time the Python loop in this process and print it as JSON")
    args = parser.parse_args()
    if args.python_loop:
        frames, width, height = (int(v) for v in args.python_loop[:3])
        print(json.dumps(python_loop(shadelab.Device(), frames, width, height, args.python_loop[3])))
        return 0
    device = shadelab.Device()
    # Pipelines built and the driver's code generated before any timing,
    # for all three (the CLI's come from the same cache folder).
    python_loop(device, 2, args.width, args.height, args.way)
    times: Dict[str, List[float]] = {"python": [], "rust": [], "cli": []}
    cpu: Dict[str, List[float]] = {"python": [], "rust": []}
    with tempfile.TemporaryDirectory() as tmp:
        paths = write_frames(Path(tmp), args.frames)
        cli_loop(paths[:2], args.width, args.height, Path(tmp))
        loops = {
            "python": lambda: python_loop_alone(args.frames, args.width, args.height, args.way),
            "rust": lambda: rust_loop(args.frames, args.width, args.height, args.way),
            "cli": lambda: cli_loop(paths, args.width, args.height, Path(tmp)),
        }
        for r in range(args.rounds):
            # Python and Rust back to back, each first in turn, so that each
            # round's ratio of the two sees one state of this shared,
            # noisy machine; then the commands. The disk is synced before
            # each loop: the commands' images written back would slow
            # whatever came next.
            pair = ["python", "rust"] if r % 2 == 0 else ["rust", "python"]
            for name in pair + ["cli"]:
                os.sync()
                measured = loops[name]()
                times[name].append(measured["wall_ms"])
                if name in cpu:
                    cpu[name].append(measured["cpu_ms"])
    median = {k: statistics.median(v) for k, v in times.items()}
    figures: Dict[str, Any] = {
        "frames": args.frames,
        "way": args.way,
        "size": f"{args.width}x{args.height}",
        "rounds": args.rounds,
        "device": device.name,
        "driver": device.driver,
        "ms": times,
        "median_ms": median,
        "cli_over_python": median["cli"] / median["python"],
        "python_over_rust": median["python"] / median["rust"],
        # Round by round, the two loops back to back: what the target reads.
        "python_over_rust_paired": statistics.median(
            p / r for p, r in zip(times["python"], times["rust"])
        ),
        "cpu_ms": cpu,
        "python_over_rust_cpu": statistics.median(
            p / r for p, r in zip(cpu["python"], cpu["rust"])
        ),
        "memory": memory(device, args.memory_renders),
    }
    print(f"{args.frames} renders, phong {args.width}x{args.height}, moving light ({args.way}), median of {args.rounds} interleaved rounds on {device.name}:")
    for k in ("python", "rust", "cli"):
        spread = ", ".join(f"{t:.0f}" for t in times[k])
        print(f"  {k:6} {median[k]:8.0f} ms  ({spread})")
    print(f"  cli / python     {figures['cli_over_python']:.2f}x  (target: at least 5)")
    paired = [p / r for p, r in zip(times["python"], times["rust"])]
    print(
        f"  python / rust    {figures['python_over_rust_paired']:.3f}x, the median of each round's ratio "
        f"({min(paired):.3f} to {max(paired):.3f}; of the medians: {figures['python_over_rust']:.3f}x)  "
        "(target: at most 1.05)"
    )
    cpu_paired = [p / r for p, r in zip(cpu["python"], cpu["rust"])]
    print(
        f"  python / rust    {figures['python_over_rust_cpu']:.3f}x in CPU time (every thread's), the median of each "
        f"round's ratio ({min(cpu_paired):.3f} to {max(cpu_paired):.3f}; medians {statistics.median(cpu['python']):.0f} "
        f"and {statistics.median(cpu['rust']):.0f} ms)"
    )
    m = figures["memory"]
    print(f"  resident size over {args.memory_renders} renders: {m['before_mib']:.1f} -> {m['after_mib']:.1f} MiB ({100 * m['growth']:+.2f} %; target: within 5 %)")
    if args.json:
        args.json.write_text(json.dumps(figures, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
