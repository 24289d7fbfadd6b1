//! `viewer.replay()`: the last transition's film strip ([`crate::render::replay`]) and each
//! view's per-frame curves from the live meter's samples, as a
//! [`crate::js_api::viewer_state::Replay`] (the crops reach JavaScript as `Uint8Array`s, so no
//! picture goes through JSON).

use wasm_bindgen::prelude::*;

use super::{Inner, Viewer};
use crate::js_api::read::to_js;
use crate::js_api::viewer_state::{Replay, ReplayCurves, ReplayFrame, Rgba8};
use crate::render::meter::MeterSample;
use crate::render::replay::{change, replay_side, RecordedFrame};
use crate::render::viewer::settings::method_name;

impl Inner {
    /// Feeds the replay with a measured frame: each view's picture, and where the largest step
    /// (view against control) changed it.
    pub(super) fn record_replay(&mut self, frame: &crate::render::gpu::MeterFrame, sample: &MeterSample) {
        if self.model.crowd.is_some() {
            return;
        }
        let largest =
            sample.steps.iter().enumerate().max_by(|a, b| a.1.silhouette.total_cmp(&b.1.silhouette));
        let step = largest.filter(|(_, s)| s.silhouette > 0.0 || s.shading > 0.0).and_then(|(i, s)| {
            let (v, c) = (frame.view_picture[i], frame.control_picture[i]);
            let side = replay_side(frame.height);
            change(&frame.pictures[c], &frame.pictures[v], frame.width, frame.height, side)
                .map(|ch| (s.silhouette, ch))
        });
        let views = frame.view_picture.iter().map(|&p| frame.pictures[p].clone()).collect();
        let recorded =
            RecordedFrame { frame: sample.frame, time: sample.time, transition: sample.transition, views };
        self.replay.push(recorded, frame.width, frame.height, step);
    }
}

#[wasm_bindgen]
impl Viewer {
    /// The last transition's replay, or null before one completed (or while a measurement holds
    /// the viewer): `{ methods, levels: [from, to], size: [width, height] (the meter picture),
    /// region: [x, y, width, height] (the crop, meter pixels), frames: [{ frame, time, t, views:
    /// [Uint8Array RGBA8 crop per view] }], curves: { frame, time, running, silhouette, shading,
    /// flip, stepSilhouette, stepFlip } }`: the curves hold every measured frame from the one
    /// before the transition to the one after, per view (silhouette in % of the view, shading in
    /// mean |ΔRGB|, FLIP 0..1; `step…` against the view's control).
    pub fn replay(&self) -> Result<JsValue, JsError> {
        let Some(inner) = self.lock() else { return Ok(JsValue::NULL) };
        match inner.replay() {
            Some(replay) => to_js(&replay),
            None => Ok(JsValue::NULL),
        }
    }
}

impl Inner {
    /// The last transition's replay, `None` before one completed.
    fn replay(&self) -> Option<Replay> {
        let replay = self.replay.last.as_ref()?;
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let (first, last) = replay.span;
        let samples: Vec<&MeterSample> =
            self.meter.history.iter().filter(|s| s.frame >= first && s.frame <= last).collect();
        let per_view = |f: &dyn Fn(&MeterSample, usize) -> f32| -> Vec<Vec<f64>> {
            (0..methods.len()).map(|i| samples.iter().map(|s| f64::from(f(s, i))).collect()).collect()
        };
        let (width, height) = self.replay.size();
        Some(Replay {
            methods: methods.iter().map(|m| method_name(*m)).collect(),
            levels: [replay.levels.0, replay.levels.1],
            size: [width, height],
            region: replay.region,
            frames: replay
                .frames
                .iter()
                .map(|f| ReplayFrame {
                    frame: f.frame,
                    time: f.time,
                    t: f64::from(f.transition.t),
                    views: f.views.iter().map(|v| Rgba8(v.clone())).collect(),
                })
                .collect(),
            curves: ReplayCurves {
                frame: samples.iter().map(|s| s.frame).collect(),
                time: samples.iter().map(|s| s.time).collect(),
                running: samples.iter().map(|s| s.transition.is_running()).collect(),
                silhouette: per_view(&|s, i| 100.0 * s.views.get(i).map_or(0.0, |v| v.silhouette)),
                shading: per_view(&|s, i| s.views.get(i).map_or(0.0, |v| v.shading)),
                flip: per_view(&|s, i| s.views.get(i).map_or(0.0, |v| v.flip)),
                step_silhouette: per_view(&|s, i| 100.0 * s.steps.get(i).map_or(0.0, |v| v.silhouette)),
                step_flip: per_view(&|s, i| s.steps.get(i).map_or(0.0, |v| v.flip)),
            },
        })
    }
}
