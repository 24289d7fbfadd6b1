//! Fills the mip levels of a base-colour texture on the GPU, each from the one above
//! (`render/mipmap.wgsl`), and reads them back for the page's tests.

use super::readback::read_texture_level;
use super::{RenderError, Renderer};
use crate::render::mipmap::MIPMAP_WGSL;

/// Draws levels `1..` of `texture` (sRGB RGBA8, with `RENDER_ATTACHMENT` and
/// `TEXTURE_BINDING`), each as the box-filtered level above it; level 0 must already hold the
/// image. One submission; a texture with one level is left alone.
pub(super) fn generate_mipmaps(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) {
    let levels = texture.mip_level_count();
    if levels < 2 {
        return;
    }
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("mipmap.wgsl"),
        source: wgpu::ShaderSource::Wgsl(MIPMAP_WGSL.into()),
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("vs_mip fs_mip"),
        // The shader's single bind group, derived from it.
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_mip"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_mip"),
            compilation_options: Default::default(),
            targets: &[Some(texture.format().into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("mipmap source"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    let level_view = |level: u32| {
        texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("mip level"),
            base_mip_level: level,
            mip_level_count: Some(1),
            ..Default::default()
        })
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    for level in 1..levels {
        let (source, target) = (level_view(level - 1), level_view(level));
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("mip source"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&source) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("mip level"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target,
                depth_slice: None,
                resolve_target: None,
                // The triangle covers every texel.
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    queue.submit([encoder.finish()]);
}

/// One mip level of a texture read back: its size and mean colour in linear light (RGBA, 0–1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureLevel {
    pub width: u32,
    pub height: u32,
    pub mean_linear: [f32; 4],
}

impl Renderer {
    /// Reads back every mip level of material `material`'s base-colour texture; empty when the
    /// material has no texture (or does not exist). A box filter keeps the mean of a
    /// power-of-two texture, so every level's mean matches level 0's up to rounding.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU cannot map a copy.
    pub async fn texture_levels(&self, material: usize) -> Result<Vec<TextureLevel>, RenderError> {
        let Some(texture) = self.meshes.materials.get(material).and_then(|m| m.texture.as_ref()) else {
            return Ok(Vec::new());
        };
        let mut levels = Vec::new();
        for level in 0..texture.mip_level_count() {
            let size = texture.size().mip_level_size(level, wgpu::TextureDimension::D2);
            let texels = read_texture_level(&self.device, &self.queue, texture, level, None).await?;
            let mut sum = [0f64; 4];
            for texel in texels.chunks_exact(4) {
                for (k, &byte) in texel.iter().enumerate() {
                    let c = f64::from(byte) / 255.0;
                    sum[k] += if k == 3 { c } else { srgb_to_linear(c) };
                }
            }
            let count = f64::from(size.width * size.height);
            levels.push(TextureLevel {
                width: size.width,
                height: size.height,
                mean_linear: sum.map(|s| (s / count) as f32),
            });
        }
        Ok(levels)
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1).
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
