//! What the viewer takes from JavaScript, as Rust types read with serde ([`super::read`]):
//! `setState(settings)` ([`ViewerSettings`], turned into the model's [`Update`]),
//! `measurePopSpike(options)` ([`SpikeOptions`]) and `Viewer.create`'s options
//! ([`CreateOptions`]). Every key is optional; a key the type does not have, or a value of the
//! wrong kind or out of range, is an error naming the call, the key and what it accepts
//! (`setState: zone must be a number in [0, 1], got 2`), and nothing changes then. The names of
//! methods, variants and overlays are the model's ([`crate::render::viewer::settings`]).

use serde::{Deserialize, Serialize};

use super::read::{nullable, Flag, List, Names, Number, OneOf, Text};
use super::viewer_state::{PresetKey, TransitionBy, ViewerMode};
use crate::render::camera;
use crate::render::crowd::MAX_INSTANCES;
use crate::render::overlay::Overlay;
use crate::render::plan::{BlendVariant, Method};
use crate::render::viewer::preset::{Preset, PRESET_NAMES, PRESET_VALUES};
use crate::render::viewer::settings::{
    method_name, method_named, overlay_name, overlay_named, variant_name, variant_named, DistanceMode,
    Update, METHOD_NAMES, OVERLAY_NAMES, VARIANT_NAMES,
};

/// `setState(settings)`: any subset of these keys.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct ViewerSettings {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paused: Option<Flag>,
    /// Animation seconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<Number>,
    /// A clip name; `null` for the rest pose.
    #[serde(deserialize_with = "nullable", skip_serializing_if = "Option::is_none")]
    pub clip: Option<Option<Text>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_mode: Option<OneOf<DistanceMode>>,
    /// × the framing distance (switches to manual).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dolly_period: Option<Number>,
    /// Degrees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub yaw: Option<Number>,
    /// Degrees, clamped to ±85.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pitch: Option<Number>,
    /// `[x, y]` in framing distances.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pan: Option<List<Number>>,
    /// `true`: yaw, pitch, pan and the manual distance back to their defaults first.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reset_camera: Option<Flag>,
    /// Pixels of screen-space error at which a level switches.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hysteresis: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transition: Option<OneOf<TransitionBy>>,
    /// Seconds per level.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zone: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transition_speed: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub magnify: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub meter: Option<Flag>,
    /// The meter also measures LDR-FLIP.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flip: Option<Flag>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variant: Option<OneOf<BlendVariant>>,
    /// One to three methods: the views, in order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub methods: Option<List<OneOf<Method>>>,
    /// A triangle count through the progressive mesh; `null` for off.
    #[serde(deserialize_with = "nullable", skip_serializing_if = "Option::is_none")]
    pub continuous_triangles: Option<Option<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub overlay: Option<OneOf<Overlay>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode: Option<OneOf<ViewerMode>>,
    /// Crowd instances.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub count: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crowd_lod: Option<Flag>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub morphs: Option<Flag>,
    /// The demonstration's exaggerated settings or the realistic defaults, applied before the
    /// call's other keys.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<OneOf<Preset>>,
}

const CALL: &str = "setState";

/// `Some(value in [lo, hi])` of a number setting, or the message naming `key`.
fn within(n: Option<Number>, key: &str, lo: f64, hi: f64) -> Result<Option<f64>, String> {
    n.map(|n| n.within(CALL, key, lo, hi)).transpose()
}

