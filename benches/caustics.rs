//! Caustics from the photon map against the forward tracer, on the GPU
//! (lavapipe here), in one run: a mirror beside a light throws a patch of
//! light on the floor whose exact value is known (a light at the mirror's
//! image, `tests/common/caustic_scenes.rs`), so both estimators are
//! measured against the exact image with no reference noise.
//!
//! - **Throughput**: caustic photons traced and gathered per second by
//!   the photon map's passes (the GPU's submissions, code generation
//!   apart).
//! - **Time to an error**: the RMSE over the floor patch of the whole
//!   image (the backward tracer's direct light, exact at the pixel's
//!   centre, plus the gathered caustic) after 2 to 128 passes, and of the
//!   forward tracer's image (which estimates both) after 2^18 to 2^24
//!   photons; a line fitted through log(time) against log(error) for
//!   each, the slopes printed (-2 is an unbiased estimator's: 4x the time,
//!   half the error; SPPM trades noise for bias and falls more slowly),
//!   and the time each takes to a few errors.
//!
//! `cargo bench --bench caustics` (about a minute on two cores).

#[path = "common/fit.rs"]
mod fit;

#[path = "../tests/common/caustic_scenes.rs"]
mod caustic_scenes;

use fit::fit;
use glam::DVec3;
use shadelab::film_sums::RenderPart;
use shadelab::gpu::raytrace::{caustics, forward};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::scene::Scene;
use shadelab::work_counter::WorkCounter;
use shadelab::LinearImage;

/// Photons per pass of the photon map: each pass's other dispatches (the
/// visible points, the grid, the update) cost about as much as 2^16
/// photons at 192 x 144, so a pass takes four times that.
const PHOTONS_PER_PASS: u32 = 1 << 18;

/// The light straight from the lamp at (0, 0.5, 0) on the floor point
/// `p`: `kd C Il cos / (d + k)`, kd C = 1, Il = 1, k = 1.
fn direct_at(p: DVec3) -> f64 {
    let to = DVec3::new(0.0, 0.5, 0.0) - p;
    let d = to.length();
    (to.y / d) / (d + 1.0)
}

/// The floor patch's pixels: (index, exact caustic, exact direct light).
fn patch(scene: &Scene) -> Vec<(usize, f64, f64)> {
    let view = shadelab::camera::View::new(scene, scene.image.width, scene.image.height);
    let mut pixels = Vec::new();
    for y in 0..scene.image.height {
        for x in 0..scene.image.width {
            let dir = view.ray_direction(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let t = -view.eye.y / dir.y;
            let p = view.eye + t * dir;
            if let Some(caustic) = caustic_scenes::mirror_caustic_at(p).filter(|_| t > 0.0) {
                pixels.push(((y * scene.image.width + x) as usize, caustic, direct_at(p)));
            }
        }
    }
    pixels
}

/// RMSE of `image`'s red channel over `patch` against `want(caustic,
/// direct)`.
fn patch_rmse(
    image: &LinearImage,
    patch: &[(usize, f64, f64)],
    want: impl Fn(f64, f64) -> f64,
) -> f64 {
    let sum: f64 = patch
        .iter()
        .map(|&(i, c, d)| (f64::from(image.pixels[i][0]) - want(c, d)).powi(2))
        .sum();
    (sum / patch.len() as f64).sqrt()
}

fn main() {
    let context = GpuContext::new(&GpuOptions::from_env()).expect("a Vulkan device");
    let mut scene = caustic_scenes::scene_of(caustic_scenes::MIRROR_BESIDE_A_LIGHT);
    (scene.image.width, scene.image.height) = (192, 144);
    let pixels = patch(&scene);
    let counter = WorkCounter::default();
    println!(
        "mirror beside a light, 192 x 144 on {}: {} floor pixels",
        context.info.name,
        pixels.len()
    );

    // The backward tracer's direct light, exact at each pixel's centre:
    // its trace's time (code generation apart, as for the others).
    let backward = shadelab::render::render(
        &shadelab::render::Device::with_gpu(context.clone()),
        &scene,
        &shadelab::render::RenderRequest::gpu(shadelab::shading::Shading::Raytrace),
    )
    .expect("the ray tracer renders the scene");
    let backward_s = backward.timings.work_ms() / 1e3;
    let direct_error = patch_rmse(&backward.image, &pixels, |_, d| d);
    println!("backward, direct light alone: {backward_s:.3} s, RMSE {direct_error:.2e} against the exact direct light");

    let mut sppm = Vec::new();
    for passes in [2u32, 8, 32, 128] {
        scene.render.caustics.photons_per_pass = PHOTONS_PER_PASS;
        scene.render.caustics.passes = passes;
        scene.render.caustics.initial_radius = 1.5;
        let out = caustics::render(&context, &scene, &RenderPart::all(passes), &counter)
            .expect("the photon map renders the scene");
        let seconds = out.timings.submit_ms / 1e3;
        let mut whole = out.image.clone();
        for (p, b) in whole.pixels.iter_mut().zip(&backward.image.pixels) {
            p[0] += b[0];
        }
        let error = patch_rmse(&whole, &pixels, |c, d| c + d);
        let s = out.stats;
        println!(
            "photon map {passes:>3} passes of 2^{}: {seconds:7.3} s  RMSE {error:.5}  ({:.2} M photons/s traced, {:.2} M landings/s, {:.2} M gathers/s)",
            PHOTONS_PER_PASS.trailing_zeros(),
            s.emitted as f64 / seconds / 1e6,
            s.landed as f64 / seconds / 1e6,
            s.gathered as f64 / seconds / 1e6,
        );
        sppm.push((seconds + backward_s, error));
    }
    let mut light = Vec::new();
    for shift in [18u32, 20, 22, 24] {
        scene.render.photons = 1 << shift;
        let out = forward::render(&context, &scene, &RenderPart::all(1 << shift), &counter)
            .expect("the forward tracer renders the scene");
        let seconds = out.timings.submit_ms / 1e3;
        let error = patch_rmse(&out.film.image(), &pixels, |c, d| c + d);
        println!(
            "forward 2^{shift} photons:          {seconds:7.3} s  RMSE {error:.5}  ({:.2} M photons/s)",
            out.stats.emitted as f64 / seconds / 1e6
        );
        light.push((seconds, error));
    }
    let (asppm, bsppm) = fit(&sppm);
    let (af, bf) = fit(&light);
    println!(
        "slopes of log time against log RMSE: photon map {bsppm:.2}, forward {bf:.2} (-2 unbiased)"
    );
    for target in [0.02, 0.01, 0.005] {
        let ts = (asppm + bsppm * f64::ln(target)).exp();
        let tf = (af + bf * f64::ln(target)).exp();
        println!(
            "to RMSE {target}: photon map {ts:.3} s, forward {tf:.3} s: the photon map takes {:.2}x the forward tracer's time",
            ts / tf
        );
    }
}
