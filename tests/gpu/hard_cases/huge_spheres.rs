//! The big-sphere family: a ball on "planet" floors of radius 1e5 to 1e20,
//! a sky sphere of radius 1e30 around the eye, smallpt's box of six spheres
//! of radius 1e5, and the side of a surface that is lit.

use super::*;
use glam::Vec3;
use shadelab::cpu::intersect::{huge_sphere, Ray};
use shadelab::rt_scene::RtScene;

const PLANETS: [(&str, f64); 4] = [
    ("planet-1e5.toml", 1e5),
    ("planet-1e6.toml", 1e6),
    ("planet-1e10.toml", 1e10),
    ("planet-1e20.toml", 1e20),
];

/// The hit distance on a sphere of radius `r` centred at `(0, -r, 0)`, from
/// `eye` along unit `d`, written from Haines, Günther and Akenine-Möller
/// (Ray Tracing Gems, ch. 7) for this geometry alone and sharing no code
/// with the project: `|e - c|² - r²` expanded by hand so that the `r²`
/// terms cancel before any rounding (`e·e + 2 e.y r`), `b = -(e - c)·d`,
/// and the near root as `c / (b + sqrt(b² - c))`, which cancels nothing.
/// `None` for a ray that misses or leaves the sphere behind.
fn planet_distance(eye: DVec3, d: DVec3, r: f64) -> Option<f64> {
    let c = eye.x * eye.x + eye.y * eye.y + eye.z * eye.z + 2.0 * eye.y * r;
    let b = -(eye.x * d.x + (eye.y + r) * d.y + eye.z * d.z);
    let disc = b * b - c;
    (c > 0.0 && b > 0.0 && disc >= 0.0).then(|| c / (b + disc.sqrt()))
}

/// The same near root computed as a shader without the anchor would, in
/// f32 from the f32 centre (the "before" of docs/hard-cases.md).
fn plain_f32_distance(centre: Vec3, r: f32, d: Vec3) -> f32 {
    let f = -centre;
    let b = -f.dot(d);
    let l = f + b * d;
    let disc = r * r - l.dot(l);
    let q = b + b.signum() * disc.max(0.0).sqrt();
    (f.dot(f) - r * r) / q
}

/// The anchored form (docs/raytracing.md, "Huge sphere") in f32, from the
/// f32-rounded record the GPU gets.
fn anchored_f32_distance(anchor: Vec3, n: Vec3, inv_r: f32, r: f32, d: Vec3) -> f32 {
    let g = -anchor;
    let cr = g.dot(g * inv_r + 2.0 * n);
    let b = -g.dot(d) * inv_r - n.dot(d);
    let q = b + b.signum() * (b * b - cr * inv_r).max(0.0).sqrt();
    let (t0, t1) = (cr / q, q * r);
    if t0.min(t1) > 0.0 {
        t0.min(t1)
    } else {
        t0.max(t1)
    }
}

/// Every pixel ray of each planet scene that meets the floor: the CPU
/// twin's anchored test agrees with the independent solution to 1e-13
/// relative, and the same test in f32, as the shader runs it, to 1e-6,
/// where the plain f32 form is off by far more from 1e6 on (measured:
/// 4e-3 relative at 1e6, the whole distance at 1e10 and beyond).
#[test]
fn planet_hit_distances_match_an_independent_solution() {
    for (name, r) in PLANETS {
        let s = hard(name);
        let rt = RtScene::new(&s);
        assert_eq!(
            rt.huge_spheres.len(),
            1,
            "{name}: the planet is tested from its anchor"
        );
        let planet = &rt.huge_spheres[0];
        let v = view(&s);
        let eye = s.camera.position;
        let (mut rays, mut worst_f64, mut worst_f32, mut worst_plain) = (0, 0.0f64, 0.0f64, 0.0f64);
        for y in (0..s.image.height).step_by(3) {
            for x in (0..s.image.width).step_by(3) {
                let d = pixel_ray(&v, x, y);
                let Some(expected) = planet_distance(eye, d, r) else {
                    continue;
                };
                rays += 1;
                let ray = Ray {
                    origin: DVec3::ZERO,
                    dir: d,
                };
                let t = huge_sphere(&ray, planet).expect("the twin hits where the solution does");
                worst_f64 = worst_f64.max((t - expected).abs() / expected);
                let a = planet.anchor;
                let t32 = anchored_f32_distance(
                    a.point.as_vec3(),
                    a.normal.as_vec3(),
                    (1.0 / r) as f32,
                    r as f32,
                    d.as_vec3(),
                );
                worst_f32 = worst_f32.max((f64::from(t32) - expected).abs() / expected);
                let plain =
                    plain_f32_distance(planet.sphere.center.as_vec3(), r as f32, d.as_vec3());
                let plain_error = (f64::from(plain) - expected).abs() / expected;
                // NaN where r² overflows f32 (r = 1e20): no distance at all.
                worst_plain = worst_plain.max(if plain_error.is_nan() {
                    f64::INFINITY
                } else {
                    plain_error
                });
            }
        }
        assert!(rays > 500, "{name}: only {rays} rays meet the floor");
        assert!(
            worst_f64 < 1e-13,
            "{name}: the f64 twin is off by {worst_f64:e}"
        );
        assert!(
            worst_f32 < 1e-6,
            "{name}: the f32 anchored form is off by {worst_f32:e}"
        );
        if r >= 1e6 {
            assert!(
                worst_plain > 1e-3,
                "{name}: the plain form held ({worst_plain:e})"
            );
        }
    }
}

