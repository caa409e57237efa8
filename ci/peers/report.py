#!/usr/bin/env python3
"""Builds the peer benchmark's report from a results folder (standard library only).

    report.py RESULTS... --size N --runs N --segs 100,316 [--smoke] [--bench-cpu]
              [--json-out FILE] [--md-out FILE]

RESULTS holds jobs.tsv (name, kind, status, rc, seconds per job, as ci/bench-peers.sh ran them)
and NAME.json, the last line of which is the job's JSON: `shadelab bench --json` for the
shadelab side, one line per peer program otherwise. Several RESULTS folders are rounds of the
same jobs (ci/bench-peers.sh --rounds): each row's ratio is then the median of the rounds'
ratios, each measured with the two sides run back to back, and the table gives their range.
Prints a Markdown table on stdout, writes it to --md-out and the same as JSON to --json-out.
Every ratio reads ">1: shadelab ahead": peer time / shadelab time, or shadelab rate / peer
rate; in the CPU-twin rows the "peer" is shadelab's own CPU path, so >1 there means the GPU
path is ahead. Exit status: 0 when the report was built (failed jobs show as such in it), 1
when it could not be.
"""
import argparse
import datetime
import json
import os
import re
import statistics
import sys

# What the figures mean, printed under the table and kept in the JSON.
NOTES = [
    "Ratios are measured in this run: peer time / shadelab time, or shadelab rate / peer rate, "
    "so >1 means shadelab is ahead. In the CPU-twin rows the 'peer' is shadelab's own CPU "
    "path: >1 means the GPU path is faster.",
    "shadelab figures are `shadelab bench` medians. Compared: `gpu_ms`, the wall time from "
    "queue submission to the fence (for the raster modes this includes copying the image into "
    "host-visible memory; for the ray tracer the image is written to host-visible memory "
    "directly); it excludes pipeline creation, BVH building and uploads. `total_ms`, the whole "
    "render with pipeline creation, is in the JSON. The raster modes are timed on the path of "
    "`render --out x.png`, into an 8-bit sRGB target (the wgpu peer's is rgba8).",
    "wgpu peers: submit + work + read-back per frame, pipeline creation and uploads excluded, "
    "so they match `gpu_ms` plus mapping the image. Embree: tracing only (BVH build apart), "
    "rays / median time. shadelab Mrays/s: bench's rays_per_second (counted rays / gpu_ms).",
    "Mitsuba: mi.render() plus conversion to an array (kernel compilation is in the warm-up "
    "run, not the median); Mrays/s ~ (pixels + hits) / time, its shadow-ray count assumed.",
    "CPU twin: `bench --cpu`'s cpu_ms where shadelab has it, else `shadelab render --backend "
    "cpu` total_ms (the whole CPU render, BVH build included).",
    "Time to image: shadelab's figure is the whole `render` command as a fresh process "
    "(device, scene, pipeline, code generation, trace, PNG); 'empty caches' means new, empty "
    "Mesa and shadelab cache folders. A peer's first image (ci/peers/first_image.py) is "
    "measured inside its fresh process, from the scene's load (Mitsuba, BVH included) or its "
    "buffers (wgpu) to the image in memory, kernel or pipeline compilation included, with new, "
    "empty Dr.Jit and Mesa caches for 'empty caches'; the library's import and the device's "
    "set-up are left out, so these rows favour the peer.",
    "Rays are each renderer's own count (in the JSON: peer_rays, shadelab_rays): Embree and "
    "Mitsuba cast a shadow ray from every hit, shadelab may cast fewer (none where the surface "
    "faces away from the light), so its Mrays/s is over slightly less work.",
]


def human_count(n):
    if n >= 1_000_000:
        return f"{n / 1e6:.1f}M"
    if n >= 10_000:
        return f"{round(n / 1000)}k"
    return f"{n:,}"


def fmt_num(v):
    return f"{v:.1f}" if v >= 10 else f"{v:.2f}"


def fmt_ms(v):
    return "-" if v is None else f"{fmt_num(v)} ms"


