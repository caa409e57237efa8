//! Flat and Gouraud shading, and screen against perspective interpolation,
//! held to the lighting formula evaluated in double precision.

use crate::common;

use common::*;
use glam::{DVec2, DVec3};
use shadelab::cpu::lighting::{shade, Surface};
use shadelab::scene::{tessellate, Interpolation, Object, Scene, Shape};
use shadelab::shading::Shading;

#[test]
fn flat_gives_each_triangle_one_colour_the_formula_at_its_centroid() {
    let mut s = scene(160, 160, 30.0);
    s.materials[0].ks = 0.6;
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: 2.0,
            segments: 12,
        },
        material: 0,
    });
    let image = render(&gpu(), &s, Shading::Flat);
    let mesh = tessellate(&s.objects[0].shape);
    let v = view(&s);
    let ids = id_map(160, 160, |x, y| {
        hit_mesh(v.eye, pixel_ray(&v, x, y), &mesh).map(|h| h.0)
    });
    let interior = interior_pixels(160, 160, &ids);
    assert!(
        interior.len() > 3000,
        "too few interior pixels: {}",
        interior.len()
    );

    let mut colour_of = std::collections::HashMap::new();
    for &(x, y, tri) in &interior {
        let got = image.get(x, y);
        // Exactly one colour per triangle: bit-identical across its pixels.
        let first = *colour_of.entry(tri).or_insert(got);
        assert_eq!(first, got, "triangle {tri} has two colours");
        let [a, b, c] = mesh.triangles[tri].map(|k| mesh.positions[k as usize]);
        let centroid = (a + b + c) / 3.0;
        let normal = (b - a).cross(c - a).normalize();
        let want = shade(
            &s.lighting,
            &s.lights,
            Surface::plain(&s.materials[0]),
            centroid,
            normal,
            v.eye,
        );
        let err = max_abs_diff(to_dvec(got), want);
        assert!(
            err < FLOAT_TOL,
            "triangle {tri} at ({x}, {y}): {got:?} vs formula {want}"
        );
    }
    assert!(
        colour_of.len() > 25,
        "only {} triangles checked",
        colour_of.len()
    );
    // And over the whole image (edges included) no pixel holds a colour that
    // is not some triangle's or the background's.
    let distinct: std::collections::HashSet<[u32; 3]> =
        image.pixels.iter().map(|p| p.map(f32::to_bits)).collect();
    assert!(distinct.len() <= mesh.triangles.len() + 1);
}

/// The shared pixel-centre grid with a glossy material, so the specular
/// term varies across it too.
fn glossy_grid() -> Scene {
    let mut s = grid_scene();
    s.materials[0].ks = 0.7;
    s.materials[0].p = 6.0;
    s
}

fn vertex_intensity(s: &Scene, world: DVec3, normal: DVec3) -> DVec3 {
    shade(
        &s.lighting,
        &s.lights,
        Surface::plain(&s.materials[0]),
        world,
        normal,
        s.camera.position,
    )
}

#[test]
fn gouraud_equals_formula_at_vertices_and_is_linear_along_edges() {
    let s = glossy_grid();
    let image = render(&gpu(), &s, Shading::Gouraud);
    let mesh = tessellate(&s.objects[0].shape);
    let v = view(&s);
    let mut checked_vertices = 0;
    let mut on_pixel = std::collections::HashMap::new();
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        let at = v.project(*p).unwrap();
        let (px, py) = (at.x - 0.5, at.y - 0.5);
        assert!(
            (px - px.round()).abs() < 1e-6 && (py - py.round()).abs() < 1e-6,
            "vertex not on a pixel centre"
        );
        let (px, py) = (px.round() as u32, py.round() as u32);
        on_pixel.insert((px, py), vertex_intensity(&s, *p, *n));
        // Border vertices sit on the square's outer edge, which the fill rule
        // may leave uncovered; interior ones are always covered.
        if (11..=89).contains(&px) && (11..=89).contains(&py) {
            let err = max_abs_diff(to_dvec(image.get(px, py)), on_pixel[&(px, py)]);
            assert!(err < FLOAT_TOL, "vertex at ({px}, {py}): error {err:.2e}");
            checked_vertices += 1;
        }
    }
    assert_eq!(checked_vertices, 9);
    // Along the horizontal edge y = 50 between the vertices at x = 30 and
    // x = 50 (and the next span), the value is linear between its ends.
    for (x0, x1) in [(30u32, 50u32), (50, 70)] {
        let (i0, i1) = (on_pixel[&(x0, 50)], on_pixel[&(x1, 50)]);
        assert!(
            max_abs_diff(i0, i1) > 0.02,
            "choose a light that varies along the edge"
        );
        for x in x0..=x1 {
            let t = f64::from(x - x0) / f64::from(x1 - x0);
            let want = i0 * (1.0 - t) + i1 * t;
            let err = max_abs_diff(to_dvec(image.get(x, 50)), want);
            assert!(err < FLOAT_TOL, "edge pixel ({x}, 50): error {err:.2e}");
        }
    }
}

