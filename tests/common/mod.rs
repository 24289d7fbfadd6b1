//! Shared helpers for the integration tests: access to the third-party models in
//! `../shared/models/` (never copied into this repository), natively through `std::fs` and under
//! `wasm-pack test --node` through node's `fs` module.
#![allow(dead_code)]

pub mod chain;

/// Path of a shared model, relative to the crate root.
pub fn model_path(name: &str) -> String {
    format!("{}/../shared/models/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The bytes of `../shared/models/<name>`, or `None` (after printing why) when the file is
/// missing.
///
/// # Panics
/// When the file is missing and the environment variable `CI` is `true`: on CI the models must be
/// there, so a missing one fails the test instead of silently skipping it.
pub fn model_bytes(name: &str) -> Option<Vec<u8>> {
    let path = model_path(name);
    match read_file(&path) {
        Some(bytes) => Some(bytes),
        None if is_ci() => panic!("model {path} is missing and CI=true"),
        None => {
            println!("skipping: model {path} is missing (set CI=true to make this an error)");
            None
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn read_file(path: &str) -> Option<Vec<u8>> {
    std::fs::read(path).ok()
}

#[cfg(not(target_arch = "wasm32"))]
fn is_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

#[cfg(target_arch = "wasm32")]
fn read_file(path: &str) -> Option<Vec<u8>> {
    use wasm_bindgen::JsValue;
    let read = js_sys::Function::new_with_args("p", "return process.getBuiltinModule('fs').readFileSync(p)");
    let bytes = read.call1(&JsValue::NULL, &JsValue::from_str(path)).ok()?;
    Some(js_sys::Uint8Array::new(&bytes).to_vec())
}

#[cfg(target_arch = "wasm32")]
fn is_ci() -> bool {
    use wasm_bindgen::JsValue;
    let get = js_sys::Function::new_no_args("return process.env.CI === 'true'");
    get.call0(&JsValue::NULL).ok().and_then(|v| v.as_bool()).unwrap_or(false)
}

/// The seeded generator the tests use (splitmix64, shared with the metrics).
#[allow(unused_imports)]
pub use clod_viewer::metrics::SplitMix64 as SplitMix;

/// Splits a GLB into its JSON (as a value) and binary chunk, by hand.
pub fn split_glb(bytes: &[u8]) -> (serde_json::Value, Vec<u8>) {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = u32::from_le_bytes(bytes[bin_at..bin_at + 4].try_into().unwrap()) as usize;
    (json, bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec())
}

/// A tiny skinned triangle as glTF JSON plus its binary buffer, for tests that edit one thing and
/// check the importer's answer. Two joints: `root` at the origin and `tip` at (0, 1, 0) below it;
/// node `tri` carries the mesh and the skin. One clip moves `tip` from (0, 1, 0) to (1, 1, 0).
pub struct TinyModel {
    pub json: serde_json::Value,
    pub bin: Vec<u8>,
}

/// Byte offsets of the buffer views of [`TinyModel`].
pub mod tiny {
    /// 3 × vec3<f32>: (0,0,0), (1,0,0), (0,1,0).
    pub const POSITIONS: usize = 0;
    /// 3 × u16: 0, 1, 2 (then 2 bytes of padding).
    pub const INDICES: usize = 36;
    /// 3 × vec4<u8>.
    pub const JOINTS: usize = 44;
    /// 3 × vec4<f32>.
    pub const WEIGHTS: usize = 56;
    /// 2 × mat4<f32>.
    pub const INVERSE_BINDS: usize = 104;
    /// 2 × f32 key times.
    pub const TIMES: usize = 232;
    /// 2 × vec3<f32> translations.
    pub const TRANSLATIONS: usize = 240;
    pub const LEN: usize = 264;
}

fn put_f32s(bin: &mut [u8], at: usize, values: &[f32]) {
    for (k, v) in values.iter().enumerate() {
        bin[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
    }
}

impl TinyModel {
    pub fn new() -> Self {
        let mut bin = vec![0u8; tiny::LEN];
        put_f32s(&mut bin, tiny::POSITIONS, &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        for (k, i) in [0u16, 1, 2].iter().enumerate() {
            bin[tiny::INDICES + 2 * k..tiny::INDICES + 2 * k + 2].copy_from_slice(&i.to_le_bytes());
        }
        bin[tiny::JOINTS..tiny::JOINTS + 12].copy_from_slice(&[0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0]);
        put_f32s(&mut bin, tiny::WEIGHTS, &[1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        let identity = glam::Mat4::IDENTITY.to_cols_array();
        let tip_from_bind = glam::Mat4::from_translation(glam::Vec3::new(0.0, -1.0, 0.0)).to_cols_array();
        put_f32s(&mut bin, tiny::INVERSE_BINDS, &identity);
        put_f32s(&mut bin, tiny::INVERSE_BINDS + 64, &tip_from_bind);
        put_f32s(&mut bin, tiny::TIMES, &[0.0, 1.0]);
        put_f32s(&mut bin, tiny::TRANSLATIONS, &[0.0, 1.0, 0.0, 1.0, 1.0, 0.0]);
        let json = r#"{
          "asset": {"version": "2.0"},
          "scene": 0,
          "scenes": [{"nodes": [0, 2]}],
          "nodes": [
            {"name": "root", "children": [1]},
            {"name": "tip", "translation": [0, 1, 0]},
            {"name": "tri", "mesh": 0, "skin": 0}
          ],
          "meshes": [{"name": "tri", "primitives": [{
            "attributes": {"POSITION": 0, "JOINTS_0": 2, "WEIGHTS_0": 3}, "indices": 1
          }]}],
          "skins": [{"joints": [0, 1], "inverseBindMatrices": 4}],
          "animations": [{"channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
                          "samplers": [{"input": 5, "output": 6}]}],
          "buffers": [{"byteLength": 264}],
          "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6},
            {"buffer": 0, "byteOffset": 44, "byteLength": 12},
            {"buffer": 0, "byteOffset": 56, "byteLength": 48},
            {"buffer": 0, "byteOffset": 104, "byteLength": 128},
            {"buffer": 0, "byteOffset": 232, "byteLength": 8},
            {"buffer": 0, "byteOffset": 240, "byteLength": 24}
          ],
          "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5121, "count": 3, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4"},
            {"bufferView": 5, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
            {"bufferView": 6, "componentType": 5126, "count": 2, "type": "VEC3"}
          ]
        }"#;
        Self { json: serde_json::from_str(json).unwrap(), bin }
    }

    /// Overwrites `values.len()` floats at byte `at` of the buffer.
    pub fn put_f32s(&mut self, at: usize, values: &[f32]) {
        put_f32s(&mut self.bin, at, values);
    }

    /// `.gltf` JSON with the buffer embedded as a base64 data URI.
    pub fn gltf(&self) -> Vec<u8> {
        use base64::Engine;
        let mut json = self.json.clone();
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        json["buffers"][0]["uri"] = serde_json::Value::from(uri);
        serde_json::to_vec(&json).unwrap()
    }

    /// `.glb` bytes: the JSON chunk and the buffer as binary chunk.
    pub fn glb(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.json).unwrap();
        json.resize(json.len().next_multiple_of(4), b' ');
        let mut bin = self.bin.clone();
        bin.resize(bin.len().next_multiple_of(4), 0);
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }
}

impl Default for TinyModel {
    fn default() -> Self {
        Self::new()
    }
}
