//! Phong shading against the lighting formula evaluated in double precision
//! at each pixel's exact sphere point, and one test per lighting parameter
//! showing it changes the image as the formula says.

use crate::common;

use common::*;
use glam::DVec3;
use shadelab::cpu::lighting::{shade, Surface};
use shadelab::scene::{Falloff, Object, PointLight, Scene, Shape};
use shadelab::shading::Shading;
use shadelab::LinearImage;

const RADIUS: f64 = 2.0;
const SEGMENTS: u32 = 512;
const SIZE: u32 = 128;

fn sphere_scene() -> Scene {
    let mut s = scene(SIZE, SIZE, 30.0);
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: RADIUS,
            segments: SEGMENTS,
        },
        material: 0,
    });
    s
}

/// The tolerance for Phong on the tessellated sphere, derived from its
/// tessellation. A UV-sphere cell spans 2*pi/S in longitude and latitude, so a
/// point inside a triangle is at most alpha = sqrt(2)*pi/S (half the cell's
/// angular diagonal) from a vertex. The flat triangle lies within
/// r*(1 - cos(alpha)) ~ r*alpha^2/2 of the sphere, and the renormalised
/// interpolated normal is within ~alpha^2/2 of the radial direction; for view
/// rays within 60 degrees of the normal the shaded point's normal then differs
/// from the exact one by at most 2*alpha^2 (a factor 2 of margin). Rotating N
/// by dtheta changes N.L by at most dtheta and R.V by at most 2*dtheta, so
/// |dI| <= L * (kd*C + 2*p*ks) * dtheta with L = max Il/(d + k). Add 1e-5 for
/// f32 arithmetic on values below ~2.
fn phong_tolerance(scene: &Scene) -> f64 {
    let m = &scene.materials[0];
    let alpha = std::f64::consts::SQRT_2 * std::f64::consts::PI / f64::from(SEGMENTS);
    let dtheta = 2.0 * alpha * alpha;
    let light_scale: f64 = scene
        .lights
        .iter()
        .map(|l| {
            let d_min = (l.position.length() - RADIUS).max(0.0);
            let divisor = scene.lighting.falloff.divisor(d_min, scene.lighting.k);
            l.intensity.max_element() / divisor.unwrap_or(1.0)
        })
        .sum();
    light_scale * (m.kd * m.color.max_element() + 2.0 * m.p * m.ks) * dtheta + 1e-5
}

/// Interior sphere pixels (3x3 neighbourhood on the sphere, view ray within
/// 60 degrees of the normal) with the formula's value at the exact hit.
fn expected_values(scene: &Scene) -> Vec<(u32, u32, DVec3)> {
    let v = view(scene);
    let (w, h) = (scene.image.width, scene.image.height);
    let ids = id_map(w, h, |x, y| {
        hit_sphere(v.eye, pixel_ray(&v, x, y), DVec3::ZERO, RADIUS).map(|_| 0)
    });
    interior_pixels(w, h, &ids)
        .into_iter()
        .filter_map(|(x, y, _)| {
            let dir = pixel_ray(&v, x, y);
            let t = hit_sphere(v.eye, dir, DVec3::ZERO, RADIUS)?;
            let p = v.eye + dir * t;
            let n = p / RADIUS;
            (n.dot(-dir) > 0.5).then(|| {
                let i = shade(
                    &scene.lighting,
                    &scene.lights,
                    Surface::plain(&scene.materials[0]),
                    p,
                    n,
                    v.eye,
                );
                (x, y, i)
            })
        })
        .collect()
}

/// Renders with Phong and asserts every interior pixel is within the derived
/// tolerance of the formula. Returns the image and the expected values.
fn assert_matches_formula(scene: &Scene) -> (LinearImage, Vec<(u32, u32, DVec3)>) {
    let image = render(&gpu(), scene, Shading::Phong);
    let expected = expected_values(scene);
    assert!(
        expected.len() > 2000,
        "too few interior pixels: {}",
        expected.len()
    );
    let tol = phong_tolerance(scene);
    let mut worst = 0.0f64;
    for &(x, y, i) in &expected {
        let err = max_abs_diff(to_dvec(image.get(x, y)), i);
        worst = worst.max(err);
        assert!(
            err <= tol,
            "pixel ({x}, {y}): GPU {:?}, formula {i}, error {err:.3e} > tolerance {tol:.3e}",
            image.get(x, y)
        );
    }
    eprintln!(
        "max error {worst:.3e} (tolerance {tol:.3e}) over {} pixels",
        expected.len()
    );
    (image, expected)
}

