//! The camera: view basis, projection and near plane, in double precision.
//!
//! Shared by every renderer so they place pixels identically. Renderers work
//! in camera-relative coordinates (world minus eye, subtracted in `f64`), so
//! a scene far from the origin loses no precision when it reaches `f32`.
//!
//! Projection: vertical field of view `fov_y`, aspect `width / height`, pixel
//! centres at `(x + 0.5, y + 0.5)` with `y` growing downward, and a reversed,
//! infinite depth range: clip `z = near`, `w = distance along the view
//! direction`, so depth is `near / w` (1 at the near plane, 0 at infinity).

use glam::{DMat4, DVec3, DVec4};

use crate::scene::{Scene, Shape};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub eye: DVec3,
    /// Unit vectors of the camera frame in world space.
    pub right: DVec3,
    pub up: DVec3,
    pub forward: DVec3,
    /// `1 / tan(fov_y / 2)`.
    pub focal: f64,
    pub aspect: f64,
    pub width: u32,
    pub height: u32,
    /// Distance of the near clipping plane along `forward`.
    pub near: f64,
}

impl View {
    pub fn new(scene: &Scene, width: u32, height: u32) -> Self {
        let cam = &scene.camera;
        let forward = (cam.look_at - cam.position).normalize();
        let right = forward.cross(cam.up).normalize();
        let up = right.cross(forward);
        let (far, nearest) = scene_distances(scene, cam.position);
        let far = far.max(1e-6);
        Self {
            eye: cam.position,
            right,
            up,
            forward,
            focal: 1.0 / (cam.fov_y_deg.to_radians() * 0.5).tan(),
            aspect: f64::from(width) / f64::from(height),
            width,
            height,
            // Reversed float depth keeps precision far away, so the near plane
            // can sit very close: only geometry within 1e-5 of the scene's
            // extent from the eye is clipped, and nearer still where a
            // surface comes nearer than 1/100 of that extent (the eye 1.5
            // above a "planet" of radius 1e20, which makes the extent 2e20):
            // then 1e-3 of that surface's distance. Never below 1e-30 of the
            // extent, where the depth `near / w` of the farthest point would
            // leave f32's normal range.
            near: (far * 1e-5).min(nearest * 1e-3).max(far * 1e-30),
        }
    }

    /// Maps a camera-relative point `p - eye` to Vulkan clip space.
    pub fn clip_from_relative(&self) -> DMat4 {
        let (sx, sy) = (self.focal / self.aspect, -self.focal);
        let col = |i: usize| DVec4::new(sx * self.right[i], sy * self.up[i], 0.0, self.forward[i]);
        DMat4::from_cols(col(0), col(1), col(2), DVec4::new(0.0, 0.0, self.near, 0.0))
    }

    /// Image coordinates in pixels of a world point (pixel centres at
    /// half-integers), or `None` for a point not in front of the near plane.
    pub fn project(&self, world: DVec3) -> Option<glam::DVec2> {
        let rel = world - self.eye;
        let w = rel.dot(self.forward);
        if w < self.near {
            return None;
        }
        let ndc_x = self.focal / self.aspect * rel.dot(self.right) / w;
        let ndc_y = -self.focal * rel.dot(self.up) / w;
        Some(glam::DVec2::new(
            (ndc_x + 1.0) * 0.5 * f64::from(self.width),
            (ndc_y + 1.0) * 0.5 * f64::from(self.height),
        ))
    }

    /// The unit direction of the ray from the eye through image point
    /// `(x, y)` in pixels (pixel centres at half-integers).
    pub fn ray_direction(&self, x: f64, y: f64) -> DVec3 {
        let ndc_x = 2.0 * x / f64::from(self.width) - 1.0;
        let ndc_y = 2.0 * y / f64::from(self.height) - 1.0;
        let dir = self.forward + self.right * (ndc_x * self.aspect / self.focal)
            - self.up * (ndc_y / self.focal);
        dir.normalize()
    }
}

/// From `eye`: an upper bound on the distance to any point of the scene,
/// and the distance to the nearest surface whose distance is known cheaply
/// and is not zero (infinite where none is): a sphere's from either side
/// (its exact altitude, `huge_sphere::altitude`), a plane's square's, a
/// box's from outside or inside, a mesh's bounding box's from outside (a
/// mesh around the eye says nothing). One pass over each mesh's vertices
/// gives both.
fn scene_distances(scene: &Scene, eye: DVec3) -> (f64, f64) {
    let (mut far, mut nearest) = (0.0f64, f64::INFINITY);
    for object in &scene.objects {
        let (reach, distance) = match &object.shape {
            Shape::Sphere { center, radius, .. } => (
                (*center - eye).length() + radius,
                crate::huge_sphere::altitude(eye, *center, *radius).0.abs(),
            ),
            Shape::Plane {
                center,
                normal,
                size,
                ..
            } => {
                let (u, v) = crate::scene::plane_axes(*normal);
                let rel = eye - *center;
                let half = size * 0.5;
                let (a, b) = (rel.dot(u), rel.dot(v));
                let beyond = DVec3::new((a.abs() - half).max(0.0), (b.abs() - half).max(0.0), 0.0);
                (
                    rel.length() + half * 2f64.sqrt(),
                    (beyond.length_squared() + rel.dot(*normal).powi(2)).sqrt(),
                )
            }
            Shape::Box {
                center,
                half_extents,
                rotation,
            } => {
                let local = (rotation.transpose() * (eye - *center)).abs() - *half_extents;
                let distance = if local.max_element() < 0.0 {
                    -local.max_element()
                } else {
                    local.max(DVec3::ZERO).length()
                };
                ((*center - eye).length() + half_extents.length(), distance)
            }
            Shape::Mesh(mesh) => {
                let (mut reach, mut lo, mut hi) = (0.0f64, DVec3::INFINITY, DVec3::NEG_INFINITY);
                for p in &mesh.positions {
                    reach = reach.max((*p - eye).length());
                    (lo, hi) = (lo.min(*p), hi.max(*p));
                }
                (reach, (lo - eye).max(eye - hi).max(DVec3::ZERO).length())
            }
        };
        far = far.max(reach);
        if distance > 0.0 {
            nearest = nearest.min(distance);
        }
    }
    (far, nearest)
}
