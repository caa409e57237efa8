//! The spine's own rules, on the CPU: which technique a request takes,
//! the refusals a plan runs before any work, the portion it traces, and a
//! cancel that stops the work.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use super::{render, Device, Plan, Portion, RenderRequest, Technique};
use crate::backend_choice::Backend;
use crate::error::Error;
use crate::scene::{default_scene, Scene};
use crate::shading::{RasterMode, Shading};
use crate::work_counter::WorkCounter;

fn with_bounces(bounces: u32) -> Scene {
    let mut scene = default_scene();
    scene.render.bounces = bounces;
    scene
}

fn usage(result: Result<Plan, Error>) -> String {
    match result {
        Err(Error::Usage(why)) => why,
        Err(e) => panic!("expected a usage error, got {e}"),
        Ok(plan) => panic!("expected a refusal, got a plan for {:?}", plan.technique),
    }
}

#[test]
fn each_mode_takes_its_technique_and_only_two_sum_into_a_film() {
    let whitted = with_bounces(0);
    let paths = with_bounces(2);
    assert_eq!(
        Technique::of(&whitted, Shading::Gouraud),
        Technique::Raster(RasterMode::Gouraud)
    );
    assert_eq!(
        Technique::of(&whitted, Shading::Raytrace),
        Technique::Whitted
    );
    assert_eq!(Technique::of(&paths, Shading::Raytrace), Technique::Paths);
    assert_eq!(
        Technique::of(&whitted, Shading::Forward),
        Technique::Forward
    );
    let film: Vec<bool> = [Shading::Phong, Shading::Raytrace, Shading::Forward]
        .map(|s| Technique::of(&whitted, s).sums_in_film())
        .into();
    assert_eq!(film, [false, false, true]);
    assert!(Technique::Paths.sums_in_film());
}

#[test]
fn a_plan_traces_the_portion_asked_for() {
    let mut scene = with_bounces(1);
    scene.render.samples = 10;
    let part = |portion| {
        let request = RenderRequest {
            portion,
            ..RenderRequest::cpu(Shading::Raytrace)
        };
        let part = Plan::new(&scene, &request).unwrap().part;
        (part.total, part.range)
    };
    assert_eq!(part(Portion::All), (10, 0..10));
    assert_eq!(part(Portion::Shard(2, 3)), (10, 3..6));
    // A range past the samples there are is clipped to them.
    assert_eq!(part(Portion::Range(4..40)), (10, 4..10));
}

#[test]
fn the_plan_refuses_before_any_work() {
    // A Whitted trace does not split.
    let shard = RenderRequest {
        portion: Portion::Shard(1, 2),
        ..RenderRequest::gpu(Shading::Raytrace)
    };
    assert!(usage(Plan::new(&with_bounces(0), &shard)).contains("--shard splits"));
    // Forward tracing needs a light with power.
    let mut dark = default_scene();
    dark.lights.clear();
    let forward = RenderRequest::gpu(Shading::Forward);
    assert!(usage(Plan::new(&dark, &forward)).contains("no light"));
    // The CPU reference's image size, on the CPU only.
    let mut huge = default_scene();
    huge.image.width = 20_000;
    huge.image.height = 20_000;
    let cpu = RenderRequest::cpu(Shading::Flat);
    assert!(usage(Plan::new(&huge, &cpu)).contains("exceeds the limit"));
    assert!(Plan::new(&huge, &RenderRequest::gpu(Shading::Flat)).is_ok());
}

#[test]
fn a_gpu_request_on_a_device_without_one_is_a_usage_error() {
    let scene = default_scene();
    let result = render(
        &Device::cpu_only(),
        &scene,
        &RenderRequest::gpu(Shading::Flat),
    );
    assert!(matches!(result, Err(Error::Usage(why)) if why.contains("without a GPU")));
}

#[test]
fn the_cpu_request_renders_with_coverage_and_no_film() {
    let mut scene = default_scene();
    scene.image.width = 32;
    scene.image.height = 24;
    let request = RenderRequest::new(Shading::Phong, Backend::Cpu);
    let rendered = render(&Device::cpu_only(), &scene, &request).unwrap();
    assert_eq!(rendered.image.pixels.len(), 32 * 24);
    let coverage = rendered.coverage.expect("the twin knows its pixels");
    assert_eq!(coverage.near_edge.len(), 32 * 24);
    assert!(rendered.film.is_none());
}

/// A cancel flag set before the render stops the forward twin before its
/// tasks (at most one, of 16384 photons, may have begun) instead of its 4
/// million, and the render answers `Cancelled`, not an image.
#[test]
fn a_cancelled_render_stops_its_work_and_says_so() {
    let mut scene = default_scene();
    scene.image.width = 16;
    scene.image.height = 12;
    scene.render.photons = 1 << 22;
    let counter = WorkCounter::default();
    let request = RenderRequest {
        progress: Some(&counter),
        cancel: Some(Arc::new(AtomicBool::new(true))),
        ..RenderRequest::cpu(Shading::Forward)
    };
    let result = render(&Device::cpu_only(), &scene, &request);
    assert!(matches!(result, Err(Error::Cancelled)));
    let (_, done, total) = counter.read();
    assert_eq!(total, 1 << 22);
    assert!(done <= 1 << 14, "traced {done} photons after the cancel");
}
