//! Shared helpers for the GPU tests: a context with the validation layer on,
//! scenes built in code, and exact double-precision ray casts that say which
//! surface point each pixel centre sees.
#![allow(dead_code)]

pub mod caustic_scenes;
pub mod cli;
pub mod closed_sphere;
pub mod doc_commands;

use std::sync::Arc;

use glam::DVec3;
use shadelab::camera::View;
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::render::{Device, RenderRequest};
use shadelab::scene::*;
use shadelab::shading::Shading;
use shadelab::LinearImage;

/// A context with the Khronos validation layer on: any validation message
/// turns the render that caused it into an error, failing the test.
pub fn gpu() -> Arc<GpuContext> {
    let options = GpuOptions {
        validation: true,
        ..GpuOptions::from_env()
    };
    GpuContext::new(&options).expect("a Vulkan device with the validation layer")
}

/// The GPU ray tracer's engines this device runs: the compute BVH always,
/// and the ray-query engine where the device offers ray queries (Mesa 24
/// and newer lavapipe does; Mesa 22.3 does not, and then the tests say so
/// on stderr and check the compute BVH alone).
pub fn engines(context: &Arc<GpuContext>) -> Vec<Traversal> {
    match &context.info.no_ray_query_because {
        None => vec![Traversal::Bvh, Traversal::Query],
        Some(why) => {
            eprintln!("ray-query engine not tested: `{}` {why}", context.info.name);
            vec![Traversal::Bvh]
        }
    }
}

/// The built-in default scene and every scene file in `assets/`, each with
/// its name ("default", or the file's path), the files in path order.
pub fn asset_scenes() -> Vec<(String, Scene)> {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets");
    let mut paths: Vec<std::path::PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    let mut out = vec![("default".to_string(), default_scene())];
    for p in paths {
        let s = load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        out.push((p.display().to_string(), s));
    }
    out
}

/// `scene` traced by `engine`.
pub fn with_engine(scene: &Scene, engine: Traversal) -> Scene {
    let mut s = scene.clone();
    s.render.traversal = engine;
    s
}

/// The GPU ray tracer's ray counts for `scene` (its counting variant).
pub fn gpu_ray_stats(context: &Arc<GpuContext>, scene: &Scene) -> shadelab::rt_scene::RayStats {
    let request = RenderRequest {
        count_rays: true,
        ..RenderRequest::gpu(Shading::Raytrace)
    };
    shadelab::render::render(&Device::with_gpu(context.clone()), scene, &request)
        .unwrap_or_else(|e| panic!("render failed: {e}"))
        .ray_stats
        .expect("the counting variant counts")
}

pub fn render(context: &Arc<GpuContext>, scene: &Scene, shading: Shading) -> LinearImage {
    let device = Device::with_gpu(context.clone());
    match shadelab::render::render(&device, scene, &RenderRequest::gpu(shading)) {
        Ok(r) => r.image,
        Err(e) => panic!("render failed: {e}"),
    }
}

pub fn material(color: DVec3, ka: f64, kd: f64, ks: f64, p: f64) -> Material {
    Material {
        name: "test".into(),
        color,
        ka,
        kd,
        ks,
        p,
        kr: 0.0,
        kt: 0.0,
        ior: 1.0,
        pattern: None,
    }
}

