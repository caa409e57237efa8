//! The scene as both ray tracers (the compute shader and the CPU twin) see
//! it: exact spheres, finite planes and oriented boxes, mesh triangles with a
//! bounding volume hierarchy, materials and lights. Everything is in
//! camera-relative coordinates (world minus eye, subtracted in `f64`), so the
//! eye is the origin and scenes far from the world origin keep precision.
//!
//! Every primitive carries the index of the scene object it came from: when
//! two hits are at exactly the same distance the lower index wins, the
//! same rule as the raster modes' "first drawn wins".

use glam::{DMat3, DVec2, DVec3, Vec3A};
use obvhs::bvh2::Bvh2;

use crate::huge_sphere::{sphere_form, SphereAnchor, SphereForm};
use crate::scene::{plane_axes, Lighting, Material, PointLight, RenderSettings, Scene, Shape};

#[derive(Debug, Clone, Copy)]
pub struct RtSphere {
    pub center: DVec3,
    pub radius: f64,
    pub material: u32,
    pub object: u32,
}

/// A sphere the plain test cannot hold in `f32` (`huge_sphere`): tested
/// from its anchor, the point of its surface nearest the eye.
#[derive(Debug, Clone, Copy)]
pub struct RtHugeSphere {
    /// Its centre relative to the eye, its radius, material and object, as
    /// any sphere's: what its normal and texture coordinates come from.
    pub sphere: RtSphere,
    pub anchor: SphereAnchor,
}

/// A finite square: points `center + a u + b v` with `|a|, |b| <= half_size`.
#[derive(Debug, Clone, Copy)]
pub struct RtPlane {
    pub center: DVec3,
    pub normal: DVec3,
    pub u: DVec3,
    pub v: DVec3,
    pub half_size: f64,
    pub material: u32,
    pub object: u32,
}

/// An oriented box: `rotation` maps box-local axes to world axes.
#[derive(Debug, Clone, Copy)]
pub struct RtBox {
    pub center: DVec3,
    pub half_extents: DVec3,
    pub rotation: DMat3,
    pub material: u32,
    pub object: u32,
}

impl RtSphere {
    /// The smallest axis-aligned box around the sphere (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (self.center - self.radius, self.center + self.radius)
    }
}

impl RtPlane {
    /// The smallest axis-aligned box around the square (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let reach = self.half_size * (self.u.abs() + self.v.abs());
        (self.center - reach, self.center + reach)
    }
}

impl RtBox {
    /// The smallest axis-aligned box around the oriented box (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let r = self.rotation;
        let reach = r.x_axis.abs() * self.half_extents.x
            + r.y_axis.abs() * self.half_extents.y
            + r.z_axis.abs() * self.half_extents.z;
        (self.center - reach, self.center + reach)
    }
}

#[derive(Debug, Clone, Copy)]
pub struct RtTriangle {
    pub positions: [DVec3; 3],
    /// Unit vertex normals, interpolated with the hit's barycentrics.
    pub normals: [DVec3; 3],
    pub material: u32,
    pub object: u32,
}

impl RtTriangle {
    /// `normalize((b - a) x (c - a))`, or zero for a degenerate triangle:
    /// what both tracers offset secondary rays along (the GPU receives it
    /// rounded to f32).
    pub fn geometric_normal(&self) -> DVec3 {
        let [a, b, c] = self.positions;
        (b - a).cross(c - a).normalize_or_zero()
    }
}

