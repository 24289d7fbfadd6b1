//! The viewer's face for links (`crate::js_api::link`): its settings as the query pairs a link
//! carries, and a link's pairs applied, so that a page's *Copy link* reopens what the reader sees.

use wasm_bindgen::prelude::*;

use super::Viewer;
use crate::js_api::link::{link_of, link_updates};
use crate::js_api::read::{read_from, to_js};

#[wasm_bindgen]
impl Viewer {
    /// The settings as a link carries them: `{ preset, pairs }`, the preset the link names and
    /// the `[key, value]` pairs that differ from it (changes queued while a measurement holds
    /// the viewer included).
    ///
    /// # Errors
    /// None in practice: the result is plain strings.
    pub fn link(&self) -> Result<JsValue, JsError> {
        to_js(&link_of(&self.settings_now()))
    }

    /// Applies a link's query pairs (`[...new URLSearchParams(location.search)]`), each on its
    /// own after the preset the page has set: returns a message for each pair whose value its
    /// setting does not take (the others apply). Keys that are not a link's are left alone.
    ///
    /// # Errors
    /// `pairs` is not an array of `[key, value]` strings.
    #[wasm_bindgen(js_name = applyLink)]
    pub fn apply_link(&self, pairs: JsValue) -> Result<Vec<String>, JsError> {
        let pairs: Vec<(String, String)> =
            read_from("applyLink", serde_wasm_bindgen::Deserializer::from(pairs))
                .map_err(|e| JsError::new(&e))?;
        let clips = self.queue.borrow().clips.clone();
        let (updates, ignored) = link_updates(&pairs, &clips);
        updates.into_iter().for_each(|update| self.push(update));
        Ok(ignored)
    }
}