#[test]
fn screen_and_perspective_agree_on_a_screen_parallel_plane() {
    let context = gpu();
    for shading in [Shading::Gouraud, Shading::Phong] {
        let persp = glossy_grid();
        let mut screen = glossy_grid();
        screen.lighting.interpolation = Interpolation::Screen;
        let (a, b) = (
            render(&context, &persp, shading),
            render(&context, &screen, shading),
        );
        let worst = worst_difference(&a, &b);
        assert!(worst < FLOAT_TOL, "{shading}: images differ by {worst}");
    }
}

/// 2D barycentric coordinates of `p` in the triangle (a, b, c).
fn barycentric(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> DVec3 {
    let area = (b - a).perp_dot(c - a);
    let wb = (p - a).perp_dot(c - a) / area;
    let wc = (b - a).perp_dot(p - a) / area;
    DVec3::new(1.0 - wb - wc, wb, wc)
}

#[test]
fn screen_and_perspective_differ_as_predicted_on_a_tilted_plane() {
    let mut s = scene(128, 128, 40.0);
    s.camera.position = DVec3::new(0.0, 0.0, 6.0);
    s.lights[0].position = DVec3::new(-3.0, 4.0, 3.0);
    s.objects.push(Object {
        // Tilted 70 degrees away from the camera, so depth varies strongly
        // across each triangle, and small enough to stay inside the image:
        // a clipped triangle gets new vertices whose `noperspective` values
        // Vulkan leaves to the implementation.
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::new(0.0, 70f64.to_radians().sin(), 70f64.to_radians().cos()),
            size: 3.2,
            segments: 1,
        },
        material: 0,
    });
    let context = gpu();
    let persp_img = render(&context, &s, Shading::Gouraud);
    let mut screen_scene = s.clone();
    screen_scene.lighting.interpolation = Interpolation::Screen;
    let screen_img = render(&context, &screen_scene, Shading::Gouraud);

    let mesh = tessellate(&s.objects[0].shape);
    let v = view(&s);
    let ids = id_map(128, 128, |x, y| {
        hit_mesh(v.eye, pixel_ray(&v, x, y), &mesh).map(|h| h.0)
    });
    let mut strongly_different = 0;
    for (x, y, tri) in interior_pixels(128, 128, &ids) {
        let corners = mesh.triangles[tri].map(|k| k as usize);
        let intensity = corners.map(|k| vertex_intensity(&s, mesh.positions[k], mesh.normals[k]));
        // Perspective-correct weights are the barycentrics of the 3D hit.
        let (_, _, u, w) = hit_mesh(v.eye, pixel_ray(&v, x, y), &mesh).unwrap();
        let persp = intensity[0] * (1.0 - u - w) + intensity[1] * u + intensity[2] * w;
        // Screen-linear weights are the barycentrics in the image plane.
        let screen_pts = corners.map(|k| v.project(mesh.positions[k]).unwrap());
        let centre = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
        let bary = barycentric(centre, screen_pts[0], screen_pts[1], screen_pts[2]);
        let screen = intensity[0] * bary.x + intensity[1] * bary.y + intensity[2] * bary.z;

        let got_persp = to_dvec(persp_img.get(x, y));
        let got_screen = to_dvec(screen_img.get(x, y));
        assert!(
            max_abs_diff(got_persp, persp) < FLOAT_TOL,
            "perspective at ({x}, {y})"
        );
        assert!(
            max_abs_diff(got_screen, screen) < FLOAT_TOL,
            "screen at ({x}, {y})"
        );
        if max_abs_diff(persp, screen) > 0.01 {
            strongly_different += 1;
        }
    }
    assert!(
        strongly_different > 200,
        "the tilt should make the rules disagree: {strongly_different} pixels"
    );
}

