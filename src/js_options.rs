//! One reader for the options objects JavaScript passes in (`setState`, `measurePopSpike`, the
//! viewer's `create` options): keys checked against the call's list, values against their range
//! or names, and every message naming the call and the key, e.g.
//! `setState: zone must be a number in [0, 1], got 2`.

use wasm_bindgen::{JsCast, JsValue};

/// `obj[key]`, when `obj` is an object and the value is neither `undefined` nor `null`.
pub fn get(obj: &JsValue, key: &str) -> Option<JsValue> {
    if !obj.is_object() {
        return None;
    }
    let value = js_sys::Reflect::get(obj, &key.into()).ok()?;
    (!value.is_undefined() && !value.is_null()).then_some(value)
}

/// A Rust resolver over a JS `resolve(name) → Uint8Array | ArrayBuffer | null` (none when
/// `resolve` is `None`), asking it for a URI's path and then for its last segment
/// ([`crate::import::by_path_or_name`]): a `.gltf`'s files dropped with it are found by name.
pub fn resolver(resolve: Option<&js_sys::Function>) -> impl FnMut(&str) -> Option<Vec<u8>> + '_ {
    crate::import::by_path_or_name(move |name: &str| {
        let value = resolve?.call1(&JsValue::NULL, &JsValue::from_str(name)).ok()?;
        let bytes =
            value.is_instance_of::<js_sys::Uint8Array>() || value.is_instance_of::<js_sys::ArrayBuffer>();
        bytes.then(|| js_sys::Uint8Array::new(&value).to_vec())
    })
}

/// `obj[key]` as a string, when it is one.
pub fn get_string(obj: &JsValue, key: &str) -> Option<String> {
    get(obj, key)?.as_string()
}

/// The `(key, value)` pairs of an options object, in its own order.
///
/// # Errors
/// When `obj` is not an object (`example` shows one), or has a key not in `known`.
pub fn entries(
    obj: &JsValue,
    call: &str,
    known: &[&str],
    example: &str,
) -> Result<Vec<(String, Value)>, String> {
    if !obj.is_object() {
        return Err(format!("{call} takes an object, e.g. {example}"));
    }
    let keys = js_sys::Object::keys(obj.unchecked_ref::<js_sys::Object>());
    keys.iter()
        .map(|key| {
            let key = key.as_string().unwrap_or_default();
            if !known.contains(&key.as_str()) {
                return Err(format!("{call}: unknown option {key:?}; known: {}", known.join(", ")));
            }
            let value = js_sys::Reflect::get(obj, &key.as_str().into()).unwrap_or(JsValue::UNDEFINED);
            Ok((key.clone(), Value { call: call.to_string(), key, value }))
        })
        .collect()
}

/// One option's value, with what it needs to say what is wrong with it.
pub struct Value {
    call: String,
    key: String,
    pub value: JsValue,
}

impl Value {
    fn wrong(&self, expected: &str) -> String {
        format!("{}: {} must be {expected}, got {:?}", self.call, self.key, self.value)
    }

    /// A finite number in `[lo, hi]`.
    pub fn number(&self, lo: f64, hi: f64) -> Result<f64, String> {
        match self.value.as_f64() {
            Some(x) if x.is_finite() && (lo..=hi).contains(&x) => Ok(x),
            _ => Err(self.wrong(&format!("a number in [{lo}, {hi}]"))),
        }
    }

    /// `true` or `false`.
    pub fn boolean(&self) -> Result<bool, String> {
        self.value.as_bool().ok_or_else(|| self.wrong("true or false"))
    }

    /// A string.
    pub fn text(&self) -> Result<String, String> {
        self.value.as_string().ok_or_else(|| self.wrong("a string"))
    }

    /// One of `names`, turned into its value by `of`.
    pub fn choice<T>(&self, names: &[&str], of: impl Fn(&str) -> Option<T>) -> Result<T, String> {
        let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
        self.value
            .as_string()
            .and_then(|name| of(&name))
            .ok_or_else(|| self.wrong(&format!("one of {}", quoted.join(", "))))
    }

    /// `null`.
    pub fn is_null(&self) -> bool {
        self.value.is_null()
    }

    /// The problem with this value, in the reader's words.
    pub fn error(&self, expected: &str) -> String {
        self.wrong(expected)
    }
}
