//! `viewer.measurePopSpike(options)`: the pop spike of each view, measured by the viewer itself
//! (issue 5's test 3, and the page's "measure" button).
//!
//! With the animation paused at the current pose, the camera moves slowly (`sweep`, a fraction of
//! the distance) through the switch to level `level`, one frame per 1/60 s of viewer time. The
//! switch sits at `at` framing distances: the tolerance is scaled for the measurement so that the
//! character stays large whatever level is measured (switch distances scale as 1 / tolerance).
//! The camera crosses the switch a quarter of the way through the frames and the time-driven
//! transition lasts half of them, so it starts and ends inside the run. Every frame is drawn
//! offscreen and read back; [`SpikeMeter`] keeps each view's frame-to-frame changes. Afterwards
//! the settings, clocks, schedule and camera are what they were.

use wasm_bindgen::prelude::*;

use super::{wait_for, Inner, Viewer};
use crate::js_api::read::{read, to_js, Number, OneOf};
use crate::js_api::viewer_settings::SpikeOptions;
use crate::js_api::viewer_state::{Num, PopSpike, SpikeView};
use crate::render::pop_spike::SpikeMeter;
use crate::render::schedule::{Schedule, Transition};
use crate::render::viewer::settings::{method_name, DistanceMode};

/// Frames of a measurement by default: the transition gets 48 of them. A geomorph's frame change
/// does not shrink as 1/frames (8-bit rounding of the slowly changing shading flips pixels every
/// frame): measured on the built-in character, 48 frames put its spike at 8-12 % of popping's, 96
/// at 6-8 %. 96 frames are 1.6 s of viewer time and about 5 s on SwiftShader at 668 × 223.
const DEFAULT_FRAMES: u32 = 96;
/// Distance swept over the run, as a fraction: small, so the camera's own motion changes the
/// picture far less than a pop does.
const DEFAULT_SWEEP: f32 = 0.008;
/// Where the switch is placed, in framing distances: framed, the character fills the view's
/// height, so a level's change covers the most pixels.
const DEFAULT_AT: f32 = 1.0;
/// Viewer time per measured frame, seconds (a 60 Hz display).
const FRAME_SECONDS: f64 = 1.0 / 60.0;

/// What `measurePopSpike` was asked for.
struct SpikeRequest {
    /// The level switched to (from `level − 1`).
    level: usize,
    frames: u32,
    sweep: f32,
    at: f32,
}

/// Reads the options ([`SpikeOptions`]): `level` (default the coarsest: the biggest change of
/// shape), `frames`, `sweep`, `at`; unknown keys are an error.
fn parse_options(options: JsValue, levels: usize) -> Result<SpikeRequest, String> {
    const CALL: &str = "measurePopSpike";
    if levels < 2 {
        return Err("the viewer has one level only: there is no change of level to measure".into());
    }
    let o: SpikeOptions = if options.is_undefined() || options.is_null() {
        SpikeOptions::default()
    } else {
        read(CALL, options, "{ level: 3, frames: 48 }")?
    };
    let within = |n: Option<Number>, key, lo, hi, default: f64| match n {
        Some(n) => n.within(CALL, key, lo, hi),
        None => Ok(default),
    };
    Ok(SpikeRequest {
        level: within(o.level, "level", 1.0, (levels - 1) as f64, (levels - 1) as f64)?.round() as usize,
        // At least 8 frames so the transition spans several; at most 600 (10 s of 60 Hz).
        frames: within(o.frames, "frames", 8.0, 600.0, DEFAULT_FRAMES.into())?.round() as u32,
        sweep: within(o.sweep, "sweep", 1e-4, 0.5, DEFAULT_SWEEP.into())? as f32,
        at: within(o.at, "at", 0.5, 50.0, DEFAULT_AT.into())? as f32,
    })
}

