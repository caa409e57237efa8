//! The render loop: bands of rows in parallel, each sample of each pixel
//! covered, depth tested and shaded on its own (or once per pixel), the
//! samples resolved to their mean, and the bands put together.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::coverage::{barycentrics, coverage, SamplePositions};
use super::edge_marks::{mark_cell_edges, mark_near_boundaries, mark_steep_intensities};
use super::setup::setup_triangles;
use super::shade::{at_least_zero, shade_sample, Sample};
use super::triangle::Triangle;
use crate::camera::View;
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::shading::RasterMode;
use crate::work_counter::WorkCounter;

/// Rows rasterized together by one task.
const BAND_ROWS: u32 = 8;

/// The reference image and, per pixel, what it shows.
pub struct CpuRender {
    pub image: LinearImage,
    /// `scene.objects` index per pixel, `None` for the background.
    pub object_ids: Vec<Option<u32>>,
    /// Triangle per pixel, numbered across all objects in scene order.
    pub triangle_ids: Vec<Option<u32>>,
    /// Pixels whose sample lies within `EDGE_MARGIN` of the boundary of a
    /// triangle that is not hidden there, or (Phong) whose interpolated
    /// normal is shorter than `VANISHING_NORMAL`: the only pixels where
    /// another conforming rasterizer may legitimately show something else.
    pub near_edge: Vec<bool>,
}

/// The rows one task rasterizes.
struct Band {
    pixels: Vec<[f32; 3]>,
    object_ids: Vec<Option<u32>>,
    triangle_ids: Vec<Option<u32>>,
    near_edge: Vec<bool>,
    cells: Vec<Option<i64>>,
}

/// Renders `scene` at its image size in `mode`, with its samples per
/// pixel (`scene.render.msaa`, a count with standard locations:
/// [`crate::msaa::positions`]): each sample covered and depth tested on its
/// own, shaded once per pixel at its centre (or, per sample, at its own
/// position), and the samples' linear values averaged.
/// Its bands of rows are counted into `counter` as they finish.
pub fn render(scene: &Scene, mode: RasterMode, counter: &WorkCounter) -> CpuRender {
    let (width, height) = (scene.image.width, scene.image.height);
    let view = View::new(scene, width, height);
    let triangles = setup_triangles(scene, &view, mode, counter);
    let msaa = scene.render.msaa;
    let offsets = msaa
        .positions()
        .expect("the render plan refuses counts without standard locations");
    let raster = Raster {
        scene,
        view: &view,
        mode,
        triangles: &triangles,
        samples: SamplePositions::new(offsets),
        per_sample: msaa.per_sample && offsets.len() > 1,
        width,
    };
    counter.begin("bands of rows", u64::from(height.div_ceil(BAND_ROWS)));
    let bands: Vec<Band> = (0..height.div_ceil(BAND_ROWS))
        .into_par_iter()
        .map(|band| {
            let y0 = band * BAND_ROWS;
            let y1 = (y0 + BAND_ROWS).min(height);
            let band = raster.band(y0, y1);
            counter.add(1);
            band
        })
        .collect();
    let (mut out, cells) = assemble(width, height, bands);
    mark_cell_edges(width as usize, height as usize, &cells, &mut out.near_edge);
    if mode == RasterMode::Gouraud {
        mark_steep_intensities(&out.image, &mut out.near_edge);
    }
    out
}

/// What every band rasterizes from.
struct Raster<'a> {
    scene: &'a Scene,
    view: &'a View,
    mode: RasterMode,
    triangles: &'a [Triangle],
    samples: SamplePositions,
    /// Multisampled and shaded per sample (else once per pixel).
    per_sample: bool,
    width: u32,
}

/// A band's samples as the depth test leaves them: pixel i's sample s at
/// i * n + s.
struct BandSamples {
    color: Vec<DVec3>,
    ids: Vec<Option<u32>>,
    tri_ids: Vec<Option<u32>>,
    vanishing: Vec<bool>,
    cells: Vec<Option<i64>>,
    /// Reversed depth: cleared to 0, nearer is greater.
    depth: Vec<f64>,
}

impl BandSamples {
    fn new(len: usize, background: DVec3) -> Self {
        BandSamples {
            color: vec![background; len],
            ids: vec![None; len],
            tri_ids: vec![None; len],
            vanishing: vec![false; len],
            cells: vec![None; len],
            depth: vec![0.0f64; len],
        }
    }
}

