//! The `<clod-viewer>` element's attributes that change the viewer's settings (`preset`, `clip`,
//! `modes`, `variant`, `tolerance`, `autoplay`, `mode`, `count`), read here rather than in the element's
//! JavaScript: each becomes the model's [`Update`], and a value the viewer does not take is an
//! error that quotes the attribute and says what it takes, e.g.
//! `tolerance="fine": must be a number of pixels in [0.01, 1000]`.
//!
//! `value` is `None` for an attribute that is absent (or was removed): the setting's default
//! ([`Settings::default`]; the first clip, 400 instances; the threshold of the element's preset),
//! so removing an attribute puts back what an element without it shows.

use super::read::Names;
use super::viewer_state::ViewerMode;
use crate::render::crowd::MAX_INSTANCES;
use crate::render::plan::{BlendVariant, Method};
use crate::render::viewer::preset::Preset;
use crate::render::viewer::settings::{Settings, Update};

/// The attributes [`attribute_update`] reads, in the order the element applies them (the preset
/// first: an explicit `tolerance` then overrides its threshold).
pub const SETTING_ATTRIBUTES: [&str; 8] =
    ["autoplay", "preset", "clip", "modes", "variant", "tolerance", "mode", "count"];

/// The words of `modes`, each with the method it shows: the short names first, then the
/// viewer's own.
const MODE_WORDS: [(&str, &str); 6] = [
    ("pop", "popping"),
    ("blend", "alpha"),
    ("morph", "geomorph"),
    ("popping", "popping"),
    ("alpha", "alpha"),
    ("geomorph", "geomorph"),
];

/// The update attribute `name` set to `value` asks for, on an element whose `preset` attribute is
/// `preset` (it decides the threshold a removed `tolerance` puts back), for a character with clips
/// `clips`.
///
/// # Errors
/// A value the attribute does not take, or an attribute that is not one of
/// [`SETTING_ATTRIBUTES`], in a sentence that quotes it.
pub fn attribute_update(
    name: &str,
    value: Option<&str>,
    preset: Option<&str>,
    clips: &[String],
) -> Result<Update, String> {
    let quoted = match value {
        Some(v) => format!("{name}={v:?}"),
        None => name.to_string(),
    };
    let wrong = |takes: &str| format!("{quoted}: must be {takes}");
    let mut u = Update::default();
    match name {
        "autoplay" => u.paused = Some(value.is_none()),
        // Absent (or removed): the realistic defaults.
        "preset" => {
            let v = value.unwrap_or(Preset::Realistic.name());
            u.preset = Some(Preset::named(v).ok_or_else(|| wrong(&names::<Preset>()))?);
        }
        "clip" => {
            u.clip = Some(match value {
                // The first clip, or the rest pose for a character without one.
                None => Settings::default().clip.filter(|&c| c < clips.len()),
                Some(v) => Some(clips.iter().position(|c| c == v).ok_or_else(|| {
                    let names: Vec<String> = clips.iter().map(|c| format!("{c:?}")).collect();
                    match names.is_empty() {
                        true => format!("{quoted}: this character has no clips"),
                        false => {
                            format!("{quoted}: no clip of that name; this character has {}", names.join(", "))
                        }
                    }
                })?),
            })
        }
        "modes" => {
            let text = value.unwrap_or("pop blend morph");
            let words: Vec<&str> = text
                .split(|c: char| c.is_whitespace() || c == ',' || c == '+')
                .filter(|w| !w.is_empty())
                .collect();
            let takes = "one to three of pop, blend, morph (or popping, alpha, geomorph), in view order";
            if !(1..=3).contains(&words.len()) {
                return Err(wrong(takes));
            }
            let mut methods = [Method::Popping; 3];
            for (m, word) in methods.iter_mut().zip(&words) {
                let lower = word.to_lowercase();
                let (_, method) = MODE_WORDS
                    .iter()
                    .find(|(w, _)| *w == lower)
                    .ok_or_else(|| format!("{quoted}: {word:?} is not a mode; use {takes}"))?;
                *m = Method::named(method).unwrap_or(Method::Popping);
            }
            u.methods = Some((methods, words.len()));
        }
        "variant" => {
            let v = value.unwrap_or(BlendVariant::OpaqueFirst.name());
            u.variant = Some(BlendVariant::named(v).ok_or_else(|| wrong(&names::<BlendVariant>()))?);
        }
        "tolerance" => match value {
            // Removed: the threshold of the element's preset (the realistic one without a valid
            // `preset`, which reports its own error), with its unit.
            None => u.tolerance_of = Some(preset.and_then(Preset::named).unwrap_or(Preset::Realistic)),
            Some(v) => {
                let t = v.trim().parse::<f64>().ok().filter(|t| (0.01..=1000.0).contains(t));
                u.tolerance = Some(t.ok_or_else(|| wrong("a number of pixels in [0.01, 1000]"))? as f32);
            }
        },
        "mode" => {
            let v = value.unwrap_or(ViewerMode::Single.name());
            u.crowd =
                Some(ViewerMode::named(v).ok_or_else(|| wrong(&names::<ViewerMode>()))? == ViewerMode::Crowd);
        }
        "count" => {
            u.crowd_count = Some(match value {
                None => Settings::default().crowd_count,
                Some(v) => {
                    let n = v.trim().parse::<f64>().ok();
                    let n = n.filter(|n| n.fract() == 0.0 && (1.0..=MAX_INSTANCES as f64).contains(n));
                    n.ok_or_else(|| wrong(&format!("a whole number in [1, {MAX_INSTANCES}]")))? as usize
                }
            });
        }
        _ => {
            return Err(format!(
                "{name} is not an attribute that changes the viewer's settings; those are {}",
                SETTING_ATTRIBUTES.join(", ")
            ))
        }
    }
    Ok(u)
}

