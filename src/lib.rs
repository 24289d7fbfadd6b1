//! Articulated progressive meshes for skinned glTF characters, and a browser viewer that compares
//! level-of-detail transitions (popping, alpha-blending, geomorphing) on them.
//!
//! The data path, from a dropped file to a frame (README.md has the same map with the file of
//! each stage):
//!
//! ```text
//! bytes ─ import::from_bytes ─▶ Character (SkinnedMesh, Skeleton, Clips, MorphDeltas)
//!   ─ clod::build ─▶ Clod: poses (multi-pose quadrics) → simplify (collapse log)
//!                    → progressive (ProgressiveMesh) → back-propagation to bind space
//!                    → chain (discrete levels, ancestor tables)
//!   ─ clod::bytes::encode / decode ─▶ (worker → page, IndexedDB cache)
//!   ─ render::lod_source::LodSource::from_clod ─▶ GPU-ready levels ─ render::gpu::Renderer::new
//! per frame: render::viewer::ViewerModel::advance (clocks, camera, schedule::step, plan::plan_view)
//!   ─ Renderer::render ─▶ render/skin.wgsl (morph and skin every view)
//!   ─ the live meter: render::meter::TransitionMeter, difference.wgsl
//! crowd mode, per frame: render::crowd::Crowd::advance (per instance: level, transition, palette row)
//!   ─ crowd.wgsl instanced draws
//! ```
//!
//! The core — [`import`], [`character`], [`mesh`], [`twins`], [`skeleton`], [`animation`],
//! [`morph`], [`skinning`], [`simplify`](mod@simplify), [`progressive`], [`clod`],
//! [`vertex_cache`], [`metrics`] and the pure half of [`render`] (schedule, plan, camera, layout,
//! the viewer's model) — has no GPU and no DOM dependency: it builds and tests natively and on
//! `wasm32-unknown-unknown`. The `js` feature adds the wasm-bindgen API used by the page and by
//! node (`js_api`); the `web` feature adds the wgpu renderer (`render::gpu`) and the page's viewer
//! (`web`).
//!
//! Conventions: right-handed, metres (whatever the file uses), column vectors, matrices named
//! `a_from_b` (they map points of space `b` into space `a`), glTF's parent-first node order.

pub mod animation;
pub mod character;
pub mod clod;
pub mod import;
pub mod mesh;
pub mod metrics;
pub mod morph;
pub mod progressive;
pub mod render;
pub mod simplify;
pub mod skeleton;
pub mod skinning;
pub mod twins;
pub mod vertex_cache;

#[cfg(feature = "js")]
pub mod js_api;
#[cfg(feature = "web")]
pub mod web;

pub use animation::{Clip, Wrap};
pub use character::Character;
pub use import::ImportError;
pub use mesh::SkinnedMesh;
pub use progressive::{PmCursor, ProgressiveMesh};
pub use simplify::{simplify, CollapseMode, Schedule, SimplifyInput, SimplifyOptions};
pub use skeleton::{Pose, Skeleton};
