//! The ray statistics of a render, for people (`--stats`), and what a
//! forward render's photons did.

use shadelab::film_sums::PhotonStats;
use shadelab::render::Timings;
use shadelab::rt_scene::RayStats;
use shadelab::shading::Shading;

/// The ray statistics as a two-column table (`docs/raytracing.md`,
/// "Counting"). A raster render has none.
pub(super) fn print_stats(stats: Option<&RayStats>, timings: &Timings, shading: Shading) {
    let Some(s) = stats else {
        println!("stats: none ({shading} casts no rays)");
        return;
    };
    if let Some(gpu) = timings.gpu_ms {
        println!("{:<18} {:>12.1}", "gpu_ms (timestamps)", gpu);
    }
    let work = timings.work_ms();
    println!("{:<18} {:>12.1}", "work_ms", work);
    println!(
        "{:<18} {:>12.0}",
        "rays_per_second",
        s.total() as f64 / (work / 1e3)
    );
    let rows = [
        ("primary", s.primary),
        ("shadow", s.shadow),
        ("reflected", s.reflected),
        ("refracted", s.refracted),
        ("total", s.total()),
        ("pruned", s.pruned),
        ("max_depth_reached", u64::from(s.max_depth_reached)),
    ];
    for (name, value) in rows {
        println!("{name:<18} {value:>12}");
    }
}

/// One line: photons emitted, how many reached the eye (the lecture's
/// measure of forward tracing's waste), and their splats.
pub(super) fn print_photons(s: &PhotonStats) {
    let one_in = if s.seen > 0 {
        format!(" (1 in {:.2})", s.emitted as f64 / s.seen as f64)
    } else {
        String::new()
    };
    println!(
        "photons: {} emitted, {} reached the eye{one_in}, {} splats",
        s.emitted, s.seen, s.splats
    );
}

/// One line: the photon map's passes and photons, what they did (on the
/// GPU), and its time.
pub(super) fn print_caustics(c: &shadelab::render::CausticReport) {
    let photons = u64::from(c.photons_per_pass) * u64::from(c.passes);
    let did = c.photons.map_or(String::new(), |p| {
        format!(
            ", {} landed on a diffuse surface through a mirror or glass, {} gathered",
            p.landed, p.gathered
        )
    });
    let stopped = if c.passes < c.asked_passes {
        format!(
            " (of {} asked: the time budget stopped them)",
            c.asked_passes
        )
    } else {
        String::new()
    };
    println!(
        "caustics: {} passes{stopped} of {} photons ({photons} in all{did}), {:.1} ms",
        c.passes, c.photons_per_pass, c.ms
    );
}
