"""A peer's first image in a fresh process, with empty caches and with warm ones: the figure
`shadelab bench --time-to-image` is set against in the report's time-to-image section.

    first_image.py RUNS PEER_SCRIPT ARGS...

Runs `python PEER_SCRIPT ARGS...` (a peer that prints one JSON line with `first_image_ms`:
from the scene's load to its first image in memory, the compilation of its kernels or
pipeline included; the library's and the device's set-up before it left out) as fresh
processes: one to fill a kept cache folder, then RUNS warm runs (that folder as HOME and
XDG_CACHE_HOME) alternated with RUNS cold ones (each a new, empty folder as both). Those two
variables hold both peers' caches: Dr.Jit keeps Mitsuba's compiled kernels in ~/.drjit, and
Mesa keeps lavapipe's code for wgpu's shaders in $XDG_CACHE_HOME/mesa_shader_cache. Prints
one JSON line: the medians of first_image_ms cold and warm, and of each process's wall clock
(Python's start-up and imports included, which is why first_image_ms is the figure
compared).
"""
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from peer_common import emit


def run_once(cmd, home):
    env = dict(os.environ, HOME=home, XDG_CACHE_HOME=os.path.join(home, ".cache"))
    env.pop("MESA_SHADER_CACHE_DIR", None)  # the cache must be the one under `home`
    started = time.perf_counter()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    wall_ms = (time.perf_counter() - started) * 1e3
    if done.returncode != 0:
        sys.exit(f"first_image.py: {' '.join(cmd)} failed (exit {done.returncode}): "
                 f"{(done.stderr.strip().splitlines() or [''])[-1]}")
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if not lines:
        sys.exit(f"first_image.py: {' '.join(cmd)} printed no JSON line")
    out = json.loads(lines[-1])
    if "first_image_ms" not in out:
        sys.exit(f"first_image.py: {' '.join(cmd)} reports no first_image_ms")
    return out, wall_ms


def main():
    if len(sys.argv) < 3 or not sys.argv[1].isdigit() or int(sys.argv[1]) < 1:
        sys.exit("usage: first_image.py RUNS PEER_SCRIPT ARGS...")
    runs = int(sys.argv[1])
    cmd = [sys.executable] + sys.argv[2:]
    kept = tempfile.mkdtemp(prefix="first-image-warm.")
    first = {"cold": [], "warm": []}
    wall = {"cold": [], "warm": []}
    try:
        peer, _ = run_once(cmd, kept)  # fills the kept caches
        for _ in range(runs):
            for kind in ("cold", "warm"):
                home = tempfile.mkdtemp(prefix="first-image-cold.") if kind == "cold" else kept
                try:
                    out, ms = run_once(cmd, home)
                finally:
                    if kind == "cold":
                        shutil.rmtree(home, ignore_errors=True)
                first[kind].append(out["first_image_ms"])
                wall[kind].append(ms)
    finally:
        shutil.rmtree(kept, ignore_errors=True)
    med = statistics.median
    # The peer's own identification (name, version, device) for the report's header.
    ident = {k: peer[k] for k in ("peer", "variant", "mitsuba", "wgpu", "device", "width", "height")
             if k in peer}
    emit(dict(ident, runs=runs,
              cold_image_ms=round(med(first["cold"]), 3), warm_image_ms=round(med(first["warm"]), 3),
              cold_process_ms=round(med(wall["cold"]), 3), warm_process_ms=round(med(wall["warm"]), 3),
              cold_image_all_ms=[round(v, 3) for v in first["cold"]],
              warm_image_all_ms=[round(v, 3) for v in first["warm"]]))


if __name__ == "__main__":
    main()
