//! Mipmaps of the base-colour textures: how many levels a texture gets, and the WGSL that makes
//! each level from the one above (`mipmap.wgsl`, run by `gpu/mipmaps.rs`; validated by
//! `tests/shaders.rs`).
//!
//! Without mipmaps a texture seen from afar is point-sampled across many texels per pixel: its
//! stripes alias and shimmer as the character moves, which in a viewer made to spot popping looks
//! like popping. Levels halve each side (rounding down, at least 1 texel) down to 1×1, as WebGPU
//! and OpenGL define them.

/// The mipmap shader: `vs_mip` and `fs_mip`.
pub const MIPMAP_WGSL: &str = include_str!(concat!(env!("OUT_DIR"), "/mipmap.wgsl"));

/// Number of mip levels of a `width` × `height` texture, down to 1×1: `⌊log₂ max(w, h)⌋ + 1`
/// (1 for a 1×1 or empty texture).
pub fn mip_level_count(width: u32, height: u32) -> u32 {
    u32::BITS - width.max(height).max(1).leading_zeros()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_go_down_to_one_texel() {
        assert_eq!(mip_level_count(0, 0), 1);
        assert_eq!(mip_level_count(1, 1), 1);
        assert_eq!(mip_level_count(2, 1), 2);
        assert_eq!(mip_level_count(3, 3), 2);
        assert_eq!(mip_level_count(256, 256), 9);
        assert_eq!(mip_level_count(1000, 600), 10);
        assert_eq!(mip_level_count(1, 4096), 13);
    }
}
