#!/usr/bin/env python3
"""Times shadelab's CPU twin of the ray tracer (standard library only), for a shadelab whose
`bench` has no --cpu flag:

    cpu_twin.py SHADELAB RUNS SIZE DEPTH|- [SCENE]

runs `SHADELAB render [SCENE] --backend cpu --shading raytrace --width SIZE --height SIZE
[--depth DEPTH] --stats --json` RUNS times (no warm-up: the CPU path compiles nothing) and
prints one JSON line: {"peer": "shadelab-cpu", median_ms, min_ms, max_ms, runs, rays, device}
from the renders' timings_ms.total_ms (the whole CPU render, BVH build included; the image
file is written after the clock stops, into a temporary folder removed on exit). DEPTH "-"
keeps the scene's own depth; no SCENE means the built-in default scene.
"""
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) not in (5, 6) or not sys.argv[2].isdigit() or not sys.argv[3].isdigit():
        sys.exit("usage: cpu_twin.py SHADELAB RUNS SIZE DEPTH|- [SCENE]")
    # A timeout's SIGTERM ends the render under way too (subprocess.run kills its child on exit).
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    shadelab, runs, size, depth = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    scene = sys.argv[5:]
    times, rays, device = [], None, ""
    with tempfile.TemporaryDirectory(prefix="shadelab-cpu-twin-") as tmp:
        cmd = [shadelab, "render", *scene, "--backend", "cpu", "--shading", "raytrace",
               "--width", size, "--height", size, "--stats", "--json", "--out", os.path.join(tmp, "cpu.png")]
        if depth != "-":
            cmd += ["--depth", depth]
        for _ in range(max(runs, 1)):
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            if p.returncode != 0:
                last = (p.stderr.strip().splitlines() or ["no message"])[-1]
                sys.exit(f"cpu_twin.py: shadelab render --backend cpu failed (exit {p.returncode}): {last}")
            out = json.loads(p.stdout.strip().splitlines()[-1])
            times.append(float(out["timings_ms"]["total_ms"]))
            device = out.get("device", "")
            stats = out.get("stats") or {}
            kinds = [k for k in ("primary", "shadow", "reflected", "refracted") if isinstance(stats.get(k), int)]
            if kinds:
                rays = sum(stats[k] for k in kinds)
    print(json.dumps({"peer": "shadelab-cpu", "device": device, "runs": len(times),
                      "median_ms": round(statistics.median(times), 3), "min_ms": round(min(times), 3),
                      "max_ms": round(max(times), 3), "rays": rays,
                      "timed": "render --backend cpu: timings_ms.total_ms"}))


if __name__ == "__main__":
    main()
