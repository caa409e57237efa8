//! Every threshold `check` applies, pinned: an error just over it fails and
//! one just under passes, for the raster limits and the ray tracer's, on
//! interior and on edge pixels. Made-up images through `check::judge`, the
//! function `check` decides with, so a limit loosened (or tightened) where
//! it is compared fails here.

use shadelab::check::{judge, CheckThresholds, Judgement};
use shadelab::shading::Shading;
use shadelab::LinearImage;

const W: u32 = 200;
const H: u32 = 200;
const GREY: f32 = 0.5;

/// A flat grey image, and the edge mask: the two left columns are edge
/// pixels (400 of them), the rest interior.
fn grey() -> (LinearImage, Vec<bool>) {
    let image = LinearImage {
        width: W,
        height: H,
        pixels: vec![[GREY; 3]; (W * H) as usize],
    };
    let edges = (0..W * H).map(|i| i % W < 2).collect();
    (image, edges)
}

fn interior_pixel(k: u32) -> usize {
    (100 * W + 50 + k) as usize
}

fn edge_pixel(k: u32) -> usize {
    // Down the first two columns.
    ((k / 2) * W + k % 2) as usize
}

fn run(actual: &LinearImage, limits: &CheckThresholds) -> Judgement {
    let (expected, edges) = grey();
    judge(&expected, actual, &edges, limits)
}

fn failures_mention(j: &Judgement, word: &str) -> bool {
    j.failures.iter().any(|f| f.contains(word))
}

const FAMILIES: [Shading; 2] = [Shading::Phong, Shading::Raytrace];

#[test]
fn the_interior_limit_flips_the_verdict_just_over_it() {
    // The limits as documented (docs/check.md), written out so that a
    // changed constant fails here as well as a changed comparison.
    for (shading, documented) in [(Shading::Phong, 1e-3), (Shading::Raytrace, 5e-3)] {
        let limits = CheckThresholds::for_shading(shading);
        for (factor, fails) in [(1.02, true), (0.98, false)] {
            let (mut actual, _) = grey();
            actual.pixels[interior_pixel(0)][1] += (documented * factor) as f32;
            let j = run(&actual, &limits);
            assert_eq!(
                !j.failures.is_empty(),
                fails,
                "{shading}: interior error {factor} x the limit: {:?}",
                j.failures
            );
            assert_eq!(failures_mention(&j, "interior"), fails, "{:?}", j.failures);
        }
    }
}

#[test]
fn an_edge_pixel_may_differ_where_an_interior_one_may_not() {
    // One pixel off by 0.5: an edge pixel is within the share of edge
    // pixels allowed to differ; the same error inside fails.
    for shading in FAMILIES {
        let limits = CheckThresholds::for_shading(shading);
        let (mut at_edge, _) = grey();
        at_edge.pixels[edge_pixel(0)][0] += 0.5;
        assert!(run(&at_edge, &limits).failures.is_empty(), "{shading}");
        let (mut inside, _) = grey();
        inside.pixels[interior_pixel(0)][0] += 0.5;
        assert!(
            failures_mention(&run(&inside, &limits), "interior"),
            "{shading}"
        );
    }
}

/// `n` edge pixels off by `error` in one channel.
fn edges_off(n: u32, error: f32) -> LinearImage {
    let (mut actual, _) = grey();
    for k in 0..n {
        actual.pixels[edge_pixel(k)][2] += error;
    }
    actual
}

#[test]
fn the_share_of_differing_edge_pixels_flips_the_verdict_one_pixel_over_it() {
    // The shares as documented (0.05% for the raster modes, 0.5% for the
    // ray tracer), written out like the interior limits.
    for (shading, documented) in [(Shading::Phong, 5e-4), (Shading::Raytrace, 5e-3)] {
        let limits = CheckThresholds::for_shading(shading);
        // The most edge pixels that may differ, of W * H.
        let allowed = (documented * f64::from(W * H)).round() as u32;
        assert!(
            allowed < 2 * H,
            "{shading}: the mask has too few edge pixels"
        );
        let over = run(&edges_off(allowed + 1, 0.05), &limits);
        assert!(
            failures_mention(&over, "edge pixels"),
            "{shading}: {:?}",
            over.failures
        );
        let at = run(&edges_off(allowed, 0.05), &limits);
        assert!(at.failures.is_empty(), "{shading}: {:?}", at.failures);
    }
}

#[test]
fn an_edge_pixel_differs_only_past_the_edge_tolerance() {
    for shading in FAMILIES {
        let limits = CheckThresholds::for_shading(shading);
        let many = (limits.edge_fraction * f64::from(W * H)) as u32 + 20;
        let tolerance = limits.edge_pixel_error as f32;
        let over = run(&edges_off(many, tolerance * 1.02), &limits);
        assert!(
            failures_mention(&over, "edge pixels"),
            "{shading}: {:?}",
            over.failures
        );
        let under = run(&edges_off(many, tolerance * 0.98), &limits);
        assert!(under.failures.is_empty(), "{shading}: {:?}", under.failures);
    }
}

