//! What a raster frame is made of, in the order `Frame::new` makes it: the
//! mesh's vertex streams and indices, the buffers the shaders read through
//! the descriptors (lights, frame uniforms, flat shading's faces, image
//! textures), then the images drawn into and the buffer they are read
//! back through.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::camera::View;
use crate::gpu::raster::flat::FlatMesh;
use crate::gpu::raster::layout::FrameUniforms;
use crate::gpu::raster::pipeline::SurfaceFeatures;
use crate::gpu::raster::samples::SampleDrawing;
use crate::gpu::raster::scene::RasterGeometry as Geometry;
use crate::gpu::raster::target::{ColorTarget, DEPTH_FORMAT};
use crate::gpu::shared::lights::lights;
use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::image::Image;
use crate::scene::Scene;

/// The vertex streams and the indices a frame draws.
pub(super) struct MeshBuffers {
    pub vertices: Buffer,
    /// The vertex colours, where the scene has them (per flat vertex: its
    /// face's).
    pub colors: Option<Buffer>,
    /// The texture coordinates, where a material has a pattern (Gouraud
    /// and Phong).
    pub uvs: Option<Buffer>,
    pub indices: Buffer,
}

impl MeshBuffers {
    /// `geometry`'s vertices and indices, or `flat_mesh`'s (a vertex per
    /// face corner) where the frame is flat shaded.
    pub fn upload(
        context: &Arc<GpuContext>,
        geometry: &Geometry,
        flat_mesh: Option<&FlatMesh>,
    ) -> Result<Self, GpuError> {
        let flat = flat_mesh.is_some();
        let (vertex_bytes, index_data): (&[u8], &[u32]) = match flat_mesh {
            Some(m) => (bytemuck::cast_slice(&m.positions), &m.indices),
            None => (bytemuck::cast_slice(&geometry.vertices), &geometry.indices),
        };
        let vertex_buffer = Buffer::with_data(
            context,
            "vertices",
            vertex_bytes,
            vk::BufferUsageFlags::VERTEX_BUFFER,
        )?;
        let colors = match flat_mesh {
            Some(m) => &m.colors,
            None => &geometry.vertex_colors,
        };
        let color_buffer = if colors.is_empty() {
            None
        } else {
            Some(Buffer::with_data(
                context,
                "vertex colours",
                bytemuck::cast_slice(colors),
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?)
        };
        let uv_buffer = if geometry.vertex_uvs.is_empty() || flat {
            None
        } else {
            Some(Buffer::with_data(
                context,
                "texture coordinates",
                bytemuck::cast_slice(&geometry.vertex_uvs),
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?)
        };
        let index_buffer = Buffer::with_data(
            context,
            "indices",
            bytemuck::cast_slice(index_data),
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        Ok(Self {
            vertices: vertex_buffer,
            colors: color_buffer,
            uvs: uv_buffer,
            indices: index_buffer,
        })
    }
}

/// The buffers the shaders read through the descriptors, in the order of
/// their bindings (`bindings_of`).
pub(super) struct ShadingBuffers {
    pub lights: Buffer,
    pub frame: Buffer,
    /// Flat shading's faces.
    pub faces: Option<Buffer>,
    /// The image textures' records and texels, where the variant samples
    /// them.
    pub textures: Option<[Buffer; 2]>,
}

impl ShadingBuffers {
    /// The scene's lights as seen from `view`, its ambient light, and
    /// `flat_mesh`'s faces and `geometry`'s textures where the frame reads
    /// them.
    pub fn upload(
        context: &Arc<GpuContext>,
        (scene, view, geometry): (&Scene, &View, &Geometry),
        flat_mesh: Option<&FlatMesh>,
        features: SurfaceFeatures,
    ) -> Result<Self, GpuError> {
        let flat = flat_mesh.is_some();
        let light_buffer = Buffer::with_data(
            context,
            "lights",
            bytemuck::cast_slice(&lights(scene, view.eye)),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let ambient = scene.lighting.ambient.as_vec3();
        let frame = FrameUniforms {
            ambient_k: [ambient.x, ambient.y, ambient.z, scene.lighting.k as f32],
        };
        let frame_buffer = Buffer::with_data(
            context,
            "frame",
            bytemuck::bytes_of(&frame),
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        let face_buffer = match flat_mesh {
            Some(m) => Some(Buffer::with_data(
                context,
                "faces",
                bytemuck::cast_slice(&m.faces),
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )?),
            None => None,
        };
        // The image textures, where the variant samples them.
        let texture_buffers = if features.texture && !flat {
            let table = &geometry.textures;
            Some([
                Buffer::with_data(
                    context,
                    "texture records",
                    bytemuck::cast_slice(&table.records),
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                )?,
                Buffer::with_data(
                    context,
                    "texels",
                    bytemuck::cast_slice(&table.texels),
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                )?,
            ])
        } else {
            None
        };
        Ok(Self {
            lights: light_buffer,
            frame: frame_buffer,
            faces: face_buffer,
            textures: texture_buffers,
        })
    }
}

/// The images a frame draws into and the buffer they are read back
/// through.
pub(super) struct FrameImages {
    /// The resolved (or only) colour image; with a pass per sample, the
    /// first pass's.
    pub color: Image,
    /// With a pass per sample, the other passes' images.
    pub pass_colors: Vec<Image>,
    /// Multisampled: the colour samples.
    pub color_samples: Option<Image>,
    pub depth: Image,
    /// Room for every pass's image, one after another.
    pub readback: Buffer,
}

impl FrameImages {
    /// The images of `extent` in `target`'s format, as many and as
    /// multisampled as `drawing` draws.
    pub fn new(
        context: &Arc<GpuContext>,
        extent: vk::Extent2D,
        target: ColorTarget,
        drawing: SampleDrawing,
    ) -> Result<Self, GpuError> {
        let color_image = |name: &str| {
            Image::new(
                context,
                name,
                extent,
                target.format(),
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                vk::ImageAspectFlags::COLOR,
            )
        };
        let color = color_image("color")?;
        let pass_colors = (1..drawing.passes())
            .map(|pass| color_image(&format!("color of sample {pass}")))
            .collect::<Result<Vec<_>, _>>()?;
        let samples = drawing.rasterization_samples();
        let color_samples = if samples > 1 {
            Some(Image::multisampled(
                context,
                "color samples",
                extent,
                (target.format(), samples),
                vk::ImageUsageFlags::COLOR_ATTACHMENT,
                vk::ImageAspectFlags::COLOR,
            )?)
        } else {
            None
        };
        let depth = Image::multisampled(
            context,
            "depth",
            extent,
            (DEPTH_FORMAT, samples),
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let pixel_bytes = target.bytes_per_pixel();
        let readback = Buffer::new(
            context,
            "readback",
            u64::from(extent.width)
                * u64::from(extent.height)
                * pixel_bytes
                * u64::from(drawing.passes()),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            color,
            pass_colors,
            color_samples,
            depth,
            readback,
        })
    }
}