/// As the planet grows its floor becomes the plane y = 0: at 10 units it
/// lies 10² / 2R below it, 5e-9 at R = 1e10. Ray traced, on the GPU and
/// the CPU, the floors of 1e10 and 1e20 show exactly the image of a flat
/// floor (an independent shape: the plane test), shadow and all; those of
/// 1e5 and 1e6 below the horizon's rows, whose place moves with R.
/// Measured: 3e-8 at 1e10, 0 at 1e20; before the anchored test the GPU
/// drew no shadow at 1e10 and no floor at 1e20.
#[test]
fn planet_floors_ray_traced_are_a_flat_floor() {
    let context = gpu();
    for (name, r) in PLANETS {
        let planet = hard(name);
        let mut flat = planet.clone();
        flat.objects[0].shape = Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Y,
            size: 2e6,
            segments: 1,
        };
        // The horizon is within a pixel of eye level at every radius here;
        // below row 48 (of 120) every ray meets the floor within 30 units.
        let first_row = if r >= 1e10 { 0 } else { 48 };
        let limit = if r >= 1e10 { 1e-6 } else { 1e-3 };
        let (p, f) = (
            render(&context, &planet, Shading::Raytrace),
            render(&context, &flat, Shading::Raytrace),
        );
        let (pc, _) = crate::common::render_cpu(&planet, Shading::Raytrace).unwrap();
        let (fc, _) = crate::common::render_cpu(&flat, Shading::Raytrace).unwrap();
        for (side, a, b) in [("GPU", &p, &f), ("CPU", &pc.image, &fc.image)] {
            let mut worst = 0.0f64;
            for y in first_row..a.height {
                for x in 0..a.width {
                    worst = worst.max(max_abs_diff(to_dvec(a.get(x, y)), to_dvec(b.get(x, y))));
                }
            }
            assert!(
                worst < limit,
                "{name} {side}: {worst:e} from the flat floor"
            );
        }
    }
}

/// The raster modes draw the planet as a fan of facets around its pole
/// under the ball, the same facets near the eye at every radius, so the
/// ball (its middle, away from its outline) and, in flat and Phong
/// shading, the floor below the horizon are the image of R = 1e5 at every
/// radius, on the GPU and the CPU. Before the near plane followed the
/// nearest surface it was 1e-5 of the scene's extent (2e15 at R = 1e20)
/// and clipped the ball away in every raster mode, on both.
#[test]
fn planet_floors_keep_the_ball_in_every_raster_mode() {
    let context = gpu();
    let small = hard("planet-1e5.toml");
    let centre = view(&small).project(DVec3::new(0.0, 1.0, 0.0)).unwrap();
    for mode in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let base = render(&context, &small, mode);
        let (base_cpu, _) = crate::common::render_cpu(&small, mode).unwrap();
        for (name, _) in &PLANETS[1..] {
            let s = hard(name);
            let image = render(&context, &s, mode);
            let (cpu, _) = crate::common::render_cpu(&s, mode).unwrap();
            for (side, a, b) in [("GPU", &image, &base), ("CPU", &cpu.image, &base_cpu.image)] {
                let mut worst_ball = 0.0f64;
                let mut worst_floor = 0.0f64;
                for y in 0..a.height {
                    for x in 0..a.width {
                        let d = max_abs_diff(to_dvec(a.get(x, y)), to_dvec(b.get(x, y)));
                        let at = glam::DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                        if (at - centre).length() < 12.0 {
                            worst_ball = worst_ball.max(d);
                        } else if y >= 90 {
                            worst_floor = worst_floor.max(d);
                        }
                    }
                }
                assert!(
                    worst_ball < 1e-4,
                    "{name} {mode} {side}: the ball differs by {worst_ball}"
                );
                if mode != Shading::Gouraud {
                    assert!(
                        worst_floor < 1e-3,
                        "{name} {mode} {side}: the floor differs by {worst_floor}"
                    );
                }
            }
        }
    }
}

