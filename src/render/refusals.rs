//! What a plan refuses before any work starts, and what it warns of: each
//! rule once, whoever asked for the render.

use crate::error::Error;
use crate::gpu::shared::image_size::MAX_PIXELS;
use crate::scene::{PointLight, Scene, Shape};
use crate::shading::Shading;

/// What the loader refuses (`narrow_view::refusal`,
/// `huge_sphere::refusal`), checked again at the size and scene a render
/// gets: `--height` can narrow a pixel's angle, and a glTF scene or a
/// built scene never passed the TOML loader.
pub(super) fn beyond_f32(scene: &Scene) -> Result<(), Error> {
    let narrow = crate::narrow_view::refusal(scene.camera.fov_y_deg, scene.image.height);
    let sphere = scene
        .objects
        .iter()
        .enumerate()
        .find_map(|(i, o)| match o.shape {
            Shape::Sphere { center, radius, .. } => {
                crate::huge_sphere::refusal(scene.camera.position, center, radius)
                    .map(|why| format!("object {} (sphere): {why}", i + 1))
            }
            _ => None,
        });
    match narrow.or(sphere) {
        Some(why) => Err(Error::Usage(why)),
        None => Ok(()),
    }
}

/// Forward tracing starts from the lights: a scene with none that emits
/// has nothing to trace; and it splats the contract's formula, not a
/// hook's (usage, exit 2). (It walks the compute BVH whatever the
/// traversal asked for: the CLI says it ignores `--traversal`.)
pub(super) fn forward_without_light(scene: &Scene) -> Result<(), Error> {
    let emits = |l: &PointLight| {
        let i = l.intensity;
        (i.x + i.y + i.z) > 0.0
    };
    if let Some(hook) = &scene.lighting_hook {
        return Err(Error::Usage(format!(
            "--lighting {}: a lighting hook replaces the local model's light at a surface, which forward tracing does not use (its splats follow docs/lighting-model.md); leave --lighting out",
            hook.path
        )));
    }
    if !scene.lights.iter().any(emits) {
        let what = if scene.lights.is_empty() {
            "no light"
        } else {
            "only lights of zero intensity"
        };
        return Err(Error::Usage(format!(
            "--shading forward traces light from the lights, and the scene has {what}; add a [[lights]] entry with an intensity above 0"
        )));
    }
    Ok(())
}

/// The CPU reference holds an image in f64 with per-pixel coverage: one
/// over the GPU's pixel cap (`MAX_PIXELS`) is refused before it runs out
/// of memory.
pub(super) fn cpu_image_size(scene: &Scene) -> Result<(), Error> {
    let (width, height) = (scene.image.width, scene.image.height);
    if u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(Error::Usage(format!(
            "a {width}x{height} image exceeds the limit of {} pixels (8192 x 8192); choose a smaller --width/--height",
            MAX_PIXELS
        )));
    }
    Ok(())
}

/// The CPU reference's rasterizer samples the standard locations only.
pub(super) fn cpu_sample_count(scene: &Scene) -> Result<(), Error> {
    let msaa = scene.render.msaa;
    if msaa.positions().is_none() {
        return Err(Error::Usage(format!(
            "{} samples per pixel: the CPU reference renders 1, 2, 4, 8 or 16 (the counts with standard sample locations)",
            msaa.samples
        )));
    }
    Ok(())
}

/// A shard splits the samples of a ray trace with bounces (or a forward
/// trace's photons): caustics first, since with them a trace without
/// bounces is no Whitted trace to render whole, and what stops the shard
/// is the photon map.
pub(super) fn unsplittable(
    scene: &Scene,
    shading: Shading,
    sums_in_film: bool,
) -> Result<(), Error> {
    if shading == Shading::Raytrace && scene.render.caustics.on() {
        return Err(Error::Usage(
            "--shard splits the samples of a ray trace, and its caustics do not split: each pass of the photon map shrinks the radius the last one left; leave out --caustics (and render.caustics) for a shard".into(),
        ));
    }
    if !sums_in_film {
        return Err(Error::Usage(
            "--shard splits the samples of a ray trace with diffuse bounces (--bounces 1 or more); a Whitted trace is exact per sample, quick, and its f32 mean does not add up across machines: render it whole".into(),
        ));
    }
    Ok(())
}

/// What forward tracing leaves black in `scene`, said as a warning: a
/// pinhole eye cannot be reached through a mirror or glass, so what those
/// surfaces reflect or transmit is missing from the image (their own
/// diffuse light still shows). `None` where no object has `kr` or `kt`.
pub(super) fn forward_blind_spots(scene: &Scene) -> Option<String> {
    let blind: Vec<String> = scene
        .objects
        .iter()
        .enumerate()
        .filter_map(|(i, o)| {
            let m = &scene.materials[o.material];
            (m.kr > 0.0 || m.kt > 0.0).then(|| format!("{} ({})", i + 1, m.name))
        })
        .collect();
    if blind.is_empty() {
        return None;
    }
    let one = blind.len() == 1;
    Some(format!(
        "forward ray tracing cannot see through mirrors or glass with a pinhole eye: what object{} {} reflect{} or transmit{} is black (their light on other surfaces, caustics included, shows); render with --shading raytrace to see it",
        if one { "" } else { "s" },
        blind.join(", "),
        if one { "s" } else { "" },
        if one { "s" } else { "" },
    ))
}
