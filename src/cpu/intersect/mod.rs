//! Ray intersection for the CPU ray tracer, in `f64`: exact spheres, finite
//! planes, oriented boxes and mesh triangles (through the BVH of
//! `rt_scene::RtScene`), following `docs/raytracing.md` ("Nearest hit")
//! formula for formula, so that the compute shader can do the same in `f32`.
//!
//! It owns only geometry: no shading, no ray tree (that is `raytrace`).
//! One file per primitive kind (`sphere.rs`, `plane.rs`, `cuboid.rs`,
//! `triangle.rs`), the walk of the BVH (`bvh_walk.rs`), and `accel.rs`,
//! which asks them all for the nearest hit or any hit of a ray, with the
//! tie rule of `hit.rs`.

mod accel;
mod bvh_walk;
mod cuboid;
mod hit;
mod plane;
mod sphere;
#[cfg(test)]
mod test_support;
mod triangle;

pub use accel::Accel;
pub use cuboid::cuboid;
pub use hit::{Hit, Ray};
pub use plane::plane;
pub use sphere::{huge_sphere, sphere};
pub use triangle::{triangle, triangle_normal};
