//! The CPU ray tracer (`cpu::raytrace`) against values computed by hand
//! from `docs/raytracing.md`, and against the CPU Phong rasterizer where the
//! contract says the two evaluate the same thing.

use crate::common;

use common::cli::shadelab;
use common::*;
use glam::{DMat3, DVec3};
use shadelab::cpu::intersect::Ray;
use shadelab::cpu::lighting::{shade, Surface};
use shadelab::cpu::raytrace::{offset_epsilon, sample_offsets, PathSignature, Tracer};
use shadelab::rt_scene::{RayStats, RtScene};
use shadelab::scene::{tessellate, Material, Object, PointLight, Scene, Shape};
use shadelab::shading::Shading;

/// `base` with reflection `kr`, transmission `kt` and index `ior`.
fn optics(base: Material, kr: f64, kt: f64, ior: f64) -> Material {
    Material {
        kr,
        kt,
        ior,
        ..base
    }
}

fn traced(scene: &Scene, origin: DVec3, dir: DVec3) -> (DVec3, RayStats) {
    let rt = RtScene::new(scene);
    let tracer = Tracer::new(&rt, view(scene));
    let mut stats = RayStats::default();
    let ray = Ray {
        origin,
        dir: dir.normalize(),
    };
    let (value, _) = tracer.trace(ray, (0, 0), &mut stats, &mut PathSignature::default());
    (value, stats)
}

/// The formula at world point `p` with normal `n`, seen along `d`.
fn formula(scene: &Scene, m: &Material, p: DVec3, n: DVec3, d: DVec3) -> DVec3 {
    shade(
        &scene.lighting,
        &scene.lights,
        Surface::plain(m),
        p,
        n,
        p - d,
    )
}

#[test]
fn depth_zero_on_a_mesh_equals_phong_in_the_interior() {
    // The contract: raytrace at depth 0 with shadows off evaluates the same
    // N, P and V as phong at every pixel centre (the ray's barycentrics are
    // the perspective-correct ones), so away from silhouettes they agree to
    // rounding. Both images hold f32; their f64 values differ by ~1e-14, so
    // they round to the same f32 unless one straddles a rounding boundary.
    // The rasterizer decides coverage on vertices snapped to 1/256 pixel:
    // within `EDGE_MARGIN` of a triangle edge (its `near_edge`) it may shade
    // with the neighbouring triangle, whose extrapolated normal differs by
    // ~1e-6. Those samples are left out.
    let mut s = scene(120, 96, 40.0);
    s.render.depth = 0;
    s.render.shadows = false;
    s.lights.push(PointLight {
        position: DVec3::new(-6.0, -1.0, 4.0),
        intensity: DVec3::new(2.0, 3.0, 5.0),
    });
    s.objects.push(Object {
        shape: Shape::Mesh(tessellate(&Shape::Sphere {
            center: DVec3::new(0.4, -0.2, 0.0),
            radius: 2.5,
            segments: 24,
        })),
        material: 0,
    });
    let (phong, coverage) = crate::common::render_cpu(&s, Shading::Phong).unwrap();
    let (ray, ray_coverage) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    let ids: Vec<Option<usize>> = coverage
        .object_ids
        .iter()
        .map(|i| i.map(|v| v as usize))
        .collect();
    let interior: Vec<_> = interior_pixels(120, 96, &ids)
        .into_iter()
        .filter(|&(x, y, _)| !coverage.near_edge[(y * 120 + x) as usize])
        .collect();
    assert!(interior.len() > 2000, "{} interior pixels", interior.len());
    for (x, y, _) in interior {
        let (a, b) = (to_dvec(phong.image.get(x, y)), to_dvec(ray.image.get(x, y)));
        assert!(
            max_abs_diff(a, b) <= 1e-9,
            "({x}, {y}): phong {a} raytrace {b}"
        );
        let i = (y * 120 + x) as usize;
        assert_eq!(ray_coverage.object_ids[i], Some(0));
    }
    let stats = ray.ray_stats.unwrap();
    assert_eq!(stats.primary, 120 * 96);
    assert_eq!(stats.shadow + stats.reflected + stats.refracted, 0);
}

