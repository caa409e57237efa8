//! How Vulkan gives us things, knowing nothing of scenes or renderers: the
//! instance and device (`context`), memory-backed `buffer`s and
//! `image`s, one-shot `commands`, `descriptors`, `pipeline` objects
//! and the cache of built ones, SPIR-V `specialise`d to a scene's
//! constants, GPU `timestamps`, the validation layer's messages
//! (`validation`), the device features ray queries need (`ray_query`),
//! how long a submission may run (`watchdog`) and the `error`s of it all.

pub mod buffer;
pub mod commands;
pub mod context;
pub mod descriptors;
pub mod error;
pub mod image;
pub mod pipeline;
pub mod ray_query;
pub mod specialise;
pub mod timestamps;
pub mod validation;
pub mod watchdog;
