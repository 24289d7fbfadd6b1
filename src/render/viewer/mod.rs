//! The viewer's application model: settings, the animation and dolly clocks, the camera, the one
//! LOD schedule every view shares, the continuous slider's morphs and each view's draw plan.
//! Pure and native-testable; `src/web` is its thin JavaScript face and `render::gpu` draws the
//! plans (the split of the wgpu examples' `Example` and eframe's `App`).
//!
//! Per frame the web layer calls [`ViewerModel::advance`] with the elapsed seconds, then draws
//! `plans` with the pose at `anim_time`. Distances are model units inside; the page sees them as
//! multiples of the framing distance (the animated bounding sphere fills a view at 1).
//!
//! The continuous slider moves through progressive-mesh states given by their triangle counts; a
//! new count morphs from the state shown to the new one over one transition duration (Hoppe 1996
//! §3.2: a geomorph joins any two states). Its two meshes are drawn as levels `levels` (the finer
//! state) and `levels + 1` (the coarser), so the plans read like those of discrete levels.

pub mod preset;
pub mod settings;

use glam::{Vec2, Vec3};

use super::camera::{self, OrbitCamera, FOVY};
use super::crowd::{Crowd, CrowdFrame, CrowdParams, PosePalette};
use super::layout::{layout, Layout, Rect};
use super::plan::{plan_view, ViewPlan};
use super::schedule::{self, advance_time, Schedule, Transition};
use crate::character::Character;
use settings::{DistanceMode, Settings, Update};

/// Longest step of the clocks per frame, seconds: a tab that was hidden for a minute resumes
/// where it was instead of jumping.
pub const MAX_STEP: f64 = 0.1;

/// The viewer's state between frames (see the module docs). `Clone`, so a measurement can save
/// and restore it whole.
#[derive(Clone, Debug)]
pub struct ViewerModel {
    pub settings: Settings,
    /// Animation clock, seconds.
    pub anim_time: f64,
    /// Dolly clock, seconds (runs while the animation is paused, so a paused pose can be dollied).
    pub dolly_time: f64,
    pub schedule: Schedule,
    /// The continuous slider's morph between progressive-mesh states (triangle counts), when on.
    pub slider: Option<Transition>,
    /// The slider's latest request; reached after the running morph.
    slider_goal: usize,
    pub camera: OrbitCamera,
    /// Framing distance for the current view shape (model units).
    pub framing: f32,
    /// Camera distance this frame (model units).
    pub distance: f32,
    pub layout: Layout,
    /// Canvas size, framebuffer pixels.
    canvas: (u32, u32),
    pub plans: [ViewPlan; 3],
    /// Geometric error of every discrete level, finest first (model units).
    errors: Vec<f32>,
    /// Crowd mode's state, while on (see [`ViewerModel::start_crowd`]).
    pub crowd: Option<CrowdState>,
    /// Counts the changes of what the views draw that are neither the clock nor a transition:
    /// crowd mode on or off, the crowd laid out again or given another clip, the levels
    /// replaced, the canvas resized. The meter compares only frames of one scene
    /// (`MeterSample::scene`): across such a change, every view's picture jumps alike.
    pub scene: u64,
}

/// Seed of every crowd's layout: the same crowd on every visit and in every test.
pub const CROWD_SEED: u64 = 2011;

/// Crowd mode's state: the crowd, the pose palette its instances read, each level's triangle
/// count and what the views draw this frame.
#[derive(Clone, Debug)]
pub struct CrowdState {
    pub crowd: Crowd,
    pub palette: PosePalette,
    pub level_triangles: Vec<usize>,
    pub frame: CrowdFrame,
    /// The view aspect it was laid out for.
    aspect: f32,
}