impl Raster<'_> {
    /// Rows `y0..y1`: every triangle drawn into them, the pixels near an
    /// edge marked, the samples resolved.
    fn band(&self, y0: u32, y1: u32) -> Band {
        let n = self.samples.count();
        let count = ((y1 - y0) * self.width) as usize;
        let mut samples = BandSamples::new(count * n, self.scene.image.background);
        for t in self.triangles {
            if t.max.1 < y0 || t.min.1 >= y1 {
                continue;
            }
            self.draw(t, (y0, y1), &mut samples);
        }
        let mut near_edge: Vec<bool> = (0..count)
            .map(|i| samples.vanishing[i * n..(i + 1) * n].iter().any(|&v| v))
            .collect();
        mark_near_boundaries(
            self.triangles,
            &self.samples,
            (y0, y1),
            self.width,
            &samples.depth,
            &mut near_edge,
        );
        resolve(&samples, near_edge, count, n)
    }

    /// `t` into the band of rows `y0..y1`: each sample it covers and wins
    /// the depth test at takes its object, triangle and shade.
    fn draw(&self, t: &Triangle, (y0, y1): (u32, u32), band: &mut BandSamples) {
        let n = self.samples.count();
        for y in t.min.1.max(y0)..=t.max.1.min(y1 - 1) {
            for x in t.min.0..=t.max.0 {
                let i = ((y - y0) * self.width + x) as usize;
                // Once per pixel: shaded at the centre (extrapolated
                // where the triangle misses it), when it wins a sample.
                let mut pixel_shade: Option<Sample> = None;
                for s in 0..n {
                    let p = self.samples.at(x, y, s);
                    let Some(bary) = coverage(t, p) else { continue };
                    let z = t.depth_at(bary);
                    let k = i * n + s;
                    if z <= band.depth[k] {
                        continue;
                    }
                    band.depth[k] = z;
                    band.ids[k] = Some(t.object);
                    band.tri_ids[k] = Some(t.primitive);
                    let sample = if self.per_sample || n == 1 {
                        shade_sample(self.scene, self.view, self.mode, t, (p, bary))
                    } else {
                        pixel_shade
                            .get_or_insert_with(|| self.shade_centre(t, x, y))
                            .clone()
                    };
                    (band.color[k], band.vanishing[k]) = (sample.color, sample.vanishing_normal);
                    band.cells[k] = sample.cell;
                }
            }
        }
    }

    /// `t` shaded at the centre of pixel `(x, y)`, light below 0 made 0.
    fn shade_centre(&self, t: &Triangle, x: u32, y: u32) -> Sample {
        let centre = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
        let mut shaded = shade_sample(
            self.scene,
            self.view,
            self.mode,
            t,
            (centre, barycentrics(t, centre)),
        );
        shaded.color = at_least_zero(shaded.color);
        shaded
    }
}

/// The resolve: the mean of the samples' linear values. A pixel whose
/// samples show different pattern cells is an edge too.
fn resolve(samples: &BandSamples, mut near_edge: Vec<bool>, count: usize, n: usize) -> Band {
    let mut pixel_cells = Vec::with_capacity(count);
    for (i, edge) in near_edge.iter_mut().enumerate() {
        let own = &samples.cells[i * n..(i + 1) * n];
        if own.iter().any(|c| *c != own[0]) {
            *edge = true;
        }
        pixel_cells.push(own[0]);
    }
    let pixels = (0..count)
        .map(|i| {
            let sum = samples.color[i * n..(i + 1) * n]
                .iter()
                .fold(DVec3::ZERO, |a, c| a + *c);
            (sum / n as f64).as_vec3().to_array()
        })
        .collect();
    Band {
        pixels,
        object_ids: (0..count).map(|i| samples.ids[i * n]).collect(),
        triangle_ids: (0..count).map(|i| samples.tri_ids[i * n]).collect(),
        near_edge,
        cells: pixel_cells,
    }
}

/// The bands, top to bottom, as one image; and the pattern cell per pixel.
fn assemble(width: u32, height: u32, bands: Vec<Band>) -> (CpuRender, Vec<Option<i64>>) {
    let mut image = LinearImage {
        width,
        height,
        pixels: Vec::with_capacity((width * height) as usize),
    };
    let mut object_ids = Vec::with_capacity((width * height) as usize);
    let mut triangle_ids = Vec::with_capacity((width * height) as usize);
    let mut near_edge = Vec::with_capacity((width * height) as usize);
    let mut cells = Vec::with_capacity((width * height) as usize);
    for band in bands {
        image.pixels.extend(band.pixels);
        object_ids.extend(band.object_ids);
        triangle_ids.extend(band.triangle_ids);
        near_edge.extend(band.near_edge);
        cells.extend(band.cells);
    }
    let out = CpuRender {
        image,
        object_ids,
        triangle_ids,
        near_edge,
    };
    (out, cells)
}
