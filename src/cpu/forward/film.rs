//! The film photons splat into: which pixel the eye sees a point in, and
//! the sums of what lands there.

use glam::DVec3;

use crate::camera::View;
use crate::linear_image::LinearImage;

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
    pixels: Vec<DVec3>,
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
            pixels: vec![DVec3::ZERO; view.width as usize * view.height as usize],
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

    pub fn add_to(&mut self, pixel: usize, value: DVec3) {
        self.pixels[pixel] += value;
    }

    /// Adds another film of the same image, pixel by pixel.
    pub fn add(&mut self, other: &Film) {
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            *a += *b;
        }
    }

    pub fn image(&self) -> LinearImage {
        LinearImage {
            width: self.width,
            height: self.height,
            pixels: self.pixels.iter().map(|p| p.as_vec3().to_array()).collect(),
        }
    }
}
