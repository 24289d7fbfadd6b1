//! The viewer's face for links (`crate::js_api::link`): its settings as the query pairs a link
//! carries, and a link's pairs applied, so that a page's *Copy link* reopens what the reader sees.
//! The pairs cross as arrays of two strings, built and read with `js_sys` (a serde round trip of
//! them cost the page 5 KiB).

use js_sys::{Array, Object, Reflect};
use wasm_bindgen::prelude::*;

use super::Viewer;
use crate::js_api::link::{link_of, link_updates};

#[wasm_bindgen]
impl Viewer {
    /// The settings as a link carries them: `{ preset, pairs }`, the preset the link names and
    /// the `[key, value]` pairs that differ from it (changes queued while a measurement holds
    /// the viewer included).
    pub fn link(&self) -> Object {
        let link = link_of(&self.settings_now());
        let pairs: Array = link
            .pairs
            .iter()
            .map(|[key, value]| Array::of2(&JsValue::from_str(key), &JsValue::from_str(value)))
            .collect();
        let object = Object::new();
        // Setting a property on a fresh plain object cannot fail.
        let _ = Reflect::set(&object, &"preset".into(), &link.preset.into());
        let _ = Reflect::set(&object, &"pairs".into(), &pairs);
        object
    }

    /// Applies a link's query pairs (`[...new URLSearchParams(location.search)]`), each on its
    /// own after the preset the page has set: returns a message for each pair whose value its
    /// setting does not take (the others apply). Keys that are not a link's are left alone.
    ///
    /// # Errors
    /// `pairs` is not an array of `[key, value]` strings.
    #[wasm_bindgen(js_name = applyLink)]
    pub fn apply_link(&self, pairs: &Array) -> Result<Vec<String>, JsError> {
        let pairs: Option<Vec<(String, String)>> = pairs
            .iter()
            .map(|pair| {
                let pair = pair.dyn_into::<Array>().ok()?;
                Some((pair.get(0).as_string()?, pair.get(1).as_string()?))
            })
            .collect();
        let pairs =
            pairs.ok_or_else(|| JsError::new("applyLink takes an array of [key, value] pairs of strings"))?;
        let clips = self.queue.borrow().clips.clone();
        let (updates, ignored) = link_updates(&pairs, &clips);
        updates.into_iter().for_each(|update| self.push(update));
        Ok(ignored)
    }
}