/// A sphere of radius 1e30 around the eye: wherever the ball and the floor
/// are not, every mode shows its inside, lit as its back, which a light
/// 1e30 away leaves at its ambient term (the light's share is 8e-30). The
/// ray tracer drew the background there before the anchored test (r² is
/// 1e60, past f32), and the raster modes clipped the ball and the floor
/// (a near plane at 2e25).
#[test]
fn a_sky_sphere_around_the_eye_shows_its_inside() {
    let s = hard("sky-sphere-1e30.toml");
    let sky = &s.materials[s.objects[0].material];
    let expected = s.lighting.ambient * sky.ka * sky.color;
    let context = gpu();
    let floor_centre = view(&s).project(DVec3::new(0.0, 0.0, 1.5)).unwrap();
    for mode in MODES {
        let image = render(&context, &s, mode);
        let (cpu, _) = crate::common::render_cpu(&s, mode).unwrap();
        for (side, image) in [("GPU", &image), ("CPU", &cpu.image)] {
            for (x, y) in [(2, 2), (image.width - 3, 2), (2, image.height / 3)] {
                let value = to_dvec(image.get(x, y));
                assert!(
                    max_abs_diff(value, expected) < 1e-6 * expected.max_element(),
                    "{mode} {side} ({x}, {y}): {value} where the sky is {expected}"
                );
            }
            let (x, y) = (floor_centre.x as u32, floor_centre.y as u32);
            assert!(
                max_abs_diff(to_dvec(image.get(x, y)), expected) > 1e-2,
                "{mode} {side}: the floor before the ball is missing"
            );
        }
    }
}

/// smallpt's box is the inside of six spheres of radius 1e5: its walls,
/// seen from inside, are lit by the light inside (their back, by the rule
/// of docs/lighting-model.md), in every mode, on the GPU and the CPU. With
/// the outside lit alone they were at their ambient term exactly. Phong
/// and the ray tracer light each point: well above the ambient term. Flat
/// and Gouraud shading light the tessellated walls where the facets'
/// centroids and corners are, about 1000 units from a light 50 away: just
/// above it (2% measured).
#[test]
fn smallpt_walls_are_lit_from_inside() {
    let s = hard("smallpt-box.toml");
    let left = &s.materials[s.objects[0].material];
    let ambient = s.lighting.ambient * left.ka * left.color;
    let context = gpu();
    for mode in MODES {
        let image = render(&context, &s, mode);
        let (cpu, _) = crate::common::render_cpu(&s, mode).unwrap();
        for (side, image) in [("GPU", &image), ("CPU", &cpu.image)] {
            // The left (red) wall, a tenth in from the left, halfway up.
            let value = to_dvec(image.get(image.width / 10, image.height / 2));
            let lit = match mode {
                Shading::Flat | Shading::Gouraud => value.x > 1.01 * ambient.x,
                _ => value.x > ambient.x + 0.05,
            };
            assert!(
                lit && value.x > 2.0 * value.z,
                "{mode} {side}: the left wall is {value}, its ambient term {ambient}"
            );
        }
    }
}

/// A plane seen from below and lit from below is lit as its back: the image
/// of a plane whose normal is +Y equals that of the same plane with normal
/// -Y, in every mode, GPU and CPU (its winding, and so which side the
/// raster modes call the front, is the other way round). Flat and Gouraud
/// shading light each triangle at its centroid or corners, and the two
/// planes split their cells along other diagonals: there both are lit,
/// not equal.
#[test]
fn a_surface_seen_from_behind_is_lit_as_its_back() {
    let up = scene::from_toml_str(
        r#"
[camera]
position = [0.3, -3.0, 5.0]
look_at  = [0.0, 0.0, 0.0]
[image]
width = 96
height = 72
[[lights]]
position = [1.0, -2.0, 2.0]
intensity = 6.0
[materials.m]
color = [0.8, 0.6, 0.3]
ks = 0.5
p = 20
[[objects]]
shape = "plane"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = 4.0
segments = 6
material = "m"
"#,
        std::path::Path::new("."),
        "below.toml",
    )
    .unwrap();
    let mut down = up.clone();
    if let Shape::Plane { normal, .. } = &mut down.objects[0].shape {
        *normal = -DVec3::Y;
    }
    let context = gpu();
    for mode in MODES {
        let (a, b) = (render(&context, &up, mode), render(&context, &down, mode));
        let (ca, _) = crate::common::render_cpu(&up, mode).unwrap();
        let (cb, _) = crate::common::render_cpu(&down, mode).unwrap();
        let lit = (0..a.height)
            .flat_map(|y| (0..a.width).map(move |x| (x, y)))
            .filter(|&(x, y)| to_dvec(cb.image.get(x, y)).x > 0.3)
            .count();
        assert!(
            lit > 500,
            "{mode}: the plane's underside is not lit ({lit} pixels)"
        );
        if matches!(mode, Shading::Flat | Shading::Gouraud) {
            let lit_up = (0..a.height)
                .flat_map(|y| (0..a.width).map(move |x| (x, y)))
                .filter(|&(x, y)| to_dvec(ca.image.get(x, y)).x > 0.3)
                .count();
            assert!(
                lit_up > 500,
                "{mode}: the +Y plane's underside is not lit ({lit_up} pixels)"
            );
            continue;
        }
        for (side, a, b) in [("GPU", &a, &b), ("CPU", &ca.image, &cb.image)] {
            let worst = worst_difference(a, b);
            assert!(worst < 1e-5, "{mode} {side}: +Y and -Y differ by {worst}");
        }
    }
}
