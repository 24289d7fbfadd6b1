//! The difference overlay's shader and its uniform mirror (`difference.wgsl`, run by
//! `gpu/difference.rs`; validated by `tests/shaders.rs`): each view tinted where it differs from
//! the full-detail reference, from the live meter's pictures of the same frame.

use bytemuck::{Pod, Zeroable};

/// The difference overlay shader: `vs_difference` and `fs_difference`.
pub const DIFFERENCE_WGSL: &str = include_str!(concat!(env!("OUT_DIR"), "/difference.wgsl"));

/// `Area` in `difference.wgsl`: the view's rectangle in its target's pixels.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct AreaRaw {
    pub origin: [f32; 2],
    pub size: [f32; 2],
}
