//! The GPU ray tracer against exact answers that need no second tracer:
//! depth 0 equals raster Phong, shadowed points get exactly the ambient
//! term, total internal reflection refracts nothing and makes no NaN, and
//! the cut-off prunes; and against the CPU twin where no exact answer is
//! at hand (every depth, long object lists, several samples per pixel).

use crate::common;

use common::*;
use glam::{DMat3, DVec3};
use shadelab::cpu::lighting::{shade, Surface};
use shadelab::gpu::raytrace;
use shadelab::rt_scene::RayStats;
use shadelab::scene::{tessellate, Material, Object, PointLight, Scene, Shape};
use shadelab::shading::Shading;
use shadelab::LinearImage;

fn trace(scene: &Scene) -> (LinearImage, RayStats) {
    let out =
        crate::common::trace_gpu_counting(&gpu(), scene, true).unwrap_or_else(|e| panic!("{e}"));
    (out.image, out.stats.expect("counted"))
}

#[test]
fn depth_zero_without_shadows_equals_raster_phong_on_a_mesh() {
    let mut s = mesh_sphere_scene();
    s.render.depth = 0;
    s.render.shadows = false;
    let (traced, stats) = trace(&s);
    let phong = render(&gpu(), &s, Shading::Phong);
    let (_, coverage) = crate::common::render_cpu(&s, Shading::Phong).unwrap();
    let mut compared = 0;
    let mut worst = 0.0f64;
    for (i, near_edge) in coverage.near_edge.iter().enumerate() {
        if *near_edge || coverage.object_ids[i].is_none() {
            continue;
        }
        // Both evaluate the formula in f32 at the same point and normal,
        // reached by different f32 arithmetic (ray barycentrics against
        // interpolated varyings): a few ulps of values below ~2, amplified
        // by pow(., p = 10). 2e-4 is 20x what was measured.
        let err = max_abs_diff(to_dvec(traced.pixels[i]), to_dvec(phong.pixels[i]));
        assert!(
            err < 2e-4,
            "pixel {i}: traced {:?} phong {:?}",
            traced.pixels[i],
            phong.pixels[i]
        );
        worst = worst.max(err);
        compared += 1;
    }
    eprintln!("depth 0 against Phong: max error {worst:.2e} over {compared} pixels");
    assert!(compared > 4000, "{compared} interior pixels");
    assert_eq!((stats.shadow, stats.reflected, stats.refracted), (0, 0, 0));
    assert_eq!(stats.primary, 128 * 128);
}

/// A floor lit from above, with an occluder between the light and the
/// floor's centre.
fn shadow_scene(occluder_x: f64) -> Scene {
    let mut s = scene(96, 96, 40.0);
    s.camera.position = DVec3::new(0.0, 6.0, 6.0);
    s.camera.look_at = DVec3::ZERO;
    s.lights = vec![PointLight {
        position: DVec3::new(0.0, 8.0, 0.0),
        intensity: DVec3::splat(20.0),
    }];
    s.objects.push(Object {
        shape: Shape::Plane {
            center: DVec3::ZERO,
            normal: DVec3::Y,
            size: 10.0,
            segments: 1,
        },
        material: 0,
    });
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::new(occluder_x, 4.0, 0.0),
            radius: 1.0,
            segments: 32,
        },
        material: 0,
    });
    s
}

#[test]
fn a_point_in_shadow_receives_exactly_the_ambient_term() {
    let shadowed = shadow_scene(0.0);
    let (image, stats) = trace(&shadowed);
    assert!(stats.shadow > 0);
    let v = view(&shadowed);
    let at = v.project(DVec3::ZERO).unwrap();
    let (x, y) = (at.x as u32, at.y as u32);
    let m = &shadowed.materials[0];
    let ambient = shadowed.lighting.ambient * m.ka * m.color;
    // The floor's centre is under the occluder: ambient only, to f32
    // rounding of one product.
    assert!(
        max_abs_diff(to_dvec(image.get(x, y)), ambient) < 1e-6,
        "{:?} vs {ambient}",
        image.get(x, y)
    );

    // Moved well aside, the occluder no longer shadows the centre: the full
    // formula returns (f32 against f64, values below ~2).
    let lit = shadow_scene(4.0);
    let (image, _) = trace(&lit);
    let dir = pixel_ray(&v, x, y);
    let hit = v.eye + dir * (-v.eye.y / dir.y);
    let want = shade(
        &lit.lighting,
        &lit.lights,
        Surface::plain(m),
        hit,
        DVec3::Y,
        v.eye,
    );
    assert!(
        max_abs_diff(to_dvec(image.get(x, y)), want) < 1e-4,
        "{:?} vs {want}",
        image.get(x, y)
    );
    assert!(want.x > ambient.x + 0.1, "the light must matter here");
}

