//! The forward tracer (photons from the lights, `cpu::forward`) held to
//! answers worked out by hand and to the backward tracer with diffuse
//! bounces, which solves the same transport (docs/lighting-model.md,
//! "Secondary illumination").

use common::closed_sphere::{closed_sphere, expected};
use glam::DVec3;
use shadelab::shading::Shading;
use shadelab::LinearImage;

use crate::common;

fn channel_values(image: &LinearImage) -> Vec<f64> {
    image.pixels.iter().map(|p| f64::from(p[0])).collect()
}

/// The pixels' mean and its standard error, measured from the pixels.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

fn rmse(values: &[f64], want: f64) -> f64 {
    (values.iter().map(|v| (v - want).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
}

/// In the closed sphere of `common::closed_sphere` each pixel's
/// expectation is the series, so the image's mean lies
/// within 5 standard errors of it (the error measured from the pixels),
/// for direct light alone and with bounces; and 16 times the photons give
/// a quarter of the error, within 20%, as an unbiased estimator must.
#[test]
fn photons_in_a_closed_sphere_converge_to_the_series() {
    for bounces in [0, 2] {
        let want = expected(bounces);
        let mut errors = Vec::new();
        for photons in [1 << 16, 1 << 20] {
            let out =
                crate::common::forward_cpu(&closed_sphere(bounces), photons).expect("a light");
            let values = channel_values(&out.image());
            let (mean, error) = mean_and_error(&values);
            assert!(
                (mean - want).abs() < 5.0 * error,
                "{bounces} bounces, {photons} photons: mean {mean} against {want} (error {error})"
            );
            assert_eq!(out.stats.emitted, u64::from(photons));
            errors.push(rmse(&values, want));
        }
        let ratio = errors[1] / errors[0];
        eprintln!(
            "{bounces} bounces: RMSE {:.5} -> {:.5}, ratio {ratio:.3}",
            errors[0], errors[1]
        );
        assert!(
            (ratio - 0.25).abs() < 0.05,
            "{bounces} bounces: 16x the photons gave {ratio} of the RMSE"
        );
    }
}

/// A diffuse box (assets/diffuse-box.toml) rendered by both estimators,
/// each from its own derivation (the eye's bounces against the photons'
/// splats): their means over each quarter of the image agree. Measured
/// 0.1% to 1.4% apart (4M photons against 256 samples a pixel, both
/// noise); 3% is twice that, and a quarter of what a missing bounce (the
/// `a^3` term, 8% to 15% of these quarters) or a wrong splat factor (the
/// pinhole's `cos^3`, 10% to 12%) moves them.
#[test]
fn forward_and_backward_agree_on_the_diffuse_box() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml");
    let mut scene = shadelab::scene::load(std::path::Path::new(path)).unwrap();
    scene.image.width = 40;
    scene.image.height = 30;
    scene.render.bounces = 2;
    scene.render.cutoff = 0.0;
    scene.render.samples = 256;
    let backward = crate::common::render_cpu(&scene, Shading::Raytrace)
        .unwrap()
        .0
        .image;
    let forward = crate::common::forward_cpu(&scene, 1 << 22).unwrap().image();
    let quarter = |image: &LinearImage, qx: u32, qy: u32| {
        let mut sum = DVec3::ZERO;
        let (w, h) = (image.width / 2, image.height / 2);
        for y in qy * h..(qy + 1) * h {
            for x in qx * w..(qx + 1) * w {
                sum += common::to_dvec(image.pixels[(y * image.width + x) as usize]);
            }
        }
        sum / f64::from(w * h)
    };
    for (qx, qy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let (b, f) = (quarter(&backward, qx, qy), quarter(&forward, qx, qy));
        let off = ((b - f) / b).abs().max_element();
        eprintln!("quarter {qx},{qy}: backward {b:.4}, forward {f:.4}, {off:.4} apart");
        assert!(off < 0.03, "quarter {qx},{qy}: backward {b}, forward {f}");
    }
}
