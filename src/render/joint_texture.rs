//! The frame's joint matrices as a texture: `model_from_bind` of every skin joint, four
//! `rgba32float` texels per column-major matrix, [`JOINTS_PER_ROW`] joints to a row.
//!
//! A texture rather than a uniform block (16 KiB in WebGL2: 256 matrices) or a storage buffer
//! (none in WebGL2 vertex shaders), so a character of any joint count the importer takes draws on
//! both backends alike; `skin.wgsl`'s `joint_matrix` reads joint `k` at texel
//! `(4 · (k mod per_row) + column, k / per_row)`, where `per_row` is the texture's width over 4.
//! Crowd mode keeps its own pose palette (`crowd::palette`).

use glam::Mat4;

/// Joints per texture row: 2,048 texels, WebGL2's smallest guaranteed texture width.
pub const JOINTS_PER_ROW: usize = 512;

/// Width and height in texels of the joint texture of `joints` joints (at least one joint's worth:
/// a texture cannot be empty). Joint `k` sits at `(4 · (k mod w / 4), k / (w / 4))`.
pub fn joint_texture_size(joints: usize) -> (u32, u32) {
    let per_row = joints.clamp(1, JOINTS_PER_ROW);
    ((4 * per_row) as u32, joints.max(1).div_ceil(per_row) as u32)
}

/// The texels of `skin` (one `model_from_bind` per joint) laid out for a joint texture of
/// `joints` joints: matrices past `skin`'s end, and the padding of the last row, are zero.
pub fn joint_texels(skin: &[Mat4], joints: usize) -> Vec<[f32; 4]> {
    let (width, height) = joint_texture_size(joints);
    let mut texels = vec![[0.0; 4]; width as usize * height as usize];
    for (slot, m) in texels.chunks_exact_mut(4).zip(skin.iter().take(joints)) {
        slot.copy_from_slice(&m.to_cols_array_2d());
    }
    texels
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn joints_fill_rows_of_512_and_the_shader_finds_each_one() {
        assert_eq!(joint_texture_size(0), (4, 1));
        assert_eq!(joint_texture_size(19), (76, 1));
        assert_eq!(joint_texture_size(512), (2048, 1));
        assert_eq!(joint_texture_size(513), (2048, 2));
        assert_eq!(joint_texture_size(65_536), (2048, 128));
        let joints = 700;
        let skin: Vec<Mat4> = (0..joints).map(|k| Mat4::from_translation(Vec3::splat(k as f32))).collect();
        let texels = joint_texels(&skin, joints);
        let (width, height) = joint_texture_size(joints);
        assert_eq!(texels.len(), (width * height) as usize);
        // What `joint_matrix` in skin.wgsl reads for joint k: four texels from (4 · (k mod
        // per_row), k / per_row).
        let per_row = width as usize / 4;
        for k in [0, 1, 511, 512, 699] {
            let at = (k / per_row) * width as usize + 4 * (k % per_row);
            let m = Mat4::from_cols_array_2d(&[texels[at], texels[at + 1], texels[at + 2], texels[at + 3]]);
            assert_eq!(m, skin[k], "joint {k}");
        }
        // The last row's padding is zero.
        assert!(texels[4 * joints..].iter().all(|t| *t == [0.0; 4]));
    }
}
