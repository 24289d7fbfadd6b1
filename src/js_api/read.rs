//! How the options objects JavaScript passes in are read: with serde, into the Rust types of
//! [`super::build_options`] and [`super::viewer_settings`], whose fields are the leaf types here.
//! Each leaf accepts one kind of JavaScript value and, for any other, says what it accepts
//! (`must be a number, got "fast"`); [`read`] runs a whole object through serde while keeping the
//! key's path, so every message names the call and the key:
//! `setState: zone must be a number, got "x"`, `buildClod: levels[1] must be a whole number of
//! triangles ≥ 1, got 1.5`. A key the type does not have is an error too, listing the keys it
//! has (`deny_unknown_fields` under serde_json; serde-wasm-bindgen looks up a struct's own fields
//! only, so [`read`] first compares the object's keys with [`field_names`]).
//!
//! The leaves read values with `deserialize_any`, so the value itself, whatever its kind, reaches
//! the visitor and can be quoted; ranges that depend on more than the value (a clip that must
//! exist, a level below the count) are checked where the object becomes the core's settings.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Serialize, Serializer};

/// Names a value of `T` goes by in JavaScript (methods, variants, modes, …), in the order the
/// messages list them.
pub trait Names: Sized + Copy + 'static {
    /// Every name, in order.
    const NAMES: &'static [&'static str];
    /// The value of a name.
    fn named(name: &str) -> Option<Self>;
    /// The name of a value.
    fn name(self) -> &'static str;
}

/// The value of one of `T`'s names; written back as that name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneOf<T>(pub T);

/// Any number (integers too; `NaN` is not one). Ranges are checked by the reader of the field,
/// with [`Number::within`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Number(pub f64);

/// `true` or `false`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Flag(pub bool);

/// A string.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Text(pub String);

/// An array whose every item is a `T`.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct List<T>(pub Vec<T>);

/// What one leaf type accepts, in the words of a message ("a number").
pub trait Accepts {
    /// E.g. `a number`.
    fn accepts() -> String;
}

impl Accepts for Number {
    fn accepts() -> String {
        "a number".into()
    }
}

impl Accepts for Flag {
    fn accepts() -> String {
        "true or false".into()
    }
}

impl Accepts for Text {
    fn accepts() -> String {
        "a string".into()
    }
}

impl<T: Names> Accepts for OneOf<T> {
    fn accepts() -> String {
        let quoted: Vec<String> = T::NAMES.iter().map(|n| format!("{n:?}")).collect();
        format!("one of {}", quoted.join(", "))
    }
}

impl<T: Accepts> Accepts for List<T> {
    fn accepts() -> String {
        format!("an array, each item {}", T::accepts())
    }
}

impl Number {
    /// The number when it lies in `[lo, hi]` (finite), else what `key` of `call` accepts.
    pub fn within(self, call: &str, key: &str, lo: f64, hi: f64) -> Result<f64, String> {
        let x = self.0;
        if x.is_finite() && (lo..=hi).contains(&x) {
            Ok(x)
        } else {
            Err(format!("{call}: {key} must be a number in [{lo}, {hi}], got {}", js_number(x)))
        }
    }
}

/// A number as JavaScript writes it (`2`, `0.5`, `Infinity`, `NaN`).
pub fn js_number(x: f64) -> String {
    match x {
        x if x.is_nan() => "NaN".into(),
        x if x.is_infinite() => if x > 0.0 { "Infinity" } else { "-Infinity" }.into(),
        x => format!("{x}"),
    }
}

/// A leaf's visitor: every kind of value reaches it; [`Take::take`] keeps the ones the leaf
/// accepts. A leaf type's `Deserialize` is `d.deserialize_any(Leaf::new())`.
pub struct Leaf<T>(PhantomData<T>);

impl<T> Leaf<T> {
    pub fn new() -> Self {
        Leaf(PhantomData)
    }
}

impl<T> Default for Leaf<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// The value a leaf was given, as a message quotes it.
pub enum Got<'a> {
    Number(f64),
    Bool(bool),
    Str(&'a str),
    Null,
    Array,
    Object,
}

impl fmt::Display for Got<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Got::Number(x) => f.write_str(&js_number(*x)),
            Got::Bool(b) => write!(f, "{b}"),
            Got::Str(s) => write!(f, "{s:?}"),
            Got::Null => f.write_str("null"),
            Got::Array => f.write_str("an array"),
            Got::Object => f.write_str("an object"),
        }
    }
}