impl ViewerModel {
    /// A model framing the sphere `(centre, radius)` (see [`animated_sphere`]) on a `width` ×
    /// `height` canvas, with levels of geometric `errors` (finest first, at least one).
    pub fn new(sphere: (Vec3, f32), errors: Vec<f32>, width: u32, height: u32) -> Self {
        let settings = Settings::default();
        let (center, radius) = sphere;
        let layout = layout(width, height, settings.view_count);
        let framing = camera::framing_distance_for(radius, layout.views[0].aspect());
        let camera = OrbitCamera {
            target: center,
            radius,
            distance: framing,
            yaw: settings.yaw_degrees.to_radians(),
            pitch: settings.pitch_degrees.to_radians(),
            pan: Vec2::ZERO,
            zoom: 1.0,
        };
        let rest = plan_view(settings.methods[0], &Transition::at(0));
        let mut model = Self {
            settings,
            anim_time: 0.0,
            dolly_time: 0.0,
            schedule: Schedule::FINEST,
            slider: None,
            slider_goal: 0,
            camera,
            framing,
            distance: framing,
            layout,
            canvas: (width, height),
            plans: [rest.clone(), rest.clone(), rest],
            errors: if errors.is_empty() { vec![0.0] } else { errors },
            crowd: None,
            scene: 0,
        };
        model.advance(0.0);
        model.settle();
        model
    }

    /// Shows the selected level at rest, without a transition: a first frame (or a new set of
    /// levels) starts where the distance puts it rather than morphing from the finest level.
    pub fn settle(&mut self) {
        let selected = self.schedule.selected;
        self.schedule.transition = Transition::at(selected);
        if self.slider.is_none() {
            self.plans = self.settings.methods.map(|m| plan_view(m, &self.schedule.transition));
        }
    }

    /// Number of discrete levels.
    pub fn level_count(&self) -> usize {
        self.errors.len()
    }

    /// Geometric error of every discrete level, finest first.
    pub fn errors(&self) -> &[f32] {
        &self.errors
    }

    /// Replaces the discrete levels (their geometric errors, finest first): the levels arriving
    /// after the full mesh was shown alone. The slider turns off, the dolly starts its sweep
    /// again from the framing distance (so a reader sees the levels change from the start of a
    /// sweep, however long the build took) and the view settles at the level the distance
    /// selects, without a transition from the finest.
    pub fn set_levels(&mut self, errors: Vec<f32>) {
        self.errors = if errors.is_empty() { vec![0.0] } else { errors };
        self.slider = None;
        self.dolly_time = 0.0;
        // The crowd is laid out for the levels' switch distances: the web layer starts it again
        // with the new levels' triangle counts.
        self.crowd = None;
        self.scene += 1;
        self.schedule = Schedule::FINEST;
        self.advance(0.0);
        self.settle();
    }

    /// Resizes the canvas (framebuffer pixels): another size is another scene.
    pub fn resize(&mut self, width: u32, height: u32) {
        if (width, height) != self.canvas {
            self.scene += 1;
        }
        self.canvas = (width, height);
        self.layout = layout(width, height, self.settings.view_count);
    }

    /// Takes the comparison settings of the viewer this one replaces ([`Settings::keep_from`]),
    /// before the first frame: the view starts at rest at the level they select, as [`Self::new`]
    /// starts it, not with a transition from the level the defaults selected.
    pub fn keep_settings_from(&mut self, previous: &Settings) {
        self.settings.keep_from(previous);
        let (w, h) = self.canvas;
        self.resize(w, h);
        self.advance(0.0);
        self.settle();
    }

    /// Applies a `setState` update. Continuous counts must be progressive-mesh states' (the web
    /// layer snaps them with the cursor).
    pub fn apply(&mut self, update: &Update) {
        if let Some(time) = update.time {
            self.anim_time = time;
        }
        update.apply(&mut self.settings);
        match update.continuous_triangles {
            Some(Some(triangles)) => {
                let triangles = triangles as usize;
                self.slider_goal = triangles;
                if self.slider.is_none() {
                    self.slider = Some(Transition::at(triangles));
                }
            }
            Some(None) => self.slider = None,
            None => {}
        }
        let (w, h) = self.canvas;
        self.resize(w, h);
    }

    /// The switch distance of every level for the current view and tolerance (model units).
    pub fn switch_distances(&self) -> Vec<f32> {
        let view_height = self.layout.views[0].height.max(1) as f32;
        schedule::switch_distances(&self.errors, view_height, FOVY, self.settings.tolerance_for(view_height))
    }