impl ViewerSettings {
    /// The model's update, for a character with clips `clips`.
    ///
    /// # Errors
    /// The first value out of its range (or a clip the character does not have), naming the key.
    pub fn update(&self, clips: &[String]) -> Result<Update, String> {
        let f = |n: Option<f64>| n.map(|x| x as f32);
        let pitch_limit = f64::from(camera::MAX_PITCH.to_degrees());
        let clip = match &self.clip {
            None => None,
            Some(None) => Some(None),
            Some(Some(Text(name))) => Some(Some(
                clips
                    .iter()
                    .position(|c| c == name)
                    .ok_or_else(|| format!("{CALL}: clip must be one of {clips:?} or null, got {name:?}"))?,
            )),
        };
        let pan = match &self.pan {
            None => None,
            Some(List(xy)) if xy.len() == 2 => {
                let range = |n: Number| n.within(CALL, "pan", -100.0, 100.0).map(|x| x as f32);
                Some([range(xy[0])?, range(xy[1])?])
            }
            Some(List(xy)) => {
                return Err(format!(
                    "{CALL}: pan must be [x, y], two numbers in [-100, 100], got an array of {}",
                    xy.len()
                ))
            }
        };
        let methods = match &self.methods {
            None => None,
            Some(List(names)) if (1..=3).contains(&names.len()) => {
                let mut methods = [Method::Popping; 3];
                for (m, OneOf(name)) in methods.iter_mut().zip(names) {
                    *m = *name;
                }
                Some((methods, names.len()))
            }
            Some(List(names)) => {
                return Err(format!(
                    "{CALL}: methods must be one to three of {}, got {}",
                    OneOf::<Method>::accepts_names(),
                    names.len()
                ))
            }
        };
        let continuous_triangles = match self.continuous_triangles {
            None => None,
            Some(None) => Some(None),
            Some(Some(n)) => Some(Some(n.within(CALL, "continuousTriangles", 1.0, 1e9)? as u32)),
        };
        Ok(Update {
            paused: self.paused.map(|b| b.0),
            time: within(self.time, "time", 0.0, 1e9)?,
            speed: f(within(self.speed, "speed", 0.0, 10.0)?),
            clip,
            distance_mode: self.distance_mode.map(|m| m.0),
            // From a tenth of the framing distance to a thousand times it: beyond, nothing to see.
            distance: f(within(self.distance, "distance", 0.1, 1000.0)?),
            dolly_period: f(within(self.dolly_period, "dollyPeriod", 0.0, 3600.0)?),
            yaw: f(within(self.yaw, "yaw", -3600.0, 3600.0)?),
            pitch: f(
                within(self.pitch, "pitch", -3600.0, 3600.0)?.map(|p| p.clamp(-pitch_limit, pitch_limit))
            ),
            // A hundred framing distances either way: far beyond, the character is off every view.
            pan,
            reset_camera: self.reset_camera.is_some_and(|b| b.0),
            tolerance: f(within(self.tolerance, "tolerance", 0.01, 1000.0)?),
            hysteresis: f(within(self.hysteresis, "hysteresis", 0.0, 10.0)?),
            by_distance: self.transition.map(|t| t.0 == TransitionBy::Distance),
            duration: f(within(self.duration, "duration", 0.0, 60.0)?),
            zone: f(within(self.zone, "zone", 0.0, 1.0)?),
            // A hundredth of real time at the slowest: a half-second transition then takes 50 s.
            transition_speed: f(within(self.transition_speed, "transitionSpeed", 0.01, 1.0)?),
            // Up to 16×: a pixel of the real view becomes a 16 × 16 block, enough to see sub-pixel
            // changes; further, a view shows a few pixels of the real one.
            magnify: f(within(self.magnify, "magnify", 1.0, 16.0)?),
            meter: self.meter.map(|b| b.0),
            flip: self.flip.map(|b| b.0),
            variant: self.variant.map(|v| v.0),
            methods,
            overlay: self.overlay.map(|o| o.0),
            continuous_triangles,
            crowd: self.mode.map(|m| m.0 == ViewerMode::Crowd),
            crowd_count: within(self.count, "count", 1.0, MAX_INSTANCES as f64)?.map(|n| n.round() as usize),
            crowd_lod: self.crowd_lod.map(|b| b.0),
            morphs: self.morphs.map(|b| b.0),
            preset: self.preset.map(|p| p.0),
            tolerance_of: None,
        })
    }
}