#[wasm_bindgen]
impl Viewer {
    /// Measures each view's pop spike at the current pose and resolves to
    /// `{ popping, alpha, geomorph, level, frames, at, sweep, duration, views }`: the largest
    /// frame-to-frame mean `|ΔR|+|ΔG|+|ΔB|` per pixel (0..765) of the view showing each method
    /// (`null` when no view shows it; the largest when several do), and per view
    /// `{ method, largest, series }`. `options` (all optional): `level` (the switch to this level
    /// from the one before; default the coarsest), `frames` (default 96), `sweep` (fraction of
    /// the distance moved, default 0.008), `at` (framing distances where the switch is placed,
    /// default 1). Alpha-blending uses the current `variant`.
    ///
    /// Takes `frames` offscreen draws and readbacks (a few seconds on a software rasterizer);
    /// meanwhile the viewer draws no frames and queues the setters. Rejects when the viewer has
    /// one level only, an option is out of range, or a readback fails; the viewer's settings are
    /// restored in every case.
    #[wasm_bindgen(js_name = measurePopSpike)]
    #[allow(clippy::await_holding_refcell_ref)] // as in read_pixels: the viewer stays locked meanwhile
    pub fn measure_pop_spike(&self, options: JsValue) -> js_sys::Promise {
        let inner = std::rc::Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let mut guard = wait_for(&inner).await;
            let options =
                parse_options(options, guard.lod.levels.len()).map_err(|e| JsValue::from_str(&e))?;
            let saved = (guard.model.clone(), guard.last_now_ms);
            let result = guard.measure(&options).await;
            (guard.model, guard.last_now_ms) = saved;
            let spike = result.map_err(|e| JsValue::from_str(&e))?;
            Ok(to_js(&spike)?)
        })
    }
}

impl Inner {
    /// Runs the measurement (see the module docs).
    async fn measure(&mut self, o: &SpikeRequest) -> Result<PopSpike, String> {
        let k = o.level;
        let current = self.model.switch_distances()[k];
        if !(current.is_finite() && current > 0.0) {
            return Err(format!("level {k} has no switch distance (its error is 0): nothing pops"));
        }
        let framing = self.model.framing;
        let m = &mut self.model;
        m.slider = None;
        let s = &mut m.settings;
        s.tolerance_px *= current / (o.at * framing);
        s.paused = true;
        s.distance_mode = DistanceMode::Manual;
        let duration = (o.frames / 2) as f64 * FRAME_SECONDS;
        s.by_distance = false;
        s.duration = duration as f32;
        s.transition_speed = 1.0;
        // Coarsening happens at the switch distance × (1 + hysteresis).
        let crossing = o.at * (1.0 + s.hysteresis.max(0.0));
        m.schedule = Schedule { selected: k - 1, transition: Transition::at(k - 1) };
        let start_ms = self.last_now_ms.unwrap_or(0.0);
        self.last_now_ms = Some(start_ms);
        let mut meter = SpikeMeter::default();
        let mut selected = Vec::with_capacity(o.frames as usize);
        for i in 0..o.frames {
            let f = i as f32 / (o.frames - 1) as f32;
            self.model.settings.manual_distance = crossing * (1.0 + o.sweep * (f - 0.25));
            self.advance(start_ms + (i + 1) as f64 * FRAME_SECONDS * 1000.0);
            selected.push(self.model.schedule.selected);
            let input = self.posed.frame_input(&self.model);
            let pixels = self.renderer.read_pixels(&input).await.map_err(|e| e.to_string())?;
            meter.push(pixels.rgba, pixels.width, self.model.layout.views);
        }
        if selected.first() != Some(&(k - 1)) || selected.last() != Some(&k) {
            return Err(format!(
                "the sweep did not cross the switch from level {} to {k} (levels shown: {selected:?})",
                k - 1
            ));
        }
        if self.model.plans.iter().any(|p| p.transition.is_running()) {
            return Err(format!("the transition to level {k} did not end within {} frames", o.frames));
        }
        Ok(self.spike(o, &meter, duration))
    }

    fn spike(&self, o: &SpikeRequest, meter: &SpikeMeter, duration: f64) -> PopSpike {
        let largest = meter.largest();
        let names = self.model.settings.methods.map(method_name);
        let by_method = |name: &str| {
            let values = (0..3).filter(|&i| names[i] == name).map(|i| largest[i]);
            values.reduce(f32::max).map(Num)
        };
        PopSpike {
            popping: by_method("popping"),
            alpha: by_method("alpha"),
            geomorph: by_method("geomorph"),
            variant: OneOf(self.model.settings.variant),
            level: o.level,
            frames: o.frames,
            at: Num(o.at),
            sweep: Num(o.sweep),
            duration: Num(duration as f32),
            views: (0..3)
                .map(|i| SpikeView {
                    method: names[i],
                    largest: Num(largest[i]),
                    series: meter.series[i].iter().map(|&x| Num(x)).collect(),
                })
                .collect(),
        }
    }
}
