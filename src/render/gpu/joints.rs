//! The joint matrices' texture (`joint_matrices` in `skin.wgsl`, laid out by
//! [`crate::render::joint_texture`]): made once per character, rewritten every frame.

use glam::Mat4;

use super::{resources, RenderError};
use crate::render::joint_texture::{joint_texels, joint_texture_size, JOINTS_PER_ROW};

pub(super) struct JointTexture {
    texture: wgpu::Texture,
    pub(super) view: wgpu::TextureView,
    /// Joints it holds.
    joints: usize,
}

impl JointTexture {
    /// The texture for `joints` joints.
    ///
    /// # Errors
    /// [`RenderError::TooManyJoints`] when their rows exceed the device's largest texture.
    pub(super) fn new(device: &wgpu::Device, joints: usize) -> Result<Self, RenderError> {
        let (width, height) = joint_texture_size(joints);
        let max = device.limits().max_texture_dimension_2d;
        if width > max || height > max {
            let most = JOINTS_PER_ROW.min(max as usize / 4) * max as usize;
            return Err(RenderError::TooManyJoints(joints, most));
        }
        let texture =
            device.create_texture(&resources::float_texture_descriptor("joint matrices", width, height));
        let view = texture.create_view(&Default::default());
        Ok(Self { texture, view, joints })
    }

    /// Writes `skin` (one `model_from_bind` per joint; missing ones are zero).
    pub(super) fn write(&self, queue: &wgpu::Queue, skin: &[Mat4]) {
        let (width, height) = joint_texture_size(self.joints);
        let texels = joint_texels(skin, self.joints);
        queue.write_texture(
            self.texture.as_image_copy(),
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 16),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
    }
}