/// A scene with a camera on +Z looking at the origin, one white light, no
/// objects, and one material.
pub fn scene(width: u32, height: u32, fov_y_deg: f64) -> Scene {
    Scene {
        camera: Camera {
            position: DVec3::new(0.0, 0.0, 10.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            fov_y_deg,
        },
        image: ImageSettings {
            width,
            height,
            background: DVec3::ZERO,
        },
        lighting: Lighting {
            ambient: DVec3::splat(0.2),
            k: 1.0,
            interpolation: Interpolation::Perspective,
            falloff: Falloff::Lecture,
        },
        lights: vec![PointLight {
            position: DVec3::new(4.0, 5.0, 8.0),
            intensity: DVec3::splat(10.0),
        }],
        materials: vec![material(DVec3::new(0.9, 0.6, 0.3), 0.3, 0.7, 0.5, 10.0)],
        objects: Vec::new(),
        render: RenderSettings::default(),
        lighting_hook: None,
        warnings: Vec::new(),
    }
}

pub fn view(scene: &Scene) -> View {
    View::new(scene, scene.image.width, scene.image.height)
}

/// The ray direction through the centre of pixel (x, y).
pub fn pixel_ray(view: &View, x: u32, y: u32) -> DVec3 {
    view.ray_direction(f64::from(x) + 0.5, f64::from(y) + 0.5)
}

/// Nearest intersection distance of a ray with a sphere.
pub fn hit_sphere(origin: DVec3, dir: DVec3, center: DVec3, radius: f64) -> Option<f64> {
    let oc = origin - center;
    let b = oc.dot(dir);
    let c = oc.length_squared() - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let t = -b - disc.sqrt();
    (t > 0.0).then_some(t)
}

/// Nearest triangle hit: (triangle index, distance, barycentrics of b and c).
pub fn hit_mesh(origin: DVec3, dir: DVec3, mesh: &TriangleMesh) -> Option<(usize, f64, f64, f64)> {
    let mut best: Option<(usize, f64, f64, f64)> = None;
    for (i, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|k| mesh.positions[k as usize]);
        let (e1, e2) = (b - a, c - a);
        let pv = dir.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-15 {
            continue;
        }
        let tv = origin - a;
        let u = tv.dot(pv) / det;
        let qv = tv.cross(e1);
        let v = dir.dot(qv) / det;
        let t = e2.dot(qv) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 || t <= 0.0 {
            continue;
        }
        if best.is_none_or(|(_, bt, _, _)| t < bt) {
            best = Some((i, t, u, v));
        }
    }
    best
}

/// For each pixel, the index of what its centre sees (None: background).
/// `classify` maps a pixel to an id.
pub fn id_map(
    width: u32,
    height: u32,
    classify: impl Fn(u32, u32) -> Option<usize>,
) -> Vec<Option<usize>> {
    let mut ids = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            ids.push(classify(x, y));
        }
    }
    ids
}

/// Pixels whose 3x3 neighbourhood all see the same id: away from every edge,
/// so the sub-pixel placement of an edge cannot change what they show.
pub fn interior_pixels(width: u32, height: u32, ids: &[Option<usize>]) -> Vec<(u32, u32, usize)> {
    let mut out = Vec::new();
    for y in 1..height.saturating_sub(1) {
        for x in 1..width.saturating_sub(1) {
            let id = ids[(y * width + x) as usize];
            let Some(id) = id else { continue };
            let same = (-1i32..=1).all(|dy| {
                (-1i32..=1).all(|dx| {
                    let (nx, ny) = ((x as i32 + dx) as u32, (y as i32 + dy) as u32);
                    ids[(ny * width + nx) as usize] == Some(id)
                })
            });
            if same {
                out.push((x, y, id));
            }
        }
    }
    out
}

/// GPU (f32) against an f64 value below ~2: f32 arithmetic there is good to
/// ~1e-6; 1e-4 leaves a wide margin and is still 40 times finer than one
/// 8-bit output step (1/255).
pub const FLOAT_TOL: f64 = 1e-4;

pub fn to_dvec(rgb: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(rgb[0]), f64::from(rgb[1]), f64::from(rgb[2]))
}

/// Largest per-channel absolute difference; infinite when either side is
/// not finite (glam's `max_element` and `f64::max` would drop a NaN).
pub fn max_abs_diff(a: DVec3, b: DVec3) -> f64 {
    let d = (a - b).abs();
    if d.is_finite() {
        d.max_element()
    } else {
        f64::INFINITY
    }
}

/// The worst per-channel difference of two images; infinite if a pixel of
/// either is not finite (`metrics::stats::pixel_errors`).
pub fn worst_difference(a: &LinearImage, b: &LinearImage) -> f64 {
    shadelab::metrics::stats::pixel_errors(a, b)
        .into_iter()
        .fold(0.0, f64::max)
}

