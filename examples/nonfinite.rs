use shadelab::scene::Interpolation;
use shadelab::shading::Shading;
fn main() {
    let mut scene = shadelab::scene::default_scene();
    scene.lighting.interpolation = Interpolation::Screen;
    let ctx = shadelab::gpu::GpuContext::new(&shadelab::gpu::GpuOptions::from_env()).unwrap();
    for sh in [Shading::Gouraud, Shading::Phong] {
        let g = shadelab::render::render_gpu(&ctx, &scene, sh)
            .unwrap()
            .image;
        let (c, _) = shadelab::render::render_cpu(&scene, sh).unwrap();
        let bad = |im: &shadelab::LinearImage| {
            im.pixels
                .iter()
                .enumerate()
                .filter(|(_, p)| p.iter().any(|v| !v.is_finite()))
                .map(|(i, _)| (i % 640, i / 640))
                .take(5)
                .collect::<Vec<_>>()
        };
        println!(
            "{sh}: gpu non-finite {:?}  cpu non-finite {:?}",
            bad(&g),
            bad(&c.image)
        );
    }
}