impl<T: Names> OneOf<T> {
    /// The names, listed for a message: `"a", "b", "c"`.
    pub fn accepts_names() -> String {
        T::NAMES.iter().map(|n| format!("{n:?}")).collect::<Vec<_>>().join(", ")
    }
}

/// `measurePopSpike(options)` (see `src/web/pop_spike.rs`): every key optional.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpikeOptions {
    /// The switch to this level from the one before (default: the coarsest).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level: Option<Number>,
    /// Offscreen frames drawn (default 96).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames: Option<Number>,
    /// Fraction of the distance moved (default 0.008).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep: Option<Number>,
    /// Framing distances where the switch is placed (default 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<Number>,
}

/// `Viewer.create(canvas, bytes, options)`'s options (the element's; see `src/web/mod.rs`).
#[derive(Default, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct CreateOptions {
    /// `"webgpu"` (default) or `"webgl2"`.
    pub backend: Option<OneOf<Backend>>,
    /// A `.gltf`'s resolver of external files by name.
    pub resolve: Option<super::build_options::Callback>,
    /// The bytes of `Character.buildClodBytes` for this same file.
    pub clod: Option<Bytes>,
    /// The build time of `clod`, ms.
    pub build_ms: Option<Number>,
    /// `"later"`: the levels arrive with `attachLod`.
    pub lod: Option<OneOf<LodLater>>,
    /// The separate Draco module's `decode`, for a file that needs it (see `usesDraco`).
    pub draco: Option<super::build_options::Callback>,
}

/// A `Uint8Array`, copied out of JavaScript.
pub struct Bytes(pub Vec<u8>);

impl<'de> Deserialize<'de> for Bytes {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use wasm_bindgen::JsCast;
        let value: wasm_bindgen::JsValue = serde_wasm_bindgen::preserve::deserialize(d)?;
        value
            .dyn_into::<js_sys::Uint8Array>()
            .map(|a| Bytes(a.to_vec()))
            .map_err(|_| serde::de::Error::custom("must be a Uint8Array"))
    }
}

/// The backends a viewer can draw with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    WebGpu,
    WebGl2,
}

/// The one value `lod` takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LodLater;

macro_rules! names {
    ($t:ty: $($value:expr => $name:literal),+ $(,)?) => {
        impl Names for $t {
            const NAMES: &'static [&'static str] = &[$($name),+];
            fn named(name: &str) -> Option<Self> {
                match name {
                    $($name => Some($value),)+
                    _ => None,
                }
            }
            fn name(self) -> &'static str {
                $(if self == $value { return $name; })+
                unreachable!("every value has a name")
            }
        }
    };
}

names!(DistanceMode: DistanceMode::Dolly => "dolly", DistanceMode::Manual => "manual");
names!(TransitionBy: TransitionBy::Time => "time", TransitionBy::Distance => "distance");
names!(ViewerMode: ViewerMode::Single => "single", ViewerMode::Crowd => "crowd");
names!(Backend: Backend::WebGpu => "webgpu", Backend::WebGl2 => "webgl2");
names!(LodLater: LodLater => "later");

impl Names for Preset {
    const NAMES: &'static [&'static str] = &PRESET_NAMES;
    fn named(name: &str) -> Option<Self> {
        Preset::named(name)
    }
    fn name(self) -> &'static str {
        Preset::name(self)
    }
}

/// The `setState` keys of [`PRESET_VALUES`], in its order.
const PRESET_KEYS: [&str; PRESET_VALUES.len()] = {
    let mut keys = [""; PRESET_VALUES.len()];
    let mut i = 0;
    while i < keys.len() {
        keys[i] = PRESET_VALUES[i].key;
        i += 1;
    }
    keys
};

impl Names for PresetKey {
    const NAMES: &'static [&'static str] = &PRESET_KEYS;
    fn named(name: &str) -> Option<Self> {
        PRESET_KEYS.iter().find(|k| **k == name).map(|k| PresetKey(k))
    }
    fn name(self) -> &'static str {
        self.0
    }
}

