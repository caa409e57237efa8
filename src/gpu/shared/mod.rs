//! What every renderer compiles and uploads the same way: the
//! `shader_catalog` build.rs compiled, the built-in shaders recompiled
//! with a user's lighting `hook`, the scene's `lights` and pattern
//! constants as `shaders/include/lights.glsl` and `pattern.glsl` read them,
//! its image textures (`texture_table`), and the `image_size` a device
//! renders, and the `watch` a render keeps on its submissions.

pub mod hook;
pub(crate) mod image_size;
pub mod lights;
pub mod shader_catalog;
pub mod texture_table;
pub(crate) mod watch;