/// Every position is relative to the eye (`scene.camera.position`).
pub struct RtScene {
    /// The spheres of the plain test.
    pub spheres: Vec<RtSphere>,
    /// The spheres of the anchored test (`huge_sphere::sphere_form`), kept
    /// apart so that a scene without one pays nothing for them.
    pub huge_spheres: Vec<RtHugeSphere>,
    pub planes: Vec<RtPlane>,
    pub boxes: Vec<RtBox>,
    pub triangles: Vec<RtTriangle>,
    /// The vertex colours of each of `triangles`, in their order; empty
    /// when no mesh of the scene has any (`DVec3::ONE` for the corners of
    /// a mesh without them in a scene where another has them). Apart from
    /// `triangles` so that a scene without colours pays nothing for them.
    pub triangle_colors: Vec<[DVec3; 3]>,
    /// The texture coordinates of each of `triangles`, like
    /// `triangle_colors`: empty unless some mesh's material has a pattern
    /// (zeros for the corners of the other meshes).
    pub triangle_uvs: Vec<[DVec2; 3]>,
    /// Over `triangles`, built from their f32-rounded positions. Its boxes
    /// bound the f32 triangles; both tracers widen them (`widened_box`).
    pub bvh: Bvh2,
    pub materials: Vec<Material>,
    /// Positions relative to the eye.
    pub lights: Vec<PointLight>,
    pub lighting: Lighting,
    pub background: DVec3,
    pub render: RenderSettings,
}

impl RtScene {
    pub fn new(scene: &Scene) -> Self {
        let eye = scene.camera.position;
        let mut rt = RtScene {
            spheres: Vec::new(),
            huge_spheres: Vec::new(),
            planes: Vec::new(),
            boxes: Vec::new(),
            triangles: Vec::new(),
            triangle_colors: Vec::new(),
            triangle_uvs: Vec::new(),
            bvh: Bvh2::default(),
            materials: scene.materials.clone(),
            lights: scene
                .lights
                .iter()
                .map(|l| PointLight {
                    position: l.position - eye,
                    intensity: l.intensity,
                })
                .collect(),
            lighting: scene.lighting,
            background: scene.image.background,
            render: scene.render,
        };
        // Exact, not doubled: at 152 bytes a triangle, growth by doubling
        // left up to 60 MB unused on a 400k-triangle mesh.
        let triangle_count = scene
            .objects
            .iter()
            .map(|o| match &o.shape {
                Shape::Mesh(m) => m.triangles.len(),
                _ => 0,
            })
            .sum();
        rt.triangles.reserve_exact(triangle_count);
        let coloured = scene
            .objects
            .iter()
            .any(|o| matches!(&o.shape, Shape::Mesh(m) if !m.colors.is_empty()));
        if coloured {
            rt.triangle_colors.reserve_exact(triangle_count);
        }
        let textured = scene.objects.iter().any(|o| {
            matches!(&o.shape, Shape::Mesh(m) if !m.uvs.is_empty())
                && scene.materials[o.material].pattern.is_some()
        });
        if textured {
            rt.triangle_uvs.reserve_exact(triangle_count);
        }
        for (index, object) in scene.objects.iter().enumerate() {
            let (material, object_index) = (object.material as u32, index as u32);
            match &object.shape {
                Shape::Sphere { center, radius, .. } => {
                    let sphere = RtSphere {
                        center: *center - eye,
                        radius: *radius,
                        material,
                        object: object_index,
                    };
                    match sphere_form(eye, *center, *radius) {
                        SphereForm::Plain => rt.spheres.push(sphere),
                        SphereForm::Anchored(anchor) => {
                            rt.huge_spheres.push(RtHugeSphere { sphere, anchor })
                        }
                    }
                }
                Shape::Plane {
                    center,
                    normal,
                    size,
                    ..
                } => {
                    let (u, v) = plane_axes(*normal);
                    rt.planes.push(RtPlane {
                        center: *center - eye,
                        normal: *normal,
                        u,
                        v,
                        half_size: size * 0.5,
                        material,
                        object: object_index,
                    });
                }
                Shape::Box {
                    center,
                    half_extents,
                    rotation,
                } => rt.boxes.push(RtBox {
                    center: *center - eye,
                    half_extents: *half_extents,
                    rotation: *rotation,
                    material,
                    object: object_index,
                }),
                Shape::Mesh(mesh) => {
                    for tri in &mesh.triangles {
                        let [a, b, c] = tri.map(|i| i as usize);
                        rt.triangles.push(RtTriangle {
                            positions: [a, b, c].map(|i| mesh.positions[i] - eye),
                            normals: [a, b, c].map(|i| mesh.normals[i]),
                            material,
                            object: object_index,
                        });
                        if coloured {
                            rt.triangle_colors.push(
                                [a, b, c]
                                    .map(|i| mesh.colors.get(i).copied().unwrap_or(DVec3::ONE)),
                            );
                        }
                        if textured {
                            rt.triangle_uvs.push(
                                [a, b, c].map(|i| mesh.uvs.get(i).copied().unwrap_or_default()),
                            );
                        }
                    }
                }
            }
        }
        rt.bvh = build_bvh(&rt.triangles);
        rt
    }