    /// Advances the clocks by `dt` seconds (clamped to [`MAX_STEP`]), moves the camera, steps the
    /// schedule (or the slider's morph) and plans every view.
    pub fn advance(&mut self, dt: f64) {
        let dt = dt.clamp(0.0, MAX_STEP);
        let s = &self.settings;
        if !s.paused {
            self.anim_time += dt * f64::from(s.speed);
        }
        self.dolly_time += dt;
        self.framing = camera::framing_distance_for(self.camera.radius, self.layout.views[0].aspect());
        let switch = self.switch_distances();
        let s = &self.settings;
        self.distance = match s.distance_mode {
            DistanceMode::Manual => s.manual_distance * self.framing,
            DistanceMode::Dolly => {
                let (near, far) = camera::dolly_range(self.framing, &switch);
                camera::dolly_distance(near, far, s.dolly_period, self.dolly_time)
            }
        };
        let transition_dt = (dt as f32) * s.transition_speed;
        let levels = self.errors.len();
        let shown = match &mut self.slider {
            Some(slider) => {
                // The continuous mesh is drawn by every view; the schedule waits at level 0.
                self.schedule = Schedule::FINEST;
                *slider = advance_time(*slider, self.slider_goal, s.duration, transition_dt);
                slider_slots(slider, levels)
            }
            None => {
                let mode = s.transition_mode();
                self.schedule.step(mode, self.distance, &switch, s.hysteresis, transition_dt);
                self.schedule.transition
            }
        };
        self.plans = s.methods.map(|m| plan_view(m, &shown));
        if self.crowd.is_some() {
            self.step_crowd(transition_dt);
        }
        let s = &self.settings;
        self.camera.distance = self.distance;
        self.camera.yaw = s.yaw_degrees.to_radians();
        self.camera.pitch = s.pitch_degrees.to_radians();
        self.camera.pan = Vec2::from(s.pan) * self.framing;
        self.camera.zoom = s.magnify;
    }

    /// Starts crowd mode (or lays the crowd out again) with `palette` and the levels' triangle
    /// counts: `settings.crowd_count` instances for the current view and switch distances, at
    /// rest on the levels their distances select, on the ground at height `floor` (model units).
    pub fn start_crowd(&mut self, palette: PosePalette, level_triangles: Vec<usize>, floor: f32) {
        let aspect = self.layout.views[0].aspect();
        let mut crowd = Crowd::new(
            self.settings.crowd_count,
            (self.camera.target, self.camera.radius),
            &self.switch_distances(),
            aspect,
            palette.duration,
            CROWD_SEED,
        );
        crowd.floor = floor;
        self.crowd =
            Some(CrowdState { crowd, palette, level_triangles, frame: CrowdFrame::default(), aspect });
        self.scene += 1;
        self.step_crowd(0.0);
    }

    /// Ends crowd mode: the single character again.
    pub fn stop_crowd(&mut self) {
        if self.crowd.take().is_some() {
            self.scene += 1;
        }
    }

    /// Replaces the crowd's pose palette (another clip).
    pub fn set_crowd_palette(&mut self, palette: PosePalette) {
        if let Some(c) = &mut self.crowd {
            c.palette = palette;
            self.scene += 1;
        }
    }

    /// Steps the crowd by `dt` seconds of transition time, laying it out again first if the
    /// count or the view's shape changed.
    fn step_crowd(&mut self, dt: f32) {
        let aspect = self.layout.views[0].aspect();
        let relayout = self.crowd.as_ref().is_some_and(|c| {
            c.crowd.instances.len() != self.settings.crowd_count || (c.aspect - aspect).abs() > 1e-3
        });
        if relayout {
            let c = self.crowd.take().expect("checked");
            self.start_crowd(c.palette, c.level_triangles, c.crowd.floor);
            return;
        }
        let switch = self.switch_distances();
        let s = &self.settings;
        let params = CrowdParams {
            mode: s.transition_mode(),
            hysteresis: s.hysteresis,
            dolly: s.distance_mode == DistanceMode::Dolly,
            dolly_period: s.dolly_period,
            tint_levels: s.overlay == super::overlay::Overlay::Levels,
            full_detail: !s.crowd_lod,
        };
        let methods = &s.methods[..s.view_count.clamp(1, 3)];
        let (dolly_time, anim_time) = (self.dolly_time, self.anim_time);
        if let Some(c) = &mut self.crowd {
            c.frame = c.crowd.advance(
                &params,
                dt,
                dolly_time,
                anim_time,
                aspect,
                &switch,
                &c.level_triangles,
                &c.palette,
                methods,
            );
        }
    }

