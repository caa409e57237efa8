//! The photon map's caustic photons (`shadelab::cpu::caustics`, issue 46):
//! light that reaches a diffuse surface through a mirror, held to the
//! answer worked out by hand, a second light at the mirror image.

use glam::DVec3;
use shadelab::cpu::caustics::caustic_photons;
use shadelab::rt_scene::RtScene;

/// A point light at (0, 0.5, 0) over a white floor (y = 0), a mirror
/// (kr = 0.8, kd = 0) standing at x = 0.5 from the floor to y = 2,
/// |z| <= 1, facing the light; the lecture's falloff `1 / (d + k)`, k = 1,
/// `d` along the light's path.
const MIRROR_BESIDE_A_LIGHT: &str = r#"
[camera]
position = [0.0, 3.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 45.0

[image]
width = 64
height = 48

[lighting]
ambient = 0.0
falloff = "lecture"
k = 1.0

[[lights]]
position = [0.0, 0.5, 0.0]
intensity = 1.0

[materials.white]
color = [1.0, 1.0, 1.0]
kd = 1.0

[materials.mirror]
color = [1.0, 1.0, 1.0]
kd = 0.0
kr = 0.8

[[objects]]
shape = "plane"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = 10.0
material = "white"

[[objects]]
shape = "plane"
center = [0.5, 1.0, 0.0]
normal = [-1.0, 0.0, 0.0]
size = 2.0
material = "mirror"
"#;

fn scene_of(toml: &str) -> shadelab::scene::Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, toml).unwrap();
    shadelab::scene::load(&path).unwrap()
}

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
