//! The settings a link to the viewer carries: the reader's comparison settings written as a URL's
//! query pairs (`magnify=1&speed=0.5`), and read back into the model's [`Update`].
//!
//! A link names one preset and carries only the settings that differ from it, so that it stays
//! short and a preset's own values keep their meaning (the demonstration's threshold is per 400 px
//! of view height: written out as pixels it would no longer scale with the view). The preset is
//! the one of the two that leaves fewer settings to write; the demonstration on a tie, since that
//! is what the page opens with. The keys are `setState`'s ([`ViewerSettings`]) and so are their
//! values, as text: numbers in the shortest form that reads back to the same `f32`, `true` or
//! `false`, names, and `pan` as `x,y`. The time, clip, methods, distance, continuous triangle
//! count and crowd mode with its instance count are not among them: the page writes those under
//! its own keys (`docs/viewer.md`); the crowd's level selection (`crowdLod`) is.

use super::read::{Flag, List, Names, Number, OneOf};
use super::viewer_settings::ViewerSettings;
use crate::render::viewer::preset::Preset;
use crate::render::viewer::settings::{overlay_name, variant_name, Settings, Update};

/// One setting a link can carry: its `setState` key, its value in `s` as text, and that text
/// read into `setState`'s settings as `setState` reads the key.
struct LinkKey {
    key: &'static str,
    text: fn(&Settings) -> String,
    read: fn(&mut ViewerSettings, &str, &str) -> Result<(), String>,
}

/// A [`LinkKey::read`] that sets `field` to what `parse(key, text)` makes of the text.
macro_rules! read {
    ($field:ident, $parse:ident) => {
        |settings, key, text| {
            settings.$field = Some($parse(key, text)?);
            Ok(())
        }
    };
}

/// The settings a link carries, in the order it writes them.
const LINK_KEYS: [LinkKey; 18] = [
    // The threshold's unit is part of it: 2.4 px per 400 px of view is not 2.4 px.
    LinkKey {
        key: "tolerance",
        text: |s| number_per(s.tolerance_px, s.tolerance_height),
        read: read!(tolerance, number),
    },
    LinkKey { key: "magnify", text: |s| decimal(s.magnify), read: read!(magnify, number) },
    LinkKey {
        key: "transitionSpeed",
        text: |s| decimal(s.transition_speed),
        read: read!(transition_speed, number),
    },
    LinkKey { key: "dollyPeriod", text: |s| decimal(s.dolly_period), read: read!(dolly_period, number) },
    LinkKey { key: "overlay", text: |s| overlay_name(s.overlay).to_string(), read: read!(overlay, name) },
    LinkKey { key: "speed", text: |s| decimal(s.speed), read: read!(speed, number) },
    LinkKey {
        key: "transition",
        text: |s| if s.by_distance { "distance" } else { "time" }.to_string(),
        read: read!(transition, name),
    },
    LinkKey { key: "duration", text: |s| decimal(s.duration), read: read!(duration, number) },
    LinkKey { key: "zone", text: |s| decimal(s.zone), read: read!(zone, number) },
    LinkKey { key: "hysteresis", text: |s| decimal(s.hysteresis), read: read!(hysteresis, number) },
    LinkKey { key: "variant", text: |s| variant_name(s.variant).to_string(), read: read!(variant, name) },
    LinkKey { key: "meter", text: |s| s.meter.to_string(), read: read!(meter, flag) },
    LinkKey { key: "flip", text: |s| s.flip.to_string(), read: read!(flip, flag) },
    LinkKey { key: "crowdLod", text: |s| s.crowd_lod.to_string(), read: read!(crowd_lod, flag) },
    LinkKey { key: "morphs", text: |s| s.morphs.to_string(), read: read!(morphs, flag) },
    LinkKey { key: "yaw", text: |s| decimal(s.yaw_degrees), read: read!(yaw, number) },
    LinkKey { key: "pitch", text: |s| decimal(s.pitch_degrees), read: read!(pitch, number) },
    LinkKey {
        key: "pan",
        text: |s| format!("{},{}", decimal(s.pan[0]), decimal(s.pan[1])),
        read: read!(pan, numbers),
    },
];

