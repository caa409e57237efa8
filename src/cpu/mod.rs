//! The CPU reference renderer: double precision, parallel with rayon, and
//! independent of the shaders (it shares only scene loading, tessellation,
//! the ray tracer's scene (`rt_scene`) and the camera with the GPU path).
//! `raster` draws flat, Gouraud and Phong; `raytrace` (with `intersect`)
//! is the ray tracer's twin, `forward` traces light from the lights (the
//! forward tracer), `caustics` keeps the photons that reach a diffuse
//! surface through mirrors and glass (the photon map's, issue 46);
//! `lighting` is the formula both shade with,
//! `surface` the colour a surface point adds to it (its texture reads in
//! `sample`). Every accuracy figure in the project is measured against it.

pub mod caustics;
mod clip;
pub mod forward;
pub mod intersect;
pub mod lighting;
pub mod raster;
pub mod raytrace;
pub mod sample;
pub mod surface;