/// A floor at y = -1 under a light at (0, 4, 0), and a small sphere between
/// them: the floor point (0, -1, 0) is in its shadow.
fn shadow_scene(occluder: DVec3) -> Scene {
    let mut s = scene(64, 64, 40.0);
    s.lights = vec![PointLight {
        position: DVec3::new(0.0, 4.0, 0.0),
        intensity: DVec3::new(9.0, 8.0, 7.0),
    }];
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::new(0.0, -1.0, 0.0),
            normal: DVec3::Y,
            size: 20.0,
            segments: 1,
        },
        material: 0,
    });
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: occluder,
            radius: 0.5,
            segments: 16,
        },
        material: 0,
    });
    s
}

#[test]
fn a_point_in_shadow_receives_exactly_the_ambient_term() {
    let point = DVec3::new(0.0, -1.0, 0.0);
    let s = shadow_scene(DVec3::new(0.0, 1.5, 0.0));
    let eye = s.camera.position;
    let (value, stats) = traced(&s, DVec3::ZERO, point - eye);
    let m = &s.materials[0];
    let ambient = s.lighting.ambient * m.ka * m.color;
    assert!(max_abs_diff(value, ambient) < 1e-12, "{value} vs {ambient}");
    assert_eq!(stats.shadow, 1);
    // The occluder moved aside: the whole formula.
    let s = shadow_scene(DVec3::new(3.0, 1.5, -3.0));
    let (value, _) = traced(&s, DVec3::ZERO, point - eye);
    let full = formula(&s, m, point, DVec3::Y, (point - eye).normalize());
    assert!(max_abs_diff(value, full) < 1e-12, "{value} vs {full}");
    assert!(max_abs_diff(full, ambient) > 0.5);
    // With shadows off the occluder changes nothing, and no shadow ray is cast.
    let mut s = shadow_scene(DVec3::new(0.0, 1.5, 0.0));
    s.render.shadows = false;
    let (value, stats) = traced(&s, DVec3::ZERO, point - eye);
    assert!(max_abs_diff(value, full) < 1e-12);
    assert_eq!(stats.shadow, 0);
}

/// A glass slab (a box 10 x 1 x 10 around the origin) with the eye inside
/// it; a light above and one below.
fn slab_scene() -> Scene {
    let mut s = scene(32, 32, 40.0);
    s.camera.position = DVec3::ZERO;
    s.camera.look_at = -DVec3::Z;
    s.lights = vec![
        PointLight {
            position: DVec3::new(3.0, 5.0, 1.0),
            intensity: DVec3::splat(6.0),
        },
        PointLight {
            position: DVec3::new(4.0, -5.0, 0.0),
            intensity: DVec3::new(2.0, 3.0, 4.0),
        },
    ];
    s.materials = vec![optics(
        material(DVec3::new(0.8, 0.9, 1.0), 0.3, 0.5, 0.2, 10.0),
        0.2,
        0.7,
        1.5,
    )];
    s.objects.push(Object {
        shape: Shape::Box {
            center: DVec3::ZERO,
            half_extents: DVec3::new(5.0, 0.5, 5.0),
            rotation: DMat3::IDENTITY,
        },
        material: 0,
    });
    s.render.depth = 1;
    s
}

