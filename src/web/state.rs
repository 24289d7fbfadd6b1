//! What `viewer.state()`, `meterHistory()` and the meter report, as JSON text: the model's state
//! ([`crate::render::viewer::ViewerModel::state`]), the renderer's facts, the crowd's numbers and
//! the live meter's summaries, with the page's names.

use super::Inner;
use crate::render::viewer::settings::{method_name, overlay_name, DistanceMode};

impl Inner {
    /// The meter's summary for `state()`: per method, the last completed transition's pop
    /// (silhouette in percent of the view's pixels, shading in mean |ΔRGB| 0..765), with the
    /// same without the control (`uncontrolled`), or null.
    fn meter_json(&self) -> String {
        // Per view, the frame-to-frame change of its difference over the history: silhouette in
        // percent of the view's pixels, shading in mean |ΔRGB|.
        let changes: Vec<String> = self
            .meter
            .changes()
            .iter()
            .map(|c| {
                format!(
                    "{{\"silhouetteMean\":{},\"silhouettePeak\":{},\"silhouettePerSecond\":{},\"shadingMean\":{},\"shadingPeak\":{},\"shadingPerSecond\":{}}}",
                    num(100.0 * c.silhouette_mean),
                    num(100.0 * c.silhouette_peak),
                    num(100.0 * c.silhouette_per_second),
                    num(c.shading_mean),
                    num(c.shading_peak),
                    num(c.shading_per_second)
                )
            })
            .collect();
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let by_method = |name: &str| -> String {
            let Some(last) = &self.meter.last else { return "null".into() };
            let pops: Vec<_> =
                methods.iter().zip(last).filter(|(m, _)| method_name(**m) == name).map(|(_, p)| *p).collect();
            if pops.is_empty() {
                return "null".into();
            }
            let largest = |f: fn(&crate::render::meter::Pop) -> f32| pops.iter().map(f).fold(0.0, f32::max);
            format!(
                "{{\"silhouette\":{},\"shading\":{},\"transitions\":{},\"uncontrolled\":{{\"silhouette\":{},\"shading\":{}}}}}",
                num(100.0 * largest(|p| p.silhouette)),
                num(largest(|p| p.shading)),
                self.meter.transitions,
                num(100.0 * largest(|p| p.uncontrolled.silhouette)),
                num(largest(|p| p.uncontrolled.shading)),
            )
        };
        format!(
            "{{\"on\":{},\"size\":[{},{}],\"transitions\":{},\"samples\":{},\"gaps\":{},\"popping\":{},\"alpha\":{},\"geomorph\":{},\"changes\":[{}],\"flip\":{}}}",
            self.model.settings.meter,
            (crate::render::gpu::METER_HEIGHT as f32 * self.model.layout.views[0].aspect()).round(),
            crate::render::gpu::METER_HEIGHT,
            self.meter.transitions,
            self.meter.history.len(),
            self.meter.gaps,
            by_method("popping"),
            by_method("alpha"),
            by_method("geomorph"),
            changes.join(","),
            self.flip_json(),
        )
    }

    /// `state().meter.flip`: LDR-FLIP of each view against the reference, `null` where the GPU
    /// cannot compute it (or before a frame needed it): the pixels per degree of the meter's
    /// picture, each view's mean error in the last measured frame, and per method the last
    /// transition's pop (its largest mean error of a frame against its control) and the same
    /// without the control (the largest frame-to-frame change of the error against the reference).
    fn flip_json(&self) -> String {
        let Some(ppd) = self.flip_ppd else { return "null".into() };
        let views: Vec<String> =
            self.meter.history.back().map_or(Vec::new(), |s| s.views.iter().map(|v| num(v.flip)).collect());
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let by_method = |name: &str, f: fn(&crate::render::meter::Pop) -> f32| -> String {
            let Some(last) = &self.meter.last else { return "null".into() };
            let pops: Vec<f32> = methods
                .iter()
                .zip(last)
                .filter(|(m, _)| method_name(**m) == name)
                .map(|(_, p)| f(p))
                .collect();
            if pops.is_empty() {
                return "null".into();
            }
            num(pops.into_iter().fold(0.0, f32::max))
        };
        let pops = |f: fn(&crate::render::meter::Pop) -> f32| {
            format!(
                "{{\"popping\":{},\"alpha\":{},\"geomorph\":{}}}",
                by_method("popping", f),
                by_method("alpha", f),
                by_method("geomorph", f)
            )
        };
        format!(
            "{{\"ppd\":{},\"views\":[{}],\"pop\":{},\"uncontrolled\":{}}}",
            num(ppd),
            views.join(","),
            pops(|p| p.flip),
            pops(|p| p.uncontrolled.flip)
        )
    }

