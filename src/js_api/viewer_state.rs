//! What the viewer reports to JavaScript, as Rust types serialized with serde (serde-wasm-bindgen
//! hands the page plain objects): `viewer.state()` ([`ViewerState`], one struct per object in it),
//! `meterHistory()` ([`MeterHistory`]) and `measurePopSpike()` ([`PopSpike`]). The names are the
//! page's (camelCase); `www/clod-viewer.d.ts` declares the same shapes, and
//! `tests/js/dts.test.mjs` checks it against a fully populated serialization of these types
//! (`tests/js/types/api-samples.json`, written by this crate's tests from the types themselves).
//!
//! Numbers are [`Num`]: an `f32` as its shortest decimal (`0.1`, not `0.10000000149011612`) and
//! `null` where it is not finite. The web layer (`src/web/state.rs`) fills these from the viewer.

use serde::{Serialize, Serializer};

use super::read::OneOf;
use crate::render::overlay::Overlay;
use crate::render::plan::BlendVariant;
use crate::render::viewer::preset::Preset;
use crate::render::viewer::settings::DistanceMode;

/// A number for JavaScript: finite values as the shortest decimal that reads back as the same
/// `f32`; `null` for infinities and NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f32);

impl From<f32> for Num {
    fn from(x: f32) -> Self {
        Num(x)
    }
}

impl Serialize for Num {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.0.is_finite() {
            // The decimal JavaScript would print for this f32, as an f64 (what JSON.parse gives).
            let decimal: f64 = format!("{}", self.0).parse().unwrap_or(f64::from(self.0));
            s.serialize_f64(decimal)
        } else {
            s.serialize_none()
        }
    }
}

/// `viewer.state()`: what the views show, with the settings in force.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ViewerState {
    /// `"webgpu"` or `"webgl2"`.
    pub backend: &'static str,
    pub adapter: String,
    /// The canvas's colour format.
    pub format: String,
    /// Samples per pixel.
    pub msaa: u32,
    /// Whether the views are drawn offscreen and composed onto the canvas.
    pub composed: bool,
    pub width: u32,
    pub height: u32,
    /// Triangles of the full mesh.
    pub triangles: usize,
    pub joints: usize,
    pub clips: Vec<String>,
    pub clip_durations: Vec<Num>,
    /// Index into `clips`; `None` for the rest pose.
    pub clip: Option<usize>,
    /// Finest first; one entry (the full mesh) until the levels arrive.
    pub levels: Vec<LevelState>,
    /// Each level's switch distance, × the framing distance.
    pub switch: Vec<Num>,
    /// Where and why the levels stop short of the coarsest count asked for.
    pub levels_stop: Option<String>,
    pub build_ms: Num,
    pub built_off_main_thread: bool,
    /// `"build"`, `"cache"` or `"inline"` once the levels are attached.
    pub lod_from: Option<&'static str>,
    /// The level the camera distance selects.
    pub selected: usize,
    /// × the framing distance.
    pub distance: Num,
    /// The cameras' vertical field of view, radians.
    pub fovy: Num,
    pub anim_time: Num,
    pub paused: bool,
    pub speed: Num,
    pub yaw: Num,
    pub pitch: Num,
    pub pan: [Num; 2],
    pub distance_mode: OneOf<DistanceMode>,
    pub overlay: OneOf<Overlay>,
    pub transition: OneOf<TransitionBy>,
    pub duration: Num,
    pub zone: Num,
    /// The alpha-blending view's variant.
    pub variant: OneOf<BlendVariant>,
    pub transition_speed: Num,
    pub magnify: Num,
    pub meter: MeterState,
    /// The continuous slider's triangle count; `None` when off.
    pub continuous_triangles: Option<usize>,
    /// The slider's range: the full mesh's triangles once the levels are there, else 0.
    pub max_triangles: usize,
    /// Views stacked top to bottom (a canvas taller than wide).
    pub stacked: bool,
    pub views: Vec<ViewState>,
    pub frames: u64,
    pub morph_targets: usize,
    pub morphs: bool,
    pub mode: OneOf<ViewerMode>,
    /// What the crowd shows this frame; `None` outside crowd mode.
    pub crowd: Option<CrowdState>,
    /// The preset the settings match, and what the presets set.
    pub preset: PresetState,
    pub errors: Vec<String>,
    pub warnings: Vec<String>,
}

/// One discrete level.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelState {
    pub triangles: usize,
    /// Model units, non-decreasing.
    pub error: Num,
}

