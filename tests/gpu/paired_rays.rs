//! Two eye rays a lane (`gpu::raytrace::pairing`, `rt_paired.glsl`): the
//! paired walk must find each ray's nearest hit, ties included, as the walk
//! of one ray does, so the image is the same to the bit. Run by CI at
//! lavapipe's 4 lanes too (`LP_NATIVE_VECTOR_WIDTH=128`, ci/test.sh).

use crate::common::*;
use glam::DVec3;
use shadelab::gpu::raytrace::TraceOptions;
use shadelab::scene::{Object, Shape};

#[test]
fn paired_eye_rays_draw_the_unpaired_image_bit_for_bit() {
    let context = gpu();
    let mut scene = mesh_sphere_scene();
    // An odd size: packets whose lanes fall off the image's edges, and the
    // pairs' second packet among them.
    scene.image.width = 97;
    scene.image.height = 71;
    // A listed sphere beside the mesh, partly in front of it: both rays'
    // lists are searched before the walk.
    scene.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::new(1.2, 0.8, 1.5),
            radius: 0.7,
            segments: 0,
        },
        material: 0,
    });
    for samples in [1, 4] {
        scene.render.samples = samples;
        let trace = |paired| {
            let options = TraceOptions {
                pair_eye_rays: Some(paired),
                ..TraceOptions::default()
            };
            trace_gpu(&context, &scene, options).unwrap().image
        };
        let (single, paired) = (trace(false), trace(true));
        let differing = single
            .pixels
            .iter()
            .zip(&paired.pixels)
            .filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits))
            .count();
        assert_eq!(differing, 0, "{samples} samples: pixels that differ");
        // Something was drawn, so agreeing means something.
        let lit = single.pixels.iter().filter(|p| p[0] > 0.05).count();
        assert!(lit > 1000, "{lit} lit pixels");
    }
    // The paired module was built and used: a pipeline of its own.
    assert_eq!(context.pipelines_kept(), 2);
}
