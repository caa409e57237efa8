//! The TOML scene file as serde reads it: one struct per table, every
//! table denying unknown keys, and the value types that check themselves
//! (a finite number, a number or `[x, y, z]`) so that the TOML parser
//! attaches the line of a bad value. Nothing here knows the [`Scene`]
//! model beyond the enums a key names directly.
//!
//! [`Scene`]: crate::scene::Scene

use std::collections::BTreeMap;
use std::fmt;

use glam::DVec3;
use serde::de::{self, Deserializer, IgnoredAny, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use crate::scene::model::{Falloff, Interpolation, Traversal};

/// A finite number; TOML integers are accepted too.
#[derive(Debug, Clone, Copy)]
pub(super) struct Finite(pub(super) f64);

struct FiniteVisitor;

impl Visitor<'_> for FiniteVisitor {
    type Value = Finite;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a finite number")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Finite, E> {
        if v.is_finite() {
            Ok(Finite(v))
        } else {
            Err(E::custom(format!(
                "non-finite number {v}; expected a finite number"
            )))
        }
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Finite, E> {
        Ok(Finite(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Finite, E> {
        Ok(Finite(v as f64))
    }
}

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FiniteVisitor)
    }
}

/// `[x, y, z]` of finite numbers.
pub(super) type V3 = [Finite; 3];

pub(super) fn v3(v: &V3) -> DVec3 {
    DVec3::new(v[0].0, v[1].0, v[2].0)
}

/// A number or `[x, y, z]`, all finite.
#[derive(Debug, Clone, Copy)]
pub(super) enum NumOr3 {
    Num(f64),
    Vec(DVec3),
}

impl NumOr3 {
    pub(super) fn splat(self) -> DVec3 {
        match self {
            NumOr3::Num(x) => DVec3::splat(x),
            NumOr3::Vec(v) => v,
        }
    }
}

struct NumOr3Visitor;

impl<'de> Visitor<'de> for NumOr3Visitor {
    type Value = NumOr3;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a finite number or an array of 3 finite numbers")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<NumOr3, E> {
        FiniteVisitor.visit_f64(v).map(|x| NumOr3::Num(x.0))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<NumOr3, E> {
        Ok(NumOr3::Num(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<NumOr3, E> {
        Ok(NumOr3::Num(v as f64))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<NumOr3, A::Error> {
        let mut out = [0.0; 3];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq
                .next_element::<Finite>()?
                .ok_or_else(|| de::Error::invalid_length(i, &self))?
                .0;
        }
        if seq.next_element::<IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok(NumOr3::Vec(DVec3::from_array(out)))
    }
}

impl<'de> Deserialize<'de> for NumOr3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NumOr3Visitor)
    }
}

