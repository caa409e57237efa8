//! `[image]` and `[render]`: the picture's size and background, and how
//! the renderers take it (depth, cut-off, shadows, samples, bounces,
//! photons, traversal, MSAA), each in its range.

use super::checks::{spanned_map, Ctx};
use super::schema::{v3, ImageRaw, MsaaRaw, RenderRaw};
use crate::scene::error::SceneError;
use crate::scene::model::{
    check_caustic_radius, watchdog_limit, ImageSettings, RenderSettings, MAX_DEPTH, MAX_RESOLUTION,
};

/// `[image]`, the defaults where it or a key is absent.
pub(super) fn image(cx: &Ctx, raw: Option<&ImageRaw>) -> Result<ImageSettings, SceneError> {
    let mut image = ImageSettings::default();
    if let Some(img) = raw {
        let why = " (an absurd resolution)";
        if let Some(w) = &img.width {
            image.width = cx.int_in(w, "image.width", 1, MAX_RESOLUTION, why)?;
        }
        if let Some(h) = &img.height {
            image.height = cx.int_in(h, "image.height", 1, MAX_RESOLUTION, why)?;
        }
        if let Some(b) = &img.background {
            image.background = cx.non_negative3(&spanned_map(b, v3), "image.background")?;
        }
    }
    Ok(image)
}

/// `[render]`, the defaults where it or a key is absent.
pub(super) fn render(cx: &Ctx, raw: Option<&RenderRaw>) -> Result<RenderSettings, SceneError> {
    let mut render = RenderSettings::default();
    if let Some(r) = raw {
        if let Some(d) = &r.depth {
            render.depth = cx.int_in(d, "render.depth", 0, i64::from(MAX_DEPTH), "")?;
            render.depth_given = true;
        }
        if let Some(c) = &r.cutoff {
            render.cutoff = cx.non_negative(c, "render.cutoff")?;
        }
        if let Some(s) = r.shadows {
            render.shadows = s;
        }
        if let Some(s) = &r.samples {
            render.samples = cx.int_in(s, "render.samples", 1, 1024, "")?;
        }
        if let Some(b) = &r.bounces {
            render.bounces = cx.int_in(b, "render.bounces", 0, i64::from(MAX_DEPTH), "")?;
            render.settle_depth().map_err(|(depth, bounces)| {
                cx.err(
                    b,
                    format!("render.bounces = {bounces} needs render.depth = {bounces} or more (each bounce is a level of the ray tree, which depth bounds), and render.depth is {depth}; raise render.depth or leave it out (it then follows the bounces)"),
                )
            })?;
        }
        if let Some(p) = &r.photons {
            let why = " (photons are numbered in 32 bits)";
            render.photons = cx.int_in(p, "render.photons", 1, i64::from(u32::MAX), why)?;
        }
        caustics(cx, r, &mut render.caustics)?;
        if let Some(t) = r.traversal {
            render.traversal = t;
        }
        if let Some(m) = &r.msaa {
            let text = match m.get_ref() {
                MsaaRaw::Count(n) => n.to_string(),
                MsaaRaw::Text(t) => t.clone(),
            };
            render.msaa = text
                .parse()
                .map_err(|e: String| cx.err(m, format!("render.msaa {e}")))?;
        }
        if let Some(w) = &r.watchdog {
            render.watchdog = watchdog_limit(w.get_ref().0)
                .map_err(|e| cx.err(w, format!("render.watchdog {e}")))?;
        }
    }
    Ok(render)
}

/// `render.caustics`, `render.caustic_passes` and `render.caustic_radius`:
/// the photon map's photons per pass, its passes and its first radius, all
/// its photons numbered in 32 bits.
fn caustics(
    cx: &Ctx,
    r: &RenderRaw,
    caustics: &mut crate::scene::model::CausticSettings,
) -> Result<(), SceneError> {
    let most = i64::from(u32::MAX);
    if let Some(p) = &r.caustics {
        let why = " (photons are numbered in 32 bits)";
        caustics.photons_per_pass = cx.int_in(p, "render.caustics", 0, most, why)?;
    }
    if let Some(p) = &r.caustic_passes {
        caustics.passes = cx.int_in(p, "render.caustic_passes", 1, 1 << 20, "")?;
    }
    if let Some(radius) = &r.caustic_radius {
        caustics.initial_radius = check_caustic_radius(radius.get_ref().0)
            .map_err(|e| cx.err(radius, format!("render.caustic_radius {e}")))?;
    }
    if let (Some(p), None) = (&r.caustics, caustics.total_photons()) {
        return Err(cx.err(
            p,
            format!(
                "render.caustics times render.caustic_passes is {} photons, past 4294967295 (photons are numbered in 32 bits)",
                u64::from(caustics.photons_per_pass) * u64::from(caustics.passes)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

    #[test]
    fn absurd_and_invalid_values() {
        for (rest, parts) in [
            (
                "[image]\nwidth = 0\n",
                &["line 5", "image.width", "0", "absurd", "16384"][..],
            ),
            (
                "[image]\nheight = 100000\n",
                &["line 5", "image.height", "100000", "absurd"],
            ),
            ("[image]\nwidth = -3\n", &["line 5", "image.width"]),
            ("[render]\ndepth = 65\n", &["line 5", "render.depth", "64"]),
            (
                "[render]\nsamples = 0\n",
                &["line 5", "render.samples", "1024"],
            ),
            (
                "[render]\nmsaa = 0\n",
                &["line 5", "render.msaa", "sample count"],
            ),
            (
                "[render]\nmsaa = \"4,sometimes\"\n",
                &["line 5", "render.msaa", "per-sample"],
            ),
            ("[render]\ncutoff = -0.1\n", &["line 5", "render.cutoff"]),
            (
                "[render]\ndepth = 3\nbounces = 4\n",
                &["line 6", "render.bounces = 4", "render.depth is 3"],
            ),
            (
                "[render]\ncaustic_radius = 1e30\n",
                &["line 5", "render.caustic_radius", "16384"],
            ),
            (
                "[render]\ncaustic_radius = 0\n",
                &["line 5", "render.caustic_radius", "above 0"],
            ),
            (
                "[render]\nwatchdog = -1\n",
                &["line 5", "render.watchdog", "86400"],
            ),
            (
                "[render]\nphotons = 0\n",
                &["line 5", "render.photons", "4294967295"],
            ),
            (
                "[render]\nphotons = 4294967296\n",
                &["line 5", "render.photons", "32 bits"],
            ),
        ] {
            let e = parse_err(&with_camera(rest));
            assert_has(&e, parts);
        }
    }

    /// `render.bounces` N reaches N bounces: the depth follows it up where
    /// the scene gives none, and stays where it gives one.
    #[test]
    fn the_depth_follows_the_bounces_where_none_is_given() {
        for (rest, depth) in [
            ("[render]\nbounces = 10\n", 10),
            ("[render]\nbounces = 2\n", 5),
            ("[render]\nbounces = 2\ndepth = 3\n", 3),
            ("[render]\ndepth = 12\nbounces = 10\n", 12),
        ] {
            let s = parse_ok(&with_camera(rest));
            assert_eq!(s.render.depth, depth, "{rest}");
        }
    }
}