/// `one of "a", "b"` for the names of `T`.
fn names<T: Names>() -> String {
    let quoted: Vec<String> = T::NAMES.iter().map(|n| format!("{n:?}")).collect();
    format!("one of {}", quoted.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn clips() -> Vec<String> {
        vec!["Walk".into(), "Wave".into()]
    }

    #[test]
    fn attributes_become_updates() {
        let u = |name, value| attribute_update(name, value, None, &clips()).unwrap();
        assert_eq!(u("autoplay", Some("")).paused, Some(false));
        assert_eq!(u("autoplay", None).paused, Some(true));
        assert_eq!(u("clip", Some("Wave")).clip, Some(Some(1)));
        // Removed: the first clip, as without the attribute; the rest pose without clips.
        assert_eq!(u("clip", None).clip, Some(Some(0)));
        assert_eq!(attribute_update("clip", None, None, &[]).unwrap().clip, Some(None));
        assert_eq!(
            u("modes", Some("morph, Pop")).methods,
            Some(([Method::Geomorph, Method::Popping, Method::Popping], 2))
        );
        assert_eq!(u("modes", None).methods.map(|m| m.1), Some(3));
        assert_eq!(u("variant", Some("dither")).variant, Some(BlendVariant::Dither));
        assert_eq!(u("tolerance", Some(" 4 ")).tolerance, Some(4.0));
        assert_eq!(u("mode", Some("crowd")).crowd, Some(true));
        assert_eq!(u("count", Some("12")).crowd_count, Some(12));
        // Removed: the defaults, not an error.
        // A removed threshold is the element's preset's, in its unit.
        assert_eq!(u("tolerance", None).tolerance_of, Some(Preset::Realistic));
        for (preset, height) in [("demonstration", Some(400.0)), ("realistic", None)] {
            let mut s = Settings::default();
            Preset::named(preset).unwrap().apply(&mut s);
            attribute_update("tolerance", Some("3"), Some(preset), &clips()).unwrap().apply(&mut s);
            assert_eq!((s.tolerance_px, s.tolerance_height), (3.0, None));
            attribute_update("tolerance", None, Some(preset), &clips()).unwrap().apply(&mut s);
            assert_eq!(Preset::of(&s), Preset::named(preset), "{preset}: {s:?}");
            assert_eq!(s.tolerance_height, height);
        }
        assert_eq!(u("count", None).crowd_count, Some(400));
        assert_eq!(u("preset", Some("demonstration")).preset, Some(Preset::Demonstration));
        assert_eq!(u("preset", None).preset, Some(Preset::Realistic));
    }

    #[test]
    fn a_value_the_viewer_does_not_take_is_quoted_with_what_it_takes() {
        for (name, value, message) in [
            (
                "modes",
                "pop fade",
                r#"modes="pop fade": "fade" is not a mode; use one to three of pop, blend, morph (or popping, alpha, geomorph), in view order"#,
            ),
            (
                "modes",
                "pop pop pop pop",
                r#"modes="pop pop pop pop": must be one to three of pop, blend, morph (or popping, alpha, geomorph), in view order"#,
            ),
            ("tolerance", "fine", r#"tolerance="fine": must be a number of pixels in [0.01, 1000]"#),
            ("variant", "soft", r#"variant="soft": must be one of "opaque-first", "naive", "dither""#),
            ("mode", "crowds", r#"mode="crowds": must be one of "single", "crowd""#),
            ("count", "2.5", r#"count="2.5": must be a whole number in [1, 4096]"#),
            ("preset", "demo", r#"preset="demo": must be one of "demonstration", "realistic""#),
            ("clip", "Run", r#"clip="Run": no clip of that name; this character has "Walk", "Wave""#),
        ] {
            assert_eq!(attribute_update(name, Some(value), None, &clips()).err().unwrap(), message);
        }
        assert!(attribute_update("src", Some("a.glb"), None, &clips()).is_err());
    }
}
