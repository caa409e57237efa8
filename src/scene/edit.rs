//! Changes to a loaded scene that need no second reading of its file: a
//! light moved or turned up between the frames of an animation (the Python
//! package's `Scene.with_light`), each value held to the rule the loader
//! holds the file's to, and refused with the key path a dict would name.

use glam::DVec3;

use super::error::SceneError;
use super::model::Scene;

impl Scene {
    /// This scene with light `index` (0-based) at `position` and of
    /// `intensity` where given: a position finite, an intensity finite
    /// and at least 0 per channel, as `[[lights]]` in a file.
    pub fn with_light(
        &self,
        index: usize,
        position: Option<[f64; 3]>,
        intensity: Option<[f64; 3]>,
    ) -> Result<Scene, SceneError> {
        let at = |key: &str, message: String| SceneError::AtKey {
            key: format!("lights[{index}].{key}"),
            message,
        };
        if index >= self.lights.len() {
            return Err(SceneError::AtKey {
                key: format!("lights[{index}]"),
                message: format!("the scene has {} lights", self.lights.len()),
            });
        }
        if let Some(p) = position.filter(|p| !p.iter().all(|v| v.is_finite())) {
            return Err(at(
                "position",
                format!("{p:?} is not finite; expected finite numbers"),
            ));
        }
        if let Some(i) = intensity.filter(|i| !i.iter().all(|v| v.is_finite() && *v >= 0.0)) {
            return Err(at(
                "intensity",
                format!("{i:?}: expected finite numbers >= 0"),
            ));
        }
        let mut scene = self.clone();
        let light = &mut scene.lights[index];
        if let Some(p) = position {
            light.position = DVec3::from(p);
        }
        if let Some(i) = intensity {
            light.intensity = DVec3::from(i);
        }
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::{default_scene, SceneError};

    #[test]
    fn a_moved_light_is_that_light_alone() {
        let scene = default_scene();
        let moved = scene.with_light(0, Some([1.0, 2.0, 3.0]), None).unwrap();
        assert_eq!(moved.lights[0].position.to_array(), [1.0, 2.0, 3.0]);
        assert_eq!(moved.lights[0].intensity, scene.lights[0].intensity);
        assert_eq!(moved.lights[1..], scene.lights[1..]);
        let brighter = scene.with_light(1, None, Some([2.0, 2.0, 2.0])).unwrap();
        assert_eq!(brighter.lights[1].intensity.to_array(), [2.0, 2.0, 2.0]);
    }

    #[test]
    fn values_the_loader_refuses_are_refused_by_key_path() {
        let scene = default_scene();
        let key = |e: SceneError| match e {
            SceneError::AtKey { key, .. } => key,
            other => panic!("{other:?}"),
        };
        let e = scene
            .with_light(0, Some([f64::NAN, 0.0, 0.0]), None)
            .unwrap_err();
        assert_eq!(key(e), "lights[0].position");
        let e = scene
            .with_light(1, None, Some([1.0, -1.0, 1.0]))
            .unwrap_err();
        assert_eq!(key(e), "lights[1].intensity");
        let e = scene.with_light(9, Some([0.0; 3]), None).unwrap_err();
        assert_eq!(key(e), "lights[9]");
    }
}
