//! Vertex colours (glTF `COLOR_0`) in every mode, GPU and CPU reference,
//! against an oracle that shares no code with either: a square parallel to
//! the screen, lit by ambient light alone, red along its left edge and blue
//! along its right, so that the colour at a point is computed here from
//! where the point is, by hand (docs/lighting-model.md, "Surface colour").

mod common;

use common::*;
use glam::DVec3;
use shadelab::scene::{Object, Scene, Shape, TriangleMesh};
use shadelab::shading::Shading;
use shadelab::LinearImage;

const SIZE: u32 = 100;
/// The square's half edge: 10 units from the eye with a 90 degree field
/// of view (focal length 1), it spans window columns and rows 40 to 60.
const HALF: f64 = 2.0;
/// The material's colour, multiplied into the vertex colour.
const FACTOR: DVec3 = DVec3::new(0.8, 1.0, 0.6);

fn square_scene() -> Scene {
    let mut s = scene(SIZE, SIZE, 90.0);
    // Ambient alone: I = Ia ka C with Ia = ka = 1, so a pixel shows C.
    s.lighting.ambient = DVec3::ONE;
    s.materials[0] = material(FACTOR, 1.0, 0.0, 0.0, 1.0);
    let red = DVec3::new(1.0, 0.0, 0.0);
    let blue = DVec3::new(0.0, 0.0, 1.0);
    s.objects.push(Object {
        shape: Shape::Mesh(TriangleMesh {
            // Bottom left, bottom right, top right, top left.
            positions: vec![
                DVec3::new(-HALF, -HALF, 0.0),
                DVec3::new(HALF, -HALF, 0.0),
                DVec3::new(HALF, HALF, 0.0),
                DVec3::new(-HALF, HALF, 0.0),
            ],
            normals: vec![DVec3::Z; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            colors: vec![red, blue, blue, red],
        }),
        material: 0,
    });
    s
}

/// The world point (x, y) in the square's plane seen at the centre of
/// pixel (px, py): window 50 +- 50 covers -10..10 at distance 10.
fn world_at(px: u32, py: u32) -> (f64, f64) {
    let to_world = |w: f64| (w / 50.0 - 1.0) * 10.0;
    (
        to_world(f64::from(px) + 0.5),
        -to_world(f64::from(py) + 0.5),
    )
}

/// What a pixel inside the square shows: red to blue linearly across it
/// (Gouraud, Phong and ray tracing alike), or per triangle the mean of its
/// corners (flat: below the diagonal from bottom left to top right, two
/// blue corners and one red; above it, the reverse).
fn expected(shading: Shading, x: f64, y: f64) -> DVec3 {
    let c = if shading == Shading::Flat {
        if y < x {
            DVec3::new(1.0, 0.0, 2.0) / 3.0
        } else {
            DVec3::new(2.0, 0.0, 1.0) / 3.0
        }
    } else {
        let t = (x + HALF) / (2.0 * HALF);
        DVec3::new(1.0 - t, 0.0, t)
    };
    FACTOR * c
}

/// The largest difference from the oracle over the pixels well inside the
/// square and, for flat shading, away from its diagonal (where the
/// rasterizer's edge rule, not the colour, decides).
fn worst_against_oracle(image: &LinearImage, shading: Shading) -> f64 {
    let mut worst = 0.0f64;
    let mut counted = 0;
    for py in 41..59 {
        for px in 41..59 {
            let (x, y) = world_at(px, py);
            if shading == Shading::Flat && (x - y).abs() < 0.5 {
                continue;
            }
            let got = to_dvec(image.get(px, py));
            worst = worst.max(max_abs_diff(got, expected(shading, x, y)));
            counted += 1;
        }
    }
    assert!(counted > 200, "only {counted} pixels checked");
    worst
}

const MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

#[test]
fn the_gpu_shows_the_material_colour_times_the_interpolated_vertex_colour() {
    let context = gpu();
    let scene = square_scene();
    for shading in MODES {
        let image = render(&context, &scene, shading);
        let worst = worst_against_oracle(&image, shading);
        // f32 against the exact value: FLOAT_TOL (tests/common).
        assert!(
            worst < FLOAT_TOL,
            "{shading:?}: {worst} from the hand-computed colours"
        );
    }
}

#[test]
fn the_cpu_reference_shows_the_same_colours() {
    let scene = square_scene();
    for shading in MODES {
        let (rendered, _) = shadelab::render::render_cpu(&scene, shading).unwrap();
        let worst = worst_against_oracle(&rendered.image, shading);
        // f64 rounded once to the image's f32.
        assert!(
            worst < 1e-6,
            "{shading:?}: {worst} from the hand-computed colours"
        );
    }
}

/// Screen-linear interpolation (`interpolation = "screen"`) interpolates
/// the colour the same way it does the normal: on a square parallel to
/// the screen the two interpolations agree, so the oracle holds as it is.
#[test]
fn screen_linear_interpolation_carries_the_colour_too() {
    let context = gpu();
    let mut scene = square_scene();
    scene.lighting.interpolation = shadelab::scene::Interpolation::Screen;
    for shading in [Shading::Gouraud, Shading::Phong] {
        let image = render(&context, &scene, shading);
        let worst = worst_against_oracle(&image, shading);
        assert!(worst < FLOAT_TOL, "{shading:?}: {worst}");
    }
}
