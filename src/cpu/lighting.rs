//! The lighting model of `docs/lighting-model.md` in `f64`: the CPU twin of
//! `shaders/include/lighting.glsl`. A change to one is a change to the other,
//! and the raster tests hold the GPU images to this function.
//!
//! Defined answers where naive code is undefined (the same on the GPU):
//! a zero normal receives the ambient term only; a light exactly at the
//! shaded point contributes nothing; `p = 0` gives `S = 1` whenever the
//! light faces the surface (x^0 = 1, also for x = 0); and a light faces it
//! only when `N·L > FACING_EPS max(1, r / d)` ([`facing`]), not by rounding.

use glam::DVec3;

/// A light must face the surface by more than rounding: `N·L <= FACING_EPS`
/// counts as behind the terminator (the twin of `FACING_EPS` in
/// lighting.glsl). A light in the surface's own plane has `N·L = 0`, which
/// f32 turns into a rounding error of either sign; without this the GPU
/// would switch the whole specular term on at random there.
pub const FACING_EPS: f64 = 1e-5;

/// Whether a light at distance `d` with `n_dot_l` faces a point `r` from
/// the eye by more than rounding: `N·L > FACING_EPS · max(1, r / d)`. The
/// GPU rounds a point relative to its distance from the eye, which near a
/// light lying in the surface (`d` much below `r`) turns `L` by about
/// 1e-7 `r / d` (assets/hard/light-on-surface.toml at 8 samples a pixel).
pub fn facing(n_dot_l: f64, d: f64, r: f64) -> bool {
    n_dot_l > FACING_EPS * (r / d).max(1.0)
}

use crate::scene::{Lighting, Material, PointLight};

/// What the formula reads of the surface at a point: its material, and the
/// colour the point adds to the material's (its vertex colour; `DVec3::ONE`
/// where it has none). The formula's `C` is `material.color * tint`
/// (docs/lighting-model.md, "Surface colour").
#[derive(Debug, Clone, Copy)]
pub struct Surface<'a> {
    pub material: &'a Material,
    pub tint: DVec3,
}

impl<'a> Surface<'a> {
    /// The material's colour alone.
    pub fn plain(material: &'a Material) -> Self {
        Surface {
            material,
            tint: DVec3::ONE,
        }
    }

    /// `C` at the point. A tint of one multiplies exactly, so an untinted
    /// surface's `C` is the material's colour bit for bit.
    pub fn color(&self) -> DVec3 {
        self.material.color * self.tint
    }
}

/// Intensity `I` (linear RGB) at point `p` with unit normal `n` (or zero),
/// seen from `eye`.
pub fn shade(
    lighting: &Lighting,
    lights: &[PointLight],
    surface: Surface,
    p: DVec3,
    n: DVec3,
    eye: DVec3,
) -> DVec3 {
    if n == DVec3::ZERO {
        return lighting.ambient * surface.material.ka * surface.color();
    }
    let v = (eye - p).normalize();
    shade_visible(lighting, lights, surface, (p, eye), n, v, |_, _| true)
}