def fmt_range(d):
    """A peer's median (min to max)."""
    med, lo, hi = d.get("median_ms"), d.get("min_ms"), d.get("max_ms")
    if lo is None or hi is None:
        return fmt_ms(med)
    return f"{fmt_ms(med)} ({fmt_num(lo)} to {fmt_num(hi)})"


def num(v):
    return v if isinstance(v, (int, float)) and not isinstance(v, bool) else None


class Results:
    def __init__(self, folder):
        self.folder = folder
        self.jobs = {}
        path = os.path.join(folder, "jobs.tsv")
        if not os.path.isfile(path):
            raise SystemExit(f"report.py: no {path}: nothing was run")
        with open(path) as f:
            for i, line in enumerate(f):
                cols = line.rstrip("\n").split("\t")
                if i == 0 or len(cols) < 5:
                    continue
                self.jobs[cols[0]] = {"name": cols[0], "kind": cols[1], "status": cols[2],
                                      "rc": cols[3], "seconds": cols[4]}
        self.data = {}
        for name, job in self.jobs.items():
            if job["status"] != "ok":
                continue
            try:
                with open(os.path.join(folder, name + ".json")) as f:
                    lines = [l for l in f.read().splitlines() if l.strip()]
                self.data[name] = json.loads(lines[-1])
            except (OSError, IndexError, ValueError) as e:
                job["status"] = "bad output"
                job["error"] = str(e)

    def ran(self, name):
        return name in self.jobs

    def get(self, name):
        return self.data.get(name)

    def why(self, name, smoke):
        """Why a job has no figure, for the table."""
        job = self.jobs.get(name)
        if job is None:
            return "not run (--smoke)" if smoke else "not run"
        if job["status"] == "unavailable":
            return "unavailable (install failed)"
        if job["status"] == "ok":
            return f"no figure in its output (results/{name}.json)"
        return f"{job['status']} (results/{name}.log)"


def bench_row(bench, shading):
    """One mode's result in a `shadelab bench --json` object."""
    if not bench:
        return None
    for r in bench.get("results", []):
        if r.get("shading") == shading:
            return r
    return None


