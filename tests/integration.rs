//! The integration tests as one test binary, natively and under `wasm-pack test --node`: each
//! file under `tests/` is a module of it (`tests/simplify/` one with a submodule), and `common`
//! and `meshgen` are shared by them. One binary links the library once: as 22 binaries the tests
//! linked it 22 times (about 24 MB each natively and 20 MB of wasm each, every one of those also
//! bound by wasm-bindgen before node ran it). Run one file's tests with its module's name:
//! `cargo test --test integration clod::`.

mod common;
mod meshgen;

mod animation;
mod bind_units;
mod builtin_character;
mod clod;
mod clod_bytes;
mod flat_shading;
mod flip;
mod generated_kinds;
mod import_bad_input;
mod import_extensions;
mod import_fuzz;
mod import_models;
mod many_joints;
mod morph;
mod progressive;
mod render_levels;
mod shaders;
#[path = "simplify/main.rs"]
mod simplify;
mod test_characters;
