//! Vertex colours (glTF `COLOR_0`) and patterns in every mode, GPU and CPU
//! reference, against an oracle that shares no code with either: a square
//! parallel to the screen, lit by ambient light alone, so that the colour
//! at a point is computed here from where the point is, by hand
//! (docs/lighting-model.md, "Surface colour"). For vertex colours it is
//! red along its left edge and blue along its right; for a pattern, a
//! checkerboard of 2 x 2 cells over texture coordinates that run 0 to 1
//! across it.

use crate::common;

use common::*;
use glam::DVec2;
use glam::DVec3;
use shadelab::scene::{Falloff, Object, Pattern, Scene, Shape, TriangleMesh};
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
            uvs: Vec::new(),
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
        let (rendered, _) = crate::common::render_cpu(&scene, shading).unwrap();
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

const CHECKER_A: DVec3 = DVec3::new(0.9, 0.2, 0.1);
const CHECKER_B: DVec3 = DVec3::new(0.1, 0.3, 0.8);

/// The square with texture coordinates 0 to 1 from its bottom left
/// corner, no vertex colours, and a checker pattern of 2 x 2 cells.
fn checker_scene() -> Scene {
    let mut s = square_scene();
    s.materials[0].pattern = Some(Pattern::Checker {
        scale: 2.0,
        colors: [CHECKER_A, CHECKER_B],
    });
    let Shape::Mesh(mesh) = &mut s.objects[0].shape else {
        unreachable!()
    };
    mesh.colors.clear();
    mesh.uvs = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(0.0, 1.0),
    ];
    s
}

/// The pattern's colour at the world point (x, y) of the square: cell
/// (i, j) = (floor(2u), floor(2v)) with u, v running 0 to 1 across it, the
/// first colour where i + j is even. Flat shading evaluates it at each
/// triangle's centroid, whose coordinates, (2/3, 1/3) and (1/3, 2/3), both
/// lie in an odd cell.
fn expected_checker(shading: Shading, x: f64, y: f64) -> DVec3 {
    if shading == Shading::Flat {
        return FACTOR * CHECKER_B;
    }
    let (u, v) = ((x + HALF) / (2.0 * HALF), (y + HALF) / (2.0 * HALF));
    let (i, j) = ((2.0 * u).floor() as i32, (2.0 * v).floor() as i32);
    FACTOR
        * if (i + j) % 2 == 0 {
            CHECKER_A
        } else {
            CHECKER_B
        }
}

/// The largest difference from `expected_checker` over the pixels well
/// inside the square, away from its cell boundaries (the middle lines)
/// and, for flat shading, its diagonal.
fn worst_against_checker(image: &LinearImage, shading: Shading) -> f64 {
    let mut worst = 0.0f64;
    let mut counted = 0;
    for py in 41..59 {
        for px in 41..59 {
            let (x, y) = world_at(px, py);
            if x.abs() < 0.5 || y.abs() < 0.5 {
                continue;
            }
            if shading == Shading::Flat && (x - y).abs() < 0.5 {
                continue;
            }
            let got = to_dvec(image.get(px, py));
            worst = worst.max(max_abs_diff(got, expected_checker(shading, x, y)));
            counted += 1;
        }
    }
    assert!(counted > 100, "only {counted} pixels checked");
    worst
}

#[test]
fn a_checker_pattern_shows_its_cells_where_the_texture_coordinates_put_them() {
    let context = gpu();
    let scene = checker_scene();
    for shading in MODES {
        let image = render(&context, &scene, shading);
        let worst = worst_against_checker(&image, shading);
        assert!(worst < FLOAT_TOL, "GPU {shading:?}: {worst}");
        let (cpu, _) = crate::common::render_cpu(&scene, shading).unwrap();
        let worst = worst_against_checker(&cpu.image, shading);
        assert!(worst < 1e-6, "CPU {shading:?}: {worst}");
    }
    let mut screen = scene.clone();
    screen.lighting.interpolation = shadelab::scene::Interpolation::Screen;
    for shading in [Shading::Gouraud, Shading::Phong] {
        let image = render(&context, &screen, shading);
        let worst = worst_against_checker(&image, shading);
        assert!(worst < FLOAT_TOL, "GPU {shading:?}, screen-linear: {worst}");
    }
}

/// Gouraud under a pattern keeps the highlight the light's colour: the
/// pattern multiplies the interpolated intensity without its specular
/// term, which is added after. A light straight in front of the square,
/// ks = 0.5: the GPU and the CPU reference agree with each other, and the
/// cells of the two colours differ by the pattern times the unlit part
/// alone, so the white highlight does not take the cell's colour.
#[test]
fn gouraud_adds_the_highlight_after_the_pattern() {
    let context = gpu();
    let mut scene = checker_scene();
    scene.lighting.ambient = DVec3::ZERO;
    scene.materials[0] = material(DVec3::ONE, 0.0, 0.5, 0.5, 1.0);
    scene.materials[0].pattern = Some(Pattern::Checker {
        scale: 2.0,
        colors: [DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 1.0)],
    });
    scene.lighting.falloff = Falloff::None;
    scene.lights[0].position = DVec3::new(0.0, 0.0, 10.0);
    scene.lights[0].intensity = DVec3::ONE;
    let gpu_image = render(&context, &scene, Shading::Gouraud);
    let (cpu, _) = crate::common::render_cpu(&scene, Shading::Gouraud).unwrap();
    // A red cell (bottom left) shows no blue but the highlight's, and a
    // blue cell (bottom right) no red but the highlight's: the same
    // amount of each, the specular part, at mirrored points.
    let red_cell = to_dvec(gpu_image.get(45, 55));
    let blue_cell = to_dvec(gpu_image.get(54, 55));
    assert!(
        red_cell.z > 0.05,
        "no highlight in the red cell: {red_cell}"
    );
    assert!(
        (red_cell.z - blue_cell.x).abs() < FLOAT_TOL,
        "{red_cell} {blue_cell}"
    );
    assert!(red_cell.x > red_cell.z + 0.1, "{red_cell}");
    assert!(worst_difference(&gpu_image, &cpu.image) < FLOAT_TOL);
}