/// `render --out x.png` renders the raster modes into an 8-bit sRGB target
/// (`ColorTarget::Srgb8`), the rest into 32-bit floats. The two give the
/// same PNG within 1 in 255 on every channel of every pixel, in every
/// raster mode, on every scene in assets/ and the default scene: the
/// driver's sRGB encoding may round a value that falls between two bytes
/// the other way from `linear_to_srgb8`, and nothing more.
#[test]
fn the_8_bit_png_path_gives_the_float_paths_png_within_one_step() {
    use shadelab::gpu::raster::ColorTarget;
    use shadelab::render::{render, RenderRequest};
    use shadelab::srgb::linear_to_srgb8;
    let scenes = asset_scenes();
    assert!(scenes.len() >= 6, "assets/ lost scenes");
    let context = gpu();
    for (name, scene) in &scenes {
        for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
            let png = |target| -> Vec<u8> {
                let request = RenderRequest {
                    target,
                    ..RenderRequest::gpu(shading)
                };
                let image = render(&common::device(&context), scene, &request)
                    .unwrap()
                    .image;
                image
                    .pixels
                    .iter()
                    .flatten()
                    .map(|&v| linear_to_srgb8(v))
                    .collect()
            };
            let (float_path, byte_path) = (png(ColorTarget::Float32), png(ColorTarget::Srgb8));
            let worst = float_path
                .iter()
                .zip(&byte_path)
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap();
            assert!(
                worst <= 1,
                "{name} {shading}: the PNGs differ by {worst} in 255"
            );
        }
    }
}

/// Back faces are culled only where they cannot show (`raster::cull`).
/// Where they can, they are drawn, and the GPU image matches the CPU
/// reference, which never culls: a plane seen from below, the inside of a
/// sphere around the eye, and a box the near plane cuts open. (Most scenes
/// of assets/ see their planes from the front and their closed objects
/// from outside, where `check` cannot tell a renderer that culls
/// everything from one that culls right; of assets/hard/, smallpt-box and
/// sky-sphere-1e30 see spheres from inside.)
#[test]
fn back_faces_are_drawn_where_they_can_show() {
    use shadelab::check::{check, CheckThresholds};
    let context = gpu();
    let mut from_below = scene(160, 120, 50.0);
    from_below.camera.position = DVec3::new(0.0, -3.0, 4.0);
    from_below.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Y,
            size: 6.0,
            segments: 2,
        },
        material: 0,
    });
    let mut inside = scene(160, 120, 60.0);
    inside.camera.position = DVec3::new(0.2, 0.1, 0.3);
    inside.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: 2.0,
            segments: 24,
        },
        material: 0,
    });
    let mut cut_open = scene(160, 120, 60.0);
    // The near plane sits at 1e-5 of the scene's extent from the eye, or
    // at 1e-3 of the nearest surface's distance where that is known
    // (camera.rs): a mesh whose bounds hold the eye says nothing of it. One
    // closed mesh of two boxes, one in front whose face passes 1e-6 from
    // the eye and one behind it: the near plane cuts the front box open.
    cut_open.camera.position = DVec3::new(0.0, 0.0, 1.0 + 1e-6);
    cut_open.camera.look_at = DVec3::new(0.0, 0.0, -1.0);
    let boxes = [DVec3::ZERO, DVec3::new(0.0, 0.0, 4.0)].map(|center| {
        tessellate(&Shape::Box {
            center,
            half_extents: DVec3::splat(1.0),
            rotation: glam::DMat3::IDENTITY,
        })
    });
    let mut two_boxes = boxes[0].clone();
    let offset = two_boxes.positions.len() as u32;
    two_boxes.positions.extend(&boxes[1].positions);
    two_boxes.normals.extend(&boxes[1].normals);
    two_boxes
        .triangles
        .extend(boxes[1].triangles.iter().map(|t| t.map(|i| i + offset)));
    cut_open.objects.push(Object {
        shape: Shape::Mesh(two_boxes),
        material: 0,
    });
    for (name, s) in [
        ("plane from below", &from_below),
        ("inside a sphere", &inside),
        ("box cut open", &cut_open),
    ] {
        for shading in [Shading::Flat, Shading::Phong] {
            let image = render(&context, s, shading);
            let lit = image.pixels.iter().filter(|p| **p != [0.0; 3]).count();
            assert!(
                lit > image.pixels.len() / 4,
                "{name} {shading}: {lit} pixels drawn"
            );
            let limits = CheckThresholds::for_shading(shading);
            let outcome = check(&crate::common::device(&context), s, s, shading, &limits).unwrap();
            assert!(
                outcome.passed(),
                "{name} {shading}: {:?}",
                outcome.judgement.failures
            );
        }
    }
}
