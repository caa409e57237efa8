//! The hard-case suite (assets/hard/): every scene in every mode, GPU and
//! CPU, finite everywhere and within `check`'s thresholds; and the exact
//! answers the cases have.

#[path = "hard_cases/answers.rs"]
mod answers;
use crate::common;
#[path = "hard_cases/huge_spheres.rs"]
mod huge_spheres;

use std::path::PathBuf;

use common::*;
use glam::DVec3;
use shadelab::check::{check, scaled, CheckThresholds};
use shadelab::scene::{self, Object, Scene, Shape, Traversal, TriangleMesh};
use shadelab::shading::Shading;

const MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

fn hard(name: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/hard")
        .join(name);
    scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_hard_case_is_finite_and_within_thresholds_in_every_mode() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/hard");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 38, "the suite lost scenes: {names:?}");
    // And the cases that ask of f32 what it cannot give, in refused/:
    // refused at load (answers::what_f32_cannot_render_is_refused_with_its_line).
    let refused: Vec<_> = std::fs::read_dir(dir.join("refused"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(
        refused.len() >= 2,
        "the refused cases are gone: {refused:?}"
    );
    for path in refused {
        assert!(scene::load(&path).is_err(), "{} loads", path.display());
    }
    let context = gpu();
    for name in names {
        let s = hard(&name);
        for mode in MODES {
            let o = check(
                &crate::common::device(&context),
                &s,
                &s,
                mode,
                &CheckThresholds::for_shading(mode),
            )
            .unwrap();
            assert!(
                o.actual.pixels.iter().flatten().all(|v| v.is_finite()),
                "{name} {mode}: GPU non-finite"
            );
            assert!(
                o.expected.pixels.iter().flatten().all(|v| v.is_finite()),
                "{name} {mode}: CPU non-finite"
            );
            assert!(o.passed(), "{name} {mode}: {:?}", o.judgement.failures);
        }
        // The ray-query engine, held to the same limits.
        for engine in engines(&context).into_iter().skip(1) {
            let q = with_engine(&s, engine);
            let limits = CheckThresholds::for_shading(Shading::Raytrace);
            let o = check(
                &crate::common::device(&context),
                &q,
                &q,
                Shading::Raytrace,
                &limits,
            )
            .unwrap();
            assert!(
                o.actual.pixels.iter().flatten().all(|v| v.is_finite()),
                "{name} {engine:?}: GPU non-finite"
            );
            assert!(o.passed(), "{name} {engine:?}: {:?}", o.judgement.failures);
        }
    }
}

/// A light in the floor's own plane faces it by rounding only: the floor
/// gets exactly its ambient term, in every mode, GPU and CPU alike.
#[test]
fn a_light_in_the_surface_plane_adds_nothing_to_it() {
    for name in ["grazing-light.toml", "light-on-surface.toml"] {
        let s = hard(name);
        let floor = &s.materials[s.objects[0].material];
        let ambient = s.lighting.ambient * floor.ka * floor.color;
        let v = view(&s);
        // A floor point away from the sphere and the light.
        let at = v.project(DVec3::new(-2.0, 0.0, 2.0)).unwrap();
        let (x, y) = (at.x as u32, at.y as u32);
        let context = gpu();
        for mode in MODES {
            let gpu_value = to_dvec(render(&context, &s, mode).get(x, y));
            let (cpu, _) = crate::common::render_cpu(&s, mode).unwrap();
            for (side, value) in [("GPU", gpu_value), ("CPU", to_dvec(cpu.image.get(x, y)))] {
                assert!(
                    max_abs_diff(value, ambient) < 1e-6,
                    "{name} {mode} {side}: {value} vs ambient {ambient}"
                );
            }
        }
    }
}

/// Far from the origin, camera-relative coordinates make the images those of
/// the same scene moved to the origin.
#[test]
fn a_far_sphere_renders_as_if_at_the_origin() {
    let context = gpu();
    for name in ["far-sphere-1e4.toml", "far-sphere-1e5.toml"] {
        let far = hard(name);
        let mut near = far.clone();
        let shift = DVec3::new(-far.camera.look_at.x, 0.0, 0.0);
        near.camera.position += shift;
        near.camera.look_at += shift;
        for l in &mut near.lights {
            l.position += shift;
        }
        for o in &mut near.objects {
            if let Shape::Sphere { center, .. } = &mut o.shape {
                *center += shift;
            }
        }
        for mode in MODES {
            let (a, b) = (render(&context, &far, mode), render(&context, &near, mode));
            let worst = worst_difference(&a, &b);
            // The host subtracts the eye in f64, so the GPU sees the same f32
            // inputs up to the f64 rounding of 1e5-sized sums (~1e-11).
            // Measured: 0 on the GPU, 1.5e-8 (one f32 step of the stored
            // value) on the CPU. World-space f32 at 1e5 would be off by
            // ~0.01 in position, and by far more than 1e-6 in the image.
            assert!(
                worst < 1e-6,
                "{name} {mode}: GPU far vs near differ by {worst}"
            );
            let (fc, _) = crate::common::render_cpu(&far, mode).unwrap();
            let (nc, _) = crate::common::render_cpu(&near, mode).unwrap();
            let worst = worst_difference(&fc.image, &nc.image);
            assert!(
                worst < 1e-6,
                "{name} {mode}: CPU far vs near differ by {worst}"
            );
        }
    }
}

/// Of two coincident planes the first listed wins everywhere, in every mode:
/// the image equals the scene without the second plane, on GPU and CPU.
#[test]
fn coincident_surfaces_have_a_deterministic_winner() {
    let both = hard("coincident-planes.toml");
    let mut first_only = both.clone();
    first_only.objects.truncate(1);
    let context = gpu();
    for mode in MODES {
        let (a, b) = (
            render(&context, &both, mode),
            render(&context, &first_only, mode),
        );
        assert_eq!(a, b, "{mode}: the second plane shows through on the GPU");
        if mode == Shading::Raytrace {
            for engine in engines(&context).into_iter().skip(1) {
                let a = render(&context, &with_engine(&both, engine), mode);
                let b = render(&context, &with_engine(&first_only, engine), mode);
                assert_eq!(a, b, "{engine:?}: the second plane shows through");
            }
        }
        let (ca, _) = crate::common::render_cpu(&both, mode).unwrap();
        let (cb, _) = crate::common::render_cpu(&first_only, mode).unwrap();
        assert_eq!(
            ca.image, cb.image,
            "{mode}: the second plane shows through on the CPU"
        );
    }
}

/// The tie rule across kinds of object, against the order the ray tracer
/// tests them in (spheres, planes and boxes one by one, then the BVH): a box
/// listed first and a smaller plane lying on its top face, both at exactly
/// representable heights so that the two distances are equal in f32 and
/// f64 alike. The box, the lower object, wins everywhere: the image equals
/// the scene without the plane, on the GPU and the CPU. (A tracer that kept
/// the first hit found at an equal distance would show the plane, which it
/// tests first.) Twice: with the box tested one by one, and with more boxes
/// than the shader tests one by one (out of sight), which puts them in the
/// BVH and the tie in its leaves.
#[test]
fn equal_distances_go_to_the_lower_object_whatever_its_kind() {
    let mut both = hard("coincident-planes.toml");
    both.objects[0].shape = Shape::Box {
        center: DVec3::new(0.0, -0.5, 0.0),
        half_extents: DVec3::new(1.5, 0.5, 1.5),
        rotation: glam::DMat3::IDENTITY,
    };
    both.objects[1].shape = Shape::Plane {
        center: DVec3::ZERO,
        normal: DVec3::Y,
        size: 2.0,
        segments: 1,
    };
    let mut in_bvh = both.clone();
    for i in 0..8 {
        in_bvh.objects.push(Object {
            shape: Shape::Box {
                center: DVec3::new(f64::from(i), 0.0, 40.0),
                half_extents: DVec3::splat(0.3),
                rotation: glam::DMat3::IDENTITY,
            },
            material: 1,
        });
    }
    let context = gpu();
    for (name, both) in [("one by one", both), ("in the BVH", in_bvh)] {
        let mut no_plane = both.clone();
        no_plane.objects.remove(1);
        for engine in engines(&context) {
            let (a, b) = (
                render(&context, &with_engine(&both, engine), Shading::Raytrace),
                render(&context, &with_engine(&no_plane, engine), Shading::Raytrace),
            );
            assert!(
                a == b,
                "{name}, {engine:?}: the plane shows through the box's face on the GPU (by up to {})",
                worst_difference(&a, &b)
            );
        }
        let (ca, _) = crate::common::render_cpu(&both, Shading::Raytrace).unwrap();
        let (cb, _) = crate::common::render_cpu(&no_plane, Shading::Raytrace).unwrap();
        assert!(
            ca.image == cb.image,
            "{name}: the plane shows through the box's face on the CPU (by up to {})",
            worst_difference(&ca.image, &cb.image)
        );
    }
}

/// Pixels less than half as bright as the median of their 5x5
/// neighbourhood, among those whose whole neighbourhood sees the same one of
/// `surfaces`: the speckles and streaks of shadow acne and of rays that
/// re-hit their own surface. Silhouettes are left out by the neighbourhood
/// rule; the scene has no thin shadows on these surfaces (the ball floats
/// above the light), so every real dark region there is wider than half
/// the neighbourhood. Half: smooth shading changes far less than 2x over
/// five pixels, while a speck of acne drops to the ambient term, under a
/// third of the lit floor's value.
/// Returns the specks and how many pixels were examined.
fn dark_specks(
    image: &shadelab::LinearImage,
    object_ids: &[Option<u32>],
    surfaces: &[u32],
) -> (Vec<(u32, u32)>, usize) {
    let luminance = |x: u32, y: u32| {
        let [r, g, b] = image.get(x, y);
        0.2126 * r + 0.7152 * g + 0.0722 * b
    };
    let object = |x: u32, y: u32| object_ids[(y * image.width + x) as usize];
    let mut found = Vec::new();
    let mut examined = 0;
    for y in 2..image.height - 2 {
        for x in 2..image.width - 2 {
            let window: Vec<(u32, u32)> = (0..25).map(|k| (x + k % 5 - 2, y + k / 5 - 2)).collect();
            let id = object(x, y);
            let one_surface = id.is_some_and(|id| surfaces.contains(&id))
                && window.iter().all(|&(u, v)| object(u, v) == id);
            if !one_surface {
                continue;
            }
            examined += 1;
            let mut around: Vec<f32> = window.iter().map(|&(u, v)| luminance(u, v)).collect();
            around.sort_by(f32::total_cmp);
            if luminance(x, y) < 0.5 * around[12] {
                found.push((x, y));
            }
        }
    }
    (found, examined)
}

/// Secondary rays leave from the offset origin of docs/raytracing.md, so the
/// floor and the wall, lit at a grazing angle and reflecting, have no dark
/// specks, on GPU and CPU. (With no offset: 1997 on the GPU, 1980 on the
/// CPU.)
#[test]
fn secondary_rays_do_not_rehit_their_own_surface() {
    let s = hard("shadow-acne.toml");
    let context = gpu();
    let (cpu, coverage) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    let mut sides = vec![("CPU".to_string(), cpu.image)];
    for engine in engines(&context) {
        let image = render(&context, &with_engine(&s, engine), Shading::Raytrace);
        sides.push((format!("GPU {engine:?}"), image));
    }
    for (side, image) in &sides {
        // Objects 0 and 1: the floor and the wall.
        let (speckles, examined) = dark_specks(image, &coverage.object_ids, &[0, 1]);
        // 16803 of the 19200 pixels see the floor or the wall across their
        // whole 5x5 window; far fewer means the object ids no longer match.
        assert!(
            examined > 10_000,
            "{side}: only {examined} floor and wall pixels examined"
        );
        assert!(
            speckles.is_empty(),
            "{side}: {} dark specks, first at {:?}",
            speckles.len(),
            speckles.first()
        );
    }
}

/// Refracted rays start exactly on the surface they cross. Made invisible
/// (index 1, `kt = 1`, no local or reflected term, no shadows), the nested
/// glass spheres must vanish: every ray crosses four surfaces, each time
/// from the offset origin, and must neither re-hit the surface it leaves
/// nor skip the next one. (The offsets themselves: docs/raytracing.md.)
#[test]
fn rays_starting_on_a_surface_cross_it_once() {
    let mut glass = hard("nested-glass.toml");
    glass.render.shadows = false;
    for o in &glass.objects[..2] {
        let m = &mut glass.materials[o.material];
        (m.ka, m.kd, m.ks, m.kr, m.kt, m.ior) = (0.0, 0.0, 0.0, 0.0, 1.0, 1.0);
    }
    let mut without = glass.clone();
    without.objects.drain(..2);
    let context = gpu();
    let (cpu_glass, _) = crate::common::render_cpu(&glass, Shading::Raytrace).unwrap();
    let (cpu_without, _) = crate::common::render_cpu(&without, Shading::Raytrace).unwrap();
    let mut sides = vec![("CPU".to_string(), cpu_glass.image, cpu_without.image)];
    for engine in engines(&context) {
        sides.push((
            format!("GPU {engine:?}"),
            render(&context, &with_engine(&glass, engine), Shading::Raytrace),
            render(&context, &with_engine(&without, engine), Shading::Raytrace),
        ));
    }
    for (side, a, b) in sides {
        let worst = worst_difference(&a, &b);
        // Each crossing moves the ray sideways by at most the offset
        // (1e-4 * |p|, ~5e-4 here), and the wall behind (whose rim is out of
        // view) changes by ~0.1 per unit: four crossings stay below 2e-4.
        // Measured: 8.5e-6 on both sides; with no offset the GPU is off by
        // up to 0.56 on 12% of the pixels.
        assert!(
            worst < 2e-4,
            "{side}: the invisible glass shows, by {worst}"
        );
    }
}

/// Zero-area triangles are dropped with a warning, and slivers change
/// nothing: the square tiled with them renders as the plain two-triangle
/// square in every mode that shades per pixel (Gouraud interpolates over
/// other triangles, flat colours each one), GPU and CPU.
#[test]
fn slivers_render_as_the_plain_square() {
    let slivers = hard("slivers.toml");
    assert!(
        slivers
            .warnings
            .iter()
            .any(|w| w.contains("dropped 3 degenerate")),
        "{:?}",
        slivers.warnings
    );
    let Shape::Mesh(mesh) = &slivers.objects[0].shape else {
        panic!("the first object is the glTF square")
    };
    assert_eq!(mesh.triangles.len(), 6, "the slivers are kept");
    // The fixture's first four vertices are the corners A B C D.
    let corners = mesh.positions[..4].to_vec();
    let up = mesh.normals[0];
    assert!(
        mesh.normals.iter().all(|n| (*n - up).length() < 1e-12),
        "face normals of a plane, slivers included: {:?}",
        mesh.normals
    );
    let mut plain = slivers.clone();
    plain.objects[0].shape = Shape::Mesh(TriangleMesh::new(
        corners,
        vec![up; 4],
        vec![[0, 3, 2], [0, 2, 1]],
    ));
    let context = gpu();
    for mode in [Shading::Phong, Shading::Raytrace] {
        let gpu_worst = worst_difference(
            &render(&context, &slivers, mode),
            &render(&context, &plain, mode),
        );
        let (a, _) = crate::common::render_cpu(&slivers, mode).unwrap();
        let (b, _) = crate::common::render_cpu(&plain, mode).unwrap();
        let cpu_worst = worst_difference(&a.image, &b.image);
        // The same plane, points and normals: only f32 interpolation over
        // different triangles differs (measured: 3.6e-7 Phong, 1.4e-6 ray
        // traced). A leak between a sliver and its neighbours would show
        // the background, ~0.5 off.
        assert!(gpu_worst < 1e-5, "{mode}: GPU differs by {gpu_worst}");
        assert!(cpu_worst < 1e-9, "{mode}: CPU differs by {cpu_worst}");
    }
}

/// Zero-length and non-unit stored normals become exactly +Y at load time;
/// where opposite normals meet, the side whose interpolated normal points
/// down gets the ambient term only and the other side is shaded as with +Y,
/// in Phong and ray tracing, GPU and CPU.
#[test]
fn bad_vertex_normals_have_defined_answers() {
    let s = hard("bad-normals.toml");
    let normals = |k: usize| match &s.objects[k].shape {
        Shape::Mesh(m) => m.normals.clone(),
        _ => panic!("object {k} is a glTF square"),
    };
    for k in [0, 1] {
        assert!(
            normals(k).iter().all(|n| *n == DVec3::Y),
            "square {k}: {:?}",
            normals(k)
        );
    }
    let mut flipped = normals(2);
    flipped.sort_by(|a, b| a.y.total_cmp(&b.y));
    assert_eq!(flipped, [-DVec3::Y, -DVec3::Y, DVec3::Y, DVec3::Y]);

    // The same scene with the third square's normals all +Y.
    let mut all_up = s.clone();
    if let Shape::Mesh(m) = &mut all_up.objects[2].shape {
        m.normals.fill(DVec3::Y);
    }
    let tile = &s.materials[s.objects[2].material];
    let ambient = s.lighting.ambient * tile.ka * tile.color;
    let v = view(&s);
    // The third square spans x 1.1..3.1 and z -1..1; its normal vanishes
    // at z = 0.
    let pixel = |p: DVec3| {
        let at = v.project(p).unwrap();
        (at.x as u32, at.y as u32)
    };
    let (near, far) = (
        pixel(DVec3::new(2.1, 0.0, 0.5)),
        pixel(DVec3::new(2.1, 0.0, -0.5)),
    );
    let context = gpu();
    for mode in [Shading::Phong, Shading::Raytrace] {
        let (cpu, _) = crate::common::render_cpu(&s, mode).unwrap();
        let (cpu_up, _) = crate::common::render_cpu(&all_up, mode).unwrap();
        let sides = [
            (
                "GPU",
                render(&context, &s, mode),
                render(&context, &all_up, mode),
            ),
            ("CPU", cpu.image, cpu_up.image),
        ];
        for (side, image, up_image) in sides {
            let (lit, dark) = (
                to_dvec(image.get(near.0, near.1)),
                to_dvec(image.get(far.0, far.1)),
            );
            let expected_lit = to_dvec(up_image.get(near.0, near.1));
            assert!(
                max_abs_diff(lit, expected_lit) < 1e-5,
                "{mode} {side}: near half {lit}, with +Y normals {expected_lit}"
            );
            // The far half reflects (kr > 0) only in the ray tracer; there
            // the reflected ray sees the background above.
            if mode == Shading::Phong {
                assert!(
                    max_abs_diff(dark, ambient) < 1e-6,
                    "{mode} {side}: far half {dark}, ambient {ambient}"
                );
            }
            assert!(
                max_abs_diff(lit, dark) > 0.1,
                "{mode} {side}: the two halves look alike"
            );
        }
    }
}

/// The scene with every intensity (lights, ambient, background) divided by
/// `factor`.
fn divided(s: &Scene, factor: f64) -> Scene {
    let mut unit = s.clone();
    for l in &mut unit.lights {
        l.intensity /= factor;
    }
    unit.lighting.ambient /= factor;
    unit.image.background /= factor;
    unit
}

/// The model is linear in the intensities: lit at 1e30 or 1e-30, every mode
/// renders 1e30 or 1e-30 times the image at unit scale, GPU and CPU; and
/// `check`, comparing in units of the brightest value, still catches a
/// light 1% too bright at 1e-30.
#[test]
fn huge_and_tiny_intensities_scale_the_image() {
    let context = gpu();
    for (name, factor) in [
        ("intensity-1e30.toml", 1e30),
        ("intensity-1e-30.toml", 1e-30),
    ] {
        let s = hard(name);
        let unit = divided(&s, factor);
        for mode in MODES {
            let (cpu, _) = crate::common::render_cpu(&s, mode).unwrap();
            let (cpu_unit, _) = crate::common::render_cpu(&unit, mode).unwrap();
            let sides = [
                (
                    "GPU",
                    render(&context, &s, mode),
                    render(&context, &unit, mode),
                ),
                ("CPU", cpu.image, cpu_unit.image),
            ];
            for (side, image, unit_image) in sides {
                let worst = worst_difference(&scaled(&image, factor), &unit_image);
                // The scale factor is not a power of two, so every product
                // rounds differently: a few f32 ulps of values up to ~2
                // (GPU), f32 storage of the f64 result (CPU). Measured: at
                // most 1.4e-6 (Gouraud on the GPU), 1.4e-7 elsewhere.
                assert!(
                    worst < 1e-5,
                    "{name} {mode} {side}: off by {worst} of unit scale"
                );
            }
        }
    }
    let tiny = hard("intensity-1e-30.toml");
    let mut brighter = tiny.clone();
    brighter.lights[0].intensity *= 1.01;
    let o = check(
        &crate::common::device(&context),
        &tiny,
        &brighter,
        Shading::Phong,
        &CheckThresholds::for_shading(Shading::Phong),
    )
    .unwrap();
    assert!(!o.passed(), "a 1% brighter light at 1e-30 went unnoticed");
    assert!(
        (o.judgement.scale / 1e-30 - 1.0).abs() < 0.5,
        "scale {}",
        o.judgement.scale
    );
}

/// A tilted grid mesh whose every pixel centre in `inner` lies on a shared
/// edge or vertex: vertices are where the rays through every other pixel
/// centre meet the plane, so edges and diagonals pass through the rest.
fn grid_on_pixel_centres() -> (
    Scene,
    std::ops::RangeInclusive<u32>,
    std::ops::RangeInclusive<u32>,
) {
    let mut s = common::scene(128, 96, 40.0);
    s.image.background = DVec3::new(0.0, 0.0, 1.0);
    s.render.shadows = false;
    let v = view(&s);
    let normal = DVec3::new(0.3, -0.2, 1.0).normalize();
    let (nx, ny) = (50u32, 36u32);
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let d = v.ray_direction(f64::from(14 + 2 * i) + 0.5, f64::from(12 + 2 * j) + 0.5);
            // The plane through the origin with `normal`, from the eye.
            let t = -v.eye.dot(normal) / d.dot(normal);
            positions.push(v.eye + t * d);
        }
    }
    let at = |i: u32, j: u32| j * (nx + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let normals = vec![normal; positions.len()];
    s.objects.push(Object {
        shape: Shape::Mesh(TriangleMesh::new(positions, normals, triangles)),
        material: 0,
    });
    (s, 15..=(13 + 2 * nx), 13..=(11 + 2 * ny))
}

/// No ray leaks through a mesh between its triangles: on a grid whose every
/// pixel centre lies exactly on a shared edge or vertex, no pixel inside
/// shows the background, GPU or CPU (the ray-query engine: a few, below).
#[test]
fn rays_along_shared_edges_do_not_leak() {
    let (s, xs, ys) = grid_on_pixel_centres();
    let context = gpu();
    let (cpu, _) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    let mut sides = vec![("CPU".to_string(), cpu.image)];
    for engine in engines(&context) {
        let image = render(&context, &with_engine(&s, engine), Shading::Raytrace);
        sides.push((format!("GPU {engine:?}"), image));
    }
    for (side, image) in sides {
        let leaks: Vec<(u32, u32)> = ys
            .clone()
            .flat_map(|y| xs.clone().map(move |x| (x, y)))
            .filter(|&(x, y)| image.get(x, y) == [0.0, 0.0, 1.0])
            .collect();
        // The ray-query engine uses the driver's triangle test, which on
        // lavapipe 25 is not watertight: measured 3 of the 7029 rays leak
        // (Möller-Trumbore: 611). Bounded here at 10 so a worse driver shows;
        // the compute BVH and the CPU twin leak none.
        let allowed = if side.ends_with("Query") { 10 } else { 0 };
        assert!(
            leaks.len() <= allowed,
            "{side}: {} of {} rays leak, first at {:?}",
            leaks.len(),
            xs.clone().count() * ys.clone().count(),
            leaks.first()
        );
    }
}

/// Two coincident meshes (the same triangles, listed twice with different
/// materials): every ray meets both at exactly the same distance, and the
/// first listed must win everywhere, as for coincident planes. The CPU twin
/// and the compute BVH apply the tie rule to every candidate. The ray-query
/// engine leaves triangles to the driver, which keeps the first of equal
/// hits it meets: each pixel must show one of the two meshes, whole
/// (measured on lavapipe: the first everywhere with a structure per mesh,
/// visited in object order; the second at 3654 of the 12288 pixels when
/// both were one structure; docs/raytracing.md, "The ray-query engine").
#[test]
fn coincident_meshes_go_to_the_first_listed() {
    let (mut both, _, _) = grid_on_pixel_centres();
    let mut green = both.materials[0].clone();
    green.color = DVec3::new(0.1, 0.9, 0.1);
    both.materials.push(green);
    let mut second = both.objects[0].clone();
    second.material = 1;
    both.objects.push(second);
    let mut first_only = both.clone();
    first_only.objects.truncate(1);
    let mut second_only = both.clone();
    second_only.objects.remove(0);
    let context = gpu();
    let (cpu_both, _) = crate::common::render_cpu(&both, Shading::Raytrace).unwrap();
    let (cpu_first, _) = crate::common::render_cpu(&first_only, Shading::Raytrace).unwrap();
    assert!(
        cpu_both.image == cpu_first.image,
        "CPU: the second mesh shows"
    );
    for engine in engines(&context) {
        let traced = |s: &Scene| render(&context, &with_engine(s, engine), Shading::Raytrace);
        let (a, first, second) = (traced(&both), traced(&first_only), traced(&second_only));
        let n = (a.width * a.height) as usize;
        // "Shows" to float rounding: a pixel centre on a shared edge may be
        // shaded from either triangle there, which differ in the last bits.
        let close = |p: [f32; 3], q: [f32; 3]| (0..3).all(|c| (p[c] - q[c]).abs() < 1e-5);
        let differs: Vec<usize> = (0..n)
            .filter(|&i| !close(a.pixels[i], first.pixels[i]))
            .collect();
        let shows_second = differs
            .iter()
            .filter(|&&i| close(a.pixels[i], second.pixels[i]))
            .count();
        // Where the driver's test lets a ray through one mesh's triangles
        // (`rays_along_shared_edges_do_not_leak`) the other may catch it:
        // as many pixels as leak may show neither image alone.
        let neither: Vec<usize> = differs
            .iter()
            .copied()
            .filter(|&i| !close(a.pixels[i], second.pixels[i]))
            .collect();
        assert!(
            neither.len() <= if engine == Traversal::Query { 10 } else { 0 },
            "{engine:?}: {} pixels show neither mesh alone, first {:?}: {:?} (first mesh {:?}, second {:?})",
            neither.len(),
            neither.first(),
            neither.first().map(|&i| a.pixels[i]),
            neither.first().map(|&i| first.pixels[i]),
            neither.first().map(|&i| second.pixels[i]),
        );
        eprintln!("{engine:?}: the second mesh shows at {shows_second} of {n} pixels");
        match engine {
            Traversal::Query => assert!(
                shows_second < n / 2,
                "{engine:?}: the second mesh shows at {shows_second} of {n} pixels"
            ),
            _ => assert_eq!(shows_second, 0, "{engine:?}: the second mesh shows"),
        }
    }
}