#[test]
fn the_flip_limit_flips_the_verdict_just_over_it() {
    for shading in FAMILIES {
        // Only FLIP judges here: the other limits are opened wide, FLIP's
        // is the mode's own.
        let limits = CheckThresholds {
            interior_max_abs: f64::INFINITY,
            edge_fraction: 1.0,
            ..CheckThresholds::for_shading(shading)
        };
        // FLIP jumps with an offset spread over the whole image (the
        // perceptual steps are coarse), so the error grows by pixels: `n`
        // spots 8 pixels apart, each off by 0.2, FLIP's mean rising by
        // about 1/n of itself with each. The least `n` over the limit is
        // found by bisection.
        let spots: Vec<usize> = (0..H / 8)
            .flat_map(|y| (1..W / 8).map(move |x| (y * 8 * W + x * 8 + 3) as usize))
            .collect();
        let flip_of = |n: usize| {
            let (mut actual, _) = grey();
            for &i in &spots[..n] {
                actual.pixels[i][0] += 0.2;
            }
            run(&actual, &limits)
        };
        assert!(
            flip_of(spots.len()).flip.mean > limits.flip_mean,
            "{shading}: too few spots"
        );
        let (mut lo, mut hi) = (0, spots.len());
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if flip_of(mid).flip.mean > limits.flip_mean {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let (over, under) = (flip_of(hi), flip_of(lo));
        assert!(
            over.flip.mean > limits.flip_mean && over.flip.mean < limits.flip_mean * 1.05,
            "{shading}: FLIP {} for limit {}",
            over.flip.mean,
            limits.flip_mean
        );
        assert!(
            failures_mention(&over, "FLIP"),
            "{shading}: {:?}",
            over.failures
        );
        assert!(under.failures.is_empty(), "{shading}: {:?}", under.failures);
    }
}

#[test]
fn outside_the_display_range_the_limits_are_relative() {
    // A reference peaking at 1e6: the interior limit applies to errors in
    // units of that peak.
    let limits = CheckThresholds::for_shading(Shading::Phong);
    let peak = 1.0e6f32;
    let (mut expected, edges) = grey();
    for p in &mut expected.pixels {
        *p = [peak; 3];
    }
    for (factor, fails) in [(1.05, true), (0.95, false)] {
        let mut actual = expected.clone();
        actual.pixels[interior_pixel(0)][1] += (limits.interior_max_abs * factor) as f32 * peak;
        let j = judge(&expected, &actual, &edges, &limits);
        assert_eq!(j.scale, f64::from(peak));
        assert_eq!(!j.failures.is_empty(), fails, "{factor}: {:?}", j.failures);
    }
}

#[test]
fn a_non_finite_pixel_always_fails() {
    let limits = CheckThresholds {
        interior_max_abs: f64::INFINITY,
        edge_fraction: 1.0,
        edge_pixel_error: f64::INFINITY,
        flip_mean: f64::INFINITY,
        mean_relative: None,
    };
    let (mut actual, _) = grey();
    actual.pixels[edge_pixel(3)][0] = f32::NAN;
    let j = run(&actual, &limits);
    assert!(failures_mention(&j, "NaN"), "{:?}", j.failures);
    // One inside and one at an edge: counted together, not netted out.
    actual.pixels[interior_pixel(2)][1] = f32::INFINITY;
    let j = run(&actual, &limits);
    assert!(failures_mention(&j, "2 pixels are NaN"), "{:?}", j.failures);
}

/// A `w` x `h` grey image whose first column is edge pixels, and a copy
/// with `n` of them off by `error`.
fn tiny(w: u32, h: u32, n: u32, error: f32) -> (LinearImage, LinearImage, Vec<bool>) {
    let expected = LinearImage {
        width: w,
        height: h,
        pixels: vec![[GREY; 3]; (w * h) as usize],
    };
    let mut actual = expected.clone();
    for k in 0..n {
        actual.pixels[(2 * k * w) as usize][0] += error;
    }
    let edges = (0..w * h).map(|i| i % w == 0).collect();
    (expected, actual, edges)
}

#[test]
fn on_a_tiny_image_a_few_edge_pixels_may_differ_whatever_their_share() {
    // The random scenes found it: at 21 x 37 one edge pixel a conforming
    // rasterizer rounds the other way is 0.13% of the image, over the
    // 0.05% share, though nothing is wrong. The share has a floor of
    // `MIN_EDGE_PIXELS` pixels, the FLIP mean the same pixels' worth.
    use shadelab::check::MIN_EDGE_PIXELS;
    assert_eq!(MIN_EDGE_PIXELS, 4, "the documented floor");
    for shading in FAMILIES {
        let limits = CheckThresholds::for_shading(shading);
        for (w, h) in [(21, 37), (8, 8), (3, 9)] {
            let (e, a, edges) = tiny(w, h, MIN_EDGE_PIXELS.min(h.div_ceil(2)), 1.0);
            let j = judge(&e, &a, &edges, &limits);
            assert!(j.failures.is_empty(), "{shading} {w}x{h}: {:?}", j.failures);
        }
        // One more differing pixel fails, on the share.
        let (e, a, edges) = tiny(21, 37, MIN_EDGE_PIXELS + 1, 1.0);
        let j = judge(&e, &a, &edges, &limits);
        assert!(
            failures_mention(&j, "edge pixels"),
            "{shading}: {:?}",
            j.failures
        );
    }
}

/// A `w` x `h` image of `background` whose first column is edge pixels,
/// and a copy with `n` of them `pixel` instead.
fn tiny_coloured(
    (w, h): (u32, u32),
    background: [f32; 3],
    pixel: [f32; 3],
    n: u32,
) -> (LinearImage, LinearImage, Vec<bool>) {
    let expected = LinearImage {
        width: w,
        height: h,
        pixels: vec![background; (w * h) as usize],
    };
    let mut actual = expected.clone();
    for k in 0..n {
        actual.pixels[(2 * k * w) as usize] = pixel;
    }
    let edges = (0..w * h).map(|i| i % w == 0).collect();
    (expected, actual, edges)
}

/// Found by the random scenes (seed 20016): at 87 x 43, two silhouette
/// pixels of a bright green box that the GPU's rasterizer covers and the
/// reference does not put flat's FLIP mean at 4.24e-3, over the floor of
/// 3 grey pixels' worth it had (3.2e-3). The floor's pixels may be any
/// colour, and FLIP judges the rest of the image: `MIN_EDGE_PIXELS` green
/// pixels on black pass, one more fails, and the same pixels
/// beside an interior change over the FLIP limit still fail on FLIP.
#[test]
fn a_few_saturated_edge_pixels_on_black_are_within_the_floor() {
    use shadelab::check::MIN_EDGE_PIXELS;
    for shading in [Shading::Flat, Shading::Raytrace] {
        let limits = CheckThresholds::for_shading(shading);
        let (e, a, edges) = tiny_coloured((87, 43), [0.0; 3], [0.0, 1.0, 0.0], MIN_EDGE_PIXELS);
        let j = judge(&e, &a, &edges, &limits);
        assert!(j.failures.is_empty(), "{shading}: {:?}", j.failures);
        let (e, a, edges) = tiny_coloured((87, 43), [0.0; 3], [0.0, 1.0, 0.0], MIN_EDGE_PIXELS + 1);
        let j = judge(&e, &a, &edges, &limits);
        // Raster: on the share; ray tracing, whose share allows 18 pixels
        // here: on FLIP, which the floor no longer spares them.
        assert!(!j.failures.is_empty(), "{shading}: five pixels passed");
        let (e, mut a, edges) = tiny_coloured((87, 43), [0.0; 3], [0.0, 1.0, 0.0], MIN_EDGE_PIXELS);
        for y in 10..30 {
            a.pixels[y * 87 + 40] = [0.05, 0.05, 0.05];
        }
        let limits = CheckThresholds {
            interior_max_abs: f64::INFINITY,
            ..limits
        };
        let j = judge(&e, &a, &edges, &limits);
        assert!(failures_mention(&j, "FLIP"), "{shading}: {:?}", j.failures);
    }
}

/// Found by the random scenes (seed 20019): a light close to a sphere
/// with the inverse-square falloff lit a Phong pixel to 99.67, and f32
/// put it 1.5e-3 (two ulps) from the reference, over the absolute 1e-3
/// inside surfaces. Interior errors are absolute up to 1 and relative
/// above: that pixel passes, the same error at 0.5 does not, nor 2e-3 of
/// 100 relative.
#[test]
fn interior_errors_are_relative_above_one() {
    let limits = CheckThresholds::for_shading(Shading::Phong);
    let (expected, edges) = grey();
    let judged = |value: f32, off: f32| {
        let mut e = expected.clone();
        e.pixels[interior_pixel(1)] = [value; 3];
        let mut a = e.clone();
        a.pixels[interior_pixel(1)][2] += off;
        judge(&e, &a, &edges, &limits)
    };
    assert!(judged(99.67, 1.5e-3).failures.is_empty());
    assert!(failures_mention(&judged(0.5, 1.5e-3), "interior"));
    assert!(failures_mention(&judged(100.0, 0.2), "interior"));
}
