//! The difference overlay on the GPU: one full-viewport triangle per view, drawn last in the
//! view's pass, reading the live meter's reference and view pictures of the same frame (see
//! `difference.wgsl`). The meter's draws are recorded before the views' for this.

use super::resources::uniform_buffer;
use super::{Renderer, DEPTH_FORMAT, DRAW_STRIDE};
use crate::render::difference::{AreaRaw, DIFFERENCE_WGSL};
use crate::render::layout::Rect;

/// The overlay's pipeline and its per-view uniform slots.
pub(super) struct DifferenceGpu {
    pipeline: wgpu::RenderPipeline,
    areas: wgpu::Buffer,
}

/// One slot per view, at WebGPU's and WebGL2's uniform offset alignment.
const AREA_STRIDE: u64 = DRAW_STRIDE;

impl DifferenceGpu {
    pub(super) fn new(device: &wgpu::Device, color_format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("difference.wgsl"),
            source: wgpu::ShaderSource::Wgsl(DIFFERENCE_WGSL.into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("difference overlay"),
            // The shader's single bind group, derived from it.
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_difference"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            // Over everything in the view, leaving its depth alone.
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: sample_count, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_difference"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: color_format,
                    blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let areas = uniform_buffer(device, "difference areas", 3 * AREA_STRIDE);
        Self { pipeline, areas }
    }
}

impl Renderer {
    /// Draws view `index`'s heat map over what its pass drew: `origin` and `rect` place the view
    /// in the pass's target; `picture` is the meter picture of its plan (0 is the reference).
    pub(super) fn draw_difference(
        &self,
        pass: &mut wgpu::RenderPass,
        index: usize,
        origin: [f32; 2],
        rect: &Rect,
        picture: usize,
    ) {
        let (Some(meter), Some(overlay)) = (self.meter.as_ref(), self.difference.as_ref()) else { return };
        let (Some(reference), Some(shown)) = (meter.picture(0), meter.picture(picture)) else { return };
        let offset = index as u64 * AREA_STRIDE;
        let area = AreaRaw { origin, size: [rect.width as f32, rect.height as f32] };
        self.queue.write_buffer(&overlay.areas, offset, bytemuck::bytes_of(&area));
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("difference"),
            layout: &overlay.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(reference) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(shown) },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &overlay.areas,
                        offset,
                        size: wgpu::BufferSize::new(std::mem::size_of::<AreaRaw>() as u64),
                    }),
                },
            ],
        });
        pass.set_pipeline(&overlay.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
