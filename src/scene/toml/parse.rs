//! From TOML text to a validated [`Scene`], table by table in a fixed
//! order (camera, image, lighting, lights, materials, objects, render), so
//! that of two errors the first in that order is the one reported.

use std::path::Path;

use super::camera_lights::{camera, lighting, lights, refuse_narrow_view};
use super::checks::Ctx;
use super::located_errors::toml_error;
use super::materials::materials;
use super::render_settings::{image, render};
use super::schema::FileRaw;
use super::shapes::objects;
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;
use crate::scene::image_file::TextureStore;
use crate::scene::model::Scene;

/// Parses and validates a TOML scene. `base_dir` resolves mesh paths;
/// `label` names the file in messages.
pub fn parse(text: &str, base_dir: &Path, label: &str) -> Result<Scene, SceneError> {
    parse_within(text, base_dir, label, &LoadLimits::default())
}

/// As [`parse`], each mesh file held to `limits` (`footprint`).
pub fn parse_within(
    text: &str,
    base_dir: &Path,
    label: &str,
    limits: &LoadLimits,
) -> Result<Scene, SceneError> {
    let raw: FileRaw = toml::from_str(text).map_err(|e| toml_error(label, text, &e))?;
    let cx = Ctx {
        label,
        text,
        base_dir,
        limits,
    };
    let cam = raw.camera.get_ref();
    let camera = camera(&cx, cam)?;
    let image = image(&cx, raw.image.as_ref())?;
    refuse_narrow_view(&cx, cam, &camera, &image)?;
    let lighting = lighting(&cx, raw.lighting.as_ref())?;
    let lights = lights(&cx, &raw.lights)?;
    let mut warnings = Vec::new();
    let mut textures = TextureStore::default();
    let mut materials = materials(&cx, &raw.materials, &mut textures, &mut warnings)?;
    let names: Vec<String> = raw.materials.keys().cloned().collect();
    let objects = objects(
        &cx,
        &raw.objects,
        &names,
        camera.position,
        &mut materials,
        &mut warnings,
        &mut textures,
    )?;
    let render = render(&cx, raw.render.as_ref())?;
    Ok(Scene {
        camera,
        image,
        lighting,
        lights,
        materials,
        objects,
        render,
        lighting_hook: None,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::super::test_support::*;
    use super::*;
    use crate::scene::model::{
        Falloff, ImageSettings, Interpolation, Lighting, Material, RenderSettings, Shape, Traversal,
    };

    /// The example of `docs/interface.md`, verbatim.
    const INTERFACE_EXAMPLE: &str = r#"[camera]
position = [0.0, 1.5, 6.0]
look_at  = [0.0, 0.0, 0.0]
up       = [0.0, 1.0, 0.0]   # optional, this default
fov_y    = 40.0              # degrees, vertical

[image]
width      = 640
height     = 480
background = [0.05, 0.05, 0.08]   # linear RGB

[lighting]
ambient = 0.2          # Ia: a number or [r, g, b]
k       = 1.0          # the constant in Il / (d + k)
interpolation = "perspective"   # or "screen" (the lecture's scanline rule)

[[lights]]
position  = [4.0, 6.0, 5.0]
intensity = 8.0        # Il: a number or [r, g, b]

[materials.plaster]
color = [0.9, 0.85, 0.8]
ka = 0.3
kd = 0.7
ks = 0.2
p  = 20
kr = 0.0               # reflectance   (ray tracing)
kt = 0.0               # transmittance (ray tracing)
ior = 1.0

[materials.glass]
color = [1.0, 1.0, 1.0]
ka = 0.0
kd = 0.05
ks = 0.8
p  = 300
kr = 0.1
kt = 0.85
ior = 1.5

[[objects]]
shape    = "sphere"
center   = [0.0, 0.0, 0.0]
radius   = 1.0
segments = 48          # tessellation for the raster modes; the ray tracer
                       # intersects the exact sphere
material = "glass"

[[objects]]
shape    = "plane"     # a finite square, the same in every mode
center   = [0.0, -1.0, 0.0]
normal   = [0.0, 1.0, 0.0]
size     = 12.0
material = "plaster"

[[objects]]
shape    = "mesh"
file     = "models/teapot.glb"
translate = [2.0, -1.0, 0.0]
rotate_deg = [0.0, 30.0, 0.0]    # XYZ Euler angles
scale    = 0.5                   # a number or [x, y, z]
material = "plaster"             # optional: overrides the file's materials

[render]                          # optional defaults, each also a CLI flag
depth   = 5                       # ray tracing: maximum recursion depth
cutoff  = 0.001                   # ray tracing: adaptive depth cut-off
shadows = true
samples = 1                       # ray tracing: samples per pixel
msaa    = 1                       # raster modes: samples per pixel ("4,per-sample": shade each)
"#;

    #[test]
    fn interface_example_parses_verbatim() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("models")).unwrap();
        std::fs::copy(fixture("cube.glb"), dir.path().join("models/teapot.glb")).unwrap();
        let s = parse(INTERFACE_EXAMPLE, dir.path(), "interface.toml")
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.camera.position, DVec3::new(0.0, 1.5, 6.0));
        assert_eq!(s.camera.look_at, DVec3::ZERO);
        assert_eq!(s.camera.up, DVec3::Y);
        assert_eq!(s.camera.fov_y_deg, 40.0);
        assert_eq!((s.image.width, s.image.height), (640, 480));
        assert_eq!(s.image.background, DVec3::new(0.05, 0.05, 0.08));
        assert_eq!(s.lighting.ambient, DVec3::splat(0.2));
        assert_eq!(s.lighting.k, 1.0);
        assert_eq!(s.lighting.interpolation, Interpolation::Perspective);
        assert_eq!(s.lighting.falloff, Falloff::Lecture);
        assert_eq!(s.lights.len(), 1);
        assert_eq!(s.lights[0].position, DVec3::new(4.0, 6.0, 5.0));
        assert_eq!(s.lights[0].intensity, DVec3::splat(8.0));
        let plaster = s
            .materials
            .iter()
            .position(|m| m.name == "plaster")
            .unwrap();
        let glass = s.materials.iter().position(|m| m.name == "glass").unwrap();
        let p = &s.materials[plaster];
        assert_eq!(p.color, DVec3::new(0.9, 0.85, 0.8));
        assert_eq!(
            (p.ka, p.kd, p.ks, p.p, p.kr, p.kt, p.ior),
            (0.3, 0.7, 0.2, 20.0, 0.0, 0.0, 1.0)
        );
        let g = &s.materials[glass];
        assert_eq!(
            (g.ka, g.kd, g.ks, g.p, g.kr, g.kt, g.ior),
            (0.0, 0.05, 0.8, 300.0, 0.1, 0.85, 1.5)
        );
        assert_eq!(s.objects.len(), 3);
        assert!(
            matches!(s.objects[0].shape, Shape::Sphere { radius, segments: 48, .. } if radius == 1.0)
        );
        assert_eq!(s.objects[0].material, glass);
        match s.objects[1].shape {
            Shape::Plane {
                center,
                normal,
                size,
                segments,
            } => {
                assert_eq!(
                    (center, normal, size, segments),
                    (DVec3::new(0.0, -1.0, 0.0), DVec3::Y, 12.0, 1)
                );
            }
            ref other => panic!("{other:?}"),
        }
        assert_eq!(s.objects[1].material, plaster);
        // The mesh: T * R * S applied to the cube's corner (0.5, 0.5, 0.5).
        assert_eq!(s.objects[2].material, plaster, "material override");
        assert_eq!(
            s.materials.len(),
            2,
            "overridden file materials are not added"
        );
        let Shape::Mesh(m) = &s.objects[2].shape else {
            panic!()
        };
        assert_eq!(m.triangles.len(), 12);
        let expected = DVec3::new(2.0, -1.0, 0.0)
            + DMat3::from_rotation_y(30f64.to_radians()) * DVec3::splat(0.25);
        assert!(m.positions.iter().any(|p| (*p - expected).length() < 1e-9));
        assert_eq!(
            s.render,
            RenderSettings {
                depth: 5,
                depth_given: true,
                cutoff: 0.001,
                shadows: true,
                samples: 1,
                bounces: 0,
                photons: 1 << 22,
                caustics: crate::scene::CausticSettings::default(),
                traversal: Traversal::Auto,
                msaa: crate::msaa::Msaa::default(),
                watchdog: Some(std::time::Duration::from_secs(120)),
            }
        );
        assert!(s.warnings.is_empty());
    }

    #[test]
    fn every_default() {
        let s = parse_ok(&with_camera(
            "[materials.m]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n\
             [[objects]]\nshape = \"plane\"\ncenter = [0, -1, 0]\nnormal = [0, 3, 0]\nsize = 4\nmaterial = \"m\"\n\
             [[objects]]\nshape = \"box\"\ncenter = [1, 2, 3]\nsize = 2\nmaterial = \"m\"\n",
        ));
        assert_eq!(s.camera.up, DVec3::Y);
        assert_eq!(s.camera.fov_y_deg, 40.0);
        assert_eq!(
            s.image,
            ImageSettings {
                width: 640,
                height: 480,
                background: DVec3::new(0.05, 0.05, 0.08)
            }
        );
        assert_eq!(
            s.lighting,
            Lighting {
                ambient: DVec3::splat(0.2),
                k: 1.0,
                interpolation: Interpolation::Perspective,
                falloff: Falloff::Lecture,
            }
        );
        assert!(s.lights.is_empty());
        assert_eq!(
            s.materials[0],
            Material {
                name: "m".into(),
                color: DVec3::ONE,
                ka: 0.2,
                kd: 0.8,
                ks: 0.0,
                p: 32.0,
                kr: 0.0,
                kt: 0.0,
                ior: 1.0,
                pattern: None,
            }
        );
        assert!(matches!(
            s.objects[0].shape,
            Shape::Sphere { segments: 32, .. }
        ));
        match s.objects[1].shape {
            Shape::Plane {
                normal, segments, ..
            } => assert_eq!((normal, segments), (DVec3::Y, 1)),
            ref o => panic!("{o:?}"),
        }
        match s.objects[2].shape {
            Shape::Box {
                center,
                half_extents,
                rotation,
            } => {
                assert_eq!(center, DVec3::new(1.0, 2.0, 3.0));
                assert_eq!(half_extents, DVec3::ONE);
                assert_eq!(rotation, DMat3::IDENTITY);
            }
            ref o => panic!("{o:?}"),
        }
        assert_eq!(s.render, RenderSettings::default());
    }

    /// `falloff` by name; the older `attenuation` agrees with it or is an
    /// error at the `falloff` line; an unknown name lists the known ones.
    #[test]
    fn falloff_by_name_and_its_older_spelling() {
        let falloff = |lighting: &str| {
            parse_ok(&with_camera(&format!("[lighting]\n{lighting}\n")))
                .lighting
                .falloff
        };
        assert_eq!(
            falloff("falloff = \"inverse-square\""),
            Falloff::InverseSquare
        );
        assert_eq!(falloff("falloff = \"none\""), Falloff::None);
        assert_eq!(falloff("falloff = \"lecture\""), Falloff::Lecture);
        assert_eq!(falloff("attenuation = false"), Falloff::None);
        assert_eq!(
            falloff("attenuation = false\nfalloff = \"none\""),
            Falloff::None
        );
        let e = parse_err(&with_camera(
            "[lighting]\nattenuation = false\nfalloff = \"inverse-square\"\n",
        ));
        assert!(
            e.contains("contradicts `lighting.attenuation = false`"),
            "{e}"
        );
        let e = parse_err(&with_camera("[lighting]\nfalloff = \"quadratic\"\n"));
        assert!(e.contains("inverse-square"), "{e}");
    }

    #[test]
    fn extensions_and_alternative_forms() {
        let s = parse_ok(&with_camera(
            "[lighting]\nambient = [0.1, 0.2, 0.3]\nk = 0\ninterpolation = \"screen\"\nattenuation = false\n\
             [[lights]]\nposition = [1, 2, 3]\nintensity = [1, 0.5, 0]\n\
             [materials.m]\n[[objects]]\nshape = \"box\"\ncenter = [0, 0, 0]\nsize = [2, 4, 6]\nrotate_deg = [0, 90, 0]\nmaterial = \"m\"\n\
             [render]\ndepth = 3\ncutoff = 0\nshadows = false\nsamples = 16\nbounces = 3\nphotons = 1000\ncaustics = 5000\ncaustic_passes = 7\ncaustic_radius = 1.5\ntraversal = \"query\"\nmsaa = \"4,per-sample\"\nwatchdog = 2.5\n",
        ));
        assert_eq!(s.lighting.ambient, DVec3::new(0.1, 0.2, 0.3));
        assert_eq!(s.lighting.k, 0.0);
        assert_eq!(s.lighting.interpolation, Interpolation::Screen);
        assert_eq!(s.lighting.falloff, Falloff::None);
        assert_eq!(s.lights[0].intensity, DVec3::new(1.0, 0.5, 0.0));
        let Shape::Box {
            half_extents,
            rotation,
            ..
        } = s.objects[0].shape
        else {
            panic!()
        };
        assert_eq!(half_extents, DVec3::new(1.0, 2.0, 3.0));
        // 90 degrees about Y maps +X to -Z.
        assert!((rotation * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        assert_eq!(
            s.render,
            RenderSettings {
                depth: 3,
                depth_given: true,
                cutoff: 0.0,
                shadows: false,
                samples: 16,
                bounces: 3,
                photons: 1000,
                caustics: crate::scene::CausticSettings {
                    photons_per_pass: 5000,
                    passes: 7,
                    initial_radius: 1.5,
                    alpha: crate::scene::defaults::CAUSTIC_ALPHA,
                },
                traversal: Traversal::Query,
                msaa: crate::msaa::Msaa {
                    samples: 4,
                    per_sample: true,
                },
                watchdog: Some(std::time::Duration::from_millis(2500)),
            }
        );
    }
}
