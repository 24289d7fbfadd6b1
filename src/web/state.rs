//! What `viewer.state()` and `meterHistory()` report: the model's state
//! ([`crate::render::viewer::ViewerModel::state`]), the renderer's facts, the crowd's numbers and
//! the live meter's summaries, gathered into the types of [`crate::js_api::viewer_state`] (which
//! serde hands to JavaScript as plain objects).

use super::Inner;
use crate::js_api::read::OneOf;
use crate::js_api::viewer_state::{
    CrowdState, FlipByMethod, HistorySample, LevelState, MeterChange, MeterFlip, MeterHistory, MeterState,
    MethodPop, Num, PresetKey, PresetState, PresetValueState, TransitionBy, UncontrolledPop, ViewState,
    ViewerMode, ViewerState,
};
use crate::render::meter::Pop;
use crate::render::viewer::preset::{Preset, PRESET_VALUES};
use crate::render::viewer::settings::{method_name, Settings};

impl Inner {
    /// The meter's summary: per method, the last completed transition's pop (silhouette in
    /// percent of the view's pixels, shading in mean |ΔRGB| 0..765), with the same without the
    /// control (`uncontrolled`), or `None`.
    fn meter_state(&self) -> MeterState {
        let changes = self
            .meter
            .changes()
            .iter()
            .map(|c| MeterChange {
                silhouette_mean: Num(100.0 * c.silhouette_mean),
                silhouette_peak: Num(100.0 * c.silhouette_peak),
                silhouette_per_second: Num(100.0 * c.silhouette_per_second),
                shading_mean: Num(c.shading_mean),
                shading_peak: Num(c.shading_peak),
                shading_per_second: Num(c.shading_per_second),
            })
            .collect();
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let by_method = |name: &str| -> Option<MethodPop> {
            let last = self.meter.last.as_ref()?;
            let pops: Vec<_> =
                methods.iter().zip(last).filter(|(m, _)| method_name(**m) == name).map(|(_, p)| *p).collect();
            if pops.is_empty() {
                return None;
            }
            let largest = |f: fn(&Pop) -> f32| pops.iter().map(f).fold(0.0, f32::max);
            Some(MethodPop {
                silhouette: Num(100.0 * largest(|p| p.silhouette)),
                shading: Num(largest(|p| p.shading)),
                transitions: self.meter.transitions,
                uncontrolled: UncontrolledPop {
                    silhouette: Num(100.0 * largest(|p| p.uncontrolled.silhouette)),
                    shading: Num(largest(|p| p.uncontrolled.shading)),
                },
            })
        };
        let height = crate::render::gpu::METER_HEIGHT;
        MeterState {
            on: self.model.settings.meter,
            flip_on: self.model.settings.flip,
            size: [Num((height as f32 * self.model.layout.views[0].aspect()).round()), Num(height as f32)],
            transitions: self.meter.transitions,
            samples: self.meter.history.len(),
            gaps: self.meter.gaps,
            popping: by_method("popping"),
            alpha: by_method("alpha"),
            geomorph: by_method("geomorph"),
            changes,
            flip: self.meter_flip(),
        }
    }

    /// `state().meter.flip`: LDR-FLIP of each view against the reference, `None` where the GPU
    /// cannot compute it, FLIP is off (then the history's FLIP values are 0, as on such a GPU),
    /// before a frame needed it, or in crowd mode (the meter measures no FLIP there, and the
    /// single character's last numbers are not the crowd's): the pixels per degree of the meter's
    /// picture, each view's mean error in the last measured frame, and per method the last
    /// transition's pop (its largest mean error of a frame against its control) and the same
    /// without the control (the largest frame-to-frame change of the error against the reference).
    fn meter_flip(&self) -> Option<MeterFlip> {
        let ppd =
            self.meter_frames.flip_ppd.filter(|_| self.model.settings.flip && self.model.crowd.is_none())?;
        let views =
            self.meter.history.back().map_or(Vec::new(), |s| s.views.iter().map(|v| Num(v.flip)).collect());
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let by_method = |name: &str, f: fn(&Pop) -> f32| -> Option<Num> {
            let last = self.meter.last.as_ref()?;
            let pops = methods.iter().zip(last).filter(|(m, _)| method_name(**m) == name).map(|(_, p)| f(p));
            pops.reduce(f32::max).map(|largest| Num(largest.max(0.0)))
        };
        let pops = |f: fn(&Pop) -> f32| FlipByMethod {
            popping: by_method("popping", f),
            alpha: by_method("alpha", f),
            geomorph: by_method("geomorph", f),
        };
        Some(MeterFlip {
            ppd: Num(ppd),
            views,
            pop: pops(|p| p.flip),
            uncontrolled: pops(|p| p.uncontrolled.flip),
        })
    }

