//! The viewer's settings and how `setState({...})` changes them. Parsing reads a plain JavaScript
//! object with `Reflect`; every key is checked, and a bad value names the key and what it accepts.

use wasm_bindgen::JsValue;

use crate::render::camera;
use crate::render::overlay::Overlay;
use crate::render::plan::{BlendVariant, Method};
use crate::render::schedule::TransitionMode;

/// Where the camera distance comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistanceMode {
    /// The dolly sweeps near → far → near.
    Dolly,
    /// The page's distance slider.
    Manual,
}

/// Everything the page can change.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub paused: bool,
    pub speed: f32,
    /// Index of the clip that plays; `None` shows the rest pose.
    pub clip: Option<usize>,
    pub distance_mode: DistanceMode,
    /// Manual distance in framing distances.
    pub manual_distance: f32,
    pub dolly_period: f32,
    pub yaw_degrees: f32,
    /// Camera elevation, degrees, within ±85 (see [`crate::render::camera::MAX_PITCH`]).
    pub pitch_degrees: f32,
    /// Shift of the point looked at along the view's right and up, in framing distances.
    pub pan: [f32; 2],
    pub tolerance_px: f32,
    pub hysteresis: f32,
    pub transition: TransitionMode,
    pub variant: BlendVariant,
    /// Method of each view, left to right (top to bottom when stacked); only the first
    /// `view_count` are shown.
    pub methods: [Method; 3],
    /// How many views the canvas shows (1..=3).
    pub view_count: usize,
    /// Triangle count of the continuous level drawn by every view, when on.
    pub continuous_triangles: Option<u32>,
    /// Drawn over every view alike.
    pub overlay: Overlay,
}

impl Default for Settings {
    fn default() -> Self {
        let variant = BlendVariant::OpaqueFirst;
        Self {
            paused: false,
            speed: 1.0,
            clip: Some(0),
            distance_mode: DistanceMode::Dolly,
            manual_distance: 1.0,
            // Slow enough to watch each transition (levels change every second or two).
            dolly_period: 16.0,
            // A three-quarter view shows silhouette and face at once.
            yaw_degrees: 30.0,
            pitch_degrees: camera::DEFAULT_PITCH.to_degrees(),
            pan: [0.0; 2],
            // Half a pixel: a strict engine setting. The chains are accurate enough that at 2 px
            // the built-in character needs its finest levels only closer than the framing
            // distance; at 0.5 px its last three switches fall inside the dolly's sweep.
            tolerance_px: 0.5,
            // 10 %: a camera hovering at a switch distance does not flicker between levels.
            hysteresis: 0.1,
            // Half a second per level: long enough to see, short enough to follow a dolly.
            transition: TransitionMode::Time { seconds_per_level: 0.5 },
            variant,
            methods: [Method::Popping, Method::AlphaBlend(variant), Method::Geomorph],
            view_count: 3,
            continuous_triangles: None,
            overlay: Overlay::None,
        }
    }
}

/// The changes one `setState` call asks for.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Update {
    pub paused: Option<bool>,
    pub time: Option<f64>,
    pub speed: Option<f32>,
    pub clip: Option<Option<usize>>,
    pub distance_mode: Option<DistanceMode>,
    pub distance: Option<f32>,
    pub dolly_period: Option<f32>,
    pub yaw: Option<f32>,
    /// Degrees, already clamped to ±85.
    pub pitch: Option<f32>,
    pub pan: Option<[f32; 2]>,
    /// Puts yaw, pitch, pan and the manual distance back to their defaults before the other keys.
    pub reset_camera: bool,
    pub tolerance: Option<f32>,
    pub hysteresis: Option<f32>,
    pub transition: Option<String>,
    pub duration: Option<f32>,
    pub zone: Option<f32>,
    pub variant: Option<BlendVariant>,
    /// The methods of the first views and how many views there are.
    pub methods: Option<([Method; 3], usize)>,
    pub overlay: Option<Overlay>,
    /// `Some(None)` turns the continuous level off.
    pub continuous_triangles: Option<Option<u32>>,
}

