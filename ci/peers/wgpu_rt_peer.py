"""Peer for shadelab's ray tracer on a small analytic scene: a plain brute-force compute-shader
tracer (the kind of the classic Vulkan 'computeraytracing' sample) in WGSL on wgpu (lavapipe
here): 4 spheres and a plane tested without a BVH, one point light, shadow rays, mirror
reflection to depth 2. ci/peers/four-spheres.toml is the same scene for shadelab.

    wgpu_rt_peer.py SIZE RUNS

Timed per frame: record, submit, dispatch, wait and read the float image back. Two warm-up
frames, then RUNS timed ones. first_image_ms: from the scene's buffers to the first frame read back,
pipeline creation and the driver's code generation at the first dispatch included; the adapter
and device before it (0.7 s in wgpu-py on lavapipe) are device_ms. Prints one JSON line: {"peer": "wgpu-rt", median_ms, ...}.
"""
import time

import numpy as np
import wgpu

from peer_common import emit, int_args, summary

SIZE, RUNS = int_args(["size", "runs"], [1024, 5])
W = H = SIZE
SRC = """
struct Sph { c: vec4f, col: vec4f };
@group(0) @binding(0) var<storage, read_write> img: array<vec4f>;
@group(0) @binding(1) var<storage, read> sph: array<Sph, 4>;
const W: u32 = WIDTHu;
const H: u32 = HEIGHTu;
fn hit(o: vec3f, d: vec3f, tmax: f32, best: ptr<function, f32>, id: ptr<function, i32>) {
  for (var i = 0; i < 4; i++) {
    let oc = sph[i].c.xyz - o; let tb = dot(oc, d); let q = oc - tb * d;
    let disc = sph[i].c.w * sph[i].c.w - dot(q, q);
    if (disc > 0.0) { let t = tb - sqrt(disc); if (t > 1e-3 && t < *best) { *best = t; *id = i; } }
  }
  if (d.y < 0.0) { let t = -(o.y + 1.0) / d.y; if (t > 1e-3 && t < *best) { *best = t; *id = 4; } }
}
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) g: vec3u) {
  if (g.x >= W || g.y >= H) { return; }
  let eye = vec3f(0.0, 0.5, 3.0);
  let fw = normalize(-eye); let s = normalize(cross(fw, vec3f(0.0, 1.0, 0.0))); let u = cross(s, fw);
  let th = tan(radians(20.0));
  let aspect = f32(W) / f32(H);
  var d = normalize(fw + ((f32(g.x) + 0.5) / f32(W) * 2.0 - 1.0) * th * aspect * s
                       + (1.0 - (f32(g.y) + 0.5) / f32(H) * 2.0) * th * u);
  var o = eye; var col = vec3f(0.0); var w = 1.0;
  let lp = vec3f(4.0, 6.0, 5.0);
  for (var depth = 0; depth < 3; depth++) {
    var t = 1e30; var id = -1;
    hit(o, d, 1e30, &t, &id);
    if (id < 0) { col += w * vec3f(0.1, 0.1, 0.2); break; }
    let p = o + t * d;
    var n = vec3f(0.0, 1.0, 0.0); var c = vec3f(0.8); var kr = 0.0;
    if (id < 4) { n = normalize(p - sph[id].c.xyz); c = sph[id].col.xyz; kr = sph[id].col.w; }
    let ld = lp - p; let dist = length(ld); let l = ld / dist;
    var ts = dist; var sid = -1;
    hit(p + n * 1e-3, l, dist, &ts, &sid);
    var local = 0.2 * 0.3 * c;
    let ndl = dot(n, l);
    if (sid < 0 && ndl > 0.0) {
      let r = 2.0 * ndl * n - l;
      local += 8.0 / (dist + 1.0) * (0.7 * c * ndl + 0.4 * pow(max(dot(r, -d), 0.0), 40.0));
    }
    col += w * local;
    if (kr <= 0.0) { break; }
    w *= kr; o = p + n * 1e-3; d = d - 2.0 * dot(d, n) * n;
  }
  img[g.y * W + g.x] = vec4f(col, 1.0);
}
"""


def main():
    t0 = time.perf_counter()
    adapter = wgpu.gpu.request_adapter_sync(power_preference="high-performance")
    info = adapter.info
    dev = adapter.request_device_sync()
    device_ms = (time.perf_counter() - t0) * 1e3
    started = time.perf_counter()
    # centre xyz, radius; colour rgb, reflectivity kr (four-spheres.toml's materials a to d)
    spheres = np.array([[0, 0, 0, 1, 0.9, 0.9, 0.9, 0.8], [-1.6, -0.4, -0.6, 0.6, 0.9, 0.2, 0.2, 0.0],
                        [1.5, -0.5, -0.2, 0.5, 0.2, 0.8, 0.3, 0.3], [0.3, -0.7, 1.4, 0.3, 0.9, 0.8, 0.1, 0.0]],
                       np.float32)
    sb = dev.create_buffer_with_data(data=spheres, usage=wgpu.BufferUsage.STORAGE)
    ib = dev.create_buffer(size=W * H * 16, usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC)
    t0 = time.perf_counter()
    sm = dev.create_shader_module(code=SRC.replace("WIDTH", str(W)).replace("HEIGHT", str(H)))
    pipe = dev.create_compute_pipeline(layout="auto", compute={"module": sm, "entry_point": "main"})
    pipeline_ms = (time.perf_counter() - t0) * 1e3
    bg = dev.create_bind_group(layout=pipe.get_bind_group_layout(0), entries=[
        {"binding": 0, "resource": {"buffer": ib}}, {"binding": 1, "resource": {"buffer": sb}}])
    times = []
    data = b""
    for _ in range(RUNS + 2):
        t0 = time.perf_counter()
        enc = dev.create_command_encoder()
        cp = enc.begin_compute_pass()
        cp.set_pipeline(pipe)
        cp.set_bind_group(0, bg)
        cp.dispatch_workgroups((W + 7) // 8, (H + 7) // 8)
        cp.end()
        dev.queue.submit([enc.finish()])
        data = dev.queue.read_buffer(ib)
        times.append(time.perf_counter() - t0)
        if len(times) == 1:
            first_image_ms = (time.perf_counter() - started) * 1e3
    img = np.frombuffer(data, np.float32).reshape(H, W, 4)
    emit(dict(summary(times[2:]), peer="wgpu-rt", wgpu=wgpu.__version__, device=info.get("device", ""),
              backend=info.get("backend_type", ""), width=W, height=H, pipeline_ms=round(pipeline_ms, 3),
              first_image_ms=round(first_image_ms, 3), device_ms=round(device_ms, 3),
              timed="submit + dispatch + read-back (rgba32f)", mean_px=round(float(img[..., :3].mean()), 4)))


if __name__ == "__main__":
    main()