    /// The meter's recent samples for the page's strip chart: `{ methods, samples: [[time,
    /// transitionRunning, silhouette % and shading of each view…]], steps: [[silhouette % and
    /// shading of each view's step…]], flip: [[FLIP against the reference and FLIP of the step,
    /// per view…]] }` (steps: against each view's control, see [`crate::render::meter`]), oldest
    /// first.
    pub(super) fn meter_history_json(&self) -> String {
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let names: Vec<String> = methods.iter().map(|m| json_str(method_name(*m))).collect();
        let samples: Vec<String> = self
            .meter
            .history
            .iter()
            .map(|s| {
                let values: Vec<String> =
                    s.views.iter().flat_map(|v| [num(100.0 * v.silhouette), num(v.shading)]).collect();
                format!("[{},{},{}]", num(s.time as f32), s.transition.is_running(), values.join(","))
            })
            .collect();
        let steps: Vec<String> = self
            .meter
            .history
            .iter()
            .map(|s| {
                let values: Vec<String> =
                    s.steps.iter().flat_map(|v| [num(100.0 * v.silhouette), num(v.shading)]).collect();
                format!("[{}]", values.join(","))
            })
            .collect();
        let flip: Vec<String> = self
            .meter
            .history
            .iter()
            .map(|s| {
                let values: Vec<String> = s
                    .views
                    .iter()
                    .zip(&s.steps)
                    .flat_map(|(v, step)| [num(v.flip), num(step.flip)])
                    .collect();
                format!("[{}]", values.join(","))
            })
            .collect();
        format!(
            "{{\"methods\":[{}],\"samples\":[{}],\"steps\":[{}],\"flip\":[{}]}}",
            names.join(","),
            samples.join(","),
            steps.join(","),
            flip.join(",")
        )
    }

