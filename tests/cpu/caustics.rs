//! The photon map's caustic photons (`shadelab::cpu::caustics`, issue 46):
//! light that reaches a diffuse surface through a mirror, held to the
//! answer worked out by hand, a second light at the mirror image.

use common::caustic_scenes::{
    mirror_caustic_ratios, scene_of, summary, GLASS_BALL_ON_A_FLOOR, MIRROR_BESIDE_A_LIGHT,
};
use glam::DVec3;
use shadelab::cpu::caustics::caustic_photons;
use shadelab::rt_scene::RtScene;

use crate::common;

/// The flux of the caustic photons that land in a patch of the floor
/// (x in [-0.5, 0.3], |z| <= 0.3, where every path from the mirror image
/// crosses the mirror well inside its edges) against what a light of
/// intensity `kr Il = 0.8` at the mirror image (1, 0.5, 0) gives there,
/// `kr Il cos / (d + k)` (the contract's "light" in image units; `d` from
/// the image, which is the path's length), integrated over the patch by
/// the midpoint rule. 2^22 photons put about 42000 in the patch: their
/// sum's own noise is 0.5%, so 2% is four standard deviations. A photon
/// that went on with the mirror's whole flux, a falloff measured from
/// the mirror rather than along the path, or photons kept at their first
/// surface would be off by far more. No photon lands without a mirror on
/// its way, and none is kept on the mirror.
#[test]
fn a_mirror_lights_the_floor_as_a_light_at_its_image_would() {
    let scene = scene_of(MIRROR_BESIDE_A_LIGHT);
    let eye = scene.camera.position;
    let rt = RtScene::new(&scene);
    let total = 1 << 22;
    let photons = caustic_photons(&rt, 0..total, total).unwrap();
    let inside = |p: DVec3| p.x >= -0.5 && p.x <= 0.3 && p.z.abs() <= 0.3;
    let mut landed = 0.0;
    let mut count = 0;
    for photon in &photons {
        let p = photon.position + eye;
        assert!(p.y.abs() < 1e-9, "a caustic photon off the floor: {p}");
        assert!(photon.normal.y > 0.99, "{:?}", photon.normal);
        if inside(p) {
            landed += photon.flux.x;
            count += 1;
        }
    }
    let image = DVec3::new(1.0, 0.5, 0.0);
    let (nx, nz) = (800, 600);
    let (dx, dz) = (0.8 / f64::from(nx), 0.6 / f64::from(nz));
    let mut expected = 0.0;
    for i in 0..nx {
        for k in 0..nz {
            let p = DVec3::new(
                -0.5 + (f64::from(i) + 0.5) * dx,
                0.0,
                -0.3 + (f64::from(k) + 0.5) * dz,
            );
            let to = image - p;
            let d2 = to.length_squared();
            let d = d2.sqrt();
            expected += 0.8 * (to.y / d) / (d + 1.0) * dx * dz;
        }
    }
    eprintln!("{count} photons in the patch: flux {landed}, by hand {expected}");
    assert!(count > 30_000, "{count}");
    assert!(
        (landed / expected - 1.0).abs() < 0.02,
        "{landed} against {expected}"
    );
}

/// The list is the same photons in the same order at any thread count,
/// and a scene with no mirror or glass keeps none.
#[test]
fn caustic_photons_are_the_same_at_any_thread_count_and_need_a_mirror() {
    let scene = scene_of(MIRROR_BESIDE_A_LIGHT);
    let rt = RtScene::new(&scene);
    let total = 1 << 17;
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let serial = one.install(|| caustic_photons(&rt, 0..total, total).unwrap());
    let parallel = caustic_photons(&rt, 0..total, total).unwrap();
    assert!(!serial.is_empty());
    assert_eq!(serial, parallel);
    let split: Vec<_> = [0..5000, 5000..total]
        .into_iter()
        .flat_map(|r| caustic_photons(&rt, r, total).unwrap())
        .collect();
    assert_eq!(split, serial);
    let no_mirror = MIRROR_BESIDE_A_LIGHT.replace("kr = 0.8", "kr = 0.0");
    let plain = RtScene::new(&scene_of(&no_mirror));
    assert!(caustic_photons(&plain, 0..total, total).unwrap().is_empty());
}