#[test]
fn total_internal_reflection_hands_kt_to_the_reflected_ray() {
    // Shadows off: each face is seen from inside and lit as its back, by
    // the light on the slab's far side, whose shadow ray would cross the
    // slab; without shadows the lights reach both hits and the sum below
    // checks every term.
    let mut s = slab_scene();
    s.render.shadows = false;
    let m = s.materials[0].clone();
    let critical = (1.0f64 / 1.5).asin();
    // Beyond the critical angle: from the centre up to the top face at 60
    // degrees from its normal.
    let theta = 60f64.to_radians();
    let d = DVec3::new(theta.sin(), theta.cos(), 0.0);
    let (value, stats) = traced(&s, DVec3::ZERO, d);
    assert!(value.is_finite());
    assert_eq!((stats.reflected, stats.refracted, stats.pruned), (1, 0, 0));
    // By hand: the top hit, then the reflected ray (weight kr + kt) from
    // the origin offset downward by eps, to the bottom face. Both faces
    // are seen from inside, so each is lit as its back: the top with -Y,
    // the bottom with +Y (docs/lighting-model.md, "Which side is lit").
    let p1 = DVec3::new(0.5 * theta.tan(), 0.5, 0.0);
    let r = DVec3::new(theta.sin(), -theta.cos(), 0.0);
    let o2 = p1 - offset_epsilon(p1, DVec3::ZERO) * DVec3::Y;
    let p2 = o2 + (o2.y + 0.5) / theta.cos() * r;
    assert!((p2.y + 0.5).abs() < 1e-15);
    let expected =
        formula(&s, &m, p1, -DVec3::Y, d) + (m.kr + m.kt) * formula(&s, &m, p2, DVec3::Y, r);
    assert!(
        max_abs_diff(value, expected) < 1e-12,
        "{value} vs {expected}"
    );
    assert_eq!(stats.shadow, 0);
    // With shadows: each face faces one light (the top, seen from inside,
    // the light below; the bottom the one above), casts one shadow ray
    // toward it through the slab, and is shadowed by the slab's other
    // face: the ambient terms alone.
    let mut shadowed = s.clone();
    shadowed.render.shadows = true;
    let (value, stats) = traced(&shadowed, DVec3::ZERO, d);
    assert_eq!(stats.shadow, 2);
    let ambient = s.lighting.ambient * m.ka * m.color;
    let expected = ambient + (m.kr + m.kt) * ambient;
    assert!(
        max_abs_diff(value, expected) < 1e-12,
        "{value} vs {expected}"
    );
    // Just beyond and just below the critical angle.
    for (degrees, refracts) in [(0.01, false), (-0.01, true)] {
        let theta = critical + f64::to_radians(degrees);
        let d = DVec3::new(theta.sin(), theta.cos(), 0.0);
        let (value, stats) = traced(&s, DVec3::ZERO, d);
        assert!(value.is_finite());
        assert_eq!(stats.refracted, u64::from(refracts), "{degrees}");
        assert_eq!(stats.reflected, 1);
    }
}

#[test]
fn the_cutoff_prunes_children_below_it() {
    let mut s = shadow_scene(DVec3::new(0.0, 0.5, 0.0));
    s.materials[0].kr = 0.3;
    s.render.cutoff = 0.5;
    let (cut, _) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    let stats = cut.ray_stats.unwrap();
    assert_eq!((stats.reflected, stats.refracted), (0, 0));
    assert!(stats.pruned > 100, "{stats:?}");
    assert_eq!(stats.max_depth_reached, 0);
    s.render.depth = 0;
    let (flat, _) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    assert_eq!(flat.ray_stats.unwrap().pruned, 0);
    assert_eq!(cut.image, flat.image);
    // Below the cut-off's reach (0.3 >= 0.25) the reflections come back.
    s.render.depth = 5;
    s.render.cutoff = 0.25;
    let (full, _) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    assert_eq!(full.ray_stats.unwrap().reflected, stats.pruned);
    assert_ne!(full.image, flat.image);
}

