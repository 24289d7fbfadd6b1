//! Morph targets on the GPU: every morph delta of the drawn source in one `rgba32float` texture
//! ([`MORPH_TEXTURE_WIDTH`] texels wide, two texels per `(vertex, target)` entry, see
//! [`LodSource::morph_texels`]) and the frame's weights in a uniform block, both in the frame bind
//! group, read by `skin.wgsl`'s `morphed` before skinning at both ends of a geomorph. A texture
//! rather than a storage buffer: WebGL2 has no storage buffers in vertex shaders, and one path on
//! both backends keeps the comparison fair.

use super::{resources, Renderer};
use crate::render::lod_source::{LodSource, MORPH_TEXTURE_WIDTH};

/// The morph-delta texture of `texels` (a 1 × 1 zero texel when there are none, or when they need
/// more rows than the device's largest texture: then `dropped` is true and the views draw the
/// base shape).
pub(super) struct MorphTexture {
    pub(super) view: wgpu::TextureView,
    pub(super) dropped: bool,
}

pub(super) fn morph_texture(device: &wgpu::Device, queue: &wgpu::Queue, texels: &[[f32; 4]]) -> MorphTexture {
    let max_rows = device.limits().max_texture_dimension_2d as usize;
    let rows = texels.len().div_ceil(MORPH_TEXTURE_WIDTH as usize);
    let dropped = rows > max_rows;
    let (width, height, data) = if texels.is_empty() || dropped {
        (1, 1, vec![[0.0f32; 4]])
    } else {
        let mut data = texels.to_vec();
        data.resize(rows * MORPH_TEXTURE_WIDTH as usize, [0.0; 4]);
        (MORPH_TEXTURE_WIDTH, rows as u32, data)
    };
    MorphTexture {
        view: resources::float_texture(device, queue, "morph deltas", width, height, &data),
        dropped,
    }
}

/// The frame bind group: camera, joint matrices, morph weights and morph deltas.
pub(super) fn frame_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    camera: &wgpu::Buffer,
    joints: &wgpu::TextureView,
    morph_weights: &wgpu::Buffer,
    morph: &MorphTexture,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(joints) },
            wgpu::BindGroupEntry { binding: 2, resource: morph_weights.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&morph.view) },
        ],
    })
}

impl Renderer {
    /// Whether the source's morph deltas did not fit the device's largest texture (the views then
    /// draw the base shape; the page says so).
    pub fn morphs_dropped(&self) -> bool {
        self.uniforms.morphs_dropped
    }

    /// Uploads `lod`'s morph deltas and binds them (after the levels change).
    pub(super) fn set_morph_deltas(&mut self, lod: &LodSource) {
        let morph = morph_texture(&self.device, &self.queue, &lod.morph_texels);
        self.uniforms.morphs_dropped = morph.dropped;
        self.uniforms.frame_group = frame_group(
            &self.device,
            &self.layouts.frame,
            &self.uniforms.camera,
            &self.uniforms.joints.view,
            &self.uniforms.morph_weights,
            &morph,
        );
    }
}
