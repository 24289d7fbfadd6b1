//! Shared helpers for the integration tests: access to the third-party models in
//! `../shared/models/` (never copied into this repository), natively through `std::fs` and under
//! `wasm-pack test --node` through node's `fs` module.
#![allow(dead_code)]

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

/// A tiny deterministic generator (splitmix64) for seeded test inputs.
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}
