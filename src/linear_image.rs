//! `LinearImage`: what every renderer produces and every encoder and metric
//! consumes. Linear RGB intensities in `f32`, row 0 at the top.

#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    /// Row-major RGB triples, `width * height` of them.
    pub pixels: Vec<[f32; 3]>,
}

impl LinearImage {
    pub fn new(width: u32, height: u32, fill: [f32; 3]) -> Self {
        Self {
            width,
            height,
            pixels: vec![fill; width as usize * height as usize],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, rgb: [f32; 3]) {
        self.pixels[y as usize * self.width as usize + x as usize] = rgb;
    }
}
