//! The viewer's settings, the changes one `setState` asks for, and the names the page and
//! JavaScript use for methods, variants and overlays (one vocabulary, parsed and reported alike).
//! Pure data: the JavaScript reader is `src/js_api/viewer_settings.rs`.

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
    /// When set, `tolerance_px` is per this many pixels of view height: the threshold scales with
    /// the view, so the switches fall at the same distances in any window (the demonstration,
    /// see [`super::preset`]). `None`: pixels, whatever the view.
    pub tolerance_height: Option<f32>,
    pub hysteresis: f32,
    /// Transitions follow the distance (morph zones) rather than time.
    pub by_distance: bool,
    /// Seconds one transition takes (time mode and the continuous slider); 0 pops.
    pub duration: f32,
    /// Morph zone, a fraction of each switch distance (distance mode).
    pub zone: f32,
    /// Slow motion of the transitions alone (1: real time, 0.1: ten times slower); the animation
    /// and the dolly keep their pace.
    pub transition_speed: f32,
    /// Magnifier: screen lengths this many times larger about the point looked at (1: off). The
    /// schedule still selects levels for the real size, so the change shown is the real one,
    /// enlarged.
    pub magnify: f32,
    /// The live transition meter runs (four small extra draws and a readback per frame).
    pub meter: bool,
    /// The meter also measures LDR-FLIP ([`crate::render::flip`]: two fragment passes per
    /// picture and one per pair; on SwiftShader, a software rasterizer, 60 % of a measured
    /// frame's time).
    pub flip: bool,
    pub variant: BlendVariant,
    /// Method of each view, left to right (top to bottom when stacked); only the first
    /// `view_count` are shown.
    pub methods: [Method; 3],
    /// How many views the canvas shows (1..=3).
    pub view_count: usize,
    /// Drawn over every view alike.
    pub overlay: Overlay,
    /// Crowd mode: the character instanced `crowd_count` times (see [`crate::render::crowd`]).
    pub crowd: bool,
    pub crowd_count: usize,
    /// The crowd selects levels (true) or draws every instance at full detail (false: the
    /// comparison that shows what LOD saves).
    pub crowd_lod: bool,
    /// Morph targets follow the clip's weights (false: the base shape, for comparison).
    pub morphs: bool,
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
            tolerance_height: None,
            // 10 %: a camera hovering at a switch distance does not flicker between levels.
            hysteresis: 0.1,
            by_distance: false,
            // Half a second per transition: long enough to see, short enough to follow a dolly.
            duration: 0.5,
            zone: 0.25,
            transition_speed: 1.0,
            magnify: 1.0,
            meter: true,
            flip: true,
            variant,
            methods: [Method::Popping, Method::AlphaBlend(variant), Method::Geomorph],
            view_count: 3,
            overlay: Overlay::None,
            crowd: false,
            crowd_count: crate::render::crowd::DEFAULT_INSTANCES,
            crowd_lod: true,
            morphs: true,
        }
    }
}

impl Settings {
    /// The threshold in pixels of a view `view_height` pixels tall (see `tolerance_height`).
    pub fn tolerance_for(&self, view_height: f32) -> f32 {
        match self.tolerance_height {
            Some(reference) if reference > 0.0 => self.tolerance_px * view_height / reference,
            _ => self.tolerance_px,
        }
    }

    /// Takes `previous`'s comparison settings: what a reader chose for one model and expects to
    /// keep when they open another in the same viewer. The thresholds and transitions, the views'
    /// methods and variant, the camera distance's mode (distances are in framing distances, so they
    /// mean the same on any model), the magnifier, overlay, meter, FLIP, crowd and morphs carry
    /// over. What belongs to the model shown stays as the new viewer set it: the clip and whether
    /// it plays, and the orbit (yaw, pitch and pan: a new model is framed from the front again).
    pub fn keep_from(&mut self, previous: &Settings) {
        // Everything else is the reader's choice: a setting added later carries over unless named here.
        *self = Settings {
            paused: self.paused,
            clip: self.clip,
            yaw_degrees: self.yaw_degrees,
            pitch_degrees: self.pitch_degrees,
            pan: self.pan,
            ..previous.clone()
        };
    }