    /// The slider's two states as `(finer, coarser)` triangle counts (equal at rest), when on:
    /// the meshes the renderer must hold as levels `levels` and `levels + 1`.
    pub fn continuous_pair(&self) -> Option<(usize, usize)> {
        self.slider.map(|s| (s.from.max(s.to), s.from.min(s.to)))
    }

    /// What the page reads back (`state()`), the model's half: see [`ViewerState`].
    pub fn state(&self) -> ViewerState {
        let views = (0..self.settings.view_count.clamp(1, 3))
            .map(|i| ViewState {
                method: settings::method_name(self.settings.methods[i]),
                transition: self.plans[i].transition,
                drawn: self.plans[i].draws.iter().map(|d| d.level).collect(),
                rect: self.layout.views[i],
            })
            .collect();
        ViewerState {
            selected: self.schedule.selected,
            distance: self.distance / self.framing,
            switch: self.switch_distances().iter().map(|d| d / self.framing).collect(),
            views,
        }
    }

    /// The slider's state shown when its morph ends (what the page reports).
    pub fn continuous_triangles(&self) -> Option<usize> {
        self.slider.map(|s| s.to)
    }
}

/// The model's half of the page's `state()`: distances in framing distances.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewerState {
    /// Level the screen-space error selects.
    pub selected: usize,
    /// Camera distance.
    pub distance: f32,
    /// Each level's switch distance (infinite where no tolerance allows it).
    pub switch: Vec<f32>,
    /// The views shown, in order.
    pub views: Vec<ViewState>,
}

/// One view: its method, the transition it shows (the same in every view) and what it draws.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewState {
    pub method: &'static str,
    pub transition: Transition,
    /// The level of each draw (the slider's meshes are `levels` and `levels + 1`).
    pub drawn: Vec<usize>,
    /// Where it is on the canvas, framebuffer pixels.
    pub rect: Rect,
}

/// The slider's morph between triangle counts as a transition between the drawn slots: `levels`
/// for the finer state, `levels + 1` for the coarser.
fn slider_slots(slider: &Transition, levels: usize) -> Transition {
    let finer = slider.from.max(slider.to);
    let slot = |triangles: usize| if triangles == finer { levels } else { levels + 1 };
    Transition { from: slot(slider.from), to: slot(slider.to), t: slider.t }
}

/// Frames per clip sampled for the animated bounds: enough that a limb's swing between two
/// samples stays inside the margin.
const BOUND_FRAMES_PER_CLIP: usize = 12;

/// Centre and radius of a sphere holding the character in its rest pose and through every clip
/// (sampled, with a 5 % margin for the motion between samples), so that a framed view shows the
/// whole character, head to feet, in every pose.
pub fn animated_sphere(character: &Character) -> (Vec3, f32) {
    let Some((lo, hi)) = animated_bounds(character) else { return (Vec3::ZERO, 1.0) };
    let radius = (0.5 * (hi - lo).length() * 1.05).max(1e-3);
    (0.5 * (lo + hi), radius)
}

/// The box holding the character in its rest pose and through every clip (sampled as for
/// [`animated_sphere`], without the margin); `None` without a finite vertex.
pub fn animated_bounds(character: &Character) -> Option<(Vec3, Vec3)> {
    let mut lo = Vec3::MAX;
    let mut hi = Vec3::MIN;
    let mut include = |positions: Vec<Vec3>| {
        for p in positions.into_iter().filter(|p| p.is_finite()) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    };
    include(character.skinned_positions(&character.skeleton.rest_pose()));
    for clip in &character.clips {
        for k in 0..BOUND_FRAMES_PER_CLIP {
            let time = clip.duration() * k as f32 / BOUND_FRAMES_PER_CLIP as f32;
            include(character.skinned_positions(&character.pose_at(clip, time)));
        }
    }
    (lo.x <= hi.x).then_some((lo, hi))
}

#[cfg(test)]
mod tests;