/// `x` in the fewest digits that read back as `x` in `f32`.
fn decimal(x: f32) -> String {
    x.to_string()
}

/// A link's number, or `setState`'s message for a value that is not one.
fn number(key: &str, text: &str) -> Result<Number, String> {
    let x = text.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    x.map(Number).ok_or_else(|| format!("setState: {key} must be a number, got {text:?}"))
}

/// A link's numbers, separated by commas (`pan=0.25,-1`).
fn numbers(key: &str, text: &str) -> Result<List<Number>, String> {
    text.split(',').map(|x| number(key, x)).collect::<Result<_, _>>().map(List)
}

/// A link's `true` or `false`.
fn flag(key: &str, text: &str) -> Result<Flag, String> {
    match text.trim() {
        "true" => Ok(Flag(true)),
        "false" => Ok(Flag(false)),
        _ => Err(format!("setState: {key} must be true or false, got {text:?}")),
    }
}

/// One of `T`'s names.
fn name<T: Names>(key: &str, text: &str) -> Result<OneOf<T>, String> {
    T::named(text.trim()).map(OneOf).ok_or_else(|| {
        format!("setState: {key} must be one of {}, got {text:?}", OneOf::<T>::accepts_names())
    })
}

/// `value`, with the view height it is given per when it scales with the view: only for telling
/// two thresholds apart (a link writes the value alone, which reads back as pixels).
fn number_per(value: f32, height: Option<f32>) -> String {
    match height {
        Some(h) => format!("{}/{}", decimal(value), decimal(h)),
        None => decimal(value),
    }
}

/// What a link says of the settings `s`: the preset it names and the pairs that differ from it.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// `"demonstration"` or `"realistic"`.
    pub preset: &'static str,
    /// `[key, value]` pairs, in the order a link writes them (the table `LINK_KEYS`).
    pub pairs: Vec<[String; 2]>,
}

/// The link of the settings `s` (see the module docs).
pub fn link_of(s: &Settings) -> Link {
    let differences = |preset: Preset| {
        let mut base = Settings::default();
        preset.apply(&mut base);
        LINK_KEYS
            .iter()
            .filter(|k| (k.text)(s) != (k.text)(&base))
            .map(|k| [k.key.to_string(), plain((k.text)(s))])
            .collect::<Vec<_>>()
    };
    let demonstration = differences(Preset::Demonstration);
    let realistic = differences(Preset::Realistic);
    let (preset, pairs) = if realistic.len() < demonstration.len() {
        (Preset::Realistic, realistic)
    } else {
        (Preset::Demonstration, demonstration)
    };
    Link { preset: preset.name(), pairs }
}

/// A threshold's value without the view height it scales with (see [`number_per`]).
fn plain(text: String) -> String {
    match text.split_once('/') {
        Some((value, _)) => value.to_string(),
        None => text,
    }
}

