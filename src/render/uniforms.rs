//! `#[repr(C)]` mirrors of the uniform structs of `skin.wgsl`, byte for byte (std140-compatible
//! layouts: every field 4 or 16 bytes, explicit padding). `tests/shaders.rs` checks each size
//! against naga's layouter, so a field added on one side only fails a test instead of drawing
//! garbage. Matrices are column-major, as glam and WGSL store them.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

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

impl CameraRaw {
    /// A camera at `eye` looking towards `target` (both in model space), with the viewer's
    /// lights: the key light above-right of the camera, so that the lit side faces the reader
    /// whatever the yaw, and a sky-and-ground hemisphere; colours linear, the shader not encoding
    /// sRGB (the renderer sets `encode_srgb` for its target). An `eye` at `target` looks down −z.
    pub fn lit(clip_from_model: Mat4, eye: Vec3, target: Vec3) -> CameraRaw {
        let forward = (target - eye).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let light = (-forward + 0.9 * Vec3::Y + 0.5 * right).normalize();
        CameraRaw {
            clip_from_model: clip_from_model.to_cols_array_2d(),
            eye_model: eye.extend(1.0).to_array(),
            light_dir: light.extend(0.85).to_array(),
            sky_color: [0.40, 0.44, 0.52, 1.0],
            ground_color: [0.14, 0.12, 0.10, 1.0],
            up: [0.0, 1.0, 0.0, 0.0],
            encode_srgb: 0,
            _pad: [0; 3],
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_key_light_is_above_right_of_the_camera_whatever_the_yaw() {
        for yaw in (0..8).map(|k| k as f32 * std::f32::consts::FRAC_PI_4) {
            let eye = Vec3::new(3.0 * yaw.sin(), 1.0, 3.0 * yaw.cos());
            let target = Vec3::new(0.0, 1.0, 0.0);
            let camera = CameraRaw::lit(Mat4::IDENTITY, eye, target);
            let light = Vec3::from_slice(&camera.light_dir[..3]);
            let forward = (target - eye).normalize();
            let right = forward.cross(Vec3::Y).normalize();
            assert!((light.length() - 1.0).abs() < 1e-6, "yaw {yaw}: a unit direction");
            assert!(light.dot(-forward) > 0.5, "yaw {yaw}: from the camera's side");
            assert!(light.y > 0.4 && light.dot(right) > 0.2, "yaw {yaw}: above and to the right");
            assert_eq!(camera.eye_model, [eye.x, eye.y, eye.z, 1.0]);
        }
        // Looking straight down, or with the eye at the target: still a light, no NaN.
        for (eye, target) in [(Vec3::Y, Vec3::ZERO), (Vec3::ONE, Vec3::ONE)] {
            let camera = CameraRaw::lit(Mat4::IDENTITY, eye, target);
            assert!(camera.light_dir.iter().all(|x| x.is_finite()), "{eye} → {target}");
        }
    }
}