    /// The meter's recent samples for the page's strip chart, oldest first: per sample, each
    /// view's difference from the reference, its step (against its control, see
    /// [`crate::render::meter`]) and both as FLIP.
    pub(super) fn meter_history(&self) -> MeterHistory {
        let methods = &self.model.settings.methods[..self.model.settings.view_count];
        let history = &self.meter.history;
        MeterHistory {
            methods: methods.iter().map(|m| method_name(*m)).collect(),
            samples: history
                .iter()
                .map(|s| HistorySample {
                    time: Num(s.time as f32),
                    transition_running: s.transition.is_running(),
                    views: s.views.iter().map(|v| (Num(100.0 * v.silhouette), Num(v.shading))).collect(),
                })
                .collect(),
            steps: history
                .iter()
                .map(|s| s.steps.iter().flat_map(|v| [Num(100.0 * v.silhouette), Num(v.shading)]).collect())
                .collect(),
            flip: history
                .iter()
                .map(|s| {
                    s.views.iter().zip(&s.steps).flat_map(|(v, step)| [Num(v.flip), Num(step.flip)]).collect()
                })
                .collect(),
        }
    }

    pub(super) fn state(&self) -> ViewerState {
        let m = &self.model;
        let s = &m.settings;
        let state = m.state();
        let views = state
            .views
            .iter()
            .enumerate()
            .map(|(i, view)| {
                let triangles: usize = match &m.crowd {
                    Some(c) => c.frame.stats.triangles.get(i).copied().unwrap_or(0),
                    None => view.drawn.iter().map(|&l| self.level_triangles(l)).sum(),
                };
                let (shown, r) = (view.transition, view.rect);
                ViewState {
                    method: view.method,
                    level: shown.from,
                    to: shown.to,
                    t: Num(shown.t),
                    triangles,
                    draws: view.drawn.len(),
                    rect: [r.x, r.y, r.width, r.height],
                }
            })
            .collect();
        let (width, height) = self.renderer.size();
        ViewerState {
            backend: self.renderer.backend,
            adapter: self.renderer.adapter_name.clone(),
            format: self.renderer.color_format_name(),
            msaa: self.renderer.sample_count(),
            composed: self.renderer.composed(),
            width,
            height,
            triangles: self.character.mesh.triangle_count(),
            joints: self.character.skeleton.joints.len(),
            clips: self.character.clips.iter().map(|c| c.name.clone()).collect(),
            clip_durations: self.character.clips.iter().map(|c| Num(c.duration())).collect(),
            clip: s.clip,
            levels: self
                .lod
                .levels
                .iter()
                .map(|l| LevelState { triangles: l.triangle_count(), error: Num(l.error) })
                .collect(),
            switch: state.switch.iter().map(|&d| Num(d)).collect(),
            levels_stop: self.clod.as_ref().and_then(|c| c.stopped_short()).map(|s| s.to_string()),
            build_ms: Num(self.lod_origin.build_ms as f32),
            built_off_main_thread: self.lod_origin.off_main_thread,
            lod_from: self.lod_origin.from,
            selected: state.selected,
            distance: Num(state.distance),
            fovy: Num(crate::render::camera::FOVY),
            anim_time: Num(m.anim_time as f32),
            paused: s.paused,
            speed: Num(s.speed),
            yaw: Num(s.yaw_degrees),
            pitch: Num(s.pitch_degrees),
            pan: s.pan.map(Num),
            distance_mode: OneOf(s.distance_mode),
            overlay: OneOf(s.overlay),
            transition: OneOf(if s.by_distance { TransitionBy::Distance } else { TransitionBy::Time }),
            duration: Num(s.duration),
            zone: Num(s.zone),
            variant: OneOf(s.variant),
            transition_speed: Num(s.transition_speed),
            magnify: Num(s.magnify),
            meter: self.meter_state(),
            continuous_triangles: m.continuous_triangles(),
            max_triangles: self.clod.as_ref().map_or(0, |_| self.character.mesh.triangle_count()),
            stacked: m.layout.stacked,
            views,
            frames: self.frames,
            morph_targets: self.character.morph_targets.len(),
            morphs: s.morphs && !self.renderer.morphs_dropped(),
            mode: OneOf(if s.crowd { ViewerMode::Crowd } else { ViewerMode::Single }),
            crowd: self.crowd_state(),
            preset: preset_state(s, s.tolerance_for(m.layout.views[0].height as f32)),
            errors: self.errors.clone(),
            warnings: self.warnings.clone(),
        }
    }

    /// What the crowd shows this frame, or `None` outside crowd mode.
    fn crowd_state(&self) -> Option<CrowdState> {
        let c = self.model.crowd.as_ref()?;
        let st = &c.frame.stats;
        Some(CrowdState {
            instances: st.instances,
            drawn: st.drawn,
            per_level: st.per_level.clone(),
            transitions: st.transitions,
            triangles_drawn: st.triangles.iter().sum(),
            triangles_full: st.triangles_full * st.triangles.len(),
            view_triangles: st.triangles.clone(),
            palette_rows: c.palette.rows,
        })
    }
}

/// `state().preset`: the preset the settings match (`None` after a control moved), the threshold
/// in pixels of this view (`tolerancePx`), and each setting the presets differ in with its current,
/// demonstration and realistic values.
fn preset_state(s: &Settings, tolerance_px: f32) -> PresetState {
    PresetState {
        name: Preset::of(s).map(OneOf),
        tolerance_px: Num(tolerance_px),
        values: PRESET_VALUES
            .iter()
            .map(|v| PresetValueState {
                key: OneOf(PresetKey(v.key)),
                label: v.label,
                value: Num(v.current(s)),
                demonstration: Num(v.demonstration),
                realistic: Num(v.realistic),
            })
            .collect(),
    }
}