/// `shade` with the unit vector toward the viewer `v` given (the ray tracer
/// passes `-d`; `eye` is the camera's, for `facing`), and light `j` counted
/// only if `visible(j, light)` says so.
/// `visible` is asked, in light order, only for the lights that would add
/// something ([`facing`] and not at the point): the ray tracer casts
/// shadow rays for exactly those.
pub fn shade_visible(
    lighting: &Lighting,
    lights: &[PointLight],
    surface: Surface,
    (p, eye): (DVec3, DVec3),
    n: DVec3,
    v: DVec3,
    mut visible: impl FnMut(usize, &PointLight) -> bool,
) -> DVec3 {
    let material = surface.material;
    let c = surface.color();
    let mut intensity = lighting.ambient * material.ka * c;
    if n == DVec3::ZERO {
        return intensity;
    }
    for (j, light) in lights.iter().enumerate() {
        let to_light = light.position - p;
        let d = to_light.length();
        if d == 0.0 {
            continue;
        }
        let l = to_light / d;
        let n_dot_l = n.dot(l);
        if !facing(n_dot_l, d, (p - eye).length()) || !visible(j, light) {
            continue;
        }
        let il = lighting.falloff.attenuate(light.intensity, d, lighting.k);
        let r = 2.0 * n_dot_l * n - l;
        let r_dot_v = r.dot(v).max(0.0);
        let s = if material.p == 0.0 {
            1.0
        } else {
            r_dot_v.powf(material.p)
        };
        intensity += il * (material.kd * c * n_dot_l + DVec3::splat(material.ks * s));
    }
    intensity
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Interpolation;

    /// A light faces a point by more than FACING_EPS, or by FACING_EPS r/d
    /// where it is nearer the point than the eye: 1e-4 faces a point 10
    /// from the eye from 100 away, not from 0.01 away (that needs 1e-2).
    #[test]
    fn facing_grows_with_the_eye_distance_over_the_light_distance() {
        assert!(facing(1e-4, 100.0, 10.0));
        assert!(!facing(1e-4, 0.01, 10.0));
        assert!(facing(2e-2, 0.01, 10.0));
        assert!(!facing(FACING_EPS, 100.0, 10.0));
        assert!(!facing(0.0, 1.0, 0.0));
    }

    fn lighting() -> Lighting {
        Lighting {
            ambient: DVec3::splat(0.2),
            k: 1.0,
            interpolation: Interpolation::Perspective,
            falloff: crate::scene::Falloff::Lecture,
        }
    }

    fn material(p: f64) -> Material {
        Material {
            name: "m".into(),
            color: DVec3::new(1.0, 0.5, 0.25),
            ka: 0.5,
            kd: 0.6,
            ks: 0.4,
            p,
            kr: 0.0,
            kt: 0.0,
            ior: 1.0,
            pattern: None,
        }
    }

    #[test]
    fn light_straight_above_matches_hand_computation() {
        // Light 3 units above the point, eye 4 units above: N·L = 1, R = N,
        // R·V = 1, so I = Ia ka C + Il/(3 + 1) (kd C + ks).
        let light = PointLight {
            position: DVec3::new(0.0, 3.0, 0.0),
            intensity: DVec3::splat(8.0),
        };
        let i = shade(
            &lighting(),
            &[light],
            Surface::plain(&material(20.0)),
            DVec3::ZERO,
            DVec3::Y,
            DVec3::new(0.0, 4.0, 0.0),
        );
        let expected =
            DVec3::new(1.0, 0.5, 0.25) * (0.2 * 0.5 + 2.0 * 0.6) + DVec3::splat(2.0 * 0.4);
        assert!(
            (i - expected).abs().max_element() < 1e-12,
            "{i} vs {expected}"
        );
    }

    /// The same light 3 units above under each falloff: Il divided by
    /// d + k = 4, by d^2 = 9, or by nothing.
    #[test]
    fn each_falloff_divides_by_what_it_names() {
        let light = PointLight {
            position: DVec3::new(0.0, 3.0, 0.0),
            intensity: DVec3::splat(8.0),
        };
        let direct = |falloff: crate::scene::Falloff| {
            let lit = Lighting {
                falloff,
                ..lighting()
            };
            let ambient = lit.ambient * 0.5 * DVec3::new(1.0, 0.5, 0.25);
            shade(
                &lit,
                &[light],
                Surface::plain(&material(20.0)),
                DVec3::ZERO,
                DVec3::Y,
                DVec3::new(0.0, 4.0, 0.0),
            ) - ambient
        };
        let unattenuated = DVec3::new(1.0, 0.5, 0.25) * (8.0 * 0.6) + DVec3::splat(8.0 * 0.4);
        use crate::scene::Falloff::*;
        for (falloff, divisor) in [(Lecture, 4.0), (InverseSquare, 9.0), (None, 1.0)] {
            let want = unattenuated / divisor;
            let got = direct(falloff);
            assert!(
                (got - want).abs().max_element() < 1e-12,
                "{falloff:?}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn defined_answers_for_degenerate_inputs() {
        let light = PointLight {
            position: DVec3::ZERO,
            intensity: DVec3::ONE,
        };
        let ambient = DVec3::new(1.0, 0.5, 0.25) * 0.1;
        // Zero normal: ambient only.
        let i = shade(
            &lighting(),
            &[light],
            Surface::plain(&material(2.0)),
            DVec3::X,
            DVec3::ZERO,
            DVec3::Y,
        );
        assert_eq!(i, ambient);
        // Light at the point: ambient only, no NaN.
        let i = shade(
            &lighting(),
            &[light],
            Surface::plain(&material(2.0)),
            DVec3::ZERO,
            DVec3::Y,
            DVec3::Y,
        );
        assert_eq!(i, ambient);
        // p = 0 with R·V = 0 (eye in the tangent plane): S = 1.
        let above = PointLight {
            position: DVec3::new(0.0, 1.0, 0.0),
            intensity: DVec3::splat(2.0),
        };
        let i = shade(
            &lighting(),
            &[above],
            Surface::plain(&material(0.0)),
            DVec3::ZERO,
            DVec3::Y,
            DVec3::X,
        );
        let expected = ambient + DVec3::new(1.0, 0.5, 0.25) * 0.6 + DVec3::splat(0.4);
        assert!((i - expected).abs().max_element() < 1e-12);
    }

    /// A tint scales the ambient and diffuse terms channel by channel and
    /// leaves the specular term the light's colour.
    #[test]
    fn a_tint_colours_ambient_and_diffuse_but_not_the_highlight() {
        let light = PointLight {
            position: DVec3::new(0.0, 3.0, 0.0),
            intensity: DVec3::splat(8.0),
        };
        let m = material(20.0);
        let tint = DVec3::new(0.5, 0.25, 2.0);
        let i = shade(
            &lighting(),
            &[light],
            Surface { material: &m, tint },
            DVec3::ZERO,
            DVec3::Y,
            DVec3::new(0.0, 4.0, 0.0),
        );
        // As in `light_straight_above_matches_hand_computation`, with C = (1, 0.5, 0.25) * tint.
        let c = DVec3::new(0.5, 0.125, 0.5);
        let expected = c * (0.2 * 0.5 + 2.0 * 0.6) + DVec3::splat(2.0 * 0.4);
        assert!(
            (i - expected).abs().max_element() < 1e-12,
            "{i} vs {expected}"
        );
    }
}
