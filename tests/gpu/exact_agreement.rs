//! The CPU reference against the GPU where their rules must agree exactly:
//! geometry whose edges and vertices pass through pixel centres, so that the
//! fill rule decides every tie, and near-plane clipping.

use crate::common;

use common::*;
use glam::DVec3;
use shadelab::scene::{Interpolation, Object, Scene, Shape};
use shadelab::shading::Shading;

fn assert_same_everywhere(scene: &Scene, shading: Shading) {
    let gpu_image = render(&gpu(), scene, shading);
    let (cpu, _) = crate::common::render_cpu(scene, shading).unwrap();
    let mut covered = 0;
    for (i, (g, c)) in gpu_image.pixels.iter().zip(&cpu.image.pixels).enumerate() {
        let err = max_abs_diff(to_dvec(*g), to_dvec(*c));
        let (x, y) = (
            i % scene.image.width as usize,
            i / scene.image.width as usize,
        );
        assert!(
            err < FLOAT_TOL,
            "{shading} pixel ({x}, {y}): GPU {g:?} CPU {c:?}"
        );
        if *c != [0.0; 3] {
            covered += 1;
        }
    }
    assert!(covered > 1000, "{shading}: {covered} pixels covered");
}

#[test]
fn fill_rule_agrees_on_edges_through_pixel_centres() {
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        assert_same_everywhere(&grid_scene(), shading);
    }
}

#[test]
fn screen_interpolation_agrees_on_a_tilted_plane() {
    let mut s = scene(96, 96, 40.0);
    s.camera.position = DVec3::new(0.0, 0.0, 6.0);
    s.lighting.interpolation = Interpolation::Screen;
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::new(0.0, 70f64.to_radians().sin(), 70f64.to_radians().cos()),
            size: 3.2,
            segments: 3,
        },
        material: 0,
    });
    // Interior pixels only: the tilted edges do not pass through samples,
    // so their sub-pixel placement may differ (f32 against f64 positions).
    let gpu_image = render(&gpu(), &s, Shading::Gouraud);
    let (cpu, coverage) = crate::common::render_cpu(&s, Shading::Gouraud).unwrap();
    let ids: Vec<Option<usize>> = coverage
        .surface_ids
        .iter()
        .map(|i| i.map(|v| v as usize))
        .collect();
    let interior = interior_pixels(96, 96, &ids);
    assert!(interior.len() > 500);
    for (x, y, _) in interior {
        let err = max_abs_diff(to_dvec(gpu_image.get(x, y)), to_dvec(cpu.image.get(x, y)));
        assert!(err < FLOAT_TOL, "({x}, {y}): {err}");
    }
}

#[test]
fn a_floor_running_under_the_eye_is_clipped_alike() {
    // The camera stands 1 unit above a large floor: the floor crosses the
    // near plane and extends behind the eye.
    let mut s = scene(96, 96, 60.0);
    s.camera.position = DVec3::new(0.0, 1.0, 0.0);
    s.camera.look_at = DVec3::new(0.0, 0.8, -5.0);
    s.lights[0].position = DVec3::new(0.0, 3.0, -4.0);
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Y,
            size: 40.0,
            segments: 1,
        },
        material: 0,
    });
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let gpu_image = render(&gpu(), &s, shading);
        let (cpu, coverage) = crate::common::render_cpu(&s, shading).unwrap();
        assert!(gpu_image.pixels.iter().flatten().all(|v| v.is_finite()));
        assert!(cpu.image.pixels.iter().flatten().all(|v| v.is_finite()));
        let ids: Vec<Option<usize>> = coverage
            .surface_ids
            .iter()
            .map(|i| i.map(|v| v as usize))
            .collect();
        let interior = interior_pixels(96, 96, &ids);
        assert!(
            interior.len() > 2000,
            "{shading}: the floor fills the lower image"
        );
        for (x, y, _) in interior {
            let err = max_abs_diff(to_dvec(gpu_image.get(x, y)), to_dvec(cpu.image.get(x, y)));
            assert!(err < FLOAT_TOL, "{shading} ({x}, {y}): {err}");
        }
    }
}

#[test]
fn screen_interpolation_stays_finite_and_agrees_on_the_default_scene() {
    // The default scene's floor reaches far outside the image; lavapipe's
    // `noperspective` path once returned infinities there, which is why
    // screen-linear interpolation is built from perspective-correct
    // varyings (shaders/include/screen_linear.glsl).
    use shadelab::check::{check, CheckThresholds};
    let mut s = shadelab::scene::default_scene();
    s.image.width = 320;
    s.image.height = 240;
    s.lighting.interpolation = Interpolation::Screen;
    let context = gpu();
    for shading in [Shading::Gouraud, Shading::Phong] {
        let o = check(
            &crate::common::device(&context),
            &s,
            &s,
            shading,
            &CheckThresholds::default(),
        )
        .unwrap();
        assert!(
            o.actual.pixels.iter().flatten().all(|v| v.is_finite()),
            "{shading}: GPU"
        );
        assert!(
            o.expected.pixels.iter().flatten().all(|v| v.is_finite()),
            "{shading}: CPU"
        );
        assert!(o.passed(), "{shading}: {:?}", o.judgement.failures);
    }
}
