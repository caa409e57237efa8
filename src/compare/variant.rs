//! A variant: a shading mode plus its settings, written
//! `mode[:key=value,...]`, e.g. `flat`, `gouraud:segments=16`,
//! `phong:interpolation=screen`, `raytrace:depth=3,cutoff=0.01,samples=4`,
//! `phong:lighting=blinn.glsl` (a lighting hook, any mode),
//! `raytrace:traversal=query` (the GPU ray tracer's engine),
//! `phong:filter=nearest` (how image textures are filtered, any mode).

use std::fmt;
use std::path::Path;
use std::str::FromStr;
use std::sync::Arc;

use crate::msaa::Msaa;
use crate::scene::{
    FilterPreset, ImageTexture, Interpolation, LightingHook, Pattern, Scene, SceneError, Shape,
    Traversal, MAX_DEPTH,
};
use crate::shading::Shading;

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Variant {
    pub shading: Shading,
    /// Sphere tessellation (raster modes; the ray tracer's spheres are exact).
    pub segments: Option<u32>,
    pub interpolation: Option<Interpolation>,
    pub depth: Option<u32>,
    pub cutoff: Option<f64>,
    pub samples: Option<u32>,
    /// The ray tracer's diffuse bounces (`--bounces`), backward or
    /// forward.
    #[serde(default)]
    pub bounces: Option<u32>,
    /// Forward ray tracing's photons (`--photons`).
    #[serde(default)]
    pub photons: Option<u32>,
    /// The ray tracer's caustics: photons per pass of its photon map
    /// (`--caustics`; 0: none).
    #[serde(default)]
    pub caustics: Option<u32>,
    /// The photon map's passes (`--caustic-passes`).
    #[serde(default)]
    pub caustic_passes: Option<u32>,
    pub shadows: Option<bool>,
    /// A lighting hook's file (`--lighting`), for every mode.
    #[serde(default)]
    pub lighting: Option<String>,
    /// The GPU ray tracer's engine (`--traversal`).
    #[serde(default)]
    pub traversal: Option<Traversal>,
    /// How every image texture is filtered, in place of its sampler's
    /// filters (its wrap modes stay).
    #[serde(default)]
    pub filter: Option<FilterPreset>,
    /// The raster modes' samples per pixel (`--msaa`).
    #[serde(default)]
    pub msaa: Option<Msaa>,
}

impl Variant {
    pub fn plain(shading: Shading) -> Self {
        Self {
            shading,
            segments: None,
            interpolation: None,
            depth: None,
            cutoff: None,
            samples: None,
            bounces: None,
            photons: None,
            caustics: None,
            caustic_passes: None,
            shadows: None,
            lighting: None,
            traversal: None,
            filter: None,
            msaa: None,
        }
    }

    /// The scene with this variant's settings applied; fails on a lighting
    /// hook's file that cannot be read, and on a depth below the bounces
    /// (`RenderSettings::settle_depth`).
    pub fn apply(&self, scene: &Scene) -> Result<Scene, SceneError> {
        let mut s = scene.clone();
        if let Some(path) = &self.lighting {
            s.lighting_hook = Some(Arc::new(LightingHook::load(Path::new(path))?));
        }
        if let Some(n) = self.segments {
            for object in &mut s.objects {
                if let Shape::Sphere { segments, .. } = &mut object.shape {
                    *segments = n;
                }
            }
        }
        if let Some(i) = self.interpolation {
            s.lighting.interpolation = i;
        }
        if let Some(d) = self.depth {
            s.render.depth = d;
            s.render.depth_given = true;
        }
        if let Some(c) = self.cutoff {
            s.render.cutoff = c;
        }
        if let Some(n) = self.samples {
            s.render.samples = n;
        }
        if let Some(n) = self.bounces {
            s.render.bounces = n;
        }
        s.render
            .settle_depth()
            .map_err(|(depth, bounces)| SceneError::Toml {
                file: format!("variant `{self}`"),
                message: format!("bounces={bounces} needs depth={bounces} or more (each bounce is a level of the ray tree), and the depth is {depth}"),
            })?;
        if let Some(n) = self.photons {
            s.render.photons = n;
        }
        if let Some(n) = self.caustics {
            s.render.caustics.photons_per_pass = n;
        }
        if let Some(n) = self.caustic_passes {
            s.render.caustics.passes = n;
        }
        if let Some(on) = self.shadows {
            s.render.shadows = on;
        }
        if let Some(t) = self.traversal {
            s.render.traversal = t;
        }
        if let Some(m) = self.msaa {
            s.render.msaa = m;
        }
        if let Some(filter) = self.filter {
            for material in &mut s.materials {
                if let Some(Pattern::Image(image)) = &mut material.pattern {
                    let mut filtered = ImageTexture::clone(image);
                    filtered.sampler = filter.applied_to(filtered.sampler);
                    *image = Arc::new(filtered);
                }
            }
        }
        Ok(s)
    }
}