class Report:
    def __init__(self, res, args):
        self.res, self.args, self.rows = res, args, []

    def add(self, section, work, peer, peer_fig, sl_fig, ratio, peer_job, sl_job, **extra):
        self.rows.append(dict(section=section, work=work, peer=peer, peer_figure=peer_fig,
                              shadelab_figure=sl_fig, ratio=None if ratio is None else round(ratio, 3),
                              peer_job=peer_job, shadelab_job=sl_job, **extra))

    def missing(self, name):
        return self.res.why(name, self.args.smoke)

    def cpu_twin(self, sl_job, cpu_job, shading="raytrace"):
        """(cpu_ms, source) from bench --cpu's cpu_ms, else the fallback job's median."""
        r = bench_row(self.res.get(sl_job), shading)
        if r and num(r.get("cpu_ms")) is not None:
            return r["cpu_ms"], "bench --cpu", sl_job
        d = self.res.get(cpu_job)
        if d and num(d.get("median_ms")) is not None:
            return d["median_ms"], "render --backend cpu", cpu_job
        return None, self.missing(cpu_job) if self.res.ran(cpu_job) else "not run", cpu_job

    def rays(self, seg):
        size, smoke = self.args.size, self.args.smoke
        tris = 4 * seg * seg
        work = f"{human_count(tris)}-triangle sphere, primary + shadow rays (depth 0), {size}x{size}"
        sl_job = f"rays-sphere{seg}.shadelab"
        sl = bench_row(self.res.get(sl_job), "raytrace")
        if sl is None and not any(self.res.ran(f"rays-sphere{seg}.{p}") for p in
                                  ("shadelab", "embree", "mitsuba-llvm", "mitsuba-scalar", "cpu")):
            return
        sl_rate = num(sl.get("rays_per_second")) if sl else None
        sl_gpu = num(sl.get("gpu_ms")) if sl else None
        sl_rays = num(sl.get("rays")) if sl else None
        sl_rate_fig = f"{sl_rate / 1e6:.2f} Mrays/s (GPU)" if sl_rate else self.missing(sl_job)
        section = "Ray casting: the peers' UV sphere"
        # Embree (Mrays/s)
        e_job = f"rays-sphere{seg}.embree"
        e = self.res.get(e_job)
        if not (self.res.ran(e_job) or self.res.ran(sl_job)):
            pass  # neither side selected (--only)
        elif e:
            peer = f"Embree {e.get('version', '3')}, 8-wide packets, {e.get('threads')} threads (CPU)"
            ratio = sl_rate / 1e6 / e["mrays_per_s"] if sl_rate and e.get("mrays_per_s") else None
            self.add(section, work, peer, f"{e['mrays_per_s']:.1f} Mrays/s", sl_rate_fig, ratio, e_job, sl_job,
                     unit="Mrays/s", peer_value=e["mrays_per_s"], shadelab_value=sl_rate and sl_rate / 1e6,
                     peer_rays=e.get("rays"), shadelab_rays=sl_rays)
        else:
            self.add(section, work, "Embree 3 (CPU)", self.missing(e_job), sl_rate_fig, None, e_job, sl_job,
                     unit="Mrays/s", shadelab_value=sl_rate and sl_rate / 1e6)
        # shadelab's CPU twin against Embree: CPU against CPU
        cpu_ms, source, cpu_job = self.cpu_twin(sl_job, f"rays-sphere{seg}.cpu")
        cpu_rays = (self.res.get(cpu_job) or {}).get("rays") if source == "render --backend cpu" else None
        cpu_rays = num(cpu_rays) or sl_rays
        if cpu_ms and cpu_rays:
            cpu_rate = cpu_rays / (cpu_ms / 1e3) / 1e6
            if e:
                self.add(section, work, f"Embree {e.get('version', '3')} (CPU) against shadelab's CPU twin",
                         f"{e['mrays_per_s']:.1f} Mrays/s",
                         f"{cpu_rate:.2f} Mrays/s (CPU twin, {source})", cpu_rate / e["mrays_per_s"], e_job, cpu_job,
                         unit="Mrays/s", peer_value=e["mrays_per_s"], shadelab_value=cpu_rate)
        # Mitsuba (ms, and approximate Mrays/s)
        for variant, key in (("llvm_ad_rgb", "mitsuba-llvm"), ("scalar_rgb", "mitsuba-scalar")):
            m_job = f"rays-sphere{seg}.{key}"
            m = self.res.get(m_job)
            if not self.res.ran(m_job) and (variant == "scalar_rgb" or not self.res.ran(sl_job)):
                continue  # optional (--all), or neither side selected (--only)
            sl_fig = (f"{fmt_ms(sl_gpu)} gpu_ms (~{sl_rate / 1e6:.2f} Mrays/s)" if sl_gpu and sl_rate
                      else fmt_ms(sl_gpu) if sl_gpu else self.missing(sl_job))
            if m:
                peer = f"Mitsuba {m.get('mitsuba', '3')} {variant}, direct, 1 spp (CPU)"
                fig = f"{fmt_range(m)} (~{m.get('mrays_per_s', 0):.1f} Mrays/s)"
                ratio = m["median_ms"] / sl_gpu if sl_gpu else None
                self.add(section, work, peer, fig, sl_fig, ratio, m_job, sl_job, unit="ms",
                         peer_value=m["median_ms"], shadelab_value=sl_gpu, peer_first_ms=m.get("first_ms"))
            else:
                self.add(section, work, f"Mitsuba 3 {variant} (CPU)", self.missing(m_job), sl_fig, None,
                         m_job, sl_job, unit="ms", shadelab_value=sl_gpu)

    def query_engine(self):
        """The ray-query engine (`--traversal query`) on the jobs that ran it: against
        the peer of the same work, and against shadelab's own compute BVH."""
        size = self.args.size
        works = [(f"rays-sphere{seg}", f"{human_count(4 * seg * seg)}-triangle sphere, primary + shadow rays "
                  f"(depth 0), {size}x{size}") for seg in self.args.segs]
        works.append(("rt-four-spheres", f"4 spheres + plane, shadows, mirror to depth 2, {size}x{size}"))
        section = "Ray tracer: the ray-query engine (--traversal query)"
        for prefix, work in works:
            q_job, b_job = f"{prefix}.shadelab-query", f"{prefix}.shadelab"
            if not self.res.ran(q_job):
                continue
            q = bench_row(self.res.get(q_job), "raytrace")
            b = bench_row(self.res.get(b_job), "raytrace")
            q_gpu = num(q.get("gpu_ms")) if q else None
            b_gpu = num(b.get("gpu_ms")) if b else None
            q_fig = f"{fmt_ms(q_gpu)} gpu_ms (query)" if q_gpu else self.missing(q_job)
            b_fig = f"{fmt_ms(b_gpu)} gpu_ms (bvh)" if b_gpu else self.missing(b_job)
            self.add(section, work, "shadelab's compute BVH (--traversal bvh)", b_fig, q_fig,
                     b_gpu / q_gpu if b_gpu and q_gpu else None, b_job, q_job, unit="ms",
                     peer_value=b_gpu, shadelab_value=q_gpu)
            if prefix.startswith("rays-sphere"):
                e_job = prefix + ".embree"
                e = self.res.get(e_job)
                rate = num(q.get("rays_per_second")) if q else None
                if e and rate:
                    self.add(section, work, f"Embree {e.get('version', '3')}, 8-wide packets (CPU)",
                             f"{e['mrays_per_s']:.1f} Mrays/s", f"{rate / 1e6:.2f} Mrays/s (query)",
                             rate / 1e6 / e["mrays_per_s"], e_job, q_job, unit="Mrays/s",
                             peer_value=e["mrays_per_s"], shadelab_value=rate / 1e6)
            else:
                p_job = prefix + ".wgpu"
                p = self.res.get(p_job)
                if p and q_gpu:
                    self.add(section, work, "wgpu compute tracer, brute force", fmt_range(p), q_fig,
                             p["median_ms"] / q_gpu, p_job, q_job, unit="ms",
                             peer_value=p["median_ms"], shadelab_value=q_gpu)

    def four_spheres(self):
        size = self.args.size
        sl_job, p_job = "rt-four-spheres.shadelab", "rt-four-spheres.wgpu"
        if not (self.res.ran(sl_job) or self.res.ran(p_job)):
            return
        sl = bench_row(self.res.get(sl_job), "raytrace")
        p = self.res.get(p_job)
        sl_gpu = num(sl.get("gpu_ms")) if sl else None
        work = f"4 spheres + plane, shadows, mirror to depth 2, {size}x{size}"
        peer = (f"wgpu {p.get('wgpu', '')} compute tracer, brute force, no BVH (GPU: {p.get('device', '?')})"
                if p else "wgpu compute tracer")
        self.add("Ray tracing: a small analytic scene", work, peer, fmt_range(p) if p else self.missing(p_job),
                 f"{fmt_ms(sl_gpu)} gpu_ms" if sl_gpu else self.missing(sl_job),
                 p["median_ms"] / sl_gpu if p and sl_gpu else None, p_job, sl_job, unit="ms",
                 peer_value=p and p["median_ms"], shadelab_value=sl_gpu,
                 shadelab_total_ms=sl and sl.get("total_ms"))

    def twins(self):
        names = []
        for name in self.res.jobs:
            m = re.match(r"twin-(.+)\.(shadelab|cpu)$", name)
            if m and m.group(1) not in names:
                names.append(m.group(1))
        for seg in self.args.segs:  # the depth-0 sphere runs give a twin row each too
            sl_job = f"rays-sphere{seg}.shadelab"
            if self.res.ran(sl_job):
                cpu_ms, source, cpu_job = self.cpu_twin(sl_job, f"rays-sphere{seg}.cpu")
                self.twin_row(f"{human_count(4 * seg * seg)}-triangle sphere, depth 0", sl_job, cpu_ms, source, cpu_job)
        for n in names:
            sl_job = f"twin-{n}.shadelab"
            cpu_ms, source, cpu_job = self.cpu_twin(sl_job, f"twin-{n}.cpu")
            label = {"default": "built-in default scene", "bench-mesh": "bench mesh (ci/make-bench-mesh.py)"}.get(
                n, f"assets/{n}.toml")
            self.twin_row(f"{label}, its own depth", sl_job, cpu_ms, source, cpu_job)

    def twin_row(self, what, sl_job, cpu_ms, source, cpu_job):
        size = self.args.size
        sl = bench_row(self.res.get(sl_job), "raytrace")
        gpu = num(sl.get("gpu_ms")) if sl else None
        total = num(sl.get("total_ms")) if sl else None
        sl_fig = f"{fmt_ms(gpu)} gpu_ms ({fmt_ms(total)} total)" if gpu else self.missing(sl_job)
        peer_fig = f"{fmt_ms(cpu_ms)} ({source})" if cpu_ms else source
        self.add("Ray tracer: GPU against shadelab's own CPU twin", f"{what}, {size}x{size}",
                 "shadelab CPU twin (same work)", peer_fig, sl_fig, cpu_ms / gpu if cpu_ms and gpu else None,
                 cpu_job, sl_job, unit="ms", peer_value=cpu_ms, shadelab_value=gpu, shadelab_total_ms=total,
                 ratio_by_total=round(cpu_ms / total, 3) if cpu_ms and total else None)

    def specialisation(self):
        """What specialising the tracer to the scene saves: `bench --every-feature`
        (every optional feature compiled in, as an uber-shader would) in the jobs
        that ran with it."""
        size = self.args.size
        for sl_job, what in (("twin-default.shadelab", "built-in default scene"),
                             ("rt-four-spheres.shadelab", "4 spheres + plane, mirror to depth 2")):
            r = bench_row(self.res.get(sl_job), "raytrace")
            if not r or num(r.get("every_feature_gpu_ms")) is None:
                continue
            gpu, uber = num(r.get("gpu_ms")), r["every_feature_gpu_ms"]
            self.add("Ray tracer: specialised to the scene against every feature compiled in",
                     f"{what}, {size}x{size}", "shadelab with every optional feature compiled in (uber-shader)",
                     f"{fmt_ms(uber)} gpu_ms", f"{fmt_ms(gpu)} gpu_ms", uber / gpu if gpu else None,
                     sl_job, sl_job, unit="ms", peer_value=uber, shadelab_value=gpu)

    def raster(self, seg, samples=1):
        def target_note(r):
            # shadelab names the colour target it timed (rgba8-srgb: the PNG path); older
            # binaries rendered into rgba32f and did not say.
            return f"{r['color_target']} target, " if r.get("color_target") else ""

        size = self.args.size
        suffix = f"-msaa{samples}" if samples > 1 else ""
        sl_job, p_job = f"raster-sphere{seg}{suffix}.shadelab", f"raster-sphere{seg}{suffix}.wgpu"
        section = ("Raster: the peers' UV sphere" if samples == 1
                   else f"Raster: the peers' UV sphere, {samples} samples per pixel (MSAA)")
        if not (self.res.ran(sl_job) or self.res.ran(p_job)):
            return
        bench = self.res.get(sl_job)
        p = self.res.get(p_job)
        tris = human_count(4 * seg * seg)
        for sl_mode, p_mode, what in (("phong", "phong", "Phong per pixel"), ("gouraud", "gouraud", "Gouraud"),
                                      ("flat", "constant", "flat (peer: constant colour, the driver's floor)")):
            r = bench_row(bench, sl_mode)
            gpu = num(r.get("gpu_ms")) if r else None
            pm = (p or {}).get("modes", {}).get(p_mode)
            peer = (f"wgpu {p.get('wgpu', '')} {p_mode} (GPU: {p.get('device', '?')})" if p
                    else f"wgpu {p_mode}")
            work = f"{tris}-triangle sphere, {what}, {size}x{size}" + (f", {samples} samples per pixel" if samples > 1 else "")
            self.add(section, work, peer,
                     fmt_range(pm) if pm else self.missing(p_job),
                     (f"{fmt_ms(gpu)} gpu_ms ({target_note(r)}{fmt_ms(r.get('total_ms'))} total)" if gpu
                      else self.missing(sl_job)),
                     pm["median_ms"] / gpu if pm and gpu else None, p_job, sl_job, unit="ms",
                     peer_value=pm and pm["median_ms"], shadelab_value=gpu,
                     shadelab_total_ms=r and r.get("total_ms"), shadelab_mode=sl_mode, peer_mode=p_mode)

    def time_to_image(self):
        """The whole `shadelab render` command (`bench --time-to-image`): warm and cold
        against the CPU twin's command, and cold against warm."""
        section = "Time to image: the whole `shadelab render` command, fresh processes"
        for name in sorted(self.res.jobs):
            m = re.match(r"image-(.+)\.shadelab$", name)
            bench = self.res.get(name)
            if not m:
                continue
            if not bench:
                self.add(section, f"{m.group(1)}: time to image", "-", "-", self.missing(name), None,
                         name, name)
                continue
            scene = "built-in default scene" if m.group(1) == "default" else bench.get("scene", m.group(1))
            size = f"{bench.get('width')}x{bench.get('height')}"
            for r in bench.get("results", []):
                t = r.get("time_to_image") or {}
                warm, cold, cpu = num(t.get("warm_ms")), num(t.get("cold_ms")), num(t.get("cpu_ms"))
                work = f"{scene}, {r.get('shading')}, {size}"
                twin = "shadelab CPU twin's command (--backend cpu)"
                for label, value in (("warm caches", warm), ("empty caches", cold)):
                    self.add(section, f"{work}, GPU with {label}", twin, fmt_ms(cpu),
                             fmt_ms(value), cpu / value if cpu and value else None, name, name,
                             unit="ms", peer_value=cpu, shadelab_value=value)
                self.add(section, f"{work}, GPU with empty caches", "the same command, warm caches",
                         fmt_ms(warm), fmt_ms(cold), warm / cold if warm and cold else None,
                         name, name, unit="ms", peer_value=warm, shadelab_value=cold)
                self.first_image_peers(section, m.group(1), work, name, warm, cold)

    # The peers whose first image in a fresh process (first_image.py) is set against the
    # whole command: job suffix and how the row names them.
    FIRST_IMAGE_PEERS = (("mitsuba-llvm", "Mitsuba 3 llvm_ad_rgb (CPU)"),
                         ("wgpu", "wgpu compute tracer (lavapipe)"))

    def first_image_peers(self, section, scene, work, sl_job, warm, cold):
        """The peers' first image against the whole command, cold against cold and warm
        against warm. The peer's figure is in-process (scene load to image, its kernels'
        or pipeline's compilation included; library and device set-up left out), the
        command's is the whole process: the comparison favours the peer."""
        for suffix, peer in self.FIRST_IMAGE_PEERS:
            job = f"image-{scene}.{suffix}"
            if not self.res.ran(job):
                continue
            p = self.res.get(job) or {}
            for label, key, value in (("empty caches", "cold_image_ms", cold),
                                      ("warm caches", "warm_image_ms", warm)):
                pv = num(p.get(key))
                self.add(section, f"{work}, GPU with {label}",
                         f"{peer}: first image in a fresh process, {label}",
                         fmt_ms(pv) if pv else self.missing(job), fmt_ms(value),
                         pv / value if pv and value else None, job, sl_job, unit="ms",
                         peer_value=pv, shadelab_value=value)

    def build(self):
        self.time_to_image()
        for seg in self.args.segs:
            self.rays(seg)
        self.four_spheres()
        self.query_engine()
        self.twins()
        self.specialisation()
        for seg in self.args.segs:
            self.raster(seg)
        for seg in self.args.segs:
            self.raster(seg, 4)


