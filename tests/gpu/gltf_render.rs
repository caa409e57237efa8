//! glTF meshes rendered end to end: the pixels they cover must be where their
//! node transforms and the scene's own transform put them. Expected world
//! positions are computed here by hand from the fixtures'
//! raw data (tests/data/make_fixtures.py), independently of the loader.

use crate::common;

use std::path::PathBuf;

use common::*;
use glam::{DMat3, DMat4, DQuat, DVec3};
use shadelab::cpu::lighting::{shade, Surface};
use shadelab::scene::{self, Scene, TriangleMesh};
use shadelab::shading::Shading;

const SIZE: u32 = 96;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Loads a TOML scene that places `file` with the extra object keys `extra`,
/// framing `expected` (the world-space triangles) from the +Z side.
fn load_scene(file: &str, extra: &str, expected: &TriangleMesh) -> Scene {
    let lo = expected
        .positions
        .iter()
        .copied()
        .fold(DVec3::splat(f64::MAX), DVec3::min);
    let hi = expected
        .positions
        .iter()
        .copied()
        .fold(DVec3::splat(f64::MIN), DVec3::max);
    let center = (lo + hi) * 0.5;
    let eye = center + DVec3::new(0.3, 0.2, 1.0).normalize() * (hi - lo).length() * 2.5;
    let text = format!(
        r#"
[camera]
position = [{}, {}, {}]
look_at = [{}, {}, {}]
fov_y = 40
[image]
width = {SIZE}
height = {SIZE}
background = [0, 0, 0]
[[lights]]
position = [{}, {}, {}]
intensity = 10
[materials.white]
color = [1, 1, 1]
[[objects]]
shape = "mesh"
file = {:?}
material = "white"
{extra}
"#,
        eye.x,
        eye.y,
        eye.z,
        center.x,
        center.y,
        center.z,
        eye.x,
        eye.y + 1.0,
        eye.z,
        fixture(file).display().to_string()
    );
    let dir = tempfile::tempdir().unwrap();
    scene::from_toml_str(&text, dir.path(), "test.toml").unwrap_or_else(|e| panic!("{e}"))
}

fn triangles(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> TriangleMesh {
    let normals = vec![DVec3::Z; positions.len()];
    TriangleMesh::new(positions, normals, triangles)
}

/// Renders flat and compares coverage with the expected triangles at every
/// pixel whose 3x3 neighbourhood is all inside or all outside them.
fn assert_lands_where_expected(scene: &Scene, expected: &TriangleMesh) -> shadelab::LinearImage {
    let image = render(&gpu(), scene, Shading::Flat);
    let v = view(scene);
    let hits = id_map(SIZE, SIZE, |x, y| {
        Some(usize::from(
            hit_mesh(v.eye, pixel_ray(&v, x, y), expected).is_some(),
        ))
    });
    let mut covered = 0;
    for (x, y, hit) in interior_pixels(SIZE, SIZE, &hits) {
        let drawn = image.get(x, y) != [0.0; 3];
        assert_eq!(
            drawn,
            hit == 1,
            "pixel ({x}, {y}): drawn {drawn}, expected {}",
            hit == 1
        );
        covered += hit;
    }
    assert!(
        covered > 150,
        "the mesh should cover a good part of the image: {covered}"
    );
    image
}

#[test]
fn indexed_triangle_with_scene_transform() {
    // T(0.5, -0.5, 0) * Rz(90) * S(2): (x, y, z) -> (-2y + 0.5, 2x - 0.5, 2z).
    let place = |x: f64, y: f64, z: f64| DVec3::new(-2.0 * y + 0.5, 2.0 * x - 0.5, 2.0 * z);
    let expected = triangles(
        vec![place(0., 0., 0.), place(1., 0., 0.), place(0., 1., 0.)],
        vec![[0, 1, 2]],
    );
    let s = load_scene(
        "tri_indexed.gltf",
        "translate = [0.5, -0.5, 0.0]\nrotate_deg = [0.0, 0.0, 90.0]\nscale = 2.0",
        &expected,
    );
    assert_lands_where_expected(&s, &expected);
}

#[test]
fn unindexed_quad() {
    let expected = triangles(
        vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::X,
            DVec3::new(1., 1., 0.),
            DVec3::Y,
        ],
        vec![[0, 1, 2], [3, 4, 5]],
    );
    let s = load_scene("tri_unindexed.gltf", "", &expected);
    assert_lands_where_expected(&s, &expected);
}

