//! The CPU reference renderer: double precision, parallel with rayon, and
//! independent of the shaders (it shares only scene loading, tessellation
//! and the camera with the GPU path). Every accuracy figure in the project is
//! measured against it.

mod clip;
pub mod lighting;
pub mod raster;
