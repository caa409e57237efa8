//! `RtScene`: a `Scene` turned camera-relative, its objects sorted into the
//! primitive kinds, its meshes' triangles gathered under one BVH.

use glam::{DVec2, DVec3};
use obvhs::bvh2::Bvh2;

use super::bvh::build_bvh;
use super::bvh_cache::cached_or_built;
use super::primitives::{Primitive, RtBox, RtHugeSphere, RtPlane, RtSphere, RtTriangle};
use crate::huge_sphere::{sphere_form, SphereForm};
use crate::scene::{
    plane_axes, Lighting, Material, Object, PointLight, RenderSettings, Scene, Shape, TriangleMesh,
};

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

/// Which per-triangle attributes the scene's meshes need, decided once
/// for all its meshes.
#[derive(Clone, Copy)]
struct MeshAttributes {
    /// Some mesh has vertex colours: every triangle gets `triangle_colors`.
    coloured: bool,
    /// Some mesh with texture coordinates has a pattern: every triangle
    /// gets `triangle_uvs`.
    textured: bool,
}

impl RtScene {
    pub fn new(scene: &Scene) -> Self {
        let mut rt = Self::without_tree(scene);
        rt.bvh = build_bvh(&rt.triangles);
        rt
    }

    /// The same scene, its tree over a big mesh from the cache folder where
    /// it holds one for these triangles (`bvh_cache`): the GPU's. The CPU
    /// twin, the reference, builds its own.
    pub fn with_cached_tree(scene: &Scene) -> Self {
        let mut rt = Self::without_tree(scene);
        rt.add_cached_tree();
        rt
    }

    /// The scene's primitives with no tree over the triangles yet (`bvh`
    /// empty): all a pipeline specialises on, known before the tree.
    pub fn without_tree(scene: &Scene) -> Self {
        let eye = scene.camera.position;
        let mut rt = RtScene::without_objects(scene, eye);
        let attributes = rt.reserve_triangles(scene);
        for (index, object) in scene.objects.iter().enumerate() {
            rt.add_object(object, index as u32, eye, attributes);
        }
        rt
    }

    /// The tree over the triangles, from the cache folder for a big mesh
    /// (`with_cached_tree`).
    pub fn add_cached_tree(&mut self) {
        self.bvh = cached_or_built(&self.triangles);
    }

    /// The scene's materials, lights (moved to camera-relative positions)
    /// and settings, with no primitive yet.
    fn without_objects(scene: &Scene, eye: DVec3) -> Self {
        RtScene {
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
            // Secondary illumination follows the light the ambient term
            // stood for; keeping it would count that light twice
            // (docs/lighting-model.md, "Secondary illumination").
            lighting: Lighting {
                ambient: if scene.render.bounces > 0 {
                    DVec3::ZERO
                } else {
                    scene.lighting.ambient
                },
                ..scene.lighting
            },
            background: scene.image.background,
            render: scene.render,
        }
    }

    /// Reserves the triangle lists for all meshes of `scene`, and says
    /// which of the optional lists they fill.
    fn reserve_triangles(&mut self, scene: &Scene) -> MeshAttributes {
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
        self.triangles.reserve_exact(triangle_count);
        let coloured = scene
            .objects
            .iter()
            .any(|o| matches!(&o.shape, Shape::Mesh(m) if !m.colors.is_empty()));
        if coloured {
            self.triangle_colors.reserve_exact(triangle_count);
        }
        let textured = scene.objects.iter().any(|o| {
            matches!(&o.shape, Shape::Mesh(m) if !m.uvs.is_empty())
                && scene.materials[o.material].pattern.is_some()
        });
        if textured {
            self.triangle_uvs.reserve_exact(triangle_count);
        }
        MeshAttributes { coloured, textured }
    }

    /// `object` (scene index `object_index`) as the primitive(s) of its
    /// kind, relative to `eye`.
    fn add_object(
        &mut self,
        object: &Object,
        object_index: u32,
        eye: DVec3,
        attributes: MeshAttributes,
    ) {
        let material = object.material as u32;
        match &object.shape {
            Shape::Sphere { center, radius, .. } => {
                let sphere = RtSphere {
                    center: *center - eye,
                    radius: *radius,
                    material,
                    object: object_index,
                };
                match sphere_form(eye, *center, *radius) {
                    SphereForm::Plain => self.spheres.push(sphere),
                    SphereForm::Anchored(anchor) => {
                        self.huge_spheres.push(RtHugeSphere { sphere, anchor })
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
                self.planes.push(RtPlane {
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
            } => self.boxes.push(RtBox {
                center: *center - eye,
                half_extents: *half_extents,
                rotation: *rotation,
                material,
                object: object_index,
            }),
            Shape::Mesh(mesh) => self.add_mesh(mesh, (material, object_index), eye, attributes),
        }
    }

    /// Every triangle of `mesh`, with the attributes the scene keeps.
    fn add_mesh(
        &mut self,
        mesh: &TriangleMesh,
        (material, object): (u32, u32),
        eye: DVec3,
        MeshAttributes { coloured, textured }: MeshAttributes,
    ) {
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|i| i as usize);
            self.triangles.push(RtTriangle {
                positions: [a, b, c].map(|i| mesh.positions[i] - eye),
                normals: [a, b, c].map(|i| mesh.normals[i]),
                material,
                object,
            });
            if coloured {
                self.triangle_colors
                    .push([a, b, c].map(|i| mesh.colors.get(i).copied().unwrap_or(DVec3::ONE)));
            }
            if textured {
                self.triangle_uvs
                    .push([a, b, c].map(|i| mesh.uvs.get(i).copied().unwrap_or_default()));
            }
        }
    }

    /// The radius of the sphere a hit is on (0 for other primitives).
    pub fn sphere_radius(&self, primitive: Primitive) -> f64 {
        match primitive {
            Primitive::Sphere(i) => self.spheres[i as usize].radius,
            Primitive::HugeSphere(i) => self.huge_spheres[i as usize].sphere.radius,
            _ => 0.0,
        }
    }

    /// Whether any material transmits light (refraction rays can exist).
    pub fn has_transmission(&self) -> bool {
        self.materials.iter().any(|m| m.kt > 0.0)
    }

    /// Whether any material reflects (reflection rays can exist).
    pub fn has_reflection(&self) -> bool {
        self.materials.iter().any(|m| m.kr > 0.0 || m.kt > 0.0)
    }
}