#[test]
fn a_mirror_sphere_shows_the_floor_at_the_mirrored_point() {
    let mut s = scene(96, 96, 40.0);
    s.lights[0].position = DVec3::new(0.0, 5.0, 8.0);
    s.materials = vec![
        optics(material(DVec3::ONE, 0.0, 0.0, 0.0, 1.0), 1.0, 0.0, 1.0),
        optics(
            material(DVec3::new(0.9, 0.6, 0.3), 0.3, 0.7, 0.5, 10.0),
            0.0,
            0.0,
            1.0,
        ),
    ];
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
            segments: 32,
        },
        material: 0,
    });
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::new(0.0, -1.5, 0.0),
            normal: DVec3::Y,
            size: 40.0,
            segments: 1,
        },
        material: 1,
    });
    let v = view(&s);
    let eye = s.camera.position;
    let rt = RtScene::new(&s);
    let tracer = Tracer::new(&rt, v);
    let mut checked = 0;
    for y in [52, 55, 58] {
        for x in [44, 48, 52] {
            // By hand, camera-relative: the sphere hit, its normal, the
            // mirrored direction, the offset origin, the floor hit.
            let d = pixel_ray(&v, x, y);
            let t = hit_sphere(DVec3::ZERO, d, -eye, 1.0).expect("the pixel sees the sphere");
            let p = t * d;
            let n = p + eye;
            let r = d - 2.0 * d.dot(n) * n;
            assert!(r.y < 0.0);
            let o = p + offset_epsilon(p, DVec3::ZERO) * n;
            let q = o + (-1.5 - eye.y - o.y) / r.y * r;
            // The floor point is lit: its segment to the light misses the
            // sphere.
            let to_light = s.lights[0].position - eye - q;
            assert!(hit_sphere(q, to_light.normalize(), -eye, 1.0)
                .is_none_or(|t| t > to_light.length()));
            let expected = formula(&s, &s.materials[1], q + eye, DVec3::Y, r);
            let got = tracer.pixel(x, y, &mut RayStats::default());
            assert!(
                max_abs_diff(got.color, expected) < 1e-12,
                "({x}, {y}): {} vs {expected}",
                got.color
            );
            assert_eq!(got.object, Some(0));
            checked += 1;
        }
    }
    assert_eq!(checked, 9);
}

#[test]
fn samples_average_the_spec_positions() {
    // Positions: the cell centres of a ceil(sqrt n) x ceil(n / kx) grid.
    assert_eq!(sample_offsets(1), vec![(0.5, 0.5)]);
    assert_eq!(
        sample_offsets(4),
        vec![(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]
    );
    assert_eq!(
        sample_offsets(3),
        vec![(0.25, 0.25), (0.75, 0.25), (0.25, 0.75)]
    );
    assert_eq!(sample_offsets(2), vec![(0.25, 0.5), (0.75, 0.5)]);
    let five = sample_offsets(5);
    assert_eq!(five.len(), 5);
    assert_eq!(five[2], (2.5 / 3.0, 0.25));
    assert_eq!(five[4], (1.5 / 3.0, 0.75));
    // A pixel on a sphere's silhouette: the mean of the four rays traced
    // through those positions, in order.
    let mut s = shadow_scene(DVec3::new(0.0, 1.5, 0.0));
    s.render.samples = 4;
    let v = view(&s);
    let rt = RtScene::new(&s);
    let tracer = Tracer::new(&rt, v);
    let (x, y) = silhouette_pixel(&s);
    let mut stats = RayStats::default();
    let got = tracer.pixel(x, y, &mut stats);
    assert_eq!(stats.primary, 4);
    let mut sum = DVec3::ZERO;
    for (sx, sy) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
        let ray = tracer.primary_ray(f64::from(x) + sx, f64::from(y) + sy);
        let (value, _) = tracer.trace(ray, (0, 0), &mut stats, &mut PathSignature::default());
        sum += value;
    }
    assert_eq!(got.color, sum / 4.0);
    // One sample (the pixel centre) sees something else than their mean.
    s.render.samples = 1;
    let rt1 = RtScene::new(&s);
    let one = Tracer::new(&rt1, v).pixel(x, y, &mut RayStats::default());
    assert!(
        max_abs_diff(got.color, one.color) > 0.01,
        "{} {}",
        got.color,
        one.color
    );
}