def row_key(row, seen):
    """A row's identity across rounds: its section, work and jobs, and which of the rows with
    those it is (some pairs of jobs give more than one row)."""
    base = (row["section"], row["work"], row["peer_job"], row["shadelab_job"])
    seen[base] = seen.get(base, 0) + 1
    return base + (seen[base],)


def merge_rounds(round_rows):
    """One row for each row some round gave, in the order first given. The ratio is the
    median over the rounds that gave one (each round measured both sides back to back, so
    drift on the machine between rounds cancels in each round's ratio), with the rounds'
    range; the figures are those of the round whose ratio is nearest that median."""
    keyed, order = {}, []
    for rows in round_rows:
        seen = {}
        for row in rows:
            key = row_key(row, seen)
            if key not in keyed:
                keyed[key] = []
                order.append(key)
            keyed[key].append(row)
    merged = []
    for key in order:
        rows = keyed[key]
        ratios = [r["ratio"] for r in rows if r["ratio"] is not None]
        if not ratios:
            merged.append(dict(rows[0], ratio_rounds=[]))
            continue
        median = statistics.median(ratios)
        nearest = min((r for r in rows if r["ratio"] is not None), key=lambda r: abs(r["ratio"] - median))
        merged.append(dict(nearest, ratio=round(median, 3), ratio_rounds=[r["ratio"] for r in rows],
                           ratio_min=min(ratios), ratio_max=max(ratios)))
    return merged


