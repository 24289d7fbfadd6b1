//! How `setState({...})` is read: a plain JavaScript object, read with `Reflect`, becomes the
//! model's [`Update`]; every key is checked, and a bad value names the key and what it accepts.
//! The names of methods, variants and overlays are the model's ([`crate::render::viewer::settings`]).

use wasm_bindgen::JsValue;

use crate::render::camera;
use crate::render::plan::{BlendVariant, Method};
use crate::render::viewer::settings::{
    method_named, overlay_named, variant_named, DistanceMode, Update, METHOD_NAMES, OVERLAY_NAMES,
    VARIANT_NAMES,
};

/// `obj[key]`, when `obj` is an object and the value is neither `undefined` nor `null`.
pub fn get(obj: &JsValue, key: &str) -> Option<JsValue> {
    if !obj.is_object() {
        return None;
    }
    let value = js_sys::Reflect::get(obj, &key.into()).ok()?;
    (!value.is_undefined() && !value.is_null()).then_some(value)
}

/// `obj[key]` as a string, when it is one.
pub fn get_string(obj: &JsValue, key: &str) -> Option<String> {
    if !obj.is_object() {
        return None;
    }
    js_sys::Reflect::get(obj, &key.into()).ok()?.as_string()
}

const KEYS: [&str; 23] = [
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
];

/// Reads a `setState` object.
///
/// # Errors
/// A message naming the first unknown key or bad value.
pub fn parse_update(obj: &JsValue, clips: &[String]) -> Result<Update, String> {
    if !obj.is_object() {
        return Err("setState takes an object, e.g. { paused: true }".into());
    }
    let mut u = Update::default();
    for key in js_sys::Object::keys(obj.unchecked_ref::<js_sys::Object>()).iter() {
        let key = key.as_string().unwrap_or_default();
        if !KEYS.contains(&key.as_str()) {
            return Err(format!("unknown setting {key:?}; known: {}", KEYS.join(", ")));
        }
        let value = js_sys::Reflect::get(obj, &key.as_str().into()).unwrap_or(JsValue::UNDEFINED);
        let number = |lo: f64, hi: f64| -> Result<f64, String> {
            match value.as_f64() {
                Some(x) if x.is_finite() && (lo..=hi).contains(&x) => Ok(x),
                _ => Err(format!("{key} must be a number in [{lo}, {hi}], got {value:?}")),
            }
        };
        let text = || value.as_string().ok_or_else(|| format!("{key} must be a string, got {value:?}"));
        match key.as_str() {
            "paused" => {
                u.paused = Some(value.as_bool().ok_or_else(|| "paused must be true or false".to_string())?)
            }
            "time" => u.time = Some(number(0.0, 1e9)?),
            "speed" => u.speed = Some(number(0.0, 10.0)? as f32),
            "clip" => {
                u.clip = Some(if value.is_null() {
                    None
                } else {
                    let name = text()?;
                    Some(
                        clips
                            .iter()
                            .position(|c| *c == name)
                            .ok_or_else(|| format!("no clip {name:?}; have {clips:?}"))?,
                    )
                })
            }
            "distanceMode" => {
                u.distance_mode = Some(match text()?.as_str() {
                    "dolly" => DistanceMode::Dolly,
                    "manual" => DistanceMode::Manual,
                    other => {
                        return Err(format!("distanceMode must be \"dolly\" or \"manual\", got {other:?}"))
                    }
                })
            }
            // From a tenth of the framing distance to a thousand times it: beyond, nothing to see.
            "distance" => u.distance = Some(number(0.1, 1000.0)? as f32),
            "dollyPeriod" => u.dolly_period = Some(number(0.0, 3600.0)? as f32),
            "yaw" => u.yaw = Some(number(-3600.0, 3600.0)? as f32),
            "pitch" => {
                let limit = camera::MAX_PITCH.to_degrees();
                u.pitch = Some((number(-3600.0, 3600.0)? as f32).clamp(-limit, limit))
            }
            // A hundred framing distances either way: far beyond, the character is off every view.
            "pan" => {
                let pair = value.clone().dyn_into::<js_sys::Array>().ok().filter(|a| a.length() == 2);
                let xy = pair.map(|a| [a.get(0).as_f64(), a.get(1).as_f64()]);
                u.pan = match xy {
                    Some([Some(x), Some(y)]) if x.abs() <= 100.0 && y.abs() <= 100.0 => {
                        Some([x as f32, y as f32])
                    }
                    _ => {
                        return Err(format!("pan must be [x, y] with numbers in [-100, 100], got {value:?}"))
                    }
                }
            }
            "resetCamera" => {
                u.reset_camera =
                    value.as_bool().ok_or_else(|| "resetCamera must be true or false".to_string())?
            }
            "tolerance" => u.tolerance = Some(number(0.01, 1000.0)? as f32),
            "hysteresis" => u.hysteresis = Some(number(0.0, 10.0)? as f32),
            "transition" => {
                u.by_distance = Some(match text()?.as_str() {
                    "time" => false,
                    "distance" => true,
                    t => return Err(format!("transition must be \"time\" or \"distance\", got {t:?}")),
                });
            }
            "duration" => u.duration = Some(number(0.0, 60.0)? as f32),
            "zone" => u.zone = Some(number(0.0, 1.0)? as f32),
            // A hundredth of real time at the slowest: a half-second transition then takes 50 s.
            "transitionSpeed" => u.transition_speed = Some(number(0.01, 1.0)? as f32),
            // Up to 16×: a pixel of the real view becomes a 16 × 16 block, enough to see sub-pixel
            // changes; further, a view shows a few pixels of the real one.
            "magnify" => u.magnify = Some(number(1.0, 16.0)? as f32),
            "meter" => {
                u.meter = Some(value.as_bool().ok_or_else(|| "meter must be true or false".to_string())?)
            }
            "variant" => {
                let name = text()?;
                u.variant = Some(variant_named(&name).ok_or_else(|| {
                    format!("variant must be one of {}, got {name:?}", VARIANT_NAMES.join(", "))
                })?)
            }
            "methods" => {
                let array: js_sys::Array =
                    value.clone().dyn_into().map_err(|_| "methods must be an array of one to three names")?;
                let count = array.length() as usize;
                if !(1..=3).contains(&count) {
                    return Err(format!("methods must name one to three views, got {count}"));
                }
                let mut methods = [Method::Popping; 3];
                for (i, m) in methods.iter_mut().enumerate().take(count) {
                    let name = array.get(i as u32).as_string();
                    *m = name
                        .as_deref()
                        .and_then(|n| method_named(n, BlendVariant::OpaqueFirst))
                        .ok_or_else(|| {
                            format!("methods[{i}] must be one of {}, got {name:?}", METHOD_NAMES.join(", "))
                        })?;
                }
                u.methods = Some((methods, count));
            }
            "continuousTriangles" => {
                u.continuous_triangles =
                    Some(if value.is_null() { None } else { Some(number(1.0, 1e9)? as u32) })
            }
            "overlay" => {
                let name = text()?;
                u.overlay = Some(overlay_named(&name).ok_or_else(|| {
                    format!("overlay must be one of {}, got {name:?}", OVERLAY_NAMES.join(", "))
                })?)
            }
            _ => unreachable!("checked against KEYS"),
        }
    }
    Ok(u)
}

use wasm_bindgen::JsCast;
