//! A glTF file's camera and lights as a scene's: the first usable
//! perspective camera of the node tree (else one framing the bounding
//! box), its `KHR_lights_punctual` point lights (else one at the camera).

use glam::{DMat4, DVec3};

use super::accessors::f32x3;
use super::document::GltfFile;
use super::locations::node_name;
use crate::scene::defaults::DEFAULT_FOV_Y_DEG;
use crate::scene::error::SceneError;
use crate::scene::model::{Camera, Object, PointLight, Shape};

/// The bounding box of the objects' meshes: its low and high corners.
pub(super) fn bounds(objects: &[Object]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for o in objects {
        if let Shape::Mesh(m) = &o.shape {
            for p in &m.positions {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
    }
    (lo, hi)
}

/// The first usable perspective camera of `nodes` (depth-first order), at
/// its node's world position looking down local -Z with local +Y up; an
/// unusable one is skipped with a warning.
pub(super) fn node_camera(
    file: &GltfFile,
    nodes: &[(gltf::Node, DMat4)],
    warnings: &mut Vec<String>,
) -> Option<Camera> {
    for (node, world) in nodes {
        let Some(cam) = node.camera() else { continue };
        let gltf::camera::Projection::Perspective(persp) = cam.projection() else {
            continue;
        };
        let fov = f64::from(persp.yfov()).to_degrees();
        let position = world.transform_point3(DVec3::ZERO);
        let forward = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(DVec3::Y).normalize_or_zero();
        let usable = fov > 0.0
            && fov < 180.0
            && position.is_finite()
            && forward != DVec3::ZERO
            && up.cross(forward).length() > 1e-9;
        if !usable {
            warnings.push(format!(
                "{}: camera on {} is unusable (field of view {fov} degrees or a degenerate node transform); it was ignored",
                file.label,
                node_name(node)
            ));
            continue;
        }
        return Some(Camera {
            position,
            look_at: position + forward,
            up,
            fov_y_deg: fov,
        });
    }
    None
}

/// The camera of a file without one: looking at the centre of the bounding
/// box `lo`..`hi` from +Z, where the bounding sphere fits the default field
/// of view.
pub(super) fn framing_camera(lo: DVec3, hi: DVec3) -> Camera {
    let center = (lo + hi) * 0.5;
    let fov = DEFAULT_FOV_Y_DEG;
    let radius = ((hi - lo).length() * 0.5).max(1e-6);
    let distance = radius / (fov.to_radians() * 0.5).sin();
    Camera {
        position: center + DVec3::Z * distance,
        look_at: center,
        up: DVec3::Y,
        fov_y_deg: fov,
    }
}

/// The `KHR_lights_punctual` point lights of `nodes` at their nodes' world
/// positions, `intensity = color * intensity`; `range` is ignored and spot
/// and directional lights skipped, each with a warning.
pub(super) fn point_lights(
    file: &GltfFile,
    nodes: &[(gltf::Node, DMat4)],
    warnings: &mut Vec<String>,
) -> Result<Vec<PointLight>, SceneError> {
    let mut lights = Vec::new();
    for (node, world) in nodes {
        let Some(light) = node.light() else { continue };
        match light.kind() {
            gltf::khr_lights_punctual::Kind::Point => {
                let intensity = f32x3(light.color()) * f64::from(light.intensity());
                let position = world.transform_point3(DVec3::ZERO);
                if !intensity.is_finite() || intensity.min_element() < 0.0 || !position.is_finite()
                {
                    return Err(SceneError::mesh(
                        &file.label,
                        format!(
                            "point light on {} has a negative or non-finite intensity or position; expected finite values >= 0",
                            node_name(node)
                        ),
                    ));
                }
                if let Some(range) = light.range() {
                    warnings.push(format!(
                        "{}: the point light on {} has range {range}, which is ignored: lights fall off as Il / (d + k) (docs/lighting-model.md)",
                        file.label,
                        node_name(node)
                    ));
                }
                lights.push(PointLight {
                    position,
                    intensity,
                });
            }
            other => warnings.push(format!(
                "{}: {} light on {} is not supported (only point lights are); it was skipped",
                file.label,
                match other {
                    gltf::khr_lights_punctual::Kind::Directional => "directional",
                    _ => "spot",
                },
                node_name(node)
            )),
        }
    }
    Ok(lights)
}

/// The light of a file without a point light: at the camera, with
/// intensity `d`, the distance to the bounding box's `center` (so that
/// `Il / (d + k)` is about 1 there), with a warning.
pub(super) fn light_at_camera(
    file: &GltfFile,
    camera: &Camera,
    center: DVec3,
    warnings: &mut Vec<String>,
) -> PointLight {
    let d = (camera.position - center).length().max(1e-6);
    warnings.push(format!(
        "{}: the file has no point light; added one at the camera with intensity {d:.3} so the scene is lit",
        file.label
    ));
    PointLight {
        position: camera.position,
        intensity: DVec3::splat(d),
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::scene::gltf::test_support::fixture;
    use crate::scene::model::RenderSettings;

    #[test]
    fn gltf_as_scene_uses_camera_and_point_light() {
        let s = crate::scene::load(&fixture("scene_with_camera_light.gltf")).unwrap();
        assert_eq!(s.camera.position, DVec3::new(0.0, 0.0, 5.0));
        assert!((s.camera.look_at - DVec3::new(0.0, 0.0, 4.0)).length() < 1e-12);
        assert_eq!(s.camera.up, DVec3::Y);
        assert!((s.camera.fov_y_deg - 0.5f64.to_degrees()).abs() < 1e-9);
        assert_eq!(s.lights.len(), 1, "the spot light is skipped");
        assert_eq!(s.lights[0].position, DVec3::new(2.0, 3.0, 4.0));
        assert_eq!(s.lights[0].intensity, DVec3::new(4.0, 2.0, 1.0));
        assert!(
            s.warnings.iter().any(|w| w.contains("spot")),
            "{:?}",
            s.warnings
        );
        // Intensity is colour times intensity (above); range is ignored, said.
        assert!(
            s.warnings
                .iter()
                .any(|w| w.contains("has range 10, which is ignored")),
            "{:?}",
            s.warnings
        );
        assert_eq!(s.objects.len(), 1);
        let m = &s.materials[s.objects[0].material];
        assert_eq!(m.name, "scene_with_camera_light/window");
        assert_eq!((m.kt, m.ior, m.p, m.kd), (0.75, 1.25, 500.0, 0.8));
        assert!((m.ks - 0.04).abs() < 1e-12);
        assert_eq!((s.image.width, s.image.height), (640, 480));
        assert_eq!(s.lighting.ambient, DVec3::splat(0.2));
        assert_eq!(s.render, RenderSettings::default());
    }

    #[test]
    fn gltf_without_camera_or_light_is_framed_and_lit() {
        let s = crate::scene::load(&fixture("cube.glb")).unwrap();
        assert_eq!(s.camera.look_at, DVec3::ZERO);
        let d = s.camera.position.z;
        let r = 0.75f64.sqrt();
        assert!((d - r / 20f64.to_radians().sin()).abs() < 1e-9);
        assert_eq!(s.camera.fov_y_deg, 40.0);
        assert_eq!(s.lights.len(), 1);
        assert_eq!(s.lights[0].position, s.camera.position);
        assert!((s.lights[0].intensity - DVec3::splat(d)).length() < 1e-12);
        assert!(s.warnings.iter().any(|w| w.contains("no point light")));
    }
}