impl Names for BlendVariant {
    const NAMES: &'static [&'static str] = &VARIANT_NAMES;
    fn named(name: &str) -> Option<Self> {
        variant_named(name)
    }
    fn name(self) -> &'static str {
        variant_name(self)
    }
}

impl Names for Overlay {
    const NAMES: &'static [&'static str] = &OVERLAY_NAMES;
    fn named(name: &str) -> Option<Self> {
        overlay_named(name)
    }
    fn name(self) -> &'static str {
        overlay_name(self)
    }
}

/// Alpha-blending's variant is the viewer's `variant` setting ([`Update::apply`] sets it).
impl Names for Method {
    const NAMES: &'static [&'static str] = &METHOD_NAMES;
    fn named(name: &str) -> Option<Self> {
        method_named(name, BlendVariant::OpaqueFirst)
    }
    fn name(self) -> &'static str {
        method_name(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::js_api::read::read_json;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn update(json: &str) -> Result<Update, String> {
        let clips = ["Walk".to_string(), "Wave".to_string()];
        read_json::<ViewerSettings>(CALL, json)?.update(&clips)
    }

    #[test]
    fn settings_become_the_models_update() {
        let u = update(r#"{"paused":true,"clip":"Wave","pan":[1,-2],"methods":["geomorph","alpha"],"pitch":120,"count":7.4,"transition":"distance","continuousTriangles":null}"#)
            .unwrap();
        assert_eq!(u.paused, Some(true));
        assert_eq!(u.clip, Some(Some(1)));
        assert_eq!(u.pan, Some([1.0, -2.0]));
        assert_eq!(
            u.methods,
            Some(([Method::Geomorph, Method::AlphaBlend(BlendVariant::OpaqueFirst), Method::Popping], 2))
        );
        assert_eq!(u.pitch, Some(camera::MAX_PITCH.to_degrees()));
        assert_eq!((u.crowd_count, u.by_distance, u.continuous_triangles), (Some(7), Some(true), Some(None)));
        assert_eq!(update(r#"{"clip":null}"#).unwrap().clip, Some(None));
        assert_eq!(update("{}").unwrap(), Update::default());
    }

    #[test]
    fn a_bad_key_or_value_names_the_key_and_what_it_takes() {
        let unknown = update(r#"{"paused":true,"zoom":2}"#).err().unwrap();
        assert!(
            unknown.starts_with("setState: unknown field `zoom`, expected one of `paused`, `time`"),
            "{unknown}"
        );
        for (json, message) in [
            (r#"{"zone":2}"#, "setState: zone must be a number in [0, 1], got 2"),
            (r#"{"zone":"x"}"#, r#"setState: zone must be a number, got "x""#),
            (r#"{"paused":1}"#, "setState: paused must be true or false, got 1"),
            (
                r#"{"variant":"soft"}"#,
                r#"setState: variant must be one of "opaque-first", "naive", "dither", got "soft""#,
            ),
            (
                r#"{"methods":["popping","blend"]}"#,
                r#"setState: methods[1] must be one of "popping", "alpha", "geomorph", got "blend""#,
            ),
            (
                r#"{"methods":[]}"#,
                r#"setState: methods must be one to three of "popping", "alpha", "geomorph", got 0"#,
            ),
            (r#"{"pan":[1]}"#, "setState: pan must be [x, y], two numbers in [-100, 100], got an array of 1"),
            (r#"{"pan":{"x":1}}"#, "setState: pan must be an array, each item a number, got an object"),
            (r#"{"clip":"Run"}"#, r#"setState: clip must be one of ["Walk", "Wave"] or null, got "Run""#),
            (
                r#"{"continuousTriangles":0}"#,
                "setState: continuousTriangles must be a number in [1, 1000000000], got 0",
            ),
        ] {
            assert_eq!(update(json).err().unwrap(), message, "{json}");
        }
    }
}