#[test]
fn total_internal_reflection_refracts_nothing_beyond_the_critical_angle() {
    // The eye at the centre of a large glass box, looking at its far face:
    // each primary ray meets that face from inside at the angle it makes
    // with the view axis, and refracts out only below the critical angle
    // asin(1 / 1.5) = 41.8 degrees.
    let mut s = scene(64, 64, 90.0);
    s.camera.position = DVec3::ZERO;
    s.camera.look_at = -DVec3::Z;
    s.materials = vec![Material {
        name: "glass".into(),
        color: DVec3::ONE,
        ka: 0.1,
        kd: 0.1,
        ks: 0.5,
        p: 50.0,
        kr: 0.1,
        kt: 0.9,
        ior: 1.5,
        pattern: None,
    }];
    s.objects.push(Object {
        shape: Shape::Box {
            center: DVec3::ZERO,
            half_extents: DVec3::splat(10.0),
            rotation: DMat3::IDENTITY,
        },
        material: 0,
    });
    s.render.depth = 1;
    s.render.shadows = false;
    let (image, stats) = trace(&s);
    assert!(
        image.pixels.iter().flatten().all(|c| c.is_finite()),
        "no NaN or infinity"
    );
    let v = view(&s);
    let mut below_critical = 0u64;
    let mut near_critical = 0u64;
    for y in 0..64 {
        for x in 0..64 {
            let sin = pixel_ray(&v, x, y).truncate().length();
            if (sin - 1.0 / 1.5).abs() < 1e-5 {
                near_critical += 1;
            } else if sin < 1.0 / 1.5 {
                below_critical += 1;
            }
        }
    }
    let refracted = stats.refracted;
    assert!(
        refracted >= below_critical && refracted <= below_critical + near_critical,
        "{refracted} refracted rays, {below_critical} primary rays below the critical angle"
    );
    assert!(
        below_critical > 100 && (64 * 64 - below_critical) > 100,
        "both cases occur"
    );
    // Every primary ray has a reflected child: kr > 0, or kt handed over
    // under total internal reflection.
    assert_eq!(stats.reflected, 64 * 64);
}

fn mirror_scene(kr: f64) -> Scene {
    let mut s = shadow_scene(0.0);
    s.materials.push(Material {
        kr,
        ..s.materials[0].clone()
    });
    s.objects[1].material = 1;
    s
}

#[test]
fn the_cutoff_prunes_children_below_it() {
    let mut pruned = mirror_scene(0.3);
    pruned.render.cutoff = 0.5;
    pruned.render.depth = 5;
    let (image, stats) = trace(&pruned);
    assert_eq!((stats.reflected, stats.refracted), (0, 0), "{stats:?}");
    assert!(stats.pruned > 0);
    let mut shallow = pruned.clone();
    shallow.render.depth = 0;
    let (depth0, _) = trace(&shallow);
    assert_eq!(
        image, depth0,
        "pruning every child must give the depth-0 image"
    );

    // With the cut-off at 0 the same scene does reflect.
    pruned.render.cutoff = 0.0;
    let (_, stats) = trace(&pruned);
    assert!(stats.reflected > 0 && stats.pruned == 0, "{stats:?}");
}

/// Between two facing mirrors some ray always survives to the depth limit
/// and none goes past it: the deepest ray equals the depth at every depth.
#[test]
fn depth_bounds_the_deepest_ray() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/hard/energy-gain.toml");
    let mirrors = shadelab::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for depth in [0, 1, 3, 8] {
        let mut s = mirrors.clone();
        s.render.depth = depth;
        let (image, stats) = trace(&s);
        assert_eq!(stats.max_depth_reached, depth, "{stats:?} at depth {depth}");
        assert!(image.pixels.iter().flatten().all(|c| c.is_finite()));
    }
}