impl Update {
    /// Applies the changes (the continuous level is applied by the viewer, which uploads it).
    pub fn apply(&self, s: &mut Settings) {
        macro_rules! set {
            ($field:ident, $value:expr) => {
                if let Some(v) = $value {
                    s.$field = v;
                }
            };
        }
        if self.reset_camera {
            let d = Settings::default();
            s.yaw_degrees = d.yaw_degrees;
            s.pitch_degrees = d.pitch_degrees;
            s.pan = d.pan;
            s.manual_distance = d.manual_distance;
        }
        set!(paused, self.paused);
        set!(speed, self.speed);
        set!(clip, self.clip);
        set!(distance_mode, self.distance_mode);
        set!(manual_distance, self.distance);
        set!(dolly_period, self.dolly_period);
        set!(yaw_degrees, self.yaw);
        set!(pitch_degrees, self.pitch);
        set!(pan, self.pan);
        set!(tolerance_px, self.tolerance);
        set!(hysteresis, self.hysteresis);
        set!(overlay, self.overlay);
        if self.distance.is_some() && self.distance_mode.is_none() {
            // Moving the distance slider takes the camera over from the dolly.
            s.distance_mode = DistanceMode::Manual;
        }
        let (mut seconds, mut zone) = match s.transition {
            TransitionMode::Time { seconds_per_level } => (seconds_per_level, 0.25),
            TransitionMode::Distance { zone } => (0.5, zone),
        };
        seconds = self.duration.unwrap_or(seconds);
        zone = self.zone.unwrap_or(zone);
        let by_distance = match self.transition.as_deref() {
            Some(kind) => kind == "distance",
            None => matches!(s.transition, TransitionMode::Distance { .. }),
        };
        s.transition = if by_distance {
            TransitionMode::Distance { zone }
        } else {
            TransitionMode::Time { seconds_per_level: seconds }
        };
        if let Some((methods, count)) = self.methods {
            s.methods = methods;
            s.view_count = count;
        }
        if let Some(v) = self.variant {
            s.variant = v;
        }
        for m in &mut s.methods {
            if let Method::AlphaBlend(_) = m {
                *m = Method::AlphaBlend(s.variant);
            }
        }
    }
}

/// The page's name of a method.
pub fn method_name(m: Method) -> &'static str {
    match m {
        Method::Popping => "popping",
        Method::AlphaBlend(_) => "alpha",
        Method::Geomorph => "geomorph",
    }
}

/// `obj[key]`, when `obj` is an object and the value is neither `undefined` nor `null`.
pub fn get(obj: &JsValue, key: &str) -> Option<JsValue> {
    if !obj.is_object() {
        return None;
    }
    let value = js_sys::Reflect::get(obj, &key.into()).ok()?;
    (!value.is_undefined() && !value.is_null()).then_some(value)
}

/// The page's name of an overlay.
pub fn overlay_name(o: Overlay) -> &'static str {
    match o {
        Overlay::None => "none",
        Overlay::Wireframe => "wireframe",
        Overlay::Levels => "levels",
        Overlay::Skeleton => "skeleton",
    }
}

/// The page's name of an alpha-blending variant.
pub fn variant_name(v: BlendVariant) -> &'static str {
    match v {
        BlendVariant::Naive => "naive",
        BlendVariant::OpaqueFirst => "opaque-first",
        BlendVariant::Dither => "dither",
    }
}

/// `obj[key]` as a string, when it is one.
pub fn get_string(obj: &JsValue, key: &str) -> Option<String> {
    if !obj.is_object() {
        return None;
    }
    js_sys::Reflect::get(obj, &key.into()).ok()?.as_string()
}

const KEYS: [&str; 20] = [
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
                let t = text()?;
                if t != "time" && t != "distance" {
                    return Err(format!("transition must be \"time\" or \"distance\", got {t:?}"));
                }
                u.transition = Some(t);
            }
            "duration" => u.duration = Some(number(0.0, 60.0)? as f32),
            "zone" => u.zone = Some(number(0.0, 1.0)? as f32),
            "variant" => u.variant = Some(parse_variant(&text()?)?),
            "methods" => {
                let array: js_sys::Array =
                    value.clone().dyn_into().map_err(|_| "methods must be an array of one to three names")?;
                let count = array.length() as usize;
                if !(1..=3).contains(&count) {
                    return Err(format!("methods must name one to three views, got {count}"));
                }
                let mut methods = [Method::Popping; 3];
                for (i, m) in methods.iter_mut().enumerate().take(count) {
                    *m = match array.get(i as u32).as_string().as_deref() {
                        Some("popping") => Method::Popping,
                        Some("alpha") => Method::AlphaBlend(BlendVariant::OpaqueFirst),
                        Some("geomorph") => Method::Geomorph,
                        other => {
                            return Err(format!(
                                "methods[{i}] must be popping, alpha or geomorph, got {other:?}"
                            ))
                        }
                    };
                }
                u.methods = Some((methods, count));
            }
            "continuousTriangles" => {
                u.continuous_triangles =
                    Some(if value.is_null() { None } else { Some(number(1.0, 1e9)? as u32) })
            }
            "overlay" => {
                u.overlay = Some(match text()?.as_str() {
                    "none" => Overlay::None,
                    "wireframe" => Overlay::Wireframe,
                    "levels" => Overlay::Levels,
                    "skeleton" => Overlay::Skeleton,
                    other => {
                        let names = "\"none\", \"wireframe\", \"levels\" or \"skeleton\"";
                        return Err(format!("overlay must be {names}, got {other:?}"));
                    }
                })
            }
            _ => unreachable!("checked against KEYS"),
        }
    }
    Ok(u)
}

fn parse_variant(name: &str) -> Result<BlendVariant, String> {
    match name {
        "naive" => Ok(BlendVariant::Naive),
        "opaque-first" => Ok(BlendVariant::OpaqueFirst),
        "dither" => Ok(BlendVariant::Dither),
        other => Err(format!("variant must be naive, opaque-first or dither, got {other:?}")),
    }
}

use wasm_bindgen::JsCast;