    /// Whether any material transmits light (refraction rays can exist).
    /// The radius of the sphere a hit is on (0 for other primitives).
    pub fn sphere_radius(&self, primitive: crate::cpu::intersect::Primitive) -> f64 {
        use crate::cpu::intersect::Primitive;
        match primitive {
            Primitive::Sphere(i) => self.spheres[i as usize].radius,
            Primitive::HugeSphere(i) => self.huge_spheres[i as usize].sphere.radius,
            _ => 0.0,
        }
    }

    pub fn has_transmission(&self) -> bool {
        self.materials.iter().any(|m| m.kt > 0.0)
    }

    /// Whether any material reflects (reflection rays can exist).
    pub fn has_reflection(&self) -> bool {
        self.materials.iter().any(|m| m.kr > 0.0 || m.kt > 0.0)
    }
}

fn build_bvh(triangles: &[RtTriangle]) -> Bvh2 {
    if triangles.is_empty() {
        return Bvh2::default();
    }
    let tris: Vec<obvhs::triangle::Triangle> = triangles
        .iter()
        .map(|t| {
            let [v0, v1, v2] = t.positions.map(|p| Vec3A::from(p.as_vec3()));
            obvhs::triangle::Triangle { v0, v1, v2 }
        })
        .collect();
    let mut build_time = std::time::Duration::default();
    obvhs::bvh2::builder::build_bvh2_from_tris(
        &tris,
        obvhs::BvhBuildParams::medium_build(),
        &mut build_time,
    )
}

/// Rays traced by kind (`docs/raytracing.md`, "Counting").
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflected: u64,
    pub refracted: u64,
    /// Children not traced because their weight fell below the cut-off.
    pub pruned: u64,
    /// The largest depth of any traced ray (0: primary rays only).
    pub max_depth_reached: u32,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflected + self.refracted
    }
}

/// The sample grid of docs/raytracing.md for `samples` per pixel:
/// `kx = ceil(sqrt(samples))` columns and `ky = ceil(samples / kx)` rows.
/// Both tracers place their samples from it.
pub fn sample_grid(samples: u32) -> (u32, u32) {
    let samples = samples.max(1);
    // The least kx with kx^2 >= samples, in integers.
    let kx = (1..).find(|k: &u32| k * k >= samples).unwrap_or(1);
    (kx, samples.div_ceil(kx))
}

/// Relative widening of the BVH's boxes: f32 rounding moves a coordinate by
/// at most 6e-8 of its magnitude, so 1e-5 leaves a factor of 100.
pub const BOX_WIDENING: f64 = 1e-5;

/// A BVH box moved outward by `BOX_WIDENING * max(1, |x|)` per coordinate.
/// The CPU needs it so that no f64 triangle pokes out of a box built from
/// its f32 rounding; the GPU so that a ray along an edge shared by two
/// boxes, which lies on both boxes' faces, is not rejected by both slab
/// tests' rounding (`tests/hard_cases.rs`, rays along shared edges).
pub fn widened_box(min: DVec3, max: DVec3) -> (DVec3, DVec3) {
    let margin = |x: DVec3| BOX_WIDENING * x.abs().max(DVec3::ONE);
    (min - margin(min), max + margin(max))
}