/// GPU against the CPU twin at several depths on the glass scene (two
/// lights, refraction, total internal reflection near the rim): `check`'s
/// thresholds hold, and both trace the same ray tree. Counts may differ only
/// where f32 and f64 decide a grazing hit or a shadow differently, a handful
/// of rays in ~10^5 (measured: none on this scene); 0.5% leaves room.
#[test]
fn gpu_and_cpu_trace_the_same_tree_at_every_depth() {
    use shadelab::check::{check, CheckThresholds};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/rt-glass.toml");
    let mut s = shadelab::scene::load(&path).unwrap();
    s.image.width = 160;
    s.image.height = 120;
    let context = gpu();
    for depth in [0, 1, 3, 8] {
        s.render.depth = depth;
        let limits = CheckThresholds::for_shading(Shading::Raytrace);
        let o = check(
            &crate::common::device(&context),
            &s,
            &s,
            Shading::Raytrace,
            &limits,
        )
        .unwrap();
        assert!(o.passed(), "depth {depth}: {:?}", o.judgement.failures);
        let gpu_stats = gpu_ray_stats(&context, &s);
        let (cpu, _) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
        let cpu_stats = cpu.ray_stats.unwrap();
        for (kind, g, c) in [
            ("primary", gpu_stats.primary, cpu_stats.primary),
            ("shadow", gpu_stats.shadow, cpu_stats.shadow),
            ("reflected", gpu_stats.reflected, cpu_stats.reflected),
            ("refracted", gpu_stats.refracted, cpu_stats.refracted),
            ("pruned", gpu_stats.pruned, cpu_stats.pruned),
        ] {
            let allowed = (c as f64 * 0.005).ceil() as u64;
            assert!(
                g.abs_diff(c) <= allowed,
                "depth {depth}, {kind}: GPU {g}, CPU {c}"
            );
        }
        assert_eq!(
            gpu_stats.max_depth_reached, cpu_stats.max_depth_reached,
            "depth {depth}"
        );
        if depth > 0 {
            assert!(
                cpu_stats.refracted > 0,
                "the glass must refract at depth {depth}"
            );
        }
    }
}

/// A scene of `spheres` spheres, `planes` planes and `boxes` boxes in rows,
/// with a mesh above them, mirrors among the spheres and depth 2, so that
/// reflections reach every object from scattered rays; `materials`
/// materials (at least 2), every one of them on some sphere.
fn object_rows(spheres: i32, planes: i32, boxes: i32, materials: usize) -> Scene {
    let mut s = scene(96, 80, 50.0);
    s.camera.position = DVec3::new(0.0, 6.0, 14.0);
    s.camera.look_at = DVec3::ZERO;
    s.render.depth = 2;
    for k in 1..materials {
        let tint = 0.1 * k as f64;
        let mut m = s.materials[0].clone();
        m.color = DVec3::new(tint, 0.5, 1.0 - tint);
        m.kr = if k % 2 == 1 { 0.5 } else { 0.0 };
        s.materials.push(m);
    }
    for i in 0..spheres {
        let (x, z) = (f64::from(i % 5) * 2.0 - 4.0, f64::from(i / 5) * 2.0 - 3.0);
        s.objects.push(Object {
            shape: Shape::Sphere {
                center: DVec3::new(x, 0.6, z),
                radius: 0.5 + 0.02 * f64::from(i),
                segments: 16,
            },
            material: i as usize % materials,
        });
    }
    for i in 0..planes {
        let x = f64::from(i) * 1.3 - 8.5;
        s.objects.push(Object {
            shape: Shape::Plane {
                center: DVec3::new(x, 0.0, -1.0),
                normal: DVec3::new(0.1, 1.0, 0.05 * f64::from(i)).normalize(),
                size: 1.2,
                segments: 1,
            },
            material: 0,
        });
    }
    for i in 0..boxes {
        let angle = 0.3 * f64::from(i);
        s.objects.push(Object {
            shape: Shape::Box {
                center: DVec3::new(f64::from(i) * 1.6 - 5.6, 2.2, -3.5),
                half_extents: DVec3::new(0.4, 0.6, 0.3),
                rotation: DMat3::from_rotation_y(angle) * DMat3::from_rotation_x(0.5 * angle),
            },
            material: 1,
        });
    }
    s.objects.push(Object {
        shape: Shape::Mesh(tessellate(&Shape::Sphere {
            center: DVec3::new(0.0, 3.5, 1.0),
            radius: 1.0,
            segments: 24,
        })),
        material: 1,
    });
    s
}

