//! A render's watchdog (`vk::watchdog`) from its scene: the limit its
//! `render.watchdog` sets, and its lighting hook as the likely cause of a
//! submission that never ends (a hook is the one piece of shader code a
//! user brings).

use crate::gpu::vk::watchdog::{watch, Guard, Watch};
use crate::scene::Scene;

/// Watches this thread's submissions as `scene` says, until the guard is
/// dropped.
pub(crate) fn watch_render(scene: &Scene) -> Guard {
    watch(Watch {
        limit: scene.render.watchdog,
        cause: scene.lighting_hook.as_ref().map(|h| h.path.as_str().into()),
    })
}
