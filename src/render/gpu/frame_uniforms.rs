//! The uniforms every draw of a frame reads, and their bind groups: group 0 holds the camera,
//! the joint texture, the morph weights and the morph deltas' texture; group 2 the per-draw
//! records, one 256-byte slot per draw at a dynamic offset. The skeleton overlay's bone lines are
//! a vertex buffer beside them. [`FrameUniforms::write`] fills the per-frame ones from a
//! [`FrameInput`] before a frame is recorded.

use super::joints::JointTexture;
use super::morph::{frame_group, morph_texture};
use super::pipelines::BindLayouts;
use super::resources::uniform_buffer;
use super::{FrameInput, RenderError, BONE_VERTEX_STRIDE, DRAW_SLOTS, DRAW_STRIDE};
use crate::render::overlay::Overlay;
use crate::render::uniforms::{CameraRaw, DrawRaw, MorphWeightsRaw};

pub(super) struct FrameUniforms {
    pub camera: wgpu::Buffer,
    pub joints: JointTexture,
    /// Points the bone-line buffer holds: two per joint is more than enough, as every bone ends
    /// at a joint and the topmost joint starts none.
    pub bone_vertices: usize,
    /// The skeleton overlay's bone lines, rewritten each frame it is shown.
    pub bones: wgpu::Buffer,
    pub morph_weights: wgpu::Buffer,
    /// Whether the morph deltas were too many for a texture (see
    /// [`super::Renderer::morphs_dropped`]).
    pub morphs_dropped: bool,
    /// The per-draw records, [`DRAW_SLOTS`] slots of [`DRAW_STRIDE`] bytes.
    pub draws: wgpu::Buffer,
    pub frame_group: wgpu::BindGroup,
    pub draw_group: wgpu::BindGroup,
}

impl FrameUniforms {
    /// The buffers and bind groups for a skeleton of `joint_count` joints and the morph deltas
    /// `morph_texels` (see [`crate::render::lod_source::LodSource::morph_texels`]).
    ///
    /// # Errors
    /// [`RenderError::TooManyJoints`] when the joint matrices do not fit the device's largest texture.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &BindLayouts,
        joint_count: usize,
        morph_texels: &[[f32; 4]],
    ) -> Result<FrameUniforms, RenderError> {
        let camera = uniform_buffer(device, "camera", std::mem::size_of::<CameraRaw>() as u64);
        let joints = JointTexture::new(device, joint_count)?;
        let bone_vertices = 2 * joint_count.max(1);
        let draws = uniform_buffer(device, "draws", DRAW_SLOTS * DRAW_STRIDE);
        let bones = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bones"),
            size: bone_vertices as u64 * BONE_VERTEX_STRIDE,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let morph_weights =
            uniform_buffer(device, "morph weights", std::mem::size_of::<MorphWeightsRaw>() as u64);
        let morph_deltas = morph_texture(device, queue, morph_texels);
        let frame_group =
            frame_group(device, &layouts.frame, &camera, &joints.view, &morph_weights, &morph_deltas);
        let draw_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("draw"),
            layout: &layouts.draw,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &draws,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<DrawRaw>() as u64),
                }),
            }],
        });
        Ok(FrameUniforms {
            camera,
            joints,
            bone_vertices,
            bones,
            morph_weights,
            morphs_dropped: morph_deltas.dropped,
            draws,
            frame_group,
            draw_group,
        })
    }

    /// Writes `frame`'s camera (`encode_srgb`: the shader encodes sRGB itself), skin matrices,
    /// morph weights and, with the skeleton overlay, bone lines; returns how many bone points to
    /// draw (0 without the overlay).
    pub fn write(&self, queue: &wgpu::Queue, frame: &FrameInput, encode_srgb: bool) -> u32 {
        let mut camera = frame.camera;
        camera.encode_srgb = u32::from(encode_srgb);
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&camera));
        self.joints.write(queue, frame.skin);
        let weights = match self.morphs_dropped {
            true => MorphWeightsRaw::new(&[]),
            false => MorphWeightsRaw::new(frame.morph_weights),
        };
        queue.write_buffer(&self.morph_weights, 0, bytemuck::bytes_of(&weights));
        if frame.overlay != Overlay::Skeleton {
            return 0;
        }
        // Whole segments only (an even count), at most what the buffer holds.
        let points = &frame.bones[..frame.bones.len().min(self.bone_vertices) & !1];
        if !points.is_empty() {
            queue.write_buffer(&self.bones, 0, bytemuck::cast_slice(points));
        }
        points.len() as u32
    }
}