/// Long object lists (more spheres, planes and boxes than lavapipe unrolls a
/// loop over) go into the BVH beside the mesh's triangles, in leaves of
/// their own kind (walked 4-wide with the mesh, binary without it), their records read a subgroup at a time with every word
/// shuffled from the lane that read it. A leaf taken for the wrong kind, a
/// record in the wrong order or a word from the wrong offset or lane moves
/// or loses objects; `check` against the CPU twin, which tests objects one
/// by one and shares none of that code, catches it (reflections at depth 2
/// reach every object from scattered rays, shadow rays take the BVH's
/// any-hit path).
#[test]
fn long_object_lists_in_the_bvh_agree_with_the_cpu() {
    use shadelab::check::{check, CheckThresholds};
    use shadelab::gpu::raytrace::bvh::gpu_bvh;
    use shadelab::gpu::raytrace::bvh::BvhKinds;
    use shadelab::rt_scene::RtScene;
    // With the mesh the tree is big enough for the 4-wide walk; without
    // it, the objects alone make a tree the binary walk takes.
    for with_mesh in [true, false] {
        let mut s = object_rows(20, 14, 8, 10);
        if !with_mesh {
            s.objects.retain(|o| !matches!(o.shape, Shape::Mesh(_)));
        }
        let rt = RtScene::new(&s);
        let kinds = BvhKinds::of(&rt);
        assert!(
            kinds.spheres && kinds.planes && kinds.boxes,
            "every list must be long enough to go into the BVH: {kinds:?}"
        );
        assert_eq!(
            gpu_bvh(&rt, kinds).unwrap().wide.is_some(),
            with_mesh,
            "which walk the shader takes"
        );
        assert!(
            !shadelab::gpu::raytrace::layout::lists_materials(s.materials.len()),
            "the materials must be too many to pick by selects, so that each lane reads its own"
        );
        let limits = CheckThresholds::for_shading(Shading::Raytrace);
        let o = check(
            &crate::common::device(&gpu()),
            &s,
            &s,
            Shading::Raytrace,
            &limits,
        )
        .unwrap();
        assert!(o.passed(), "mesh {with_mesh}: {:?}", o.judgement.failures);
    }
}

/// The longest lists still tested one by one, and as many materials as the
/// shader picks by selects: every object and material is read once per
/// invocation into the shader's arrays, which must hold them all (an object
/// or a material past an array's end would be lost or moved). The long
/// lists above have more materials than that, each lane reading its own.
/// The CPU twin, which shares none of that code, is the oracle.
#[test]
fn the_longest_listed_objects_agree_with_the_cpu() {
    use shadelab::check::{check, CheckThresholds};
    use shadelab::gpu::raytrace::bvh::BvhKinds;
    use shadelab::gpu::raytrace::layout::{
        lists_materials, UNROLLED_BOXES, UNROLLED_MATERIALS, UNROLLED_PLANES, UNROLLED_SPHERES,
    };
    use shadelab::rt_scene::RtScene;
    let count = |n: usize| i32::try_from(n).unwrap();
    let s = object_rows(
        count(UNROLLED_SPHERES),
        count(UNROLLED_PLANES),
        count(UNROLLED_BOXES),
        UNROLLED_MATERIALS,
    );
    // Every material is on some sphere (object_rows), so each one is seen.
    const _: () = assert!(UNROLLED_SPHERES >= UNROLLED_MATERIALS);
    assert!(
        lists_materials(s.materials.len()) && s.materials.len() == UNROLLED_MATERIALS,
        "the shader must pick these materials by selects, as many as it holds"
    );
    assert_eq!(
        BvhKinds::of(&RtScene::new(&s)),
        BvhKinds::default(),
        "every list must be short enough to be tested one by one"
    );
    let limits = CheckThresholds::for_shading(Shading::Raytrace);
    let o = check(
        &crate::common::device(&gpu()),
        &s,
        &s,
        Shading::Raytrace,
        &limits,
    )
    .unwrap();
    assert!(o.passed(), "{:?}", o.judgement.failures);
}

