//! How `setState({...})` is read: a plain JavaScript object, read with `Reflect`, becomes the
//! model's [`Update`]; every key is checked, and a bad value names the key and what it accepts.
//! The names of methods, variants and overlays are the model's ([`crate::render::viewer::settings`]).

use wasm_bindgen::{JsCast, JsValue};

use crate::js_options::entries;
use crate::render::camera;
use crate::render::crowd::MAX_INSTANCES;
use crate::render::plan::{BlendVariant, Method};
use crate::render::viewer::preset::{Preset, PRESET_NAMES};
use crate::render::viewer::settings::{
    method_named, overlay_named, variant_named, DistanceMode, Update, METHOD_NAMES, OVERLAY_NAMES,
    VARIANT_NAMES,
};

const KEYS: [&str; 28] = [
    "paused",
    "time",
    "speed",
    "clip",
    "distanceMode",
    "distance",
    "dollyPeriod",
    "yaw",
    "pitch",
    "pan",
    "resetCamera",
    "tolerance",
    "hysteresis",
    "transition",
    "duration",
    "zone",
    "transitionSpeed",
    "magnify",
    "meter",
    "variant",
    "methods",
    "continuousTriangles",
    "overlay",
    "mode",
    "count",
    "crowdLod",
    "morphs",
    "preset",
];

/// Reads a `setState` object.
///
/// # Errors
/// A message naming the first unknown key or bad value.
pub fn parse_update(obj: &JsValue, clips: &[String]) -> Result<Update, String> {
    let mut u = Update::default();
    for (key, v) in entries(obj, "setState", &KEYS, "{ paused: true }")? {
        match key.as_str() {
            "paused" => u.paused = Some(v.boolean()?),
            "time" => u.time = Some(v.number(0.0, 1e9)?),
            "speed" => u.speed = Some(v.number(0.0, 10.0)? as f32),
            "clip" => {
                u.clip = Some(if v.is_null() {
                    None
                } else {
                    let name = v.text()?;
                    Some(
                        clips
                            .iter()
                            .position(|c| *c == name)
                            .ok_or_else(|| format!("no clip {name:?}; have {clips:?}"))?,
                    )
                })
            }
            "distanceMode" => {
                let modes = [("dolly", DistanceMode::Dolly), ("manual", DistanceMode::Manual)];
                u.distance_mode =
                    Some(v.choice(&["dolly", "manual"], |n| modes.iter().find(|m| m.0 == n).map(|m| m.1))?)
            }
            // From a tenth of the framing distance to a thousand times it: beyond, nothing to see.
            "distance" => u.distance = Some(v.number(0.1, 1000.0)? as f32),
            "dollyPeriod" => u.dolly_period = Some(v.number(0.0, 3600.0)? as f32),
            "yaw" => u.yaw = Some(v.number(-3600.0, 3600.0)? as f32),
            "pitch" => {
                let limit = camera::MAX_PITCH.to_degrees();
                u.pitch = Some((v.number(-3600.0, 3600.0)? as f32).clamp(-limit, limit))
            }
            // A hundred framing distances either way: far beyond, the character is off every view.
            "pan" => {
                let pair = v.value.clone().dyn_into::<js_sys::Array>().ok().filter(|a| a.length() == 2);
                u.pan = match pair.map(|a| [a.get(0).as_f64(), a.get(1).as_f64()]) {
                    Some([Some(x), Some(y)]) if x.abs() <= 100.0 && y.abs() <= 100.0 => {
                        Some([x as f32, y as f32])
                    }
                    _ => return Err(v.error("[x, y] with numbers in [-100, 100]")),
                }
            }
            "resetCamera" => u.reset_camera = v.boolean()?,
            "tolerance" => u.tolerance = Some(v.number(0.01, 1000.0)? as f32),
            "hysteresis" => u.hysteresis = Some(v.number(0.0, 10.0)? as f32),
            "transition" => {
                u.by_distance = Some(v.choice(&["time", "distance"], |n| match n {
                    "time" => Some(false),
                    "distance" => Some(true),
                    _ => None,
                })?)
            }
            "duration" => u.duration = Some(v.number(0.0, 60.0)? as f32),
            "zone" => u.zone = Some(v.number(0.0, 1.0)? as f32),
            // A hundredth of real time at the slowest: a half-second transition then takes 50 s.
            "transitionSpeed" => u.transition_speed = Some(v.number(0.01, 1.0)? as f32),
            // Up to 16×: a pixel of the real view becomes a 16 × 16 block, enough to see sub-pixel
            // changes; further, a view shows a few pixels of the real one.
            "magnify" => u.magnify = Some(v.number(1.0, 16.0)? as f32),
            "meter" => u.meter = Some(v.boolean()?),
            "variant" => u.variant = Some(v.choice(&VARIANT_NAMES, variant_named)?),
            "methods" => {
                let array: js_sys::Array = v
                    .value
                    .clone()
                    .dyn_into()
                    .map_err(|_| v.error("an array of one to three method names"))?;
                let count = array.length() as usize;
                if !(1..=3).contains(&count) {
                    return Err(v.error("one to three method names"));
                }
                let mut methods = [Method::Popping; 3];
                for (i, m) in methods.iter_mut().enumerate().take(count) {
                    let name = array.get(i as u32).as_string();
                    *m = name
                        .as_deref()
                        .and_then(|n| method_named(n, BlendVariant::OpaqueFirst))
                        .ok_or_else(|| {
                            format!(
                                "setState: methods[{i}] must be one of {}, got {name:?}",
                                METHOD_NAMES.join(", ")
                            )
                        })?;
                }
                u.methods = Some((methods, count));
            }
            "continuousTriangles" => {
                u.continuous_triangles =
                    Some(if v.is_null() { None } else { Some(v.number(1.0, 1e9)? as u32) })
            }
            "overlay" => u.overlay = Some(v.choice(&OVERLAY_NAMES, overlay_named)?),
            "mode" => {
                u.crowd = Some(v.choice(&["single", "crowd"], |n| match n {
                    "single" => Some(false),
                    "crowd" => Some(true),
                    _ => None,
                })?)
            }
            "crowdLod" => u.crowd_lod = Some(v.boolean()?),
            "morphs" => u.morphs = Some(v.boolean()?),
            "preset" => u.preset = Some(v.choice(&PRESET_NAMES, Preset::named)?),
            "count" => u.crowd_count = Some(v.number(1.0, MAX_INSTANCES as f64)?.round() as usize),
            _ => unreachable!("entries() checked the key against KEYS"),
        }
    }
    Ok(u)
}