    /// How the schedule drives transitions.
    pub fn transition_mode(&self) -> TransitionMode {
        if self.by_distance {
            TransitionMode::Distance { zone: self.zone }
        } else {
            TransitionMode::Time { seconds: self.duration }
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
    /// `Some(true)`: distance-driven transitions.
    pub by_distance: Option<bool>,
    pub duration: Option<f32>,
    pub zone: Option<f32>,
    pub transition_speed: Option<f32>,
    pub magnify: Option<f32>,
    pub meter: Option<bool>,
    pub flip: Option<bool>,
    pub variant: Option<BlendVariant>,
    /// The methods of the first views and how many views there are.
    pub methods: Option<([Method; 3], usize)>,
    pub overlay: Option<Overlay>,
    /// `Some(None)` turns the continuous level off; counts are those of progressive-mesh states.
    pub continuous_triangles: Option<Option<u32>>,
    /// `Some(true)`: crowd mode; `Some(false)`: the single character.
    pub crowd: Option<bool>,
    /// Instances of the crowd (1..=[`crate::render::crowd::MAX_INSTANCES`]).
    pub crowd_count: Option<usize>,
    pub crowd_lod: Option<bool>,
    pub morphs: Option<bool>,
    /// A preset's settings, applied before the call's other keys (see [`super::preset`]).
    pub preset: Option<super::preset::Preset>,
    /// A preset's threshold alone, with its unit, applied after `preset` and before `tolerance`.
    pub tolerance_of: Option<super::preset::Preset>,
}

impl Update {
    /// Applies the changes to the settings (the clock and the continuous level are the model's).
    pub fn apply(&self, s: &mut Settings) {
        macro_rules! set {
            ($field:ident, $value:expr) => {
                if let Some(v) = $value {
                    s.$field = v;
                }
            };
        }
        if let Some(preset) = self.preset {
            preset.apply(s);
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
        if let Some(preset) = self.tolerance_of {
            preset.apply_threshold(s);
        }
        if let Some(tolerance) = self.tolerance {
            // A threshold given in pixels is pixels, whatever the view.
            s.tolerance_px = tolerance;
            s.tolerance_height = None;
        }
        set!(hysteresis, self.hysteresis);
        set!(overlay, self.overlay);
        set!(by_distance, self.by_distance);
        set!(duration, self.duration);
        set!(zone, self.zone);
        set!(transition_speed, self.transition_speed);
        set!(magnify, self.magnify);
        set!(meter, self.meter);
        set!(flip, self.flip);
        set!(crowd, self.crowd);
        set!(crowd_lod, self.crowd_lod);
        set!(morphs, self.morphs);
        set!(crowd_count, self.crowd_count.map(|n| n.clamp(1, crate::render::crowd::MAX_INSTANCES)));
        if self.distance.is_some() && self.distance_mode.is_none() {
            // Moving the distance slider takes the camera over from the dolly.
            s.distance_mode = DistanceMode::Manual;
        }
        if let Some((methods, count)) = self.methods {
            s.methods = methods;
            s.view_count = count;
        }
        set!(variant, self.variant);
        for m in &mut s.methods {
            if let Method::AlphaBlend(_) = m {
                *m = Method::AlphaBlend(s.variant);
            }
        }
    }
}

/// The page's names of the methods, in view order of the default page.
pub const METHOD_NAMES: [&str; 3] = ["popping", "alpha", "geomorph"];
/// The page's names of the alpha-blending variants.
pub const VARIANT_NAMES: [&str; 3] = ["opaque-first", "naive", "dither"];
/// The page's names of the overlays.
pub const OVERLAY_NAMES: [&str; 5] = ["none", "wireframe", "levels", "skeleton", "difference"];

/// The page's name of a method.
pub fn method_name(m: Method) -> &'static str {
    match m {
        Method::Popping => METHOD_NAMES[0],
        Method::AlphaBlend(_) => METHOD_NAMES[1],
        Method::Geomorph => METHOD_NAMES[2],
    }
}

/// The method of a page name (alpha-blending with `variant`).
pub fn method_named(name: &str, variant: BlendVariant) -> Option<Method> {
    match METHOD_NAMES.iter().position(|&n| n == name)? {
        0 => Some(Method::Popping),
        1 => Some(Method::AlphaBlend(variant)),
        _ => Some(Method::Geomorph),
    }
}

/// The page's name of an alpha-blending variant.
pub fn variant_name(v: BlendVariant) -> &'static str {
    match v {
        BlendVariant::OpaqueFirst => VARIANT_NAMES[0],
        BlendVariant::Naive => VARIANT_NAMES[1],
        BlendVariant::Dither => VARIANT_NAMES[2],
    }
}

/// The variant of a page name.
pub fn variant_named(name: &str) -> Option<BlendVariant> {
    [BlendVariant::OpaqueFirst, BlendVariant::Naive, BlendVariant::Dither]
        .into_iter()
        .find(|&v| variant_name(v) == name)
}

/// The page's name of an overlay.
pub fn overlay_name(o: Overlay) -> &'static str {
    match o {
        Overlay::None => OVERLAY_NAMES[0],
        Overlay::Wireframe => OVERLAY_NAMES[1],
        Overlay::Levels => OVERLAY_NAMES[2],
        Overlay::Skeleton => OVERLAY_NAMES[3],
        Overlay::Difference => OVERLAY_NAMES[4],
    }
}

/// The overlay of a page name.
pub fn overlay_named(name: &str) -> Option<Overlay> {
    [Overlay::None, Overlay::Wireframe, Overlay::Levels, Overlay::Skeleton, Overlay::Difference]
        .into_iter()
        .find(|&o| overlay_name(o) == name)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn names_round_trip() {
        for name in METHOD_NAMES {
            assert_eq!(method_name(method_named(name, BlendVariant::Dither).unwrap()), name);
        }
        for name in VARIANT_NAMES {
            assert_eq!(variant_name(variant_named(name).unwrap()), name);
        }
        for name in OVERLAY_NAMES {
            assert_eq!(overlay_name(overlay_named(name).unwrap()), name);
        }
        assert_eq!(method_named("blend", BlendVariant::Naive), None);
    }

    #[test]
    fn a_distance_takes_the_camera_from_the_dolly_and_the_variant_follows() {
        let mut s = Settings::default();
        Update { distance: Some(3.0), variant: Some(BlendVariant::Dither), ..Default::default() }
            .apply(&mut s);
        assert_eq!((s.distance_mode, s.manual_distance), (DistanceMode::Manual, 3.0));
        assert_eq!(s.methods[1], Method::AlphaBlend(BlendVariant::Dither));
        Update { by_distance: Some(true), zone: Some(0.4), ..Default::default() }.apply(&mut s);
        assert_eq!(s.transition_mode(), TransitionMode::Distance { zone: 0.4 });
    }
}
