//! The camera, the projection and the tessellation against oracles of
//! their own: the GPU and the CPU reference share `camera::View` and
//! `tessellate`, so their agreement says nothing about either.

use glam::{DVec3, DVec4};
use shadelab::camera::View;
use shadelab::scene::{default_scene, tessellate, Shape};

/// A camera at (1, 2, 3) looking down -z, its `up` tilted 45 degrees in
/// the image plane (and not perpendicular to the view until projected),
/// 90-degree vertical field of view, a 200 x 100 image.
fn rolled_view() -> View {
    let mut scene = default_scene();
    scene.camera.position = DVec3::new(1.0, 2.0, 3.0);
    scene.camera.look_at = DVec3::new(1.0, 2.0, 0.0);
    scene.camera.up = DVec3::new(1.0, 1.0, 0.5);
    scene.camera.fov_y_deg = 90.0;
    View::new(&scene, 200, 100)
}

/// By hand: forward f = (0, 0, -1); right = normalize(f x up) =
/// (1, -1, 0) / sqrt 2; true up = right x f = (1, 1, 0) / sqrt 2. With
/// tan(45 deg) = 1 and aspect 2, pixel (x, y)'s centre looks along
/// f + (2 (x + 1/2) / 200 - 1) * 2 * right + (1 - 2 (y + 1/2) / 100) * up.
fn by_hand(x: u32, y: u32) -> DVec3 {
    let s = 0.5f64.sqrt();
    let (f, right, up) = (
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(s, -s, 0.0),
        DVec3::new(s, s, 0.0),
    );
    let u = (2.0 * (f64::from(x) + 0.5) / 200.0 - 1.0) * 2.0;
    let v = 1.0 - 2.0 * (f64::from(y) + 0.5) / 100.0;
    (f + u * right + v * up).normalize()
}

const PIXELS: [(u32, u32); 5] = [(0, 0), (199, 0), (0, 99), (199, 99), (137, 41)];

#[test]
fn pixel_centres_become_the_rays_computed_by_hand() {
    let view = rolled_view();
    // The top-left pixel written out: u = -1.99, v = 0.99, so the ray is
    // f - 1.99 right + 0.99 up = (-1.99 s + 0.99 s, 1.99 s + 0.99 s, -1).
    let s = 0.5f64.sqrt();
    let corner = DVec3::new(-s, 2.98 * s, -1.0).normalize();
    assert!((view.ray_direction(0.5, 0.5) - corner).length() < 1e-12);
    for (x, y) in PIXELS {
        let got = view.ray_direction(f64::from(x) + 0.5, f64::from(y) + 0.5);
        assert!(
            (got - by_hand(x, y)).length() < 1e-12,
            "pixel ({x}, {y}): {got} against {}",
            by_hand(x, y)
        );
    }
}

#[test]
fn the_raster_projection_puts_each_rays_points_on_its_pixel_centre() {
    // Vulkan's conventions: x right, y down in normalised device
    // coordinates from -1 to 1 across the viewport; depth reversed (near
    // is 1, far towards 0) and within [0, 1].
    let view = rolled_view();
    let clip = view.clip_from_relative();
    for (x, y) in PIXELS {
        for distance in [0.5, 3.0, 40.0] {
            let relative = by_hand(x, y) * distance;
            let c = clip * DVec4::new(relative.x, relative.y, relative.z, 1.0);
            let (px, py) = (
                (c.x / c.w + 1.0) / 2.0 * 200.0,
                (c.y / c.w + 1.0) / 2.0 * 100.0,
            );
            assert!(
                (px - f64::from(x) - 0.5).abs() < 1e-9 && (py - f64::from(y) - 0.5).abs() < 1e-9,
                "pixel ({x}, {y}) at distance {distance}: projected to ({px}, {py})"
            );
            let depth = c.z / c.w;
            assert!((0.0..=1.0).contains(&depth), "depth {depth}");
        }
    }
    // Nearer is greater (reversed Z).
    let depth = |d: f64| {
        let r = by_hand(100, 50) * d;
        let c = clip * DVec4::new(r.x, r.y, r.z, 1.0);
        c.z / c.w
    };
    assert!(depth(1.0) > depth(2.0) && depth(2.0) > depth(50.0));
}

#[test]
fn tessellated_spheres_and_boxes_have_no_cracks() {
    // Every edge, by the positions of its ends, is used by exactly two
    // triangles, once in each direction: no crack, no T-junction, no
    // flipped triangle.
    let shapes = [
        Shape::Sphere {
            center: DVec3::new(0.5, -1.0, 2.0),
            radius: 1.7,
            segments: 3,
        },
        Shape::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
            segments: 37,
        },
        Shape::Box {
            center: DVec3::new(1.0, 2.0, 3.0),
            half_extents: DVec3::new(0.5, 2.0, 1.0),
            rotation: glam::DMat3::from_rotation_x(0.4) * glam::DMat3::from_rotation_z(1.1),
        },
    ];
    for shape in shapes {
        let mesh = tessellate(&shape);
        let key = |p: DVec3| [p.x, p.y, p.z].map(|c| (c * 1e9).round() as i64);
        let mut edges = std::collections::HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                let (a, b) = (
                    mesh.positions[t[k] as usize],
                    mesh.positions[t[(k + 1) % 3] as usize],
                );
                *edges.entry((key(a), key(b))).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "{shape:?}: edge {a:?} -> {b:?} used {n} times");
            assert_eq!(
                edges.get(&(b, a)),
                Some(&1),
                "{shape:?}: edge {a:?} -> {b:?} has no opposite"
            );
        }
    }
}

/// `View::project`, which the tests use to find the pixel a point lands
/// on, against the hand-worked rays: every point along a pixel's ray lands
/// on that pixel's centre, and a point behind the near plane has no pixel.
/// (cargo-mutants found it unguarded: six mutants of it survived.)
#[test]
fn a_point_projects_to_the_centre_of_the_pixel_whose_ray_holds_it() {
    let view = rolled_view();
    let eye = DVec3::new(1.0, 2.0, 3.0);
    for (x, y) in PIXELS {
        for distance in [0.5, 3.0, 40.0] {
            let at = view
                .project(eye + by_hand(x, y) * distance)
                .unwrap_or_else(|| panic!("pixel ({x}, {y}) at {distance}: no pixel"));
            assert!(
                (at.x - f64::from(x) - 0.5).abs() < 1e-9
                    && (at.y - f64::from(y) - 0.5).abs() < 1e-9,
                "pixel ({x}, {y}) at distance {distance}: projected to {at}"
            );
        }
    }
    // Behind the eye, and in front of it but nearer than the near plane.
    assert_eq!(view.project(eye - by_hand(137, 41)), None);
    assert_eq!(view.project(eye + by_hand(137, 41) * view.near * 0.5), None);
}