/// The mean over the common interior pixels of image `b` minus image `a`,
/// on the GPU and by the formula; the two must agree.
fn assert_change_as_predicted(
    (a_img, a_exp): &(LinearImage, Vec<(u32, u32, DVec3)>),
    (b_img, b_exp): &(LinearImage, Vec<(u32, u32, DVec3)>),
    min_change: f64,
) {
    let mut gpu = DVec3::ZERO;
    let mut formula = DVec3::ZERO;
    for (&(x, y, ea), &(_, _, eb)) in a_exp.iter().zip(b_exp) {
        gpu += to_dvec(b_img.get(x, y)) - to_dvec(a_img.get(x, y));
        formula += eb - ea;
    }
    let n = a_exp.len() as f64;
    let (gpu, formula) = (gpu / n, formula / n);
    assert!(
        formula.abs().max_element() >= min_change,
        "the parameter should change the image by at least {min_change}, formula says {formula}"
    );
    assert!(
        max_abs_diff(gpu, formula) < 1e-3,
        "mean change on the GPU {gpu} differs from the formula's {formula}"
    );
}

#[test]
fn phong_sphere_matches_formula_through_exr() {
    let scene = sphere_scene();
    let image = render(&gpu(), &scene, Shading::Phong);
    // Through the EXR encoder and decoder: linear floats survive exactly.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sphere.exr");
    shadelab::output::write_image(&image, &path).unwrap();
    let decoded = shadelab::output::read_image(&path).unwrap();
    assert_eq!(decoded, image, "EXR round trip must be lossless");
    let tol = phong_tolerance(&scene);
    let expected = expected_values(&scene);
    assert!(expected.len() > 2000);
    for (x, y, i) in expected {
        let err = max_abs_diff(to_dvec(decoded.get(x, y)), i);
        assert!(err <= tol, "pixel ({x}, {y}): error {err:.3e} > {tol:.3e}");
    }
}

#[test]
fn background_where_nothing_is_hit() {
    let scene = sphere_scene();
    let mut s = scene.clone();
    s.image.background = DVec3::new(0.1, 0.2, 0.3);
    let image = render(&gpu(), &s, Shading::Phong);
    let corner = image.get(0, 0);
    assert_eq!(corner, [0.1, 0.2, 0.3]);
}

#[test]
fn several_lights_add_up() {
    let mut one = sphere_scene();
    one.lights = vec![PointLight {
        position: DVec3::new(-6.0, 2.0, 6.0),
        intensity: DVec3::splat(6.0),
    }];
    let mut other = sphere_scene();
    other.lights = vec![PointLight {
        position: DVec3::new(5.0, -3.0, 7.0),
        intensity: DVec3::new(2.0, 8.0, 4.0),
    }];
    let mut both = sphere_scene();
    both.lights = vec![one.lights[0], other.lights[0]];
    both.lights.push(PointLight {
        position: DVec3::new(0.0, 9.0, 2.0),
        intensity: DVec3::splat(3.0),
    });
    assert_matches_formula(&both);
    // Linearity in the lights: I(L1 + L2) = I(L1) + I(L2) - ambient, at every
    // pixel (the geometry, hence the coverage, is identical in all three).
    both.lights.truncate(2);
    let context = gpu();
    let (a, b, ab) = (
        render(&context, &one, Shading::Phong),
        render(&context, &other, Shading::Phong),
        render(&context, &both, Shading::Phong),
    );
    let m = &one.materials[0];
    let ambient = one.lighting.ambient * m.ka * m.color;
    let mut lit = 0;
    for i in 0..ab.pixels.len() {
        if a.pixels[i] == [0.0; 3] {
            continue; // background
        }
        let sum = to_dvec(a.pixels[i]) + to_dvec(b.pixels[i]) - ambient;
        // f32 rounding of three sums of terms below ~2.
        assert!(max_abs_diff(sum, to_dvec(ab.pixels[i])) < 1e-5, "pixel {i}");
        lit += 1;
    }
    assert!(lit > 5000);
}

