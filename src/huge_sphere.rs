//! Spheres that the plain ray/sphere test cannot hold in `f32`: a "planet"
//! floor of radius 1e6 under a unit ball, a wall of smallpt's box, a sky
//! sphere of radius 1e30 around the eye.
//!
//! The plain test (`docs/raytracing.md`, "Nearest hit") needs
//! `c = |o - centre|² - r²`. Near the surface of a sphere much larger than
//! the eye's height above it, both terms are about `r²` and their
//! difference is a rounding error: at `r = 1e6` an `f32` hit distance is off
//! by a few hundredths, so shadows land in the wrong place; at `r = 1e20`
//! the centre itself, rounded to `f32`, is off by 1e13; at `r = 1e30` the
//! square overflows. The remedy (Haines, Günther and Akenine-Möller,
//! "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems,
//! 2019, ch. 7, taken one step further): describe the sphere from the point
//! of its surface nearest the eye, its *anchor*, where the rays are. With
//! `g = o - anchor` and `n` the outward normal there,
//! `c / r = g·(g / r + 2 n)`: the `r²` terms cancel exactly in the algebra,
//! not in the rounding. The anchor's place is one `f64` number, the eye's
//! height above the surface, which [`altitude`] finds with error-free
//! products so that even `r = 1e20` (where the eye relative to the centre
//! does not exist in `f64`) loses nothing.
//!
//! [`sphere_form`] decides, from the eye alone, which test a sphere gets;
//! both ray tracers (GPU and CPU) follow it, and a sphere neither test can
//! hold is refused when the scene is loaded ([`refusal`]).

use glam::DVec3;

/// A sphere is tested from its anchor when its radius is more than this
/// many times the eye's height above (or depth below) its surface: then
/// the plain test's relative error in `c` (about `6e-8 r / (2 h)`) would
/// exceed about 5e-7, and it grows without bound as the eye nears the
/// surface. Below it the plain test is as good and keeps the sphere in the
/// fast paths (the BVH of spheres, the ray-query engine's boxes).
pub const ANCHOR_RATIO: f64 = 16.0;

/// The plain test squares `|o - centre|`, which `f32` holds up to about
/// 1.8e19: a sphere reaching farther from the eye than this is tested from
/// its anchor.
pub const PLAIN_REACH: f64 = 1.0e18;

/// The anchored test divides `|g|²` by `r`; the anchor must be near enough
/// that this stays far below `f32`'s 3.4e38 (`h² / r` below this).
pub const ANCHORED_REACH: f64 = 1.0e36;

/// The largest radius every mode renders. The ray tracer holds up to about
/// 1e37 (the far side of a sphere is `2 r` away, and an `f32` distance
/// ends at 3.4e38), but the raster modes' facets of such a sphere lie `r`
/// from the eye, and lavapipe's f32 interpolation over them gives out
/// first: Gouraud on the planet floor and the sky sphere passes `check` at
/// 1e33 and fails it from 1e34 (the sky at 1e34 off by 1.3e-2, the planet
/// at 1e36 by 4.5e-3; flat, Phong and the ray tracer still pass there).
pub const MAX_RADIUS: f64 = 1.0e33;

/// A sphere as the anchored test sees it, relative to the eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereAnchor {
    /// The point of the surface nearest the eye, relative to the eye
    /// (`-altitude * normal`).
    pub point: DVec3,
    /// The unit outward normal at `point` (from the centre toward the eye;
    /// `+Y` for an eye at the very centre).
    pub normal: DVec3,
    /// The eye's signed height above the surface: negative inside.
    pub altitude: f64,
}

/// Which ray/sphere test a sphere gets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SphereForm {
    /// The plain stable form: the sphere is small or far enough.
    Plain,
    /// The anchored form, for a sphere large where the eye is.
    Anchored(SphereAnchor),
}

/// The eye's signed height above the sphere's surface, and the unit
/// outward normal at the surface point nearest the eye.
///
/// `|e - c|² - r²` is summed from error-free products (`mul_add` gives each
/// product's rounding error exactly) and the exact differences `e_i - c_i`
/// (as a rounded value and its error), so the cancellation of the `r²`
/// terms costs nothing; the height is then that difference over
/// `|e - c| + r`, which cancels nothing.
pub fn altitude(eye: DVec3, centre: DVec3, radius: f64) -> (f64, DVec3) {
    // On the stack: the camera's near plane takes every sphere's altitude
    // on every render.
    let mut terms = [0.0f64; 14];
    let mut offset = DVec3::ZERO;
    for axis in 0..3 {
        let (hi, lo) = two_difference(eye[axis], centre[axis]);
        offset[axis] = hi;
        let (square, square_error) = two_product(hi, hi);
        terms[4 * axis..4 * axis + 4].copy_from_slice(&[
            square,
            square_error,
            2.0 * hi * lo,
            lo * lo,
        ]);
    }
    let (r2, r2_error) = two_product(radius, radius);
    terms[12..].copy_from_slice(&[-r2, -r2_error]);
    let difference = compensated_sum(&mut terms);
    let distance = offset.length();
    let height = difference / (distance + radius);
    let normal = if distance > 0.0 {
        offset / distance
    } else {
        DVec3::Y
    };
    (height, normal)
}