    pub(super) fn state_json(&self) -> String {
        let m = &self.model;
        let s = &m.settings;
        let levels: Vec<String> = self
            .lod
            .levels
            .iter()
            .map(|l| format!("{{\"triangles\":{},\"error\":{}}}", l.triangle_count(), num(l.error)))
            .collect();
        let state = m.state();
        let views: Vec<String> = state
            .views
            .iter()
            .enumerate()
            .map(|(i, view)| {
                let triangles: usize = match &m.crowd {
                    Some(c) => c.frame.stats.triangles.get(i).copied().unwrap_or(0),
                    None => view.drawn.iter().map(|&l| self.level_triangles(l)).sum(),
                };
                let (shown, r) = (view.transition, view.rect);
                format!(
                    "{{\"method\":{},\"level\":{},\"to\":{},\"t\":{},\"triangles\":{},\"draws\":{},\"rect\":[{},{},{},{}]}}",
                    json_str(view.method),
                    shown.from,
                    shown.to,
                    num(shown.t),
                    triangles,
                    view.drawn.len(),
                    r.x,
                    r.y,
                    r.width,
                    r.height
                )
            })
            .collect();
        let list = |v: &[String]| v.iter().map(|e| json_str(e)).collect::<Vec<_>>().join(",");
        let (w, h) = self.renderer.size();
        let switch: Vec<String> = state.switch.iter().map(|&d| num(d)).collect();
        format!(
            concat!(
                "{{\"backend\":{},\"adapter\":{},\"format\":{},\"msaa\":{},\"composed\":{},\"width\":{},\"height\":{},",
                "\"triangles\":{},\"joints\":{},\"clips\":[{}],\"clipDurations\":[{}],\"clip\":{},\"levels\":[{}],\"switch\":[{}],\"levelsStop\":{},\"buildMs\":{},\"builtOffMainThread\":{},\"lodFrom\":{},",
                "\"selected\":{},\"distance\":{},\"fovy\":{},\"animTime\":{},\"paused\":{},\"speed\":{},",
                "\"yaw\":{},\"pitch\":{},\"pan\":[{},{}],\"distanceMode\":{},\"overlay\":{},",
                "\"transition\":{},\"duration\":{},\"zone\":{},\"transitionSpeed\":{},\"magnify\":{},",
                "\"meter\":{},\"continuousTriangles\":{},\"maxTriangles\":{},\"stacked\":{},\"views\":[{}],\"frames\":{},",
                "\"morphTargets\":{},\"morphs\":{},\"mode\":{},\"crowd\":{},\"preset\":{},\"errors\":[{}],\"warnings\":[{}]}}"
            ),
            json_str(self.renderer.backend),
            json_str(&self.renderer.adapter_name),
            json_str(&self.renderer.color_format_name()),
            self.renderer.sample_count(),
            self.renderer.composed(),
            w,
            h,
            self.character.mesh.triangle_count(),
            self.character.skeleton.joints.len(),
            list(&self.character.clips.iter().map(|c| c.name.clone()).collect::<Vec<_>>()),
            self.character.clips.iter().map(|c| num(c.duration())).collect::<Vec<_>>().join(","),
            s.clip.map_or("null".to_string(), |c| c.to_string()),
            levels.join(","),
            switch.join(","),
            self.clod.as_ref().and_then(|c| c.stopped_short()).map_or("null".to_string(), |s| json_str(&s.to_string())),
            num(self.build_ms as f32),
            self.built_off_main_thread,
            self.lod_from.map_or("null".to_string(), json_str),
            state.selected,
            num(state.distance),
            num(crate::render::camera::FOVY),
            num(m.anim_time as f32),
            s.paused,
            num(s.speed),
            num(s.yaw_degrees),
            num(s.pitch_degrees),
            num(s.pan[0]),
            num(s.pan[1]),
            json_str(if s.distance_mode == DistanceMode::Manual { "manual" } else { "dolly" }),
            json_str(overlay_name(s.overlay)),
            json_str(if s.by_distance { "distance" } else { "time" }),
            num(s.duration),
            num(s.zone),
            num(s.transition_speed),
            num(s.magnify),
            self.meter_json(),
            m.continuous_triangles().map_or("null".to_string(), |t| t.to_string()),
            self.clod.as_ref().map_or(0, |_| self.character.mesh.triangle_count()),
            m.layout.stacked,
            views.join(","),
            self.frames,
            self.character.morph_targets.len(),
            s.morphs && !self.renderer.morphs_dropped(),
            json_str(if s.crowd { "crowd" } else { "single" }),
            self.crowd_json(),
            preset_json(s, s.tolerance_for(m.layout.views[0].height as f32)),
            list(&self.errors),
            list(&self.warnings),
        )
    }

    /// `state().crowd`: what the crowd shows this frame, or null outside crowd mode.
    fn crowd_json(&self) -> String {
        let Some(c) = &self.model.crowd else { return "null".into() };
        let st = &c.frame.stats;
        let list = |v: &[usize]| v.iter().map(usize::to_string).collect::<Vec<_>>().join(",");
        format!(
            "{{\"instances\":{},\"drawn\":{},\"perLevel\":[{}],\"transitions\":{},\"trianglesDrawn\":{},\"trianglesFull\":{},\"viewTriangles\":[{}],\"paletteRows\":{}}}",
            st.instances,
            st.drawn,
            list(&st.per_level),
            st.transitions,
            st.triangles.iter().sum::<usize>(),
            st.triangles_full * st.triangles.len(),
            list(&st.triangles),
            c.palette.rows,
        )
    }
}

/// `state().preset`: the preset the settings match (`null` after a control moved), the threshold
/// in pixels of this view (`tolerancePx`), and each setting the presets differ in with its current,
/// demonstration and realistic values.
fn preset_json(s: &crate::render::viewer::settings::Settings, tolerance_px: f32) -> String {
    use crate::render::viewer::preset::{Preset, PRESET_VALUES};
    let values: Vec<String> = PRESET_VALUES
        .iter()
        .map(|v| {
            format!(
                "{{\"key\":{},\"label\":{},\"value\":{},\"demonstration\":{},\"realistic\":{}}}",
                json_str(v.key),
                json_str(v.label),
                num(v.current(s)),
                num(v.demonstration),
                num(v.realistic)
            )
        })
        .collect();
    let name = Preset::of(s).map_or("null".to_string(), |p| json_str(p.name()));
    format!("{{\"name\":{},\"tolerancePx\":{},\"values\":[{}]}}", name, num(tolerance_px), values.join(","))
}

pub(super) fn num(x: f32) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "null".into()
    }
}

pub(super) fn json_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
