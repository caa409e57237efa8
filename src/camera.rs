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
        let far = farthest_scene_distance(scene, cam.position).max(1e-6);
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
            // extent from the eye is clipped.
            near: far * 1e-5,
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

/// An upper bound on the distance from `eye` to any point of the scene.
fn farthest_scene_distance(scene: &Scene, eye: DVec3) -> f64 {
    let mut far: f64 = 0.0;
    for object in &scene.objects {
        let reach = match &object.shape {
            Shape::Sphere { center, radius, .. } => (*center - eye).length() + radius,
            Shape::Plane { center, size, .. } => {
                (*center - eye).length() + size * 0.5 * 2f64.sqrt()
            }
            Shape::Box {
                center,
                half_extents,
                ..
            } => (*center - eye).length() + half_extents.length(),
            Shape::Mesh(mesh) => mesh
                .positions
                .iter()
                .map(|p| (*p - eye).length())
                .fold(0.0, f64::max),
        };
        far = far.max(reach);
    }
    far
}
