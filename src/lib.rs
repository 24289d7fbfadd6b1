//! Articulated progressive meshes for skinned glTF characters, and a browser viewer that compares
//! level-of-detail transitions (popping, alpha-blending, geomorphing) on them.
//!
//! The core — [`import`], [`skeleton`], [`animation`], [`morph`], [`skinning`] — has no GPU and no DOM
//! dependency: it builds and tests natively and on `wasm32-unknown-unknown`. The `js` feature adds
//! the wasm-bindgen API used by the page and by node; the `web` feature adds the renderer.
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
pub mod vertex_cache;

#[cfg(feature = "js")]
pub mod js_api;
#[cfg(feature = "js")]
pub mod js_options;
#[cfg(feature = "web")]
pub mod web;

pub use animation::{Clip, Wrap};
pub use character::Character;
pub use import::ImportError;
pub use mesh::SkinnedMesh;
pub use progressive::{PmCursor, ProgressiveMesh};
pub use simplify::{simplify, CollapseMode, Schedule, SimplifyInput, SimplifyOptions};
pub use skeleton::{Pose, Skeleton};
