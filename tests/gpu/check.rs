//! `check` passes where GPU and CPU implement the same contract, and fails
//! when the reference is perturbed in the small ways a real defect looks
//! like: a light moved by 1%, `p` off by one, one normal flipped, the
//! interpolation rule swapped.

use crate::common;

use common::{asset_scenes, gpu};
use shadelab::check::{check, CheckThresholds};
use shadelab::scene::{self, tessellate, Interpolation, Scene, Shape};
use shadelab::shading::Shading;

const MODES: [Shading; 3] = [Shading::Flat, Shading::Gouraud, Shading::Phong];
const ALL_MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

fn small(mut scene: Scene) -> Scene {
    scene.image.width = 320;
    scene.image.height = 240;
    scene
}

fn assets() -> Vec<(String, Scene)> {
    let scenes = asset_scenes();
    assert!(scenes.len() > 1, "assets/ holds example scenes");
    scenes
}

#[test]
fn every_mode_of_every_scene_passes() {
    let context = gpu();
    for (name, scene) in assets() {
        for mode in ALL_MODES {
            let limits = CheckThresholds::for_shading(mode);
            let o = check(
                &crate::common::device(&context),
                &scene,
                &scene,
                mode,
                &limits,
            )
            .unwrap();
            assert!(o.passed(), "{name} {mode}: {:?}", o.judgement.failures);
            // The case's time holds both renders, which run side by side:
            // at least the longer one. (No upper bound: on a busy 2-core
            // machine the two slow each other, and each one's own clock
            // starts after the thread hand-over.)
            let longer = o.gpu_ms.max(o.cpu_ms);
            assert!(
                o.renders_ms >= longer,
                "{name} {mode}: renders {} ms, GPU {} ms, CPU {} ms",
                o.renders_ms,
                o.gpu_ms,
                o.cpu_ms
            );
        }
    }
}

/// Checks the GPU render of `scene` against the CPU render of `reference`
/// and asserts the verdict is a failure for each of `modes`.
fn assert_caught(scene: &Scene, reference: &Scene, modes: &[Shading], what: &str) {
    let context = gpu();
    for &mode in modes {
        let o = check(
            &crate::common::device(&context),
            scene,
            reference,
            mode,
            &CheckThresholds::for_shading(mode),
        )
        .unwrap();
        assert!(
            !o.passed(),
            "{what} in {mode} went unnoticed: interior max {:.2e}",
            o.judgement.interior.max_abs
        );
        eprintln!("{what} in {mode}: {}", o.judgement.failures.join("; "));
    }
}

#[test]
fn a_light_moved_by_one_percent_is_caught() {
    let scene = small(scene::default_scene());
    let mut reference = scene.clone();
    reference.lights[0].position *= 1.01;
    assert_caught(&scene, &reference, &ALL_MODES, "light moved by 1%");
}

#[test]
fn glossiness_off_by_one_is_caught() {
    // At the default scene's p = 100 and 300, one step of p moves S = x^p by
    // at most max|x^p ln x| / p = 1/(e p) < 4e-3 before the ks and light
    // factors, and flat shading samples S at face centroids only, which the
    // highlight rarely hits: 8e-5 measured, below any fair threshold. So the
    // scene's glossy materials get p = 20, where one step is clearly visible.
    let mut scene = small(scene::default_scene());
    for m in &mut scene.materials {
        if m.ks > 0.0 {
            m.p = 20.0;
        }
    }
    let mut reference = scene.clone();
    for m in &mut reference.materials {
        m.p += 1.0;
    }
    assert_caught(&scene, &reference, &MODES, "p off by one");
}

#[test]
fn one_flipped_normal_is_caught() {
    // The glossy red sphere as an explicit mesh, so one of its normals can be
    // flipped in the reference alone.
    let mut scene = small(scene::default_scene());
    let red = scene
        .objects
        .iter()
        .position(|o| scene.materials[o.material].name == "red_gloss")
        .expect("the default scene has the red sphere");
    let mesh = tessellate(&scene.objects[red].shape);
    scene.objects[red].shape = Shape::Mesh(mesh.clone());

    // Gouraud and Phong read vertex normals: flip the one nearest the
    // highlight side (facing the camera).
    let mut reference = scene.clone();
    let to_eye = (scene.camera.position - mesh.positions[0]).normalize();
    let facing = (0..mesh.normals.len())
        .max_by(|&a, &b| {
            mesh.normals[a]
                .dot(to_eye)
                .total_cmp(&mesh.normals[b].dot(to_eye))
        })
        .unwrap();
    if let Shape::Mesh(m) = &mut reference.objects[red].shape {
        m.normals[facing] = -m.normals[facing];
    }
    assert_caught(
        &scene,
        &reference,
        &[Shading::Gouraud, Shading::Phong],
        "one vertex normal flipped",
    );

    // Flat reads the geometric normal. (Flipping a triangle's winding no
    // longer shows: a face seen from behind is lit as its back, which is
    // the flipped face lit as its front; docs/lighting-model.md, "Which
    // side is lit".) Tilt the facets around the facing vertex instead, by
    // moving it outward by 0.05 (the sphere's radius is 0.8).
    let mut reference = scene.clone();
    if let Shape::Mesh(m) = &mut reference.objects[red].shape {
        m.positions[facing] += 0.05 * m.normals[facing];
    }
    assert_caught(
        &scene,
        &reference,
        &[Shading::Flat],
        "the facets around one vertex tilted",
    );
}

#[test]
fn swapped_interpolation_is_caught() {
    let scene = small(scene::default_scene());
    let mut reference = scene.clone();
    reference.lighting.interpolation = Interpolation::Screen;
    // Flat has nothing to interpolate.
    assert_caught(
        &scene,
        &reference,
        &[Shading::Gouraud, Shading::Phong],
        "interpolation swapped",
    );
}
