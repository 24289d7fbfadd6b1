//! `#[repr(C)]` mirrors of the uniform structs of `skin.wgsl`, byte for byte (std140-compatible
//! layouts: every field 4 or 16 bytes, explicit padding). `tests/shaders.rs` checks each size
//! against naga's layouter, so a field added on one side only fails a test instead of drawing
//! garbage. Matrices are column-major, as glam and WGSL store them.

use bytemuck::{Pod, Zeroable};

pub use crate::morph::MAX_MORPH_TARGETS;

/// The skinning shader (`skin.wgsl` without its comments, see `build.rs`), validated by
/// `tests/shaders.rs`.
pub const SKIN_WGSL: &str = include_str!(concat!(env!("OUT_DIR"), "/skin.wgsl"));

/// The crowd's shader: `skin.wgsl` with `crowd.wgsl`'s instanced entry points appended (they
/// share its bindings, vertex layouts and fragment shading); validated by `tests/shaders.rs`.
pub const CROWD_WGSL: &str = concat!(
    include_str!(concat!(env!("OUT_DIR"), "/skin.wgsl")),
    include_str!(concat!(env!("OUT_DIR"), "/crowd.wgsl"))
);

/// `Camera` in `skin.wgsl`: one per frame, shared by the three views.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CameraRaw {
    pub clip_from_model: [[f32; 4]; 4],
    pub eye_model: [f32; 4],
    /// xyz: unit direction towards the light (model space); w: intensity.
    pub light_dir: [f32; 4],
    pub sky_color: [f32; 4],
    pub ground_color: [f32; 4],
    pub up: [f32; 4],
    /// 1 when the colour target is not an sRGB format and the shader must encode.
    pub encode_srgb: u32,
    pub _pad: [u32; 3],
}

/// `MorphWeights` in `skin.wgsl`: the frame's morph-target weights, target `t` at
/// `weights[t / 4][t % 4]`, unused targets zero.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MorphWeightsRaw {
    pub weights: [[f32; 4]; MAX_MORPH_TARGETS / 4],
}

impl MorphWeightsRaw {
    /// The weights packed four to a vector; targets past [`MAX_MORPH_TARGETS`] are dropped (the
    /// importer allows no more).
    pub fn new(weights: &[f32]) -> Self {
        let mut raw = Self::zeroed();
        for (t, &w) in weights.iter().enumerate().take(MAX_MORPH_TARGETS) {
            raw.weights[t / 4][t % 4] = if w.is_finite() { w } else { 0.0 };
        }
        raw
    }
}

/// `Material` in `skin.wgsl`: one per glTF material (and one for the default material).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MaterialRaw {
    /// Linear RGBA.
    pub base_color_factor: [f32; 4],
    pub alpha_cutoff: f32,
    pub double_sided: u32,
    pub _pad: [u32; 2],
}

/// `Draw` in `skin.wgsl`: one per draw call, at a dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DrawRaw {
    pub morph_t: f32,
    pub opacity: f32,
    /// 0 none, 1 keep pixels below the threshold, 2 keep the others.
    pub dither_mode: u32,
    pub _pad0: u32,
    pub dither_threshold: f32,
    pub _pad1: f32,
    pub viewport_origin: [f32; 2],
    /// Level overlay: linear RGB and the share of the surface colour it replaces (0: none).
    pub tint: [f32; 4],
}

/// The WGSL struct name each mirror stands for, with the mirror's size: what `tests/shaders.rs`
/// compares against naga's layout.
pub const MIRRORS: [(&str, usize); 4] = [
    ("Camera", std::mem::size_of::<CameraRaw>()),
    ("MorphWeights", std::mem::size_of::<MorphWeightsRaw>()),
    ("Material", std::mem::size_of::<MaterialRaw>()),
    ("Draw", std::mem::size_of::<DrawRaw>()),
];