/// The uber-shader build (`bench --every-feature`: reflection, refraction,
/// the specular term and the BVH walk compiled in whether used or not)
/// traces the same image as the pipeline specialised to the scene, on
/// scenes that leave each of those features out: what it measures is the
/// cost of the features, not a different picture.
#[test]
fn every_feature_build_traces_the_same_image() {
    use raytrace::TraceOptions;
    let context = gpu();
    let plain = plain_sphere_scene();
    let mut default = shadelab::scene::default_scene();
    default.image.width = 64;
    default.image.height = 48;
    for s in [plain, default] {
        let trace = |every_feature| {
            let options = TraceOptions {
                every_feature,
                ..TraceOptions::default()
            };
            crate::common::trace_gpu(&context, &s, options)
                .unwrap_or_else(|e| panic!("{e}"))
                .image
        };
        let worst = worst_difference(&trace(false), &trace(true));
        // Only the compiled code differs, not the arithmetic of any pixel.
        assert!(worst <= 1e-6, "worst difference {worst}");
    }
}

/// The shader's subgroups take the image from a work queue, a counter the
/// host zeroes on the device before each dispatch. Renders in a row on one
/// context (whose allocator hands a freed buffer's memory to the next
/// render) must each write every pixel: a counter left at the last
/// render's end would write none, and the image would be the memory's old
/// contents. Odd sizes leave work items partly off the image.
#[test]
fn every_render_writes_every_pixel_of_its_own_image() {
    let context = gpu();
    let backgrounds = [DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
    for (width, height) in [(37, 29), (1, 1), (300, 7)] {
        for round in 0..4 {
            let background = backgrounds[round % 2];
            let mut s = scene(width, height, 30.0);
            s.image.background = background;
            let out = crate::common::trace_gpu_counting(&context, &s, false)
                .unwrap_or_else(|e| panic!("{e}"));
            for (i, p) in out.image.pixels.iter().enumerate() {
                // Every ray misses: exactly the background, in f32.
                assert_eq!(
                    to_dvec(*p),
                    background,
                    "{width}x{height}, render {round}, pixel {i}"
                );
            }
        }
    }
}

/// Several samples per pixel: the GPU traces the stratified positions the
/// CPU twin traces and averages them in the same way (docs/raytracing.md),
/// so the two images agree pixel by pixel on the sphere's silhouette too,
/// where a single sample per pixel sees something else. Three samples, so
/// that the 2 x 2 grid is not full. No shadows: the samples are the point.
#[test]
fn several_samples_per_pixel_agree_with_the_cpu() {
    let mut s = mesh_sphere_scene();
    s.image.width = 64;
    s.image.height = 64;
    s.render.depth = 0;
    s.render.shadows = false;
    s.render.samples = 3;
    let (traced, stats) = trace(&s);
    assert_eq!(stats.primary, 3 * 64 * 64);
    let (cpu, _) = crate::common::render_cpu(&s, Shading::Raytrace).unwrap();
    s.render.samples = 1;
    let (one, _) = trace(&s);
    let mut silhouette = 0;
    for (i, (gpu_pixel, cpu_pixel)) in traced.pixels.iter().zip(&cpu.image.pixels).enumerate() {
        // f32 against f64 at the same ray positions: 2e-4 at most on this
        // scene's interior (above); 1e-3 leaves room for a sample that
        // grazes a silhouette edge, and is far below a sample's share of
        // the contrast there (about 0.1), which a missing sample costs.
        let err = max_abs_diff(to_dvec(*gpu_pixel), to_dvec(*cpu_pixel));
        assert!(
            err < 1e-3,
            "pixel {i}: GPU {gpu_pixel:?}, CPU {cpu_pixel:?}"
        );
        if max_abs_diff(to_dvec(one.pixels[i]), to_dvec(*cpu_pixel)) > 0.02 {
            silhouette += 1;
        }
    }
    // The test means something only where the samples see different things.
    assert!(
        silhouette > 20,
        "{silhouette} pixels where one sample differs"
    );
}