/// One view of the canvas: the transition it draws this frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewState {
    /// `"popping"`, `"alpha"` or `"geomorph"`.
    pub method: &'static str,
    /// The level shown, and the level the running transition goes to (equal when none runs).
    pub level: usize,
    pub to: usize,
    /// The transition's progress, 0..1.
    pub t: Num,
    /// Triangles drawn in this view (crowd: over every instance).
    pub triangles: usize,
    /// Draw calls of the view.
    pub draws: usize,
    /// `[x, y, width, height]`, canvas pixels.
    pub rect: [u32; 4],
}

/// The live meter's summary.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MeterState {
    pub on: bool,
    /// FLIP is measured (`setState({ flip })`).
    pub flip_on: bool,
    /// The meter's picture size per view, `[width, height]` pixels.
    pub size: [Num; 2],
    pub transitions: u32,
    pub samples: usize,
    /// Frames with no free readback.
    pub gaps: u32,
    pub popping: Option<MethodPop>,
    pub alpha: Option<MethodPop>,
    pub geomorph: Option<MethodPop>,
    /// Per view, how its difference from full detail changes over the history.
    pub changes: Vec<MeterChange>,
    /// LDR-FLIP in the meter; `None` where the GPU cannot compute it, FLIP is off, or before a
    /// frame needed it.
    pub flip: Option<MeterFlip>,
}

/// The live meter's pop for one method through the last transition: its largest step, the
/// difference between a frame and its control (the same frame drawn with the view's plan of the
/// previous measured frame); 0 for a view whose plan held.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MethodPop {
    /// % of the view's pixels whose coverage the step changed.
    pub silhouette: Num,
    /// Mean |ΔRGB| per pixel both cover, 0..765.
    pub shading: Num,
    pub transitions: u32,
    /// Without the control: the largest frame-to-frame change of the difference from the
    /// full-detail reference (includes the animation's own change).
    pub uncontrolled: UncontrolledPop,
}

/// A pop measured without the control.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct UncontrolledPop {
    /// % of the view's pixels.
    pub silhouette: Num,
    /// Mean |ΔRGB|, 0..765.
    pub shading: Num,
}

/// `state().meter.flip`: LDR-FLIP of each view against the full-detail reference.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeterFlip {
    /// Pixels per degree of the meter's picture.
    pub ppd: Num,
    /// Each view's mean FLIP error in the last measured frame, 0..1.
    pub views: Vec<Num>,
    /// Per method, the last transition's FLIP pop (its largest mean error of a frame against
    /// its control).
    pub pop: FlipByMethod,
    /// The same without the control: the largest frame-to-frame change of the error against
    /// the reference.
    pub uncontrolled: FlipByMethod,
}

/// A FLIP number per method; `None` for a method no view shows (or before a transition).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FlipByMethod {
    pub popping: Option<Num>,
    pub alpha: Option<Num>,
    pub geomorph: Option<Num>,
}

/// `state().preset`: the preset the settings match (`None` once a control moved), the threshold
/// in pixels of this view, and each setting the presets differ in.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PresetState {
    pub name: Option<OneOf<Preset>>,
    /// The LOD threshold in pixels of this view (the demonstration's is per 400 px of view height).
    pub tolerance_px: Num,
    pub values: Vec<PresetValueState>,
}

/// A setting the two presets differ in: its `setState` key, what it means, its current value and
/// both presets' values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PresetValueState {
    pub key: OneOf<PresetKey>,
    pub label: &'static str,
    pub value: Num,
    pub demonstration: Num,
    pub realistic: Num,
}

/// The `setState` key of a setting the presets differ in (a name of
/// [`crate::render::viewer::preset::PRESET_VALUES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PresetKey(pub &'static str);

/// Per view, the frame-to-frame change of its difference from full detail over the history:
/// silhouette in % of the view's pixels, shading in mean |ΔRGB|.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MeterChange {
    pub silhouette_mean: Num,
    pub silhouette_peak: Num,
    pub silhouette_per_second: Num,
    pub shading_mean: Num,
    pub shading_peak: Num,
    pub shading_per_second: Num,
}

/// What the crowd shows this frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CrowdState {
    pub instances: usize,
    pub drawn: usize,
    /// Instances drawn at each level.
    pub per_level: Vec<usize>,
    pub transitions: usize,
    pub triangles_drawn: usize,
    pub triangles_full: usize,
    pub view_triangles: Vec<usize>,
    pub palette_rows: usize,
}

