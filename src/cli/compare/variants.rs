//! Which variants `compare` renders: those given (each once) or a list
//! chosen for the scene, less those over the memory limit (left out with
//! the reason) and, of the chosen list, the sample counts the device does
//! not render.

use std::collections::BTreeMap;

use shadelab::compare::{default_variants, Variant};
use shadelab::gpu::DeviceInfo;
use shadelab::memory::MemoryLimit;
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use crate::cli::common::failure::Failure;

/// The variants `--variants` names, or, where it names none, the list
/// chosen for the scene; refused when the list is empty or names one twice.
pub(super) fn variants_of(given: &[String], scene: &Scene) -> Result<Vec<Variant>, Failure> {
    let variants: Vec<Variant> = if given.is_empty() {
        default_variants(scene)
    } else {
        given
            .iter()
            .map(|v| v.trim())
            .filter(|v| !v.is_empty())
            .map(|v| v.parse::<Variant>().map_err(Failure::usage))
            .collect::<Result<_, _>>()?
    };
    if variants.is_empty() {
        return Err(Failure::usage("--variants names no variant".into()));
    }
    refuse_repeats(&variants)?;
    Ok(variants)
}

/// The modes of the variants, each once, in the variants' order.
pub(super) fn modes_of(variants: &[Variant]) -> Vec<Shading> {
    let mut modes: Vec<Shading> = Vec::new();
    for v in variants {
        if !modes.contains(&v.shading) {
            modes.push(v.shading);
        }
    }
    modes
}

/// Refuses a variant given twice (by its canonical name, or by the file its
/// image would be written to).
fn refuse_repeats(variants: &[Variant]) -> Result<(), Failure> {
    for (k, v) in variants.iter().enumerate() {
        let (name, stem) = (
            v.to_string(),
            shadelab::compare::report::file_stem(&v.to_string()),
        );
        if let Some(earlier) = variants[..k].iter().find(|e| {
            e.to_string() == name || shadelab::compare::report::file_stem(&e.to_string()) == stem
        }) {
            return Err(Failure::usage(format!(
                "--variants names {name} twice (as {earlier} and {v}); give each variant once"
            )));
        }
    }
    Ok(())
}

/// The variants over the memory limit, by name, with the reason: each
/// variant (its tessellation may differ) against the references, the global
/// one traced on the CPU, a local one per mode. One over the limit is left
/// out and the others run; none that fits refuses the run, as a render over
/// the limit is.
pub(super) fn over_the_limit(
    scene: &Scene,
    name: &str,
    variants: &[Variant],
    memory: &MemoryLimit,
) -> Result<BTreeMap<String, String>, Failure> {
    // Only a tessellation override changes the geometry; copying the scene
    // for the others would double the memory this check guards.
    let mut over_the_limit = BTreeMap::new();
    for variant in variants {
        let varied = match (variant.segments, variant.msaa) {
            (None, None) => std::borrow::Cow::Borrowed(scene),
            _ => std::borrow::Cow::Owned(variant.apply(scene)?),
        };
        let modes = [variant.shading];
        let references = [variant.shading, Shading::Raytrace];
        if let Err(e) = memory.check(name, &varied, &modes, &references) {
            over_the_limit.insert(variant.to_string(), Failure::from(e));
        }
    }
    if over_the_limit.len() == variants.len() {
        let first = over_the_limit.remove(&variants[0].to_string());
        return Err(first.expect("every variant is over the limit"));
    }
    Ok(over_the_limit
        .into_iter()
        .map(|(name, failure)| (name, failure.message))
        .collect())
}

/// The variants whose sample count the device renders.
pub(super) fn rendered_by(info: &DeviceInfo, variants: Vec<Variant>) -> Vec<Variant> {
    variants
        .into_iter()
        .filter(|v| {
            v.msaa
                .is_none_or(|m| shadelab::gpu::raster::renders_samples(info, m))
        })
        .collect()
}