/// The caustic image (SPPM over the photons above, `render_caustics`): on
/// the floor patch where the mirror's light falls (away from the mirror's
/// edges and its foot), each pixel against `kd C kr Il cos / (d + k)` from
/// the mirror image at the point its centre sees. 64 passes of 2^18
/// photons from radius 0.05 at 192 x 144: the pixels' ratios spread by
/// 3.9% (measured), so the mean of the patch's 166 pixels has a standard
/// error of 0.3% and is held to 1% (the target; measured 0.34%
/// off), and every pixel to 20% (five spreads; the worst measured 14.5%).
/// A radius that did not shrink by the rule would still converge here
/// (the light is smooth); an area, a weight or a pass count wrong by a
/// factor fails at once.
#[test]
fn the_gathered_caustic_is_the_mirror_images_light() {
    use shadelab::cpu::caustics::{render_caustics, CausticSettings};
    let mut scene = scene_of(MIRROR_BESIDE_A_LIGHT);
    (scene.image.width, scene.image.height) = (192, 144);
    let settings = CausticSettings {
        photons_per_pass: 1 << 18,
        passes: 64,
        // 1.5 pixel footprints: 0.05 on the floor under the patch.
        initial_radius: 1.5,
        alpha: shadelab::scene::defaults::CAUSTIC_ALPHA,
    };
    let image = render_caustics(&scene, &settings).unwrap();
    let ratios = mirror_caustic_ratios(&scene, &image);
    let (mean, spread, worst) = summary(&ratios);
    eprintln!(
        "{} pixels: mean ratio {mean}, spread {spread}, worst {worst}",
        ratios.len()
    );
    assert!(ratios.len() > 150, "{}", ratios.len());
    assert!((mean - 1.0).abs() < 0.01, "{mean}");
    assert!(worst < 0.2, "{worst}");
}

/// Where both see the same paths, the floor seen directly under a glass
/// ball, the gathered caustic is the forward tracer's: its image (direct
/// light and caustic: the light tracer splats both) less the backward
/// tracer's direct light (shadow rays, which glass blocks) leaves the
/// caustic, photons through the ball. Over the floor pixels that do not
/// see the ball the two caustics' sums agree within 3%. Measured: the
/// forward image's own noise over them is 0.6% of the caustic (2^23
/// against 2^25 photons); SPPM's sum after 128 passes is 0.06% off at an
/// initial radius of 0.02 and 1.3% at 0.01 (after 32 passes it still
/// moved by 5% with the radius: its finite-pass bias and noise, where a
/// concentrated caustic gives each pixel few photons). Refraction, total
/// internal reflection and the falloff along the path follow the same
/// rules in both; a wrong one moves the caustic's sum or its place by far
/// more. The brightest pixel of each is the same pixel or a neighbour.
#[test]
fn the_gathered_caustic_under_a_glass_ball_is_the_forward_tracers() {
    use shadelab::cpu::caustics::{render_caustics, CausticSettings};
    let scene = scene_of(GLASS_BALL_ON_A_FLOOR);
    let width = scene.image.width as usize;
    let forward = crate::common::forward_cpu(&scene, 1 << 23).unwrap().image();
    let backward = crate::common::trace_cpu(&scene);
    let settings = CausticSettings {
        photons_per_pass: 1 << 18,
        passes: 128,
        // Half a pixel footprint: 0.02 on the floor under the ball.
        initial_radius: 0.5,
        alpha: shadelab::scene::defaults::CAUSTIC_ALPHA,
    };
    let gathered = render_caustics(&scene, &settings).unwrap();
    let (mut from_forward, mut from_map) = (0.0, 0.0);
    let (mut brightest_forward, mut brightest_map) = ((0.0, 0), (0.0, 0));
    for (i, object) in backward.primary_object_ids.iter().enumerate() {
        if *object != Some(0) {
            continue;
        }
        let f = f64::from(forward.pixels[i][0] - backward.image.pixels[i][0]);
        let c = f64::from(gathered.pixels[i][0]);
        from_forward += f;
        from_map += c;
        if f > brightest_forward.0 {
            brightest_forward = (f, i);
        }
        if c > brightest_map.0 {
            brightest_map = (c, i);
        }
    }
    eprintln!("caustic: forward less backward {from_forward}, gathered {from_map}; brightest at {:?} and {:?}", brightest_forward, brightest_map);
    assert!(from_map > 1.0, "{from_map}");
    assert!(
        (from_map / from_forward - 1.0).abs() < 0.03,
        "{from_map} against {from_forward}"
    );
    let at = |i: usize| ((i % width) as i64, (i / width) as i64);
    let (a, b) = (at(brightest_forward.1), at(brightest_map.1));
    assert!(
        (a.0 - b.0).abs() <= 1 && (a.1 - b.1).abs() <= 1,
        "{a:?} and {b:?}"
    );
}