/// The test a sphere gets, seen from `eye`: see [`ANCHOR_RATIO`] and
/// [`PLAIN_REACH`].
pub fn sphere_form(eye: DVec3, centre: DVec3, radius: f64) -> SphereForm {
    let (altitude, normal) = altitude(eye, centre, radius);
    let reach = (eye - centre).length() + radius;
    if radius > ANCHOR_RATIO * altitude.abs() || reach > PLAIN_REACH {
        SphereForm::Anchored(SphereAnchor {
            point: -altitude * normal,
            normal,
            altitude,
        })
    } else {
        SphereForm::Plain
    }
}

/// Why `f32` cannot trace this sphere seen from `eye`, if it cannot: the
/// message a scene loader puts after the object's name.
pub fn refusal(eye: DVec3, centre: DVec3, radius: f64) -> Option<String> {
    if radius > MAX_RADIUS {
        return Some(format!(
            "radius {radius:e} is over {MAX_RADIUS:e}: the raster modes' 32-bit float \
             interpolation over facets that far from the camera loses the image (Gouraud is off \
             by 1e-2 at 1e34)"
        ));
    }
    let (altitude, _) = altitude(eye, centre, radius);
    if altitude * altitude / radius > ANCHORED_REACH {
        return Some(format!(
            "its surface is {:e} from the camera, too far for radius {radius:e}: the ray test's \
             square of that distance over the radius ({:e}) would overflow 32-bit floats (limit \
             {ANCHORED_REACH:e}); move the camera nearer or the sphere closer",
            altitude.abs(),
            altitude * altitude / radius
        ));
    }
    None
}

/// `a - b` as its rounded value and the exact rounding error.
fn two_difference(a: f64, b: f64) -> (f64, f64) {
    let s = a - b;
    let bb = s - a;
    let error = (a - (s - bb)) - (b + bb);
    (s, error)
}

/// `a * b` as its rounded value and the exact rounding error.
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Neumaier's compensated sum, largest magnitudes first.
fn compensated_sum(terms: &mut [f64]) -> f64 {
    terms.sort_by(|a, b| b.abs().total_cmp(&a.abs()));
    let (mut sum, mut carry) = (0.0f64, 0.0f64);
    for &x in terms.iter() {
        let t = sum + x;
        carry += if sum.abs() >= x.abs() {
            (sum - t) + x
        } else {
            (x - t) + sum
        };
        sum = t;
    }
    sum + carry
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_height_above_a_planet_is_exact_where_the_offset_is_not() {
        // The eye 1.5 above a sphere of radius 1e20: e - c = 1e20 + 1.5 is
        // not an f64 (its spacing there is 16384), yet the height is.
        let r = 1e20;
        let (h, n) = altitude(DVec3::new(0.0, 1.5, 6.0), DVec3::new(0.0, -r, 0.0), r);
        // sqrt((r + 1.5)² + 36) - r = 1.5 + 18 / r + ...
        assert!((h - 1.5).abs() < 1e-12, "{h}");
        assert!((n - DVec3::Y).length() < 1e-15, "{n}");
        // And below the surface, by as much.
        let (h, _) = altitude(DVec3::new(0.0, -1.5, 0.0), DVec3::new(0.0, -r, 0.0), r);
        assert!((h + 1.5).abs() < 1e-12, "{h}");
    }

    #[test]
    fn an_eye_at_the_centre_is_a_radius_below_the_surface() {
        let (h, n) = altitude(DVec3::ZERO, DVec3::ZERO, 1e30);
        assert!((h + 1e30).abs() < 1e15, "{h}");
        assert_eq!(n, DVec3::Y);
        assert!(matches!(
            sphere_form(DVec3::ZERO, DVec3::ZERO, 1e30),
            SphereForm::Anchored(a) if (a.point - DVec3::new(0.0, 1e30, 0.0)).length() < 1e15
        ));
    }

    #[test]
    fn small_and_middling_spheres_keep_the_plain_test() {
        let eye = DVec3::new(0.0, 1.5, 6.0);
        assert_eq!(sphere_form(eye, DVec3::ZERO, 1.0), SphereForm::Plain);
        assert_eq!(
            sphere_form(eye, DVec3::new(1e5, 0.0, 0.0), 1.0),
            SphereForm::Plain
        );
        // The eye 1.5 above a sphere of radius 20: under the ratio.
        assert_eq!(
            sphere_form(DVec3::new(0.0, 1.5, 0.0), DVec3::new(0.0, -20.0, 0.0), 20.0),
            SphereForm::Plain
        );
        assert!(matches!(
            sphere_form(DVec3::new(0.0, 1.5, 0.0), DVec3::new(0.0, -30.0, 0.0), 30.0),
            SphereForm::Anchored(_)
        ));
    }

    #[test]
    fn what_f32_cannot_hold_is_refused() {
        let eye = DVec3::ZERO;
        assert!(refusal(eye, DVec3::new(0.0, -1e30, 0.0), 1e30).is_none());
        assert!(refusal(eye, DVec3::new(0.0, -1e33, 0.0), 1e33).is_none());
        assert!(refusal(eye, DVec3::new(0.0, -2e33, 0.0), 2e33).is_some());
        // A unit sphere 1e20 away: 1e40 / 1 overflows.
        assert!(refusal(eye, DVec3::new(1e20, 0.0, 0.0), 1.0).is_some());
        assert!(refusal(eye, DVec3::new(1e17, 0.0, 0.0), 1.0).is_none());
    }
}