impl fmt::Display for Variant {
    /// The canonical spelling, which parses back to the same variant.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut keys = Vec::new();
        if let Some(n) = self.segments {
            keys.push(format!("segments={n}"));
        }
        if let Some(i) = self.interpolation {
            keys.push(format!("interpolation={}", i.name()));
        }
        if let Some(d) = self.depth {
            keys.push(format!("depth={d}"));
        }
        if let Some(c) = self.cutoff {
            keys.push(format!("cutoff={c}"));
        }
        if let Some(n) = self.samples {
            keys.push(format!("samples={n}"));
        }
        if let Some(n) = self.bounces {
            keys.push(format!("bounces={n}"));
        }
        if let Some(n) = self.photons {
            keys.push(format!("photons={n}"));
        }
        if let Some(n) = self.caustics {
            keys.push(format!("caustics={n}"));
        }
        if let Some(n) = self.caustic_passes {
            keys.push(format!("caustic_passes={n}"));
        }
        if let Some(on) = self.shadows {
            keys.push(format!("shadows={on}"));
        }
        if let Some(path) = &self.lighting {
            keys.push(format!("lighting={path}"));
        }
        if let Some(t) = self.traversal {
            keys.push(format!("traversal={}", t.name()));
        }
        if let Some(filter) = self.filter {
            keys.push(format!("filter={}", filter.name()));
        }
        if let Some(m) = self.msaa {
            keys.push(format!("msaa={m}"));
        }
        if keys.is_empty() {
            write!(f, "{}", self.shading)
        } else {
            write!(f, "{}:{}", self.shading, keys.join(","))
        }
    }
}

impl FromStr for Variant {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let (mode, settings) = text.split_once(':').unwrap_or((text, ""));
        let mut v = Variant::plain(
            mode.trim()
                .parse()
                .map_err(|e| format!("variant `{text}`: {e}"))?,
        );
        let mut seen: Vec<&str> = Vec::new();
        for pair in settings.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            // `msaa=4,per-sample`: the rate follows the count.
            if pair == "per-sample" || pair == "per-pixel" {
                let Some(m) = v.msaa.as_mut() else {
                    return Err(format!("variant `{text}`: `{pair}` follows msaa=N"));
                };
                m.per_sample = pair == "per-sample";
                continue;
            }
            let (key, value) = pair
                .split_once('=')
                .ok_or_else(|| format!("variant `{text}`: `{pair}` is not key=value"))?;
            let key = key.trim();
            let value = value.trim();
            // Given twice, one value would win without a word.
            if seen.contains(&key) {
                return Err(format!("variant `{text}`: `{key}` is given more than once"));
            }
            seen.push(key);
            v.set(&Setting { text, key, value })?;
        }
        Ok(v)
    }
}

/// One `key=value` of a variant's text, and what to say when it is wrong.
struct Setting<'a> {
    /// The whole variant, as the user wrote it.
    text: &'a str,
    key: &'a str,
    value: &'a str,
}

impl Setting<'_> {
    fn bad(&self, expected: &str) -> String {
        format!(
            "variant `{}`: {}={} is invalid; expected {expected}",
            self.text, self.key, self.value
        )
    }

    fn only(&self, ok: bool, modes: &str) -> Result<(), String> {
        if ok {
            Ok(())
        } else {
            Err(format!(
                "variant `{}`: `{}` applies to {modes} only",
                self.text, self.key
            ))
        }
    }
}