#[test]
fn rgb_light_intensity_lights_only_its_channels() {
    let mut s = sphere_scene();
    s.lights[0].intensity = DVec3::new(10.0, 0.0, 0.0);
    let (image, expected) = assert_matches_formula(&s);
    let m = &s.materials[0];
    let ambient = s.lighting.ambient * m.ka * m.color;
    for (x, y, _) in expected {
        let [r, g, b] = image.get(x, y);
        assert!((f64::from(g) - ambient.y).abs() < 1e-6 && (f64::from(b) - ambient.z).abs() < 1e-6);
        assert!(f64::from(r) >= ambient.x - 1e-6);
    }
}

#[test]
fn rgb_ambient_is_per_channel() {
    let mut s = sphere_scene();
    s.lights.clear();
    s.lighting.ambient = DVec3::new(0.5, 0.25, 1.0);
    let (image, expected) = assert_matches_formula(&s);
    let m = &s.materials[0];
    for (x, y, _) in expected {
        let want = s.lighting.ambient * m.ka * m.color;
        assert!(max_abs_diff(to_dvec(image.get(x, y)), want) < 1e-6);
    }
}

#[test]
fn attenuation_constant_k() {
    let mut near = sphere_scene();
    near.lighting.k = 0.0;
    let mut far = sphere_scene();
    far.lighting.k = 8.0;
    assert_change_as_predicted(
        &assert_matches_formula(&near),
        &assert_matches_formula(&far),
        0.05,
    );
}

/// `falloff = "inverse-square"`: Il / d^2, about a tenth of the lecture's
/// 10 / (d + 1) at d ~ 10, so the image darkens by most of its diffuse
/// light, as the formula says pixel by pixel.
#[test]
fn inverse_square_falloff() {
    let lecture = sphere_scene();
    let mut physical = sphere_scene();
    physical.lighting.falloff = Falloff::InverseSquare;
    assert_change_as_predicted(
        &assert_matches_formula(&lecture),
        &assert_matches_formula(&physical),
        0.05,
    );
}

#[test]
fn attenuation_switched_off() {
    let on = sphere_scene();
    let mut off = sphere_scene();
    off.lighting.falloff = Falloff::None;
    // Unattenuated, 3 is about three times the 10 / (d + 1) the light gives at d ~ 10.
    off.lights[0].intensity = DVec3::splat(3.0);
    assert_change_as_predicted(
        &assert_matches_formula(&on),
        &assert_matches_formula(&off),
        0.05,
    );
}

#[test]
fn ambient_coefficient_ka() {
    let base = sphere_scene();
    let mut more = sphere_scene();
    more.materials[0].ka = 0.9;
    assert_change_as_predicted(
        &assert_matches_formula(&base),
        &assert_matches_formula(&more),
        0.05,
    );
}

#[test]
fn diffuse_coefficient_kd() {
    let base = sphere_scene();
    let mut less = sphere_scene();
    less.materials[0].kd = 0.1;
    assert_change_as_predicted(
        &assert_matches_formula(&base),
        &assert_matches_formula(&less),
        0.05,
    );
}

#[test]
fn specular_coefficient_ks() {
    let base = sphere_scene();
    let mut matte = sphere_scene();
    matte.materials[0].ks = 0.0;
    assert_change_as_predicted(
        &assert_matches_formula(&base),
        &assert_matches_formula(&matte),
        0.01,
    );
}

#[test]
fn glossiness_p() {
    let base = sphere_scene();
    let mut glossy = sphere_scene();
    glossy.materials[0].p = 60.0;
    assert_change_as_predicted(
        &assert_matches_formula(&base),
        &assert_matches_formula(&glossy),
        0.01,
    );
}

#[test]
fn material_color_tints_ambient_and_diffuse_not_specular() {
    let mut s = sphere_scene();
    s.materials[0].color = DVec3::new(0.0, 0.0, 1.0);
    s.materials[0].ks = 0.8;
    let (image, expected) = assert_matches_formula(&s);
    // Red and green receive only the untinted specular term, so they are
    // equal everywhere, and nonzero at the highlight.
    let mut highlight = 0.0f32;
    for (x, y, _) in expected {
        let [r, g, _] = image.get(x, y);
        assert!((r - g).abs() < 1e-6);
        highlight = highlight.max(r);
    }
    assert!(highlight > 0.1, "specular highlight missing: {highlight}");
}
