"""shadelab's two estimators of secondary illumination against Mitsuba 3's, on the diffuse
box (assets/diffuse-box.toml at 80 x 60, two bounces): backward (`--shading raytrace
--bounces 2`, samples per pixel) against Mitsuba's `path`, forward (`--shading forward
--bounces 2`, photons) against Mitsuba's `ptracer` (llvm_ad_rgb, through mitsuba_box.py).

    estimators_vs_mitsuba.py SHADELAB_BIN WORK_DIR

1. Agreement: each renderer's most converged image against the reference, the mean of
   Mitsuba's path and ptracer at 2048 samples a pixel (an independent renderer's answer):
   the image mean and the four quarters' means, relative.
2. Time to error: each estimator at three sample or photon counts, its warm render's time
   (shadelab: the GPU's submission to completion, `phases_ms.render_ms` of a second run;
   Mitsuba: a timed render after a warm-up) against its RMSE to the reference, the
   reference's own noise taken out; the log-log line through them gives each one's time to
   RMSE 0.05 and 0.1, and the ratios the issue asks for: forward / ptracer, backward / path.
Prints a Markdown table and writes WORK_DIR/estimators.json.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
if len(sys.argv) != 3:
    sys.exit("usage: estimators_vs_mitsuba.py SHADELAB_BIN WORK_DIR")
BIN, WORK = sys.argv[1], os.path.abspath(sys.argv[2])
os.makedirs(WORK, exist_ok=True)
BOUNCES = 2
TARGETS = (0.1, 0.05)


def box_scene():
    """assets/diffuse-box.toml at 80 x 60."""
    text = open(os.path.join(REPO, "assets/diffuse-box.toml")).read()
    text = text.replace("width  = 160", "width  = 80").replace("height = 120", "height = 60")
    path = os.path.join(WORK, "box80.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def read_exr(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32)
    return np.array(bitmap, dtype=np.float64)


def mitsuba(integrator, spp, scene):
    out = os.path.join(WORK, f"mitsuba-{integrator}-{spp}.exr")
    line = subprocess.run([sys.executable, os.path.join(HERE, "mitsuba_box.py"), "llvm_ad_rgb", integrator,
                           scene, str(BOUNCES), str(spp), out],
                          check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1]
    return read_exr(out), json.loads(line)["ms"]


def shadelab(mode, count, scene):
    out = os.path.join(WORK, f"shadelab-{mode}-{count}.exr")
    flag = ["--samples", str(count)] if mode == "raytrace" else ["--photons", str(count)]
    args = [BIN, "render", scene, "--shading", mode, "--bounces", str(BOUNCES), *flag, "--out", out, "--json", "-q"]
    ms = None
    for _ in range(2):  # the second run is warm: its pipeline and code built
        done = subprocess.run(args, check=True, capture_output=True, text=True)
        ms = json.loads(done.stdout)["phases_ms"]["render_ms"]
    return read_exr(out), ms


def quarters(image):
    h, w = image.shape[:2]
    return [image[y * h // 2:(y + 1) * h // 2, x * w // 2:(x + 1) * w // 2].mean() for y in (0, 1) for x in (0, 1)]


def rmse(a, b):
    return float(np.sqrt(((a - b) ** 2).mean()))


def time_at(points, target):
    """The time the log-log line through (ms, rmse) points gives for `target`."""
    xs = np.log([p[0] for p in points])
    ys = np.log([p[1] for p in points])
    slope, intercept = np.polyfit(xs, ys, 1)
    return float(math.exp((math.log(target) - intercept) / slope)), float(slope)


def main():
    scene = box_scene()
    path_ref, _ = mitsuba("path", 2048, scene)
    pt_ref, _ = mitsuba("ptracer", 2048, scene)
    reference = (path_ref + pt_ref) / 2
    # The reference's own RMSE: half the two's distance (independent, equal noise).
    ref_noise = rmse(path_ref, pt_ref) / 2
    series = {
        "backward (shadelab raytrace)": [shadelab("raytrace", n, scene) for n in (16, 64, 256)],
        "path (Mitsuba)": [mitsuba("path", n, scene) for n in (16, 64, 256)],
        "forward (shadelab forward)": [shadelab("forward", n, scene) for n in (1 << 18, 1 << 20, 1 << 22)],
        "ptracer (Mitsuba)": [mitsuba("ptracer", n, scene) for n in (16, 64, 256)],
    }
    report = {"reference_noise_rmse": ref_noise, "estimators": {}}
    for name, runs in series.items():
        best = runs[-1][0]
        mean = (best.mean() - reference.mean()) / reference.mean()
        quarter = [a / b - 1 for a, b in zip(quarters(best), quarters(reference))]
        points = [(ms, math.sqrt(max(rmse(img, reference) ** 2 - ref_noise ** 2, 1e-12))) for img, ms in runs]
        times = {}
        slope = None
        for target in TARGETS:
            times[str(target)], slope = time_at(points, target)
        report["estimators"][name] = {"mean_apart": mean, "quarters_apart": quarter, "points_ms_rmse": points,
                                      "slope": slope, "ms_to_rmse": times}
    e = report["estimators"]
    report["ratios"] = {
        f"forward / ptracer at {t}": e["forward (shadelab forward)"]["ms_to_rmse"][str(t)]
        / e["ptracer (Mitsuba)"]["ms_to_rmse"][str(t)] for t in TARGETS}
    report["ratios"].update({
        f"backward / path at {t}": e["backward (shadelab raytrace)"]["ms_to_rmse"][str(t)]
        / e["path (Mitsuba)"]["ms_to_rmse"][str(t)] for t in TARGETS})
    with open(os.path.join(WORK, "estimators.json"), "w") as f:
        json.dump(report, f, indent=1)
    print(f"diffuse box, 80 x 60, {BOUNCES} bounces; reference: Mitsuba path + ptracer at 2048 spp "
          f"(its own RMSE {ref_noise:.4f}, taken out)\n")
    print("| estimator | image mean apart | quarters apart, worst | slope | ms to RMSE 0.1 | ms to RMSE 0.05 |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for name, r in e.items():
        worst = max(abs(q) for q in r["quarters_apart"])
        print(f"| {name} | {r['mean_apart'] * 100:+.2f}% | {worst * 100:.2f}% | {r['slope']:.2f} | "
              f"{r['ms_to_rmse']['0.1']:.1f} | {r['ms_to_rmse']['0.05']:.1f} |")
    print()
    for name, ratio in report["ratios"].items():
        print(f"- {name}: {ratio:.2f}x")


main()
