"""Peer for shadelab's raster modes: wgpu-py (wgpu-native on Vulkan, lavapipe here) drawing the
peers' lit UV sphere offscreen, the same work as `shadelab bench` on ci/peers/sphere_scene.py's
scene: SIZExSIZE, depth test, back-face culling, one point light, the same lighting formula per
pixel (phong), per vertex (gouraud), or none (constant colour: the driver's floor).

    wgpu_raster_peer.py SEG SIZE RUNS [SAMPLES]

SAMPLES > 1 draws into a multisampled colour and depth target (sample_count = SAMPLES) resolved
into the rgba8 image at the end of the pass, as `shadelab bench --msaa SAMPLES` times.

Timed per frame: record, submit, wait and read the colour image back (rgba8), i.e. the
frame's work and its read-back; pipeline creation is timed apart. Two warm-up frames, then
RUNS timed ones. Prints one JSON line: {"peer": "wgpu-raster", "modes": {MODE: {median_ms,
min_ms, max_ms, runs, pipeline_ms, mean_px}}, ...}.
"""
import time

import numpy as np
import wgpu

from peer_common import emit, int_args, summary

SEG, SIZE, RUNS, SAMPLES = int_args(["seg", "size", "runs", "samples"], [100, 1024, 5, 1])
W = H = SIZE