/// The updates a link's query pairs ask for, one per pair, in order, and a message for each pair
/// whose value the setting does not take (`"magnify: setState: magnify must be a number in
/// [1, 16], got 40"`). Keys that are not a link's (the page's own: `model`, `t`, ...) are left
/// alone; for a key given twice the last counts. `clips` are the character's.
pub fn link_updates(pairs: &[(String, String)], clips: &[String]) -> (Vec<Update>, Vec<String>) {
    let mut updates = Vec::new();
    let mut ignored = Vec::new();
    for (key, text) in pairs {
        let Some(link_key) = LINK_KEYS.iter().find(|k| k.key == key) else { continue };
        let mut settings = ViewerSettings::default();
        match (link_key.read)(&mut settings, key, text).and_then(|()| settings.update(clips)) {
            Ok(u) => updates.push(u),
            Err(message) => ignored.push(format!("{key}: {message}")),
        }
    }
    (updates, ignored)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::overlay::Overlay;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn pairs(link: &Link) -> Vec<(String, String)> {
        link.pairs.iter().map(|[k, v]| (k.clone(), v.clone())).collect()
    }

    /// Opens a link as the page does: the preset first, then the pairs.
    fn open(link: &Link) -> Settings {
        let mut s = Settings::default();
        Preset::named(link.preset).unwrap().apply(&mut s);
        let (updates, ignored) = link_updates(&pairs(link), &[]);
        assert_eq!(ignored, Vec::<String>::new());
        updates.iter().for_each(|u| u.apply(&mut s));
        s
    }

    #[test]
    fn a_preset_is_a_link_with_no_pairs() {
        for preset in [Preset::Demonstration, Preset::Realistic] {
            let mut s = Settings::default();
            preset.apply(&mut s);
            assert_eq!(link_of(&s), Link { preset: preset.name(), pairs: vec![] });
        }
    }

    #[test]
    fn a_link_carries_what_differs_from_the_nearer_preset_and_reads_back_the_same() {
        // The demonstration, at real size, slower, without FLIP, from another side.
        let mut s = Settings::default();
        Preset::Demonstration.apply(&mut s);
        (s.magnify, s.speed, s.flip, s.yaw_degrees, s.pan) = (1.0, 0.3, false, -37.5, [0.25, -1.0]);
        let link = link_of(&s);
        assert_eq!(link.preset, "demonstration");
        let expected =
            [("magnify", "1"), ("speed", "0.3"), ("flip", "false"), ("yaw", "-37.5"), ("pan", "0.25,-1")];
        assert_eq!(pairs(&link), expected.map(|(k, v)| (k.to_string(), v.to_string())));
        assert_eq!(open(&link), s, "the demonstration's threshold still scales with the view");

        // Realistic but for the overlay, a threshold in pixels, a crowd at full detail and the
        // base shape.
        let mut s = Settings::default();
        (s.overlay, s.tolerance_px, s.crowd_lod, s.morphs) = (Overlay::Wireframe, 2.4, false, false);
        let link = link_of(&s);
        assert_eq!(link.preset, "realistic");
        assert_eq!(
            pairs(&link),
            [("tolerance", "2.4"), ("overlay", "wireframe"), ("crowdLod", "false"), ("morphs", "false")]
                .map(|(k, v)| (k.to_string(), v.to_string()))
        );
        assert_eq!(open(&link), s);
    }

    #[test]
    fn a_threshold_in_pixels_is_not_the_demonstrations_per_view_threshold() {
        let mut s = Settings::default();
        Preset::Demonstration.apply(&mut s);
        Update { tolerance: Some(2.4), ..Default::default() }.apply(&mut s);
        let link = link_of(&s);
        assert_eq!(pairs(&link), [("tolerance".to_string(), "2.4".to_string())]);
        assert_eq!(open(&link), s);
    }

    #[test]
    fn bad_values_are_named_and_the_rest_still_applies() {
        let given =
            [("magnify", "40"), ("overlay", "glow"), ("model", "x.glb"), ("speed", "0.5"), ("pan", "1")];
        let given: Vec<(String, String)> =
            given.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        let (updates, ignored) = link_updates(&given, &[]);
        assert_eq!(updates, [Update { speed: Some(0.5), ..Default::default() }]);
        assert_eq!(
            ignored,
            [
                "magnify: setState: magnify must be a number in [1, 16], got 40",
                r#"overlay: setState: overlay must be one of "none", "wireframe", "levels", "skeleton", "difference", got "glow""#,
                "pan: setState: pan must be [x, y], two numbers in [-100, 100], got an array of 1",
            ]
        );
    }
}