/// Turns one given value into a leaf (`None`: the message says what the leaf accepts).
pub trait Take: Accepts + Sized {
    fn take(got: &Got<'_>) -> Option<Self>;
}

fn refuse<T: Accepts, E: de::Error>(got: &Got<'_>) -> E {
    E::custom(format_args!("must be {}, got {got}", T::accepts()))
}

impl<'de, T: Take> Visitor<'de> for Leaf<T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&T::accepts())
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<T, E> {
        let got = Got::Number(v);
        T::take(&got).ok_or_else(|| refuse::<T, E>(&got))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<T, E> {
        self.visit_f64(v as f64)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<T, E> {
        self.visit_f64(v as f64)
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<T, E> {
        let got = Got::Bool(v);
        T::take(&got).ok_or_else(|| refuse::<T, E>(&got))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<T, E> {
        let got = Got::Str(v);
        T::take(&got).ok_or_else(|| refuse::<T, E>(&got))
    }

    fn visit_unit<E: de::Error>(self) -> Result<T, E> {
        Err(refuse::<T, E>(&Got::Null))
    }

    fn visit_none<E: de::Error>(self) -> Result<T, E> {
        Err(refuse::<T, E>(&Got::Null))
    }

    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        d.deserialize_any(self)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, _: A) -> Result<T, A::Error> {
        Err(refuse::<T, A::Error>(&Got::Array))
    }

    fn visit_map<A: MapAccess<'de>>(self, _: A) -> Result<T, A::Error> {
        Err(refuse::<T, A::Error>(&Got::Object))
    }
}

impl Take for Number {
    fn take(got: &Got<'_>) -> Option<Self> {
        match *got {
            Got::Number(x) if !x.is_nan() => Some(Number(x)),
            _ => None,
        }
    }
}

impl Take for Flag {
    fn take(got: &Got<'_>) -> Option<Self> {
        match *got {
            Got::Bool(b) => Some(Flag(b)),
            _ => None,
        }
    }
}

impl Take for Text {
    fn take(got: &Got<'_>) -> Option<Self> {
        match *got {
            Got::Str(s) => Some(Text(s.to_owned())),
            _ => None,
        }
    }
}

impl<T: Names> Take for OneOf<T> {
    fn take(got: &Got<'_>) -> Option<Self> {
        match *got {
            Got::Str(s) => T::named(s).map(OneOf),
            _ => None,
        }
    }
}

macro_rules! leaf {
    ($($t:ty),*) => {$(
        impl<'de> Deserialize<'de> for $t {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                d.deserialize_any(Leaf::<$t>(PhantomData))
            }
        }
    )*};
}
leaf!(Number, Flag, Text);

impl<'de, T: Names> Deserialize<'de> for OneOf<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(Leaf::<OneOf<T>>(PhantomData))
    }
}

impl<T: Names> Serialize for OneOf<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.0.name())
    }
}

/// A list's visitor: an array of items, each read as a `T` (an item's path is `key[i]`).
struct ListVisitor<T>(PhantomData<T>);

impl<'de, T: Deserialize<'de> + Accepts> Visitor<'de> for ListVisitor<T> {
    type Value = List<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&List::<T>::accepts())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<List<T>, A::Error> {
        let mut items = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(List(items))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<List<T>, E> {
        Err(refuse::<List<T>, E>(&Got::Number(v)))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<List<T>, E> {
        self.visit_f64(v as f64)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<List<T>, E> {
        self.visit_f64(v as f64)
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<List<T>, E> {
        Err(refuse::<List<T>, E>(&Got::Bool(v)))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<List<T>, E> {
        Err(refuse::<List<T>, E>(&Got::Str(v)))
    }

    fn visit_unit<E: de::Error>(self) -> Result<List<T>, E> {
        Err(refuse::<List<T>, E>(&Got::Null))
    }

    fn visit_none<E: de::Error>(self) -> Result<List<T>, E> {
        Err(refuse::<List<T>, E>(&Got::Null))
    }

    fn visit_map<A: MapAccess<'de>>(self, _: A) -> Result<List<T>, A::Error> {
        Err(refuse::<List<T>, A::Error>(&Got::Object))
    }
}

impl<'de, T: Deserialize<'de> + Accepts> Deserialize<'de> for List<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ListVisitor(PhantomData))
    }
}

/// For a field where `null` means something (off, the rest pose) and a missing key means
/// "unchanged": `Some(None)` for `null`, `Some(Some(v))` for a value (use with
/// `#[serde(default, deserialize_with = "nullable")]`).
pub fn nullable<'de, D, T>(d: D) -> Result<Option<Option<T>>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    Option::<T>::deserialize(d).map(Some)
}