impl Variant {
    /// Sets one setting, checked against the mode and its range.
    fn set(&mut self, setting: &Setting) -> Result<(), String> {
        let raster = self.shading.raster_mode().is_some();
        let backward = self.shading == Shading::Raytrace;
        let forward = self.shading == Shading::Forward;
        let (value, bad) = (setting.value, |expected: &str| setting.bad(expected));
        match setting.key {
            "segments" => {
                setting.only(raster, "flat, gouraud and phong")?;
                let n: u32 = value.parse().map_err(|_| bad("an integer from 3 to 4096"))?;
                if !(3..=4096).contains(&n) {
                    return Err(bad("an integer from 3 to 4096"));
                }
                self.segments = Some(n);
            }
            "interpolation" => {
                setting.only(raster, "flat, gouraud and phong")?;
                self.interpolation = Some(
                    Interpolation::from_name(value).ok_or_else(|| bad("perspective or screen"))?,
                );
            }
            "depth" => {
                setting.only(!raster, "raytrace and forward")?;
                let range = format!("an integer from 0 to {MAX_DEPTH}");
                let d: u32 = value.parse().map_err(|_| bad(&range))?;
                if d > MAX_DEPTH {
                    return Err(bad(&range));
                }
                self.depth = Some(d);
            }
            "cutoff" => {
                setting.only(backward, "raytrace")?;
                let c: f64 = value.parse().map_err(|_| bad("a number >= 0"))?;
                if !c.is_finite() || c < 0.0 {
                    return Err(bad("a number >= 0"));
                }
                self.cutoff = Some(c);
            }
            "samples" => {
                setting.only(backward, "raytrace")?;
                let n: u32 = value.parse().map_err(|_| bad("an integer from 1 to 1024"))?;
                if !(1..=1024).contains(&n) {
                    return Err(bad("an integer from 1 to 1024"));
                }
                self.samples = Some(n);
            }
            "bounces" => {
                setting.only(!raster, "raytrace and forward")?;
                let n: u32 = value.parse().map_err(|_| bad("an integer from 0 to 64"))?;
                if n > MAX_DEPTH {
                    return Err(bad("an integer from 0 to 64"));
                }
                self.bounces = Some(n);
            }
            "photons" => {
                setting.only(forward, "forward")?;
                let range = "an integer from 1 to 4294967295";
                let n: u32 = value.parse().map_err(|_| bad(range))?;
                if n == 0 {
                    return Err(bad(range));
                }
                self.photons = Some(n);
            }
            "caustics" | "caustic_passes" => {
                setting.only(backward, "raytrace")?;
                self.set_caustics(setting)?;
            }
            "shadows" => {
                setting.only(backward, "raytrace")?;
                self.shadows = Some(value.parse().map_err(|_| bad("true or false"))?);
            }
            "lighting" => {
                if value.is_empty() {
                    return Err(bad("a GLSL file"));
                }
                self.lighting = Some(value.to_string());
            }
            "traversal" => {
                setting.only(backward, "raytrace")?;
                self.traversal = Some(value.parse().map_err(|_| bad("auto, bvh or query"))?);
            }
            "msaa" => {
                setting.only(raster, "flat, gouraud and phong")?;
                self.msaa = Some(value.parse().map_err(|_| bad("a sample count such as 4"))?);
            }
            "filter" => {
                self.filter = Some(
                    FilterPreset::from_name(value)
                        .ok_or_else(|| bad("nearest, bilinear or trilinear"))?,
                );
            }
            key => {
                return Err(format!(
                    "variant `{}`: unknown setting `{key}`; expected segments, interpolation, depth, cutoff, samples, bounces, photons, caustics, caustic_passes, shadows, lighting, traversal, filter or msaa",
                    setting.text
                ))
            }
        }
        Ok(())
    }
}

impl Variant {
    /// `caustics=N` (0 to 2^32 - 1) or `caustic_passes=P` (1 to 2^20),
    /// all the photons numbered in 32 bits.
    fn set_caustics(&mut self, setting: &Setting) -> Result<(), String> {
        let bad = |expected: &str| setting.bad(expected);
        if setting.key == "caustics" {
            let range = "an integer from 0 to 4294967295";
            self.caustics = Some(setting.value.parse().map_err(|_| bad(range))?);
        } else {
            let range = "an integer from 1 to 1048576";
            let n: u32 = setting.value.parse().map_err(|_| bad(range))?;
            if !(1..=1 << 20).contains(&n) {
                return Err(bad(range));
            }
            self.caustic_passes = Some(n);
        }
        self.check_caustic_photons(setting)
    }

