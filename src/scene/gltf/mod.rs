//! glTF 2.0 (`.gltf` with embedded or external buffers, `.glb`) as meshes
//! for a TOML scene, or as a whole scene.
//!
//! # Geometry
//!
//! The default scene (else the first scene; else every node that is no
//! other node's child) is walked depth-first; node transforms are composed
//! in `f64`. Every primitive with mode `TRIANGLES` becomes one
//! [`Object`](crate::scene::Object) with a [`Shape::Mesh`](crate::scene::Shape::Mesh) in world space (other modes are skipped
//! with a warning):
//!
//! - positions are transformed by the world matrix `M` (for a TOML `mesh`
//!   object `M = T * R * S * node_world`); a non-finite position is an error
//!   naming the file, mesh and accessor;
//! - when `det(M) < 0` the winding is flipped (indices 1 and 2 swapped) so
//!   triangles stay counter-clockwise seen from their front;
//! - **degenerate triangles**: a triangle is dropped when two of its indices
//!   are equal or when `|(b - a) x (c - a)| <= 1e-12 * max(|b - a|^2,
//!   |c - a|^2, |c - b|^2)` in world space (twice its area is at most 1e-12
//!   times its longest edge squared, i.e. its vertices are collinear up to
//!   rounding). Each primitive's dropped count is reported in
//!   `Scene::warnings`; a primitive with no triangle left is an error.
//!   Vertices no kept triangle uses are removed;
//! - **normals**: stored normals are transformed by the inverse transpose of
//!   the upper 3x3 of `M` and renormalised. Missing normals are computed
//!   area-weighted: the sum of the unnormalised face normals
//!   `(b - a) x (c - a)` of the kept triangles around the vertex, normalised.
//!   A stored normal that is zero-length or non-finite (before or after the
//!   transform) is replaced by that computed normal. Where the area-weighted
//!   sum itself cancels to zero, the unit face normal of the first kept
//!   triangle using the vertex is used;
//! - the node hierarchy must be a set of disjoint trees (a node reached
//!   twice, through a cycle or two parents, is an error);
//! - an index out of range, a sparse accessor, an accessor of the wrong type
//!   or one that does not fit its buffer view is an error; a primitive whose
//!   node transform is singular (a zero scale) is skipped with a warning.
//!
//! # Materials
//!
//! See [`map_material`] for the exact rule. Materials are added to
//! `Scene::materials` named `<file stem>/<material name or index>` (a
//! primitive without material uses `<file stem>/default`), once per file.
//!
//! # Base colour textures
//!
//! `pbrMetallicRoughness.baseColorTexture` becomes the material's
//! [`Pattern::Image`](crate::scene::Pattern::Image), multiplying
//! `baseColorFactor` (which stays the material's `color`):
//!
//! - texture coordinates: the primitive's `TEXCOORD_n` for the texture's
//!   `texCoord` n (or its `KHR_texture_transform` `texCoord`), floats or
//!   normalised unsigned bytes or shorts; a primitive without that set is
//!   an error naming the primitive, the set and the material;
//! - the sampler: `wrapS`/`wrapT` REPEAT (10497), CLAMP_TO_EDGE (33071),
//!   MIRRORED_REPEAT (33648); `magFilter` NEAREST (9728) or LINEAR (9729);
//!   `minFilter` NEAREST, LINEAR (no mipmaps) or NEAREST_MIPMAP_NEAREST
//!   (9984), LINEAR_MIPMAP_NEAREST (9985), NEAREST_MIPMAP_LINEAR (9986),
//!   LINEAR_MIPMAP_LINEAR (9987) (the first word within a level, the last
//!   between levels). glTF leaves the filters to the viewer where a
//!   sampler or a filter is absent: shadelab takes
//!   [`Sampler::GLTF_DEFAULT`](crate::scene::Sampler::GLTF_DEFAULT)
//!   (REPEAT, LINEAR, LINEAR_MIPMAP_LINEAR). A value glTF does not define
//!   is an error naming the sampler and key;
//! - the image: a buffer view (in a GLB or any buffer), a base64 data URI,
//!   or a file beside the glTF (its URI percent-decoded), PNG or JPEG by
//!   its content, sRGB, decoded once per scene (`image_file`) and refused
//!   before decoding when it would not fit the memory limit. Its alpha is
//!   ignored, with a warning per image where it is not all opaque;
//! - `KHR_texture_transform` on it: `uv' = T R S uv` with `T` the offset,
//!   `S` the scale and `R = [[cos r, sin r], [-sin r, cos r]]` for the
//!   rotation `r` (the extension's convention), as a
//!   [`UvTransform`](crate::scene::UvTransform).
//!
//! # Files
//!
//! - `import.rs`: the entry points (meshes for a TOML `mesh` object, a
//!   whole scene from a file or from memory);
//! - `document.rs`: the file read and parsed, after the checks of
//!   `validation.rs` on its raw JSON, and its buffers loaded by
//!   `buffers.rs` (the GLB's binary chunk, data URIs, files);
//! - `contents.rs`: what a file contributes, walking `nodes.rs` (node
//!   transforms, the instanced size);
//! - `meshes.rs` (with `accessors.rs` and `vertex_attributes.rs`): a
//!   primitive as a triangle mesh;
//! - `materials.rs`, `textures.rs`, `images.rs`: materials and their base
//!   colour textures;
//! - `cameras_and_lights.rs`: a whole scene's camera and lights;
//! - `locations.rs`: how messages name a node, mesh or material;
//! - `uris.rs`: percent escapes in the file names URIs give.

mod accessors;
mod buffers;
mod cameras_and_lights;
mod contents;
mod document;
mod images;
mod import;
mod locations;
mod materials;
mod meshes;
mod nodes;
#[cfg(test)]
mod test_support;
mod textures;
mod uris;
mod validation;
mod vertex_attributes;

pub(crate) use contents::Loading;
pub use import::scene_from_slice;
pub(crate) use import::{load_meshes, load_scene};
pub use materials::map_material;
