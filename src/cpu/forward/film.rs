//! The film photons splat into: which pixel the eye sees a point in, and
//! the sums of what lands there, in the GPU's fixed point
//! (`film_sums`), so that films add up in any order to the same bits.

use glam::DVec3;

use crate::camera::View;
use crate::film_sums::{to_fixed, FilmSums};

/// A pinhole eye at the origin of camera-relative coordinates and its
/// image's pixel sums.
#[derive(Clone)]
pub struct Film {
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    focal: f64,
    aspect: f64,
    width: u32,
    height: u32,
    sums: FilmSums,
}

impl Film {
    pub fn new(view: &View) -> Self {
        Film {
            right: view.right,
            up: view.up,
            forward: view.forward,
            focal: view.focal,
            aspect: view.aspect,
            width: view.width,
            height: view.height,
            sums: FilmSums::zero(view.width, view.height),
        }
    }

    /// The pixel the eye sees camera-relative point `p` in, and the cosine
    /// between the ray to it and the view axis; `None` behind the eye or
    /// off the image. The inverse of `View::ray_direction`.
    pub fn pixel_of(&self, p: DVec3) -> Option<(usize, f64)> {
        let dir = p.normalize();
        let cos = dir.dot(self.forward);
        if cos.is_nan() || cos <= 0.0 {
            return None;
        }
        let ndc_x = self.focal / self.aspect * dir.dot(self.right) / cos;
        let ndc_y = -self.focal * dir.dot(self.up) / cos;
        let x = (ndc_x + 1.0) * 0.5 * f64::from(self.width);
        let y = (ndc_y + 1.0) * 0.5 * f64::from(self.height);
        let inside = |v: f64, size: u32| (0.0..f64::from(size)).contains(&v);
        if !inside(x, self.width) || !inside(y, self.height) {
            return None;
        }
        Some((y as usize * self.width as usize + x as usize, cos))
    }

    /// A pixel's area on the image plane at unit distance from the eye
    /// (pixels are square: the aspect is the image's).
    pub fn pixel_area(&self) -> f64 {
        let side = 2.0 / (self.focal * f64::from(self.height));
        side * side
    }

    /// Adds a splat to its pixel's sums, rounded to nearest as the GPU
    /// rounds (`add_to_film` in shaders/include/rt_photon.glsl); one that
    /// is not finite adds nothing.
    pub fn add_to(&mut self, pixel: usize, value: DVec3) {
        for (c, v) in value.to_array().into_iter().enumerate() {
            let sum = &mut self.sums.sums[3 * pixel + c];
            *sum = sum.wrapping_add(to_fixed(v));
        }
    }

    /// Adds another film of the same image, sum by sum.
    pub fn add(&mut self, other: &Film) {
        self.sums
            .add(&other.sums)
            .expect("films of one view are the same size");
    }

    /// The sums.
    pub fn into_sums(self) -> FilmSums {
        self.sums
    }
}
