//! The lecture's claim about forward ray tracing, measured: how long the
//! forward tracer (photons from the lights) takes to reach the error the
//! backward tracer with diffuse bounces reaches, on a scene where both see
//! the same paths (`assets/diffuse-box.toml`: all diffuse, two bounces),
//! both on the f64 CPU twins, in one run.
//!
//! The reference is the forward tracer at `M` photons. Photons `0..N` of a
//! smaller render are the reference's first `N`, so their squared distance
//! to it is `s^2 (1/N - 1/M)` for photons of variance `s^2`: the forward
//! error (against the exact image) is that distance over `sqrt(1 - N/M)`.
//! The backward tracer's random numbers are its own, so its distance to the
//! reference holds the reference's noise too, `s^2 / M`, taken away. The
//! time to a given error comes from a line fitted through log(time)
//! against log(error); printed with the slopes (-2 is the unbiased
//! estimators' promise: 4x the time, half the error) and the share of
//! photons that reached the eye.
//!
//! `cargo bench --bench estimators` (about a minute on two cores).

#[path = "common/fit.rs"]
mod fit;

use fit::fit;
use std::path::Path;
use std::time::Instant;

use shadelab::cpu::forward;
use shadelab::scene::Scene;
use shadelab::shading::Shading;
use shadelab::LinearImage;

fn backward(scene: &Scene, samples: u32) -> (LinearImage, f64) {
    let mut s = scene.clone();
    s.render.samples = samples;
    let started = Instant::now();
    let device = shadelab::render::Device::cpu_only();
    let request = shadelab::render::RenderRequest::cpu(Shading::Raytrace);
    let image = shadelab::render::render(&device, &s, &request)
        .expect("the CPU twin renders the box")
        .image;
    (image, started.elapsed().as_secs_f64())
}

fn photons(scene: &Scene, count: u32) -> (forward::ForwardImage, f64) {
    let started = Instant::now();
    let all = shadelab::film_sums::RenderPart::all(count);
    let out = forward::render(scene, &all, &Default::default()).expect("the box has a light");
    (out, started.elapsed().as_secs_f64())
}

fn rmse(a: &LinearImage, b: &LinearImage) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| f64::from(x - y).powi(2)))
        .sum();
    (sum / (3 * a.pixels.len()) as f64).sqrt()
}

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/diffuse-box.toml");
    let mut scene = shadelab::scene::load(&path).expect("assets/diffuse-box.toml loads");
    scene.image.width = 80;
    scene.image.height = 60;
    scene.render.bounces = 2;
    scene.render.cutoff = 0.0;
    let reference_photons: u32 = 1 << 25;
    let (reference, _) = photons(&scene, reference_photons);
    let reference = reference.image();
    let m = f64::from(reference_photons);
    let mut forward_points = Vec::new();
    // The photons' variance s^2, from each nested render.
    let mut variances = Vec::new();
    for shift in [16, 18, 20, 22] {
        let (out, seconds) = photons(&scene, 1 << shift);
        let n = f64::from(1u32 << shift);
        let apart = rmse(&out.image(), &reference);
        let error = apart / (1.0 - n / m).sqrt();
        variances.push(apart * apart / (1.0 / n - 1.0 / m));
        let s = out.stats;
        println!(
            "forward  2^{shift} photons: {seconds:8.3} s  RMSE {error:.5}  ({} of {} photons reached the eye, 1 in {:.2}; {} splats)",
            s.seen,
            s.emitted,
            s.emitted as f64 / s.seen.max(1) as f64,
            s.splats
        );
        forward_points.push((seconds, error));
    }
    let reference_noise = variances.iter().sum::<f64>() / variances.len() as f64 / m;
    println!(
        "the reference (2^25 photons): RMSE {:.5} from its own noise",
        reference_noise.sqrt()
    );
    let mut backward_points = Vec::new();
    for samples in [4, 16, 64, 256] {
        let (image, seconds) = backward(&scene, samples);
        let apart = rmse(&image, &reference);
        let error = (apart * apart - reference_noise).max(0.0).sqrt();
        println!("backward {samples:>4} samples: {seconds:8.3} s  RMSE {error:.5}");
        backward_points.push((seconds, error));
    }
    let (ab, bb) = fit(&backward_points);
    let (af, bf) = fit(&forward_points);
    println!(
        "slopes of log time against log RMSE: backward {bb:.2}, forward {bf:.2} (-2 promised)"
    );
    for target in [0.04, 0.02, 0.01] {
        let tb = (ab + bb * f64::ln(target)).exp();
        let tf = (af + bf * f64::ln(target)).exp();
        println!(
            "to RMSE {target}: backward {tb:.3} s, forward {tf:.3} s: forward takes {:.2}x backward's time",
            tf / tb
        );
    }
}