/// Reads an options object of `call` from a deserializer (serde-wasm-bindgen's in the browser,
/// serde_json's in the native tests, whose messages end with a position in the text), naming the
/// key in any message.
///
/// # Errors
/// `"{call}: {key} must be …, got …"`, or `"{call}: unknown field …, expected one of …"`.
pub fn read_from<'de, D, T>(call: &str, d: D) -> Result<T, String>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    serde_path_to_error::deserialize(d).map_err(|e| {
        let path = e.path().to_string();
        // serde-wasm-bindgen's errors are JavaScript `Error`s, which print as "Error: …".
        let inner = e.inner().to_string();
        let message = inner.strip_prefix("Error: ").unwrap_or(&inner);
        // An unknown key's path is the key itself, which serde's message already quotes.
        if path == "." || path.is_empty() || message.starts_with("unknown field") {
            format!("{call}: {message}")
        } else {
            format!("{call}: {path} {message}")
        }
    })
}

/// Reads an options object of `call` from JavaScript; `example` shows one in the message when
/// `value` is not an object.
///
/// # Errors
/// As [`read_from`], or `"{call} takes an object, e.g. {example}"`.
pub fn read<T: serde::de::DeserializeOwned>(
    call: &str,
    value: wasm_bindgen::JsValue,
    example: &str,
) -> Result<T, String> {
    use wasm_bindgen::JsCast;
    if !value.is_object() || js_sys::Array::is_array(&value) {
        return Err(format!("{call} takes an object, e.g. {example}"));
    }
    // serde-wasm-bindgen reads a struct by looking up its fields, so it never sees another key:
    // those are found here, with serde's words for them.
    let fields = field_names::<T>();
    let object: &js_sys::Object = value.unchecked_ref();
    for key in js_sys::Object::keys(object).iter().filter_map(|k| k.as_string()) {
        if !fields.contains(&key.as_str()) {
            return Err(format!("{call}: {}", unknown_field(&key, fields)));
        }
    }
    read_from(call, serde_wasm_bindgen::Deserializer::from(value))
}

/// serde's message for an unknown key: "unknown field `zoom`, expected one of `a`, `b`".
pub fn unknown_field(key: &str, fields: &'static [&'static str]) -> String {
    <serde::de::value::Error as de::Error>::unknown_field(key, fields).to_string()
}

/// The keys of struct `T` as serde reads them (after renaming), found by asking `T` to read
/// itself from a deserializer that only notes what it is asked for.
pub fn field_names<'de, T: Deserialize<'de>>() -> &'static [&'static str] {
    struct Probe<'a>(&'a mut &'static [&'static str]);
    impl<'de> Deserializer<'de> for Probe<'_> {
        type Error = de::value::Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
            Err(de::Error::custom("not a struct"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Self::Error> {
            *self.0 = fields;
            Err(de::Error::custom("noted"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option
            unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier ignored_any
        }
    }
    let mut fields: &'static [&'static str] = &[];
    let _ = T::deserialize(Probe(&mut fields));
    fields
}

/// Writes a result for JavaScript: plain objects and arrays, `null` for `None` (never
/// `undefined`), as `JSON.parse` of the same value would give; bytes (pictures, see
/// [`super::viewer_state::Rgba8`]) as `Uint8Array`s.
pub fn to_js<T: Serialize>(value: &T) -> Result<wasm_bindgen::JsValue, wasm_bindgen::JsError> {
    let serializer = serde_wasm_bindgen::Serializer::json_compatible().serialize_bytes_as_arrays(false);
    value
        .serialize(&serializer)
        .map_err(|e| wasm_bindgen::JsError::new(&format!("cannot hand a result to JavaScript: {e}")))
}

/// `read_from` over JSON text, without serde_json's position (for the native tests).
#[cfg(test)]
pub fn read_json<T: serde::de::DeserializeOwned>(call: &str, json: &str) -> Result<T, String> {
    read_from(call, &mut serde_json::Deserializer::from_str(json)).map_err(|e| match e.rfind(" at line ") {
        Some(at) => e[..at].to_string(),
        None => e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn the_keys_of_a_struct_are_its_renamed_fields() {
        let fields = field_names::<super::super::build_options::BuildOptions>();
        assert_eq!(fields, ["pose", "levels", "mode", "weights", "schedule", "maxError", "onProgress"]);
        assert_eq!(
            unknown_field("level", fields),
            "unknown field `level`, expected one of `pose`, `levels`, `mode`, `weights`, `schedule`, `maxError`, `onProgress`"
        );
    }
}