#[test]
fn node_hierarchy_composes_parent_and_child() {
    // parent T(1, 2, 3) S(2), child R = 90 degrees about +Z.
    let parent = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        DQuat::IDENTITY,
        DVec3::new(1., 2., 3.),
    );
    let child = DMat4::from_quat(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2));
    let world = parent * child;
    let pts = [DVec3::X, DVec3::Y, DVec3::Z].map(|p| world.transform_point3(p));
    // The fixture's comment states the same points.
    assert!((pts[0] - DVec3::new(1., 4., 3.)).length() < 1e-12);
    let expected = triangles(pts.to_vec(), vec![[0, 1, 2]]);
    let s = load_scene("hierarchy.gltf", "", &expected);
    assert_lands_where_expected(&s, &expected);
}

#[test]
fn mesh_without_normals_gets_area_weighted_normals() {
    let pts = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let expected = triangles(pts, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
    let s = load_scene("no_normals.gltf", "", &expected);
    assert_lands_where_expected(&s, &expected);
    // Vertex 3 = (0, 0, 1) touches faces with unnormalised normals (0, -1, 0),
    // (-1, 0, 0) and (1, 1, 1); each is twice its face's area.
    let mesh = match &s.objects[0].shape {
        scene::Shape::Mesh(m) => m,
        _ => panic!("a mesh"),
    };
    let i = mesh.positions.iter().position(|p| *p == DVec3::Z).unwrap();
    let want = (DVec3::new(0., -1., 0.) + DVec3::new(-1., 0., 0.) + DVec3::ONE).normalize();
    assert_eq!(want, DVec3::Z);
    assert!(
        (mesh.normals[i] - want).length() < 1e-12,
        "{} vs {want}",
        mesh.normals[i]
    );
}

#[test]
fn binary_glb_cube() {
    let mut pts = Vec::new();
    let mut tris = Vec::new();
    // A unit cube centred on the origin, as 12 triangles.
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let n = DMat3::IDENTITY.col(axis) * sign;
            let (u, w) = (
                DMat3::IDENTITY.col((axis + 1) % 3),
                DMat3::IDENTITY.col((axis + 2) % 3),
            );
            let base = pts.len() as u32;
            for (a, b) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                pts.push(n * 0.5 + u * a + w * b);
            }
            tris.push([base, base + 1, base + 2]);
            tris.push([base, base + 2, base + 3]);
        }
    }
    let expected = triangles(pts, tris);
    let s = load_scene("cube.glb", "", &expected);
    assert_lands_where_expected(&s, &expected);
}

#[test]
fn mirroring_transform_keeps_the_lit_side_lit() {
    // scale [-1, 1, 1]: the triangle lands at x <= 0; the loader flips its
    // winding so the geometric normal still agrees with the normal (+Z).
    let expected = triangles(vec![DVec3::ZERO, -DVec3::X, DVec3::Y], vec![[0, 1, 2]]);
    let s = load_scene("mirrored.gltf", "", &expected);
    let image = assert_lands_where_expected(&s, &expected);
    let centroid = (-DVec3::X + DVec3::Y) / 3.0;
    let want = shade(
        &s.lighting,
        &s.lights,
        Surface::plain(&s.materials[0]),
        centroid,
        DVec3::Z,
        s.camera.position,
    );
    let v = view(&s);
    let at = v.project(centroid).unwrap();
    let got = to_dvec(image.get(at.x as u32, at.y as u32));
    assert!(
        max_abs_diff(got, want) < 1e-4,
        "flat colour {got} vs lit side {want}"
    );
}
