//! `viewer.replay()`: the last transition's film strip ([`crate::render::replay`]) and each
//! view's per-frame curves from the live meter's samples, as a JavaScript object (the crops as
//! `Uint8Array`s, so no picture goes through JSON).

use wasm_bindgen::prelude::*;

use super::{Inner, Viewer};
use crate::render::meter::MeterSample;
use crate::render::replay::{change, replay_side, RecordedFrame};
use crate::render::viewer::settings::method_name;

fn set(object: &js_sys::Object, key: &str, value: impl Into<JsValue>) {
    let _ = js_sys::Reflect::set(object, &key.into(), &value.into());
}

fn numbers(values: impl IntoIterator<Item = f64>) -> js_sys::Array {
    values.into_iter().map(JsValue::from_f64).collect()
}

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
    pub fn replay(&self) -> JsValue {
        let Some(inner) = self.lock() else { return JsValue::NULL };
        let Some(replay) = &inner.replay.last else { return JsValue::NULL };
        let out = js_sys::Object::new();
        let methods = &inner.model.settings.methods[..inner.model.settings.view_count];
        set(
            &out,
            "methods",
            methods.iter().map(|m| JsValue::from_str(method_name(*m))).collect::<js_sys::Array>(),
        );
        set(&out, "levels", numbers([replay.levels.0 as f64, replay.levels.1 as f64]));
        set(&out, "size", numbers([inner.replay.size().0 as f64, inner.replay.size().1 as f64]));
        set(&out, "region", numbers(replay.region.map(f64::from)));
        let frames = js_sys::Array::new();
        for f in &replay.frames {
            let item = js_sys::Object::new();
            set(&item, "frame", f.frame as f64);
            set(&item, "time", f.time);
            set(&item, "t", f64::from(f.transition.t));
            let views: js_sys::Array =
                f.views.iter().map(|v| JsValue::from(js_sys::Uint8Array::from(v.as_slice()))).collect();
            set(&item, "views", views);
            frames.push(&item);
        }
        set(&out, "frames", frames);
        let (first, last) = replay.span;
        let samples: Vec<&MeterSample> =
            inner.meter.history.iter().filter(|s| s.frame >= first && s.frame <= last).collect();
        let curves = js_sys::Object::new();
        set(&curves, "frame", numbers(samples.iter().map(|s| s.frame as f64)));
        set(&curves, "time", numbers(samples.iter().map(|s| s.time)));
        set(
            &curves,
            "running",
            samples.iter().map(|s| JsValue::from_bool(s.transition.is_running())).collect::<js_sys::Array>(),
        );
        let per_view = |f: &dyn Fn(&MeterSample, usize) -> f32| -> js_sys::Array {
            (0..methods.len())
                .map(|i| JsValue::from(numbers(samples.iter().map(|s| f64::from(f(s, i))))))
                .collect()
        };
        set(&curves, "silhouette", per_view(&|s, i| 100.0 * s.views.get(i).map_or(0.0, |v| v.silhouette)));
        set(&curves, "shading", per_view(&|s, i| s.views.get(i).map_or(0.0, |v| v.shading)));
        set(&curves, "flip", per_view(&|s, i| s.views.get(i).map_or(0.0, |v| v.flip)));
        set(
            &curves,
            "stepSilhouette",
            per_view(&|s, i| 100.0 * s.steps.get(i).map_or(0.0, |v| v.silhouette)),
        );
        set(&curves, "stepFlip", per_view(&|s, i| s.steps.get(i).map_or(0.0, |v| v.flip)));
        set(&out, "curves", curves);
        out.into()
    }
}
