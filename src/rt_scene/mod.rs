//! The scene as both ray tracers (the compute shader and the CPU twin) see
//! it: exact spheres, finite planes and oriented boxes, mesh triangles with a
//! bounding volume hierarchy, materials and lights. Everything is in
//! camera-relative coordinates (world minus eye, subtracted in `f64`), so the
//! eye is the origin and scenes far from the world origin keep precision.
//!
//! Every primitive carries the index of the scene object it came from: when
//! two hits are at exactly the same distance the lower index wins, the
//! same rule as the raster modes' "first drawn wins".
//!
//! `primitives.rs` holds the primitive kinds (and `Primitive`, which of
//! them a hit is on), `scene.rs` builds `RtScene` from a `Scene`, `bvh.rs`
//! the tree over its triangles and the widening both tracers give its
//! boxes, `bvh_cache.rs` the GPU's copy of a big mesh's tree in the cache
//! folder, `rays.rs` what both tracers agree on per pixel (sample grid, ray
//! counts), `light_shares.rs` how forward tracing splits its photons
//! over the lights.

mod bvh;
mod bvh_cache;
mod light_shares;
mod primitives;
mod rays;
mod scene;

pub use bvh::{widened_box, BOX_WIDENING};
pub use light_shares::{LightShares, SHARE_UNITS};
pub use primitives::{Primitive, RtBox, RtHugeSphere, RtPlane, RtSphere, RtTriangle};
pub use rays::{sample_grid, RayStats};
pub use scene::RtScene;