def fmt_ratio(v):
    return f"{v:.2f}" if v >= 0.1 else f"{v:.2g}"


def machine():
    cpu, cores = "unknown CPU", os.cpu_count() or 0
    try:
        with open("/proc/cpuinfo") as f:
            text = f.read()
        m = re.search(r"^model name\s*:\s*(.+)$", text, re.M)
        if m:
            cpu = m.group(1).strip()
        cores = len(re.findall(r"^processor\s*:", text, re.M)) or cores
    except OSError:
        pass
    try:
        usable = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        usable = cores
    return {"cpu": cpu, "cores": cores, "usable_cores": usable}


def vulkan(res):
    """The Vulkan device and driver: bench's `driver`/`device` fields, else `shadelab info --json`."""
    device = driver = None
    for name, d in res.data.items():
        if name.endswith(".shadelab") and isinstance(d, dict):
            device = device or d.get("device")
            driver = driver or d.get("driver")
    info = res.get("info")
    if info:
        devs = info.get("devices") or []
        sel = info.get("selected")
        chosen = next((x for x in devs if isinstance(x, dict) and x.get("index") == sel), None)
        chosen = chosen or (devs[0] if devs and isinstance(devs[0], dict) else {})
        device = device or chosen.get("name")
        driver = driver or chosen.get("driver")
        if chosen.get("api_version") and driver and "Vulkan" not in driver:
            driver = f"{driver}, Vulkan {chosen['api_version']}"
    return device or "unknown device", driver or "unknown driver"