/// A pixel whose first two samples (top row) see the sphere and whose last
/// two do not, or the other way round.
fn silhouette_pixel(s: &Scene) -> (u32, u32) {
    let v = view(s);
    let eye = s.camera.position;
    let Shape::Sphere { center, radius, .. } = s.objects[1].shape else {
        unreachable!()
    };
    let sees =
        |x: f64, y: f64| hit_sphere(DVec3::ZERO, v.ray_direction(x, y), center - eye, radius);
    for y in 0..s.image.height {
        let (x, fy) = (32u32, f64::from(y));
        if sees(32.25, fy + 0.25).is_some() != sees(32.25, fy + 0.75).is_some() {
            return (x, y);
        }
    }
    panic!("no pixel on the sphere's top or bottom silhouette");
}

#[test]
fn four_samples_of_a_flat_coloured_scene_equal_one() {
    // A plane filling the view, lit by ambient light only: one colour.
    let mut s = scene(24, 16, 40.0);
    s.lights.clear();
    s.lighting.ambient = DVec3::ONE;
    s.materials = vec![material(DVec3::new(0.3, 0.5, 0.7), 1.0, 0.0, 0.0, 1.0)];
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Z,
            size: 100.0,
            segments: 1,
        },
        material: 0,
    });
    let one = crate::common::trace_cpu(&s);
    s.render.samples = 4;
    let four = crate::common::trace_cpu(&s);
    assert_eq!(four.stats.primary, 4 * one.stats.primary);
    assert_eq!(one.image, four.image);
    assert_eq!(one.image.get(3, 5), [0.3, 0.5, 0.7]);
}

#[test]
fn path_signatures_change_at_shadow_and_silhouette_edges_only() {
    let s = shadow_scene(DVec3::new(0.0, 0.5, 0.0));
    let out = crate::common::trace_cpu(&s);
    let distinct: std::collections::HashSet<u64> = out.path_signatures.iter().copied().collect();
    // Background; floor lit; floor in shadow; the sphere lit; the sphere's
    // lower half facing away from the light.
    assert_eq!(distinct.len(), 5, "{} signatures", distinct.len());
    let (_, coverage) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    let marked = coverage.near_edge.iter().filter(|&&e| e).count();
    assert!(
        marked > 50 && marked < 64 * 64 / 4,
        "{marked} pixels near an edge"
    );
    // Deterministic: a second render gives the same signatures.
    assert_eq!(
        crate::common::trace_cpu(&s).path_signatures,
        out.path_signatures
    );
}

#[test]
fn default_scene_traces_every_kind_of_ray() {
    let mut s = shadelab::scene::default_scene();
    s.image.width = 80;
    s.image.height = 60;
    let out = crate::common::trace_cpu(&s);
    let st = out.stats;
    assert_eq!(st.primary, 80 * 60);
    assert!(
        st.shadow > 0 && st.reflected > 0 && st.refracted > 0,
        "{st:?}"
    );
    assert!(st.max_depth_reached >= 3 && st.max_depth_reached <= 5);
    assert!(out.image.pixels.iter().flatten().all(|c| c.is_finite()));
}

#[test]
fn cli_prints_ray_stats() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--backend",
        "cpu",
        "--shading",
        "raytrace",
        "--width",
        "40",
        "--height",
        "30",
        "--depth",
        "2",
        "--stats",
    ];
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("primary"), "{}", run.stdout);
    assert!(run.stdout.contains("1200"), "{}", run.stdout);
    assert!(dir.path().join("default-raytrace.png").exists());
    let mut json_args = args.to_vec();
    json_args.push("--json");
    let run = shadelab(dir.path(), &json_args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let value: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(value["stats"]["primary"], 1200);
    assert_eq!(value["stats"]["max_depth_reached"], 2);
}
