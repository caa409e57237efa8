//! `shadelab info`: the Vulkan devices, and the one in use.

use clap::Args;
use shadelab::gpu::{list_devices, GpuContext, GpuOptions};

use crate::cli::common::failure::Failure;

#[derive(Args)]
pub struct InfoArgs {
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    pub machine: crate::cli::common::args::MachineArgs,
}

pub fn run(args: InfoArgs, options: &GpuOptions) -> Result<(), Failure> {
    let devices = list_devices()?;
    let selected = GpuContext::new(options).map(|c| c.info.index);
    if args.json {
        let value = serde_json::json!({
            "devices": devices,
            "selected": selected.as_ref().ok(),
            "selection_error": selected.as_ref().err().map(|e| e.to_string()),
        });
        println!("{value}");
    } else {
        for d in &devices {
            let mark = if selected.as_ref().ok() == Some(&d.index) {
                "*"
            } else {
                " "
            };
            let note = match (&d.unusable_because, &d.no_ray_tracer_because) {
                (Some(w), _) => format!(" (unusable: {w})"),
                (None, Some(w)) => format!(" (no GPU ray tracer: {w})"),
                (None, None) => match &d.no_ray_query_because {
                    None => " (ray tracer: --traversal bvh or query)".to_string(),
                    Some(w) => format!(" (ray tracer: --traversal bvh; no ray queries: {w})"),
                },
            };
            let counts: Vec<String> = d.msaa_counts.iter().map(u32::to_string).collect();
            // Shaded per sample: a pass per sample, where a viewport can
            // move by the standard positions (sixteenths of a pixel).
            let per_sample = shadelab::msaa::STANDARD_COUNTS
                .iter()
                .filter(|&&n| {
                    n > 1
                        && shadelab::gpu::raster::renders_samples(
                            d,
                            shadelab::msaa::Msaa {
                                samples: n,
                                per_sample: true,
                            },
                        )
                })
                .map(u32::to_string)
                .collect::<Vec<_>>();
            let per_sample = if per_sample.is_empty() {
                String::new()
            } else {
                format!(" (per sample: {})", per_sample.join(", "))
            };
            println!(
                "{mark} {}: {} [{}] Vulkan {} - {}{note}; --msaa {}{per_sample}",
                d.index,
                d.name,
                d.device_type,
                d.api_version,
                d.driver,
                counts.join(" or ")
            );
        }
        if devices.is_empty() {
            println!("no Vulkan devices found");
        }
    }
    selected.map(|_| ()).map_err(Failure::from)
}