def peer_versions(res):
    seen = []
    for d in res.data.values():
        p = d.get("peer") if isinstance(d, dict) else None
        v = {"embree": lambda: f"Embree {d.get('version')}", "mitsuba": lambda: f"Mitsuba {d.get('mitsuba')}",
             "wgpu-rt": lambda: f"wgpu {d.get('wgpu')} on {d.get('device')}",
             "wgpu-raster": lambda: f"wgpu {d.get('wgpu')} on {d.get('device')}"}.get(p)
        if v and v() not in seen:
            seen.append(v())
    return seen


def cell(s):
    return str(s).replace("|", "\\|")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", nargs="+", help="one results folder per round")
    ap.add_argument("--size", type=int, required=True)
    ap.add_argument("--runs", type=int, required=True)
    ap.add_argument("--segs", required=True, help="comma-separated sphere SEG values")
    ap.add_argument("--smoke", action="store_true")
    ap.add_argument("--bench-cpu", action="store_true", help="shadelab bench had --cpu")
    ap.add_argument("--shadelab", default="", help="the binary measured, for the header")
    ap.add_argument("--json-out")
    ap.add_argument("--md-out")
    args = ap.parse_args()
    try:
        args.segs = [int(s) for s in args.segs.split(",") if s]
    except ValueError:
        ap.error(f"--segs {args.segs!r}: expected integers")
    rounds = [Results(folder) for folder in args.results]
    reports = []
    for res in rounds:
        rep = Report(res, args)
        rep.build()
        reports.append(rep)
    res = rounds[0]
    rows = reports[0].rows if len(rounds) == 1 else merge_rounds([rep.rows for rep in reports])
    device, driver = vulkan(res)
    mach = machine()
    when = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
    header = (f"shadelab peer benchmark{' (smoke: shadelab side only)' if args.smoke else ''}, "
              f"{args.size}x{args.size}, median of {args.runs} timed run(s) after warm-up"
              + (f"; {len(rounds)} rounds, each ratio the median of the rounds' (their range in "
                 f"brackets), the figures from the round nearest it" if len(rounds) > 1 else "")
              + f", {when}. "
              f"Machine: {mach['cpu']}, {mach['cores']} cores. Vulkan: {device}, {driver}."
              + (f" shadelab: {args.shadelab}." if args.shadelab else ""))
    peers = peer_versions(res)
    lines = [header, ""]
    if peers:
        lines += ["Peers: " + "; ".join(peers) + ".", ""]
    lines += ["| work | peer | peer figure | shadelab figure | ratio (>1: shadelab ahead) |",
              "| --- | --- | --- | --- | --- |"]
    for r in rows:
        ratio = "-" if r["ratio"] is None else fmt_ratio(r["ratio"])
        if r.get("ratio_min") is not None and len(r["ratio_rounds"]) > 1:
            ratio += f" ({fmt_ratio(r['ratio_min'])} to {fmt_ratio(r['ratio_max'])})"
        lines.append("| " + " | ".join(cell(x) for x in (r["work"], r["peer"], r["peer_figure"],
                                                         r["shadelab_figure"], ratio)) + " |")
    jobs = [dict(j, round=i + 1) if len(rounds) > 1 else j for i, r in enumerate(rounds) for j in r.jobs.values()]
    bad = [j for j in jobs if j["status"] != "ok"]
    lines.append("")
    lines += [f"- {n}" for n in NOTES]
    if bad:
        lines += ["", "Jobs without a figure: " + ", ".join(
            f"{j['name']} ({j['status']}{', round ' + str(j['round']) if 'round' in j else ''})" for j in bad) + "."]
    md = "\n".join(lines) + "\n"
    sys.stdout.write(md)
    if args.md_out:
        with open(args.md_out, "w") as f:
            f.write(md)
    if args.json_out:
        doc = {"header": header, "generated": when, "machine": mach, "vulkan_device": device,
               "shadelab": args.shadelab,
               "vulkan_driver": driver, "size": args.size, "runs": args.runs, "rounds": len(rounds),
               "smoke": args.smoke,
               "bench_has_cpu_flag": args.bench_cpu, "peers": peers,
               "ratio_meaning": ">1: shadelab ahead (peer time / shadelab time, or shadelab rate / peer rate); "
                                "CPU-twin rows: >1: the GPU path is ahead of the CPU twin",
               "notes": NOTES, "rows": rows, "jobs": jobs,
               "raw": res.data if len(rounds) == 1 else [r.data for r in rounds]}
        os.makedirs(os.path.dirname(os.path.abspath(args.json_out)), exist_ok=True)
        with open(args.json_out, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")
    if not rows:
        print("report.py: no rows: no job gave a result", file=sys.stderr)
        return 1
    # A shadelab command that succeeded but whose output lacks a figure: its JSON changed shape.
    drift = sorted({job for res, rep in zip(rounds, reports) for r in rep.rows
                    for job, value in ((r["shadelab_job"], r.get("shadelab_value")),
                                       (r["peer_job"], r.get("peer_value")))
                    if value is None and res.jobs.get(job, {}).get("kind") == "shadelab"
                    and res.jobs[job]["status"] == "ok"})
    if drift:
        print(f"report.py: no figure found in the output of {', '.join(drift)}: has the JSON changed?",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