/// `meterHistory()`: the meter's recent samples for a strip chart, oldest first (empty while a
/// measurement holds the viewer).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MeterHistory {
    /// The method of each view.
    pub methods: Vec<&'static str>,
    pub samples: Vec<HistorySample>,
    /// Per sample, `[silhouette %, shading, … per view]`: each view's step (against its control).
    pub steps: Vec<Vec<Num>>,
    /// Per sample, `[FLIP against full detail, FLIP of the step, … per view]`, 0..1.
    pub flip: Vec<Vec<Num>>,
}

/// One frame of the history, written as the array `[seconds, transitionRunning, silhouette %,
/// shading, … per view]`.
#[derive(Clone, Debug, PartialEq)]
pub struct HistorySample {
    pub time: Num,
    pub transition_running: bool,
    /// `(silhouette %, shading)` per view.
    pub views: Vec<(Num, Num)>,
}

impl Serialize for HistorySample {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeSeq;
        let mut seq = s.serialize_seq(Some(2 + 2 * self.views.len()))?;
        seq.serialize_element(&self.time)?;
        seq.serialize_element(&self.transition_running)?;
        for (silhouette, shading) in &self.views {
            seq.serialize_element(silhouette)?;
            seq.serialize_element(shading)?;
        }
        seq.end()
    }
}

/// `measurePopSpike()`'s result: each method's largest frame-to-frame mean |ΔRGB| per pixel
/// (0..765) through one LOD switch, `None` for a method no view shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PopSpike {
    pub popping: Option<Num>,
    pub alpha: Option<Num>,
    pub geomorph: Option<Num>,
    pub variant: OneOf<BlendVariant>,
    pub level: usize,
    pub frames: u32,
    /// Where the switch was placed, × the framing distance.
    pub at: Num,
    /// The distance swept, a fraction.
    pub sweep: Num,
    /// Seconds of viewer time the measurement covered.
    pub duration: Num,
    pub views: Vec<SpikeView>,
}

/// One view's part of a pop-spike measurement.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SpikeView {
    pub method: &'static str,
    pub largest: Num,
    /// The change at every frame.
    pub series: Vec<Num>,
}

/// `flipImages()`'s result: LDR-FLIP's error map of two pictures, summarized.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FlipResult {
    pub mean: Num,
    /// The 99th percentile.
    pub p99: Num,
    pub max: Num,
    /// The pixels per degree the pictures were seen at.
    pub ppd: Num,
}

/// `replay()`: every view's meter pictures across the last transition, cropped to the region of
/// its largest change, and each view's per-frame curves from the frame before it to the frame
/// after. Its numbers are the meter's as they are (`f64`), not shortened like [`Num`]'s.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Replay {
    pub methods: Vec<&'static str>,
    /// `[from, to]` levels.
    pub levels: [usize; 2],
    /// The meter picture's `[width, height]`, pixels.
    pub size: [u32; 2],
    /// The crop, `[x, y, width, height]` in meter pixels.
    pub region: [u32; 4],
    /// The frame before the transition, evenly spread frames of it and the frame after.
    pub frames: Vec<ReplayFrame>,
    pub curves: ReplayCurves,
}

/// One frame of the replay's film strip.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplayFrame {
    pub frame: u64,
    /// Dolly seconds.
    pub time: f64,
    /// The transition's progress, 0..1.
    pub t: f64,
    /// Each view's crop.
    pub views: Vec<Rgba8>,
}

/// Per measured frame; the per-view lists hold one value per frame. Silhouette in % of the view,
/// shading in mean |ΔRGB|, FLIP 0..1; `step…` against the view's control.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ReplayCurves {
    pub frame: Vec<u64>,
    pub time: Vec<f64>,
    pub running: Vec<bool>,
    pub silhouette: Vec<Vec<f64>>,
    pub shading: Vec<Vec<f64>>,
    pub flip: Vec<Vec<f64>>,
    pub step_silhouette: Vec<Vec<f64>>,
    pub step_flip: Vec<Vec<f64>>,
}

/// RGBA8 pixels, rows top first: a `Uint8Array` in JavaScript ([`super::read::to_js`]), an
/// array of numbers in JSON.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba8(pub Vec<u8>);

impl Serialize for Rgba8 {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(&self.0)
    }
}

/// Whether transitions follow time or the camera distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransitionBy {
    Time,
    Distance,
}

/// One character, or a crowd of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewerMode {
    Single,
    Crowd,
}
