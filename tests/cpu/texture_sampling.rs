//! The texture lookup against values worked out by hand, sharing no code
//! with it (docs/surface-colour.md, "Sampling"): a 2 x 2 texture whose
//! texels are A (top left), B (top right), C (bottom left) and D (bottom
//! right), read in every wrap mode and filter, at magnification and
//! minification. Texel centres lie at u, v = 0.25 and 0.75.

use glam::{DVec2, DVec3};
use shadelab::cpu::sample::sample;
use shadelab::scene::texture::{Filter, Sampler, Texture, Wrap};

// Powers of two apart, so that every mean below is exact in f32.
const A: [f32; 3] = [1.0, 0.0, 0.0];
const B: [f32; 3] = [0.0, 1.0, 0.0];
const C: [f32; 3] = [0.0, 0.0, 1.0];
const D: [f32; 3] = [0.5, 0.5, 0.5];

fn texture() -> Texture {
    Texture::new(2, 2, vec![A, B, C, D])
}

fn v(t: [f32; 3]) -> DVec3 {
    DVec3::from_array(t.map(f64::from))
}

fn sampler(wrap: Wrap, filter: Filter, mipmap: Option<Filter>) -> Sampler {
    Sampler {
        wrap_u: wrap,
        wrap_v: wrap,
        magnification: filter,
        minification: filter,
        mipmap,
    }
}

fn at(s: &Sampler, u: f64, vv: f64, lambda: f64) -> DVec3 {
    sample(&texture(), s, DVec2::new(u, vv), lambda)
}

fn close(got: DVec3, want: DVec3) {
    assert!(
        (got - want).abs().max_element() < 1e-12,
        "{got} against {want}"
    );
}

#[test]
fn the_mip_chain_is_the_box_mean() {
    let t = texture();
    assert_eq!(t.levels.len(), 2);
    assert_eq!((t.levels[1].width, t.levels[1].height), (1, 1));
    close(v(t.levels[1].texels[0]), (v(A) + v(B) + v(C) + v(D)) / 4.0);
    // 3 x 1: the next level is 1 x 1, the mean of the first two (the odd
    // last texel left out).
    let odd = Texture::new(3, 1, vec![A, B, C]);
    assert_eq!(odd.levels.len(), 2);
    close(v(odd.levels[1].texels[0]), (v(A) + v(B)) / 2.0);
}

#[test]
fn nearest_takes_the_texel_the_coordinates_fall_in() {
    let s = sampler(Wrap::Repeat, Filter::Nearest, None);
    close(at(&s, 0.25, 0.25, 0.0), v(A));
    close(at(&s, 0.75, 0.25, 0.0), v(B));
    close(at(&s, 0.25, 0.75, 0.0), v(C));
    close(at(&s, 0.99, 0.99, 0.0), v(D));
    // On the line between texels: the one to the right (floor of 1.0).
    close(at(&s, 0.5, 0.25, 0.0), v(B));
}

#[test]
fn linear_blends_the_four_nearest_texel_centres() {
    let s = sampler(Wrap::ClampToEdge, Filter::Linear, None);
    // At a texel centre, that texel.
    close(at(&s, 0.25, 0.25, 0.0), v(A));
    // Midway between all four centres.
    close(at(&s, 0.5, 0.5, 0.0), (v(A) + v(B) + v(C) + v(D)) / 4.0);
    // Midway down the left column.
    close(at(&s, 0.25, 0.5, 0.0), (v(A) + v(C)) / 2.0);
    // A quarter of the way from A's centre to B's: 3/4 A, 1/4 B.
    close(at(&s, 0.375, 0.25, 0.0), v(A) * 0.75 + v(B) * 0.25);
}

