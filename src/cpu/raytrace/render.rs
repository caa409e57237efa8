//! The ray-traced image: every row in parallel, its pixels traced by a
//! `Tracer`, their colours, first objects, signatures and ray counts put
//! together.

use rayon::prelude::*;

use super::tracer::{PixelTrace, Tracer};
use crate::camera::View;
use crate::film_sums::{FilmSums, RenderPart};
use crate::linear_image::LinearImage;
use crate::rt_scene::{RayStats, RtScene};
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

/// The ray-traced image and, per pixel, what its rays saw.
pub struct RayTraced {
    pub image: LinearImage,
    pub stats: RayStats,
    /// `scene.objects` index hit by the pixel's first sample (`None`:
    /// background).
    pub primary_object_ids: Vec<Option<u32>>,
    /// Per pixel, the hash of everything discrete along its ray trees
    /// (`PathSignature`): neighbours with the same signature see the same
    /// surfaces and shadows.
    pub path_signatures: Vec<u64>,
    /// Wall time of the tracing alone, after the scene and its BVH are
    /// built (what the GPU's dispatch time compares with).
    pub trace_ms: f64,
    /// With diffuse bounces: the pixels' fixed-point sums of the part's
    /// samples, as the GPU sums them (`image` is read from them, so the
    /// films of a render's shards add up to its image bit for bit).
    pub film: Option<FilmSums>,
}

fn add_stats(a: RayStats, b: RayStats) -> RayStats {
    RayStats {
        primary: a.primary + b.primary,
        shadow: a.shadow + b.shadow,
        reflected: a.reflected + b.reflected,
        refracted: a.refracted + b.refracted,
        pruned: a.pruned + b.pruned,
        max_depth_reached: a.max_depth_reached.max(b.max_depth_reached),
    }
}

/// Ray traces `scene` at its image size with its `[render]` settings:
/// `part`'s samples of each pixel (all of them, or a shard's run; its time
/// budget is not looked at), counting its rows into `counter` as they
/// finish.
pub fn render(scene: &Scene, part: &RenderPart, counter: &WorkCounter) -> RayTraced {
    let (width, height) = (scene.image.width, scene.image.height);
    let samples = part.range.clone();
    let rt = RtScene::new(scene);
    let tracer = Tracer::new(&rt, View::new(scene, width, height));
    let started = std::time::Instant::now();
    counter.begin("rows", u64::from(height));
    let rows: Vec<(Vec<PixelTrace>, RayStats)> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut stats = RayStats::default();
            let row = (0..width)
                .map(|x| tracer.pixel_part(x, y, samples.clone(), &mut stats))
                .collect();
            counter.add(1);
            (row, stats)
        })
        .collect();
    let trace_ms = started.elapsed().as_secs_f64() * 1e3;
    let count = width as usize * height as usize;
    let mut out = RayTraced {
        image: LinearImage {
            width,
            height,
            pixels: Vec::with_capacity(count),
        },
        stats: RayStats::default(),
        primary_object_ids: Vec::with_capacity(count),
        path_signatures: Vec::with_capacity(count),
        trace_ms,
        film: None,
    };
    // Only with bounces: a Whitted image keeps its f64 mean.
    let mut film = FilmSums::zero(width, height * u32::from(rt.render.bounces > 0));
    for (row, stats) in rows {
        out.stats = add_stats(out.stats, stats);
        for px in row {
            let at = 3 * out.image.pixels.len();
            if let Some(sums) = film.sums.get_mut(at..at + 3) {
                sums.copy_from_slice(&px.sums);
            }
            out.image.pixels.push(px.color.as_vec3().to_array());
            out.primary_object_ids.push(px.object);
            out.path_signatures.push(px.signature);
        }
    }
    if rt.render.bounces > 0 {
        out.image = film.image();
        out.film = Some(film);
    }
    out
}