def uv_sphere(seg):
    """The peers' sphere (see sphere_scene.py): rings = seg, sectors = 2 seg, 4 seg^2 triangles."""
    rings, sectors = seg, 2 * seg
    th = np.linspace(0, np.pi, rings + 1)
    ph = np.linspace(0, 2 * np.pi, sectors + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    n = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    verts = np.concatenate([n, n], 1).astype(np.float32)  # position (unit sphere), normal
    idx = []
    for r in range(rings):
        a = r * (sectors + 1) + np.arange(sectors)
        b = a + sectors + 1
        idx.append(np.stack([a, b, a + 1, a + 1, b, b + 1], 1))
    return verts, np.concatenate(idx).astype(np.uint32).reshape(-1)


COMMON = """
struct U { mvp: mat4x4f, eye: vec4f, light: vec4f, };
@group(0) @binding(0) var<uniform> u: U;
struct VOut { @builtin(position) pos: vec4f, @location(0) wp: vec3f, @location(1) n: vec3f, @location(2) c: vec3f, };
fn shade(p: vec3f, nn: vec3f) -> vec3f {
  let n = normalize(nn);
  let l = normalize(u.light.xyz - p);
  let d = length(u.light.xyz - p);
  let v = normalize(u.eye.xyz - p);
  let ndl = dot(n, l);
  let r = 2.0 * ndl * n - l;
  var s = 0.0;
  if (ndl > 0.0) { s = pow(max(dot(r, v), 0.0), 40.0); }
  let i = 0.2 * 0.3 + 8.0 / (d + 1.0) * (0.7 * max(ndl, 0.0) + 0.4 * s);
  return vec3f(i) * vec3f(0.9, 0.85, 0.8);
}
@vertex fn vs(@location(0) pos: vec3f, @location(1) n: vec3f) -> VOut {
  var o: VOut; o.pos = u.mvp * vec4f(pos, 1.0); o.wp = pos; o.n = n; o.c = GOURAUD; return o;
}
"""
FS = {
    "phong": "@fragment fn fs(i: VOut) -> @location(0) vec4f { return vec4f(shade(i.wp, i.n), 1.0); }",
    "gouraud": "@fragment fn fs(i: VOut) -> @location(0) vec4f { return vec4f(i.c, 1.0); }",
    "constant": "@fragment fn fs(i: VOut) -> @location(0) vec4f { return vec4f(0.5, 0.5, 0.5, 1.0); }",
}


def perspective(fovy, aspect, near, far):
    f = 1 / np.tan(np.radians(fovy) / 2)
    m = np.zeros((4, 4), np.float32)
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[2, 2] = far / (near - far)
    m[2, 3] = near * far / (near - far)
    m[3, 2] = -1
    return m


def look_at(eye, at, up):
    f = at - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4, dtype=np.float32)
    m[0, :3] = s
    m[1, :3] = u
    m[2, :3] = -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def main():
    adapter = wgpu.gpu.request_adapter_sync(power_preference="high-performance")
    info = adapter.info
    dev = adapter.request_device_sync()
    verts, idx = uv_sphere(SEG)
    vb = dev.create_buffer_with_data(data=verts, usage=wgpu.BufferUsage.VERTEX)
    ib = dev.create_buffer_with_data(data=idx, usage=wgpu.BufferUsage.INDEX)
    eye = np.array([0, 0.5, 3.0], np.float32)
    mvp = perspective(40, W / H, 0.1, 100) @ look_at(eye, np.zeros(3, np.float32), np.array([0, 1, 0], np.float32))
    ubo = np.zeros(24, np.float32)
    ubo[:16] = mvp.T.reshape(-1)
    ubo[16:19] = eye
    ubo[20:23] = [4, 6, 5]
    ub = dev.create_buffer_with_data(data=ubo, usage=wgpu.BufferUsage.UNIFORM)
    color = dev.create_texture(size=(W, H, 1), format=wgpu.TextureFormat.rgba8unorm,
                               usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC)
    depth = dev.create_texture(size=(W, H, 1), format=wgpu.TextureFormat.depth32float,
                               usage=wgpu.TextureUsage.RENDER_ATTACHMENT, sample_count=SAMPLES)
    # Multisampled: the samples drawn here, resolved into `color` at the end of the pass.
    samples = (dev.create_texture(size=(W, H, 1), format=wgpu.TextureFormat.rgba8unorm,
                                  usage=wgpu.TextureUsage.RENDER_ATTACHMENT, sample_count=SAMPLES)
               if SAMPLES > 1 else None)
    modes = {}
    for mode, fs in FS.items():
        g = "shade(pos, n)" if mode == "gouraud" else "vec3f(0.0)"
        t0 = time.perf_counter()
        sm = dev.create_shader_module(code=COMMON.replace("GOURAUD", g) + fs)
        pipe = dev.create_render_pipeline(
            layout="auto",
            vertex={"module": sm, "entry_point": "vs", "buffers": [{"array_stride": 24, "attributes": [
                {"format": "float32x3", "offset": 0, "shader_location": 0},
                {"format": "float32x3", "offset": 12, "shader_location": 1}]}]},
            primitive={"topology": "triangle-list", "cull_mode": "back", "front_face": "ccw"},
            depth_stencil={"format": "depth32float", "depth_write_enabled": True, "depth_compare": "less"},
            fragment={"module": sm, "entry_point": "fs", "targets": [{"format": "rgba8unorm"}]},
            multisample={"count": SAMPLES},
        )
        bg = dev.create_bind_group(layout=pipe.get_bind_group_layout(0),
                                   entries=[{"binding": 0, "resource": {"buffer": ub}}])
        pipeline_ms = (time.perf_counter() - t0) * 1e3
        times = []
        data = b""
        for _ in range(RUNS + 2):
            t0 = time.perf_counter()
            enc = dev.create_command_encoder()
            rp = enc.begin_render_pass(
                color_attachments=[{"view": (samples or color).create_view(),
                                    "resolve_target": color.create_view() if samples else None,
                                    "clear_value": (0, 0, 0, 1), "load_op": "clear",
                                    "store_op": "discard" if samples else "store"}],
                depth_stencil_attachment={"view": depth.create_view(), "depth_clear_value": 1.0,
                                          "depth_load_op": "clear", "depth_store_op": "store"})
            rp.set_pipeline(pipe)
            rp.set_bind_group(0, bg)
            rp.set_vertex_buffer(0, vb)
            rp.set_index_buffer(ib, wgpu.IndexFormat.uint32)
            rp.draw_indexed(len(idx))
            rp.end()
            dev.queue.submit([enc.finish()])
            data = dev.queue.read_texture({"texture": color}, {"bytes_per_row": W * 4}, (W, H, 1))
            times.append(time.perf_counter() - t0)
        img = np.frombuffer(data, np.uint8).reshape(H, W, 4)
        modes[mode] = dict(summary(times[2:]), pipeline_ms=round(pipeline_ms, 3),
                           mean_px=round(float(img[..., :3].mean()), 3))
    emit({"peer": "wgpu-raster", "wgpu": wgpu.__version__, "device": info.get("device", ""),
          "backend": info.get("backend_type", ""), "description": info.get("description", ""),
          "triangles": len(idx) // 3, "width": W, "height": H, "samples": SAMPLES,
          "timed": "submit + draw + read-back (rgba8)",
          "modes": modes})


if __name__ == "__main__":
    main()