    /// A variant's caustic photons in all are numbered in 32 bits.
    fn check_caustic_photons(&self, setting: &Setting) -> Result<(), String> {
        let photons = u64::from(self.caustics.unwrap_or(0));
        let passes = u64::from(self.caustic_passes.unwrap_or(1));
        if photons * passes > u64::from(u32::MAX) {
            return Err(format!(
                "variant `{}`: caustics times caustic_passes is {} photons, past 4294967295",
                setting.text,
                photons * passes
            ));
        }
        Ok(())
    }
}

/// The variants that show a scene's interesting axes: every mode; a
/// tessellation sweep of the raster modes if the scene has spheres; screen
/// against perspective interpolation; 4 samples per pixel in each raster
/// mode; a depth sweep and a cut-off sweep of
/// the ray tracer if anything reflects or refracts; where the scene asks
/// for caustics (and has some), its photon map at 4, 16 and 64 passes and
/// none; the three texture
/// filters in Phong shading and ray tracing if an object has an image.
pub fn default_variants(scene: &Scene) -> Vec<Variant> {
    let parse = |s: &str| s.parse::<Variant>().expect("built-in variants parse");
    let mut list = Vec::new();
    let has_spheres = scene
        .objects
        .iter()
        .any(|o| matches!(o.shape, Shape::Sphere { .. }));
    for mode in ["flat", "gouraud", "phong"] {
        if has_spheres {
            for n in [8, 16, 32, 64, 128, 256] {
                list.push(parse(&format!("{mode}:segments={n}")));
            }
        } else {
            list.push(parse(mode));
        }
    }
    list.push(parse("gouraud:interpolation=screen"));
    list.push(parse("phong:interpolation=screen"));
    // What 4 samples a pixel cost and buy, beside the ray tracer's 4.
    for mode in ["flat", "gouraud", "phong"] {
        list.push(parse(&format!("{mode}:msaa=4")));
    }
    let secondary = scene.materials.iter().any(|m| m.kr > 0.0 || m.kt > 0.0);
    if secondary {
        for d in [0, 1, 2, 3, 5] {
            list.push(parse(&format!("raytrace:depth={d},cutoff=0")));
        }
        for c in ["0.1", "0.01"] {
            list.push(parse(&format!("raytrace:depth=5,cutoff={c}")));
        }
    } else {
        list.push(parse("raytrace"));
    }
    list.push(parse("raytrace:samples=4"));
    if scene.render.caustics.on() && crate::render::caustics::no_caustic(scene).is_none() {
        // SPPM's error pass by pass, at the scene's photons per pass; and
        // the ray tracer without them, what the caustics cost and buy.
        for passes in [4, 16, 64] {
            list.push(parse(&format!("raytrace:caustic_passes={passes}")));
        }
        list.push(parse("raytrace:caustics=0"));
    }
    let textured = scene
        .objects
        .iter()
        .any(|o| matches!(scene.materials[o.material].pattern, Some(Pattern::Image(_))));
    if textured {
        for mode in ["phong", "raytrace"] {
            for filter in ["nearest", "bilinear", "trilinear"] {
                list.push(parse(&format!("{mode}:filter={filter}")));
            }
        }
    }
    list
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Filter, Sampler};

    #[test]
    fn variants_round_trip_through_their_names() {
        for text in [
            "flat",
            "gouraud:segments=16",
            "phong:interpolation=screen",
            "raytrace:depth=3,cutoff=0.01,samples=4",
            "raytrace:shadows=false",
            "phong:lighting=examples/lighting/blinn-phong.glsl",
            "raytrace:depth=2,lighting=hook.glsl",
            "raytrace:depth=1,traversal=query",
            "raytrace:traversal=bvh",
            "phong:filter=nearest",
            "raytrace:depth=2,filter=trilinear",
            "flat:filter=bilinear",
            "phong:msaa=4",
            "gouraud:segments=16,msaa=4,per-sample",
            "raytrace:samples=16,bounces=2",
            "forward:bounces=2,photons=1048576",
            "raytrace:caustics=65536,caustic_passes=16",
        ] {
            let v: Variant = text.parse().unwrap();
            assert_eq!(v.to_string(), text);
            assert_eq!(v.to_string().parse::<Variant>().unwrap(), v);
        }
    }

    /// A filter replaces every image's filters and keeps its wrap modes;
    /// checkers and untextured materials are left alone.
    #[test]
    fn a_filter_variant_sets_every_image_sampler() {
        use crate::scene::{Texture, UvTransform, Wrap};
        let mut scene = crate::scene::default_scene();
        let clamped = Sampler {
            wrap_u: Wrap::ClampToEdge,
            wrap_v: Wrap::MirroredRepeat,
            ..Sampler::GLTF_DEFAULT
        };
        scene.materials[0].pattern = Some(Pattern::Image(Arc::new(ImageTexture {
            name: "t".into(),
            texture: Texture::new(1, 1, vec![[1.0; 3]]),
            sampler: clamped,
            transform: UvTransform::IDENTITY,
        })));
        let sampler_of = |s: &Scene| match &s.materials[0].pattern {
            Some(Pattern::Image(image)) => image.sampler,
            _ => panic!("an image"),
        };
        for (name, filter, mipmap) in [
            ("nearest", Filter::Nearest, None),
            ("bilinear", Filter::Linear, None),
            ("trilinear", Filter::Linear, Some(Filter::Linear)),
        ] {
            let v: Variant = format!("phong:filter={name}").parse().unwrap();
            let applied = sampler_of(&v.apply(&scene).unwrap());
            assert_eq!(
                applied,
                Sampler {
                    magnification: filter,
                    minification: filter,
                    mipmap,
                    ..clamped
                },
                "{name}"
            );
            assert_eq!(v.apply(&scene).unwrap().materials[1], scene.materials[1]);
        }
        let names: Vec<String> = default_variants(&scene)
            .iter()
            .map(|v| v.to_string())
            .collect();
        assert!(
            names.iter().any(|n| n == "raytrace:filter=nearest"),
            "{names:?}"
        );
        let plain: Vec<String> = default_variants(&crate::scene::default_scene())
            .iter()
            .map(|v| v.to_string())
            .collect();
        assert!(!plain.iter().any(|n| n.contains("filter")), "{plain:?}");
    }

    #[test]
    fn bad_variants_say_what_is_wrong() {
        for (text, word) in [
            ("toon", "variant `toon`: unknown shading mode `toon`"),
            ("flat:depth=3", "raytrace and forward only"),
            ("forward:samples=4", "raytrace only"),
            ("raytrace:photons=1000", "forward only"),
            ("forward:photons=0", "1 to 4294967295"),
            ("phong:caustics=1000", "raytrace only"),
            ("raytrace:caustic_passes=0", "1 to 1048576"),
            (
                "raytrace:caustics=100000,caustic_passes=100000",
                "past 4294967295",
            ),
            ("raytrace:segments=8", "flat, gouraud and phong only"),
            ("gouraud:segments=2", "3 to 4096"),
            ("raytrace:cutoff=-1", ">= 0"),
            ("phong:shiny=1", "unknown setting"),
            ("phong:segments", "key=value"),
            ("phong:traversal=query", "raytrace only"),
            ("raytrace:traversal=rtx", "auto, bvh or query"),
            ("phong:filter=anisotropic", "nearest, bilinear or trilinear"),
            ("raytrace:msaa=4", "flat, gouraud and phong only"),
            ("phong:msaa=zero", "a sample count"),
            ("phong:per-sample", "follows msaa=N"),
            (
                "raytrace:depth=3,depth=4",
                "`depth` is given more than once",
            ),
            (
                "phong:segments=8, segments=8",
                "`segments` is given more than once",
            ),
        ] {
            let e = text.parse::<Variant>().unwrap_err();
            assert!(e.contains(word), "{text}: {e}");
        }
    }

    #[test]
    fn the_default_list_sweeps_the_interesting_axes() {
        let list = default_variants(&crate::scene::default_scene());
        // The engine is the device's choice unless asked for.
        assert!(list.iter().all(|v| v.traversal.is_none()));
        let names: Vec<String> = list.iter().map(|v| v.to_string()).collect();
        for want in [
            "flat:segments=8",
            "phong:segments=256",
            "gouraud:interpolation=screen",
            "raytrace:depth=0,cutoff=0",
            "raytrace:depth=5,cutoff=0.01",
        ] {
            assert!(
                names.iter().any(|n| n == want),
                "{want} missing from {names:?}"
            );
        }
    }
}
