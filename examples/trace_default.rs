//! Ray traces a scene (default: the built-in one) on the GPU, writes
//! trace.png and prints the ray statistics and timings.

fn main() {
    let scene = match std::env::args().nth(1) {
        Some(p) => shadelab::scene::load(std::path::Path::new(&p)).expect("scene loads"),
        None => shadelab::scene::default_scene(),
    };
    let context = shadelab::gpu::GpuContext::new(&shadelab::gpu::GpuOptions::from_env()).unwrap();
    let count = std::env::var("COUNT").is_ok();
    let out = shadelab::gpu::raytrace::render(&context, &scene, count).unwrap();
    shadelab::output::write_image(&out.image, std::path::Path::new("trace.png")).unwrap();
    println!("{:?}\n{:?}", out.stats, out.timings);
    for _ in 0..2 {
        let r =
            shadelab::gpu::raster::render(&context, &scene, shadelab::shading::RasterMode::Flat)
                .unwrap();
        println!("raster: {:?}", r.timings);
        let again = shadelab::gpu::raytrace::render(&context, &scene, count).unwrap();
        println!("again: {:?}", again.timings);
    }
}