#[test]
fn each_wrap_mode_reads_outside_zero_to_one_its_own_way() {
    let linear = |wrap| sampler(wrap, Filter::Linear, None);
    let nearest = |wrap| sampler(wrap, Filter::Nearest, None);
    // u = 0 on the top row lies midway between A's centre and the texel
    // left of it: B when repeating, A itself when clamped or mirrored.
    close(
        at(&linear(Wrap::Repeat), 0.0, 0.25, 0.0),
        (v(A) + v(B)) / 2.0,
    );
    close(at(&linear(Wrap::ClampToEdge), 0.0, 0.25, 0.0), v(A));
    close(at(&linear(Wrap::MirroredRepeat), 0.0, 0.25, 0.0), v(A));
    // u = 1.25 falls in texel column 2: column 0 repeated, column 1
    // clamped, column 1 mirrored (2, 3 mirror to 1, 0).
    close(at(&nearest(Wrap::Repeat), 1.25, 0.25, 0.0), v(A));
    close(at(&nearest(Wrap::ClampToEdge), 1.25, 0.25, 0.0), v(B));
    close(at(&nearest(Wrap::MirroredRepeat), 1.25, 0.25, 0.0), v(B));
    // u = 1.75, column 3: B repeated, B clamped, A mirrored.
    close(at(&nearest(Wrap::Repeat), 1.75, 0.25, 0.0), v(B));
    close(at(&nearest(Wrap::ClampToEdge), 1.75, 0.25, 0.0), v(B));
    close(at(&nearest(Wrap::MirroredRepeat), 1.75, 0.25, 0.0), v(A));
    // u = -0.25, column -1: B repeated, A clamped, A mirrored.
    close(at(&nearest(Wrap::Repeat), -0.25, 0.25, 0.0), v(B));
    close(at(&nearest(Wrap::ClampToEdge), -0.25, 0.25, 0.0), v(A));
    close(at(&nearest(Wrap::MirroredRepeat), -0.25, 0.25, 0.0), v(A));
}

#[test]
fn minification_picks_or_blends_mip_levels_by_lambda() {
    let mean = (v(A) + v(B) + v(C) + v(D)) / 4.0;
    // Magnification and minification filters apart: nearest up close,
    // linear from afar (no mip levels): at A's centre both give A; a
    // quarter of the way to B, nearest A, linear the blend.
    let split = Sampler {
        magnification: Filter::Nearest,
        ..sampler(Wrap::Repeat, Filter::Linear, None)
    };
    close(at(&split, 0.375, 0.25, 0.0), v(A));
    close(at(&split, 0.375, 0.25, 1.0), v(A) * 0.75 + v(B) * 0.25);
    // NEAREST_MIPMAP_NEAREST: level nearest(lambda) = ceil(lambda + 0.5) - 1:
    // level 0 up to lambda 0.5, level 1 above.
    let nn = sampler(Wrap::Repeat, Filter::Nearest, Some(Filter::Nearest));
    close(at(&nn, 0.25, 0.25, 0.5), v(A));
    close(at(&nn, 0.25, 0.25, 0.6), mean);
    // Beyond the chain: its last level.
    close(at(&nn, 0.25, 0.25, 7.0), mean);
    // NEAREST_MIPMAP_LINEAR and LINEAR_MIPMAP_LINEAR at A's centre, lambda
    // 0.25: 3/4 of level 0 (A), 1/4 of level 1 (the mean).
    let nl = sampler(Wrap::Repeat, Filter::Nearest, Some(Filter::Linear));
    close(at(&nl, 0.25, 0.25, 0.25), v(A) * 0.75 + mean * 0.25);
    let ll = sampler(Wrap::Repeat, Filter::Linear, Some(Filter::Linear));
    close(at(&ll, 0.25, 0.25, 0.25), v(A) * 0.75 + mean * 0.25);
    // LINEAR_MIPMAP_NEAREST between centres at lambda 0.3: level 0, linear.
    let ln = sampler(Wrap::Repeat, Filter::Linear, Some(Filter::Nearest));
    close(at(&ln, 0.5, 0.25, 0.3), (v(A) + v(B)) / 2.0);
}

#[test]
fn srgb_bytes_decode_to_linear_texels() {
    // 255 is 1, 0 is 0, and 188 is about 0.5 (sRGB's mid-grey).
    let t = Texture::from_srgb8_rgba(1, 1, &[255, 0, 188, 17]);
    let [r, g, b] = t.levels[0].texels[0];
    assert_eq!((r, g), (1.0, 0.0));
    assert!((b - 0.5029).abs() < 1e-3, "{b}");
}
