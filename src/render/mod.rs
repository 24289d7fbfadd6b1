//! The viewer's renderer: three views of one animated character that differ only in how a change
//! of level of detail is shown (popping, alpha-blending, geomorphing).
//!
//! The pure parts — [`layout`] of the views, the orbit [`camera`], the LOD [`schedule`] with its
//! hysteresis and transitions, the per-view draw [`plan`], the GPU-ready [`lod_source`] arrays and
//! the [`uniforms`] that mirror `skin.wgsl` — build and test natively. The wgpu code (`gpu`, behind
//! the `web` feature) only executes the plan: one render pass, one viewport per view, GPU skinning
//! from a texture of joint matrices ([`joint_texture`]; the same on WebGPU and WebGL2, for
//! fairness).

pub mod camera;
pub mod crowd;
pub mod difference;
pub mod flip;
pub mod joint_texture;
pub mod layout;
pub mod lod_source;
pub mod meter;
pub mod mipmap;
pub mod overlay;
pub mod plan;
pub mod pop_spike;
pub mod replay;
pub mod schedule;
pub mod uniforms;
pub mod viewer;

#[cfg(feature = "web")]
pub mod gpu;
