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

    /// An image from tightly packed RGBA texels of `N`-byte channels,
    /// each channel's bytes turned into a linear value by `channel`; alpha
    /// is dropped.
    fn from_rgba_texels<const N: usize>(
        width: u32,
        height: u32,
        bytes: &[u8],
        channel: impl Fn([u8; N]) -> f32,
    ) -> Self {
        let at = |t: &[u8], c: usize| channel(std::array::from_fn(|i| t[c * N + i]));
        let pixels = bytes[..width as usize * height as usize * 4 * N]
            .chunks_exact(4 * N)
            .map(|t| [at(t, 0), at(t, 1), at(t, 2)])
            .collect();
        Self {
            width,
            height,
            pixels,
        }
    }

    /// An image from tightly packed RGBA 32-bit float texels in native byte
    /// order (what the GPU renderers read back); alpha is dropped.
    pub fn from_rgba32f_bytes(width: u32, height: u32, bytes: &[u8]) -> Self {
        Self::from_rgba_texels(width, height, bytes, f32::from_ne_bytes)
    }

    /// An image from tightly packed RGBA 16-bit unsigned-normalised texels
    /// in native byte order, each holding a value / `range` (a multisampled
    /// PNG render's resolve); alpha is dropped.
    pub fn from_scaled_rgba16_unorm_bytes(
        width: u32,
        height: u32,
        bytes: &[u8],
        range: f32,
    ) -> Self {
        Self::from_rgba_texels(width, height, bytes, |b| {
            f32::from(u16::from_ne_bytes(b)) / 65535.0 * range
        })
    }

    /// An image from tightly packed 8-bit sRGB RGBA texels (the raster
    /// modes' 8-bit target), decoded to linear; alpha is dropped. Encoding
    /// it as PNG gives back the same bytes.
    pub fn from_srgba8_bytes(width: u32, height: u32, bytes: &[u8]) -> Self {
        let table: Vec<f32> = (0..=255).map(crate::srgb::srgb8_to_linear).collect();
        Self::from_rgba_texels(width, height, bytes, |[v]: [u8; 1]| table[usize::from(v)])
    }

    /// Pixels with a NaN or infinite channel: a render that made one has
    /// gone wrong (a lighting hook's `sqrt` of a negative, say), and a PNG
    /// would show it as black or white without a word.
    pub fn non_finite_pixels(&self) -> usize {
        self.pixels
            .iter()
            .filter(|p| !p.iter().all(|c| c.is_finite()))
            .count()
    }

    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, rgb: [f32; 3]) {
        self.pixels[y as usize * self.width as usize + x as usize] = rgb;
    }
}