/// The whole file: `[camera]` is required, every other table optional.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileRaw {
    pub(super) camera: Spanned<CameraRaw>,
    pub(super) image: Option<ImageRaw>,
    pub(super) lighting: Option<LightingRaw>,
    #[serde(default)]
    pub(super) lights: Vec<Spanned<LightRaw>>,
    #[serde(default)]
    pub(super) materials: BTreeMap<String, Spanned<MaterialRaw>>,
    #[serde(default)]
    pub(super) objects: Vec<Spanned<ObjectRaw>>,
    pub(super) render: Option<RenderRaw>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraRaw {
    pub(super) position: Spanned<V3>,
    pub(super) look_at: Spanned<V3>,
    pub(super) up: Option<Spanned<V3>>,
    pub(super) fov_y: Option<Spanned<Finite>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ImageRaw {
    pub(super) width: Option<Spanned<i64>>,
    pub(super) height: Option<Spanned<i64>>,
    pub(super) background: Option<Spanned<V3>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightingRaw {
    pub(super) ambient: Option<Spanned<NumOr3>>,
    pub(super) k: Option<Spanned<Finite>>,
    pub(super) interpolation: Option<Interpolation>,
    pub(super) attenuation: Option<bool>,
    pub(super) falloff: Option<Spanned<Falloff>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightRaw {
    pub(super) position: V3,
    pub(super) intensity: Spanned<NumOr3>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialRaw {
    pub(super) color: Option<Spanned<V3>>,
    pub(super) ka: Option<Spanned<Finite>>,
    pub(super) kd: Option<Spanned<Finite>>,
    pub(super) ks: Option<Spanned<Finite>>,
    pub(super) p: Option<Spanned<Finite>>,
    pub(super) kr: Option<Spanned<Finite>>,
    pub(super) kt: Option<Spanned<Finite>>,
    pub(super) ior: Option<Spanned<Finite>>,
    pub(super) pattern: Option<Spanned<PatternRaw>>,
    pub(super) texture: Option<Spanned<TextureRaw>>,
}

/// `texture = { file = "floor.png", scale = 1, wrap = "repeat", filter =
/// "trilinear" }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TextureRaw {
    pub(super) file: Spanned<String>,
    pub(super) scale: Option<Spanned<Finite>>,
    pub(super) rotation: Option<Spanned<Finite>>,
    pub(super) offset: Option<Spanned<[Finite; 2]>>,
    pub(super) wrap: Option<Spanned<String>>,
    pub(super) filter: Option<Spanned<String>>,
}

/// `pattern = { kind = "checker", scale = 8, colors = [[...], [...]] }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PatternRaw {
    pub(super) kind: Spanned<String>,
    pub(super) scale: Option<Spanned<Finite>>,
    pub(super) colors: Option<Spanned<Vec<V3>>>,
}

/// The union of every shape's keys; which ones are allowed is checked per
/// shape after parsing, so that every key keeps its line.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ObjectRaw {
    pub(super) shape: Spanned<String>,
    pub(super) center: Option<Spanned<V3>>,
    pub(super) radius: Option<Spanned<Finite>>,
    pub(super) segments: Option<Spanned<i64>>,
    pub(super) normal: Option<Spanned<V3>>,
    pub(super) size: Option<Spanned<NumOr3>>,
    pub(super) rotate_deg: Option<Spanned<V3>>,
    pub(super) material: Option<Spanned<String>>,
    pub(super) file: Option<Spanned<String>>,
    pub(super) translate: Option<Spanned<V3>>,
    pub(super) scale: Option<Spanned<NumOr3>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RenderRaw {
    pub(super) depth: Option<Spanned<i64>>,
    pub(super) cutoff: Option<Spanned<Finite>>,
    pub(super) shadows: Option<bool>,
    pub(super) samples: Option<Spanned<i64>>,
    pub(super) bounces: Option<Spanned<i64>>,
    pub(super) photons: Option<Spanned<i64>>,
    pub(super) caustics: Option<Spanned<i64>>,
    pub(super) caustic_passes: Option<Spanned<i64>>,
    pub(super) caustic_radius: Option<Spanned<Finite>>,
    pub(super) traversal: Option<Traversal>,
    pub(super) msaa: Option<Spanned<MsaaRaw>>,
    pub(super) watchdog: Option<Spanned<Finite>>,
}

/// `msaa = 4` or `msaa = "4,per-sample"`.
#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum MsaaRaw {
    Count(i64),
    Text(String),
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

    #[test]
    fn non_finite_numbers_are_rejected_with_their_line() {
        for (text, line) in [
            (with_camera("[lighting]\nk = nan\n"), "line 5"),
            (with_camera("[lighting]\nambient = inf\n"), "line 5"),
            (
                with_camera("[[lights]]\nposition = [0, -inf, 0]\nintensity = 1\n"),
                "line 5",
            ),
            (
                "[camera]\nposition = [0, 0, nan]\nlook_at = [0, 0, 0]\n".to_string(),
                "line 2",
            ),
            (with_camera("[materials.m]\np = -inf\n"), "line 5"),
        ] {
            let e = parse_err(&text);
            assert_has(&e, &[line, "non-finite", "finite number"]);
        }
    }
}