/// A screen-parallel 4x4 grid whose vertices land exactly on pixel centres:
/// 101x101 pixels, a 90 degree field of view (focal length 1), the plane 10
/// units away. Vertex columns and rows fall on pixel centres 10.5, 30.5,
/// 50.5, 70.5 and 90.5, so every triangle edge passes through samples.
pub fn grid_scene() -> Scene {
    let mut s = scene(101, 101, 90.0);
    s.lights[0].position = DVec3::new(3.0, 2.0, 2.0);
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Z,
            size: 2.0 * 10.0 * 40.0 / 50.5,
            segments: 4,
        },
        material: 0,
    });
    s
}

/// A 128x128 view of a tessellated sphere (48 segments): a mesh whose BVH
/// is big enough for the ray tracer's 4-wide walk.
pub fn mesh_sphere_scene() -> Scene {
    let mut s = scene(128, 128, 30.0);
    let sphere = Shape::Sphere {
        center: DVec3::ZERO,
        radius: 2.0,
        segments: 48,
    };
    s.objects.push(Object {
        shape: Shape::Mesh(tessellate(&sphere)),
        material: 0,
    });
    s
}

/// A 64x48 view of one exact sphere with no specular term: a scene that
/// leaves out every optional feature of the ray tracer but shadows.
pub fn plain_sphere_scene() -> Scene {
    let mut plain = scene(64, 48, 45.0);
    plain.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
            segments: 16,
        },
        material: 0,
    });
    plain.materials[0].ks = 0.0;
    plain
}

/// The GPU's render of `scene` in `shading` through the library's one
/// door (`shadelab::render`), as most tests want it.
pub fn render_gpu(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
) -> Result<shadelab::render::Rendered, shadelab::error::Error> {
    let device = Device::with_gpu(context.clone());
    shadelab::render::render(&device, scene, &RenderRequest::gpu(shading))
}

/// The CPU reference's render of `scene` in `shading` and its coverage.
pub fn render_cpu(
    scene: &Scene,
    shading: Shading,
) -> Result<(shadelab::render::Rendered, shadelab::render::Coverage), shadelab::error::Error> {
    let request = RenderRequest::cpu(shading);
    let mut rendered = shadelab::render::render(&Device::cpu_only(), scene, &request)?;
    let coverage = rendered
        .coverage
        .take()
        .expect("the CPU reference knows its pixels");
    Ok((rendered, coverage))
}

/// The library's device over a context a test opened.
pub fn device(context: &Arc<GpuContext>) -> Device {
    Device::with_gpu(context.clone())
}

/// The GPU tracer's render of all of `scene`'s samples as `options` say.
pub fn trace_gpu(
    context: &Arc<GpuContext>,
    scene: &Scene,
    options: shadelab::gpu::raytrace::TraceOptions,
) -> Result<shadelab::gpu::raytrace::TraceOutput, shadelab::gpu::GpuError> {
    let all = shadelab::film_sums::RenderPart::all(scene.render.samples);
    shadelab::gpu::raytrace::render(context, scene, options, &all, &Default::default())
}

/// The GPU tracer's render of all of `scene`'s samples, counting rays
/// where `count_rays`.
pub fn trace_gpu_counting(
    context: &Arc<GpuContext>,
    scene: &Scene,
    count_rays: bool,
) -> Result<shadelab::gpu::raytrace::TraceOutput, shadelab::gpu::GpuError> {
    let options = shadelab::gpu::raytrace::TraceOptions {
        count_rays,
        ..Default::default()
    };
    trace_gpu(context, scene, options)
}

/// The CPU twin's trace of all of `scene`'s samples.
pub fn trace_cpu(scene: &Scene) -> shadelab::cpu::raytrace::RayTraced {
    let all = shadelab::film_sums::RenderPart::all(scene.render.samples);
    shadelab::cpu::raytrace::render(scene, &all, &Default::default())
}

/// The CPU forward tracer's photons `0..photons` of `scene` (`None`: no
/// light with power).
pub fn forward_cpu(scene: &Scene, photons: u32) -> Option<shadelab::cpu::forward::ForwardImage> {
    let all = shadelab::film_sums::RenderPart::all(photons);
    shadelab::cpu::forward::render(scene, &all, &Default::default())
}
