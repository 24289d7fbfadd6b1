//! The live transition meter: how far each view's picture is from the full-detail reference drawn
//! at the same pose and camera, every frame, and how much a transition changes at once (its *pop*).
//!
//! Two channels, after Larkin (2011), who found the silhouette the cue people notice first:
//! - **silhouette**: how much of the view's area the two pictures cover differently,
//!   `Σ |α_reference − α_view|` over the pixels divided by their number. Coverage is the target's
//!   alpha: cleared to 0, brought to 1 by opaque surfaces, to the layer's opacity by a fading
//!   one, and to the covered share of a pixel's samples by the MSAA resolve, so an edge that moves
//!   by a fraction of a pixel, or a level that fades in, changes it by a fraction, not a whole
//!   pixel at a threshold;
//! - **shading**: `|ΔR| + |ΔG| + |ΔB|` (0..765, 8-bit sRGB) summed over the pixels both cover
//!   fully (alpha 255), divided by all of the view's pixels;
//! - **FLIP**: the mean LDR-FLIP error (Andersson et al. 2020, [`crate::render::flip`]) over the
//!   view's pixels, 0..1, computed on the GPU from the same pictures, seen at the pixels per
//!   degree the meter's picture has when the view is seen at FLIP's standard 67 ppd.
//!
//! **The pop isolates the transition.** Each measured frame also draws every view's *control*:
//! the same frame (pose, camera, clock) drawn with the plan that view had in the previous measured
//! frame. The control is what the frame would show had the transition not moved on; the view's
//! difference from its control (the *step*, same channels) is what the transition itself changed
//! on screen in that frame. A view whose plan held draws its control exactly: its step is 0
//! however the character moves. A transition's pop, per channel, is the largest step from the
//! frame it starts (popping's switch) to the first frame after it ends: popping's whole change
//! lands in one step, a geomorph's is spread over all of them.
//!
//! The former pop, the largest frame-to-frame change of the difference from the reference, is
//! kept as `uncontrolled`: the reference moves with the animation, but the outline's
//! rasterization does not cancel, so it includes the animation's own change (about 0.02 % of the
//! view per frame on the built-in character walking, as large as a geomorph's step) and depends
//! on the frame rate. Frames arrive a frame or two late (read back asynchronously) and may skip
//! one when the GPU is slow; the next step then spans two frames (reported by `gap`).

use std::collections::VecDeque;

use super::plan::ViewPlan;
use super::schedule::Transition;

/// A view's difference from the reference in one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameDifference {
    /// Area (a share of the view, 0..1) the two pictures cover differently.
    pub silhouette: f32,
    /// Mean `|ΔRGB|` per pixel of the view (0..765) over pixels both cover fully.
    pub shading: f32,
    /// Mean LDR-FLIP error over the view's pixels (0..1, see [`crate::render::flip`]; 0 where
    /// the GPU cannot compute it).
    pub flip: f32,
}

/// The difference of two RGBA8 pictures of the same size (see the module docs).
///
/// # Panics
/// If the slices differ in length.
pub fn frame_difference(reference: &[u8], view: &[u8]) -> FrameDifference {
    assert_eq!(reference.len(), view.len(), "pictures of one size");
    let pixels = reference.len() / 4;
    if pixels == 0 {
        return FrameDifference::default();
    }
    let mut outline = 0u64;
    let mut shading = 0u64;
    for (r, v) in reference.chunks_exact(4).zip(view.chunks_exact(4)) {
        outline += u64::from(r[3].abs_diff(v[3]));
        if r[3] == 255 && v[3] == 255 {
            shading += (0..3).map(|c| u64::from(r[c].abs_diff(v[c]))).sum::<u64>();
        }
    }
    FrameDifference {
        silhouette: outline as f32 / (255.0 * pixels as f32),
        shading: shading as f32 / pixels as f32,
        flip: 0.0,
    }
}

/// The pairs of pictures `(reference, test)` FLIP compares in a measured frame, each once, given
/// the picture each view drew and the picture of its control (picture 0 is the full-detail
/// reference; views and controls with equal plans share a picture): every view against the
/// reference and against its control, where they are different pictures.
pub fn flip_pairs(view_picture: &[usize], control_picture: &[usize]) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for (&v, &c) in view_picture.iter().zip(control_picture) {
        for pair in [(0, v), (c, v)] {
            if pair.0 != pair.1 && !pairs.contains(&pair) {
                pairs.push(pair);
            }
        }
    }
    pairs
}

/// One measured frame: the transition every view showed and each view's difference.
#[derive(Clone, Debug, PartialEq)]
pub struct MeterSample {
    /// Frame number (consecutive frames differ by 1).
    pub frame: u64,
    /// Viewer seconds (the dolly clock) when the frame was drawn.
    pub time: f64,
    pub transition: Transition,
    /// The scene the frame drew (`ViewerModel::scene`): frames of different scenes are never
    /// compared, neither for a transition's pop nor for the crowd's changes.
    pub scene: u64,
    /// Each view's difference from the reference.
    pub views: Vec<FrameDifference>,
    /// Each view's difference from its control (see the module docs): what this frame's step of
    /// the transition changed; 0 where the view's plan held.
    pub steps: Vec<FrameDifference>,
}

/// The pop of one transition in one view: its largest step per channel (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pop {
    pub silhouette: f32,
    pub shading: f32,
    /// The largest mean LDR-FLIP error of a frame against its control.
    pub flip: f32,
    /// Without the control: the largest frame-to-frame change of each channel of the difference
    /// from the reference (the animation's own change included).
    pub uncontrolled: FrameDifference,
}

impl Pop {
    /// Grows by the frame whose difference from the reference went from `before` to `after` and
    /// whose step was `step`.
    fn grow(&mut self, before: &FrameDifference, after: &FrameDifference, step: &FrameDifference) {
        self.silhouette = self.silhouette.max(step.silhouette);
        self.shading = self.shading.max(step.shading);
        self.flip = self.flip.max(step.flip);
        let u = &mut self.uncontrolled;
        u.silhouette = u.silhouette.max((after.silhouette - before.silhouette).abs());
        u.shading = u.shading.max((after.shading - before.shading).abs());
        u.flip = u.flip.max((after.flip - before.flip).abs());
    }
}

/// Samples kept for the page's strip chart: ten seconds at 60 frames per second.
pub const HISTORY: usize = 600;

/// Collects samples into transitions (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct TransitionMeter {
    previous: Option<MeterSample>,
    /// The running transition's pops so far, per view, and its `(from, to)`.
    open: Option<((usize, usize), Vec<Pop>)>,
    /// The last completed transition's pop per view.
    pub last: Option<Vec<Pop>>,
    /// Transitions completed.
    pub transitions: u32,
    /// Frames measured that did not follow the previous one (a readback was skipped).
    pub gaps: u32,
    /// The latest samples, oldest first, at most [`HISTORY`].
    pub history: VecDeque<MeterSample>,
}

impl TransitionMeter {
    /// Adds a frame's sample (frames in increasing order); returns whether a transition ended
    /// with it. A sample whose view count or scene differs from the previous one starts afresh
    /// (the page changed its views, or what they draw).
    pub fn push(&mut self, sample: MeterSample) -> bool {
        let mut completed = false;
        let comparable = |p: &MeterSample| p.views.len() == sample.views.len() && p.scene == sample.scene;
        if let Some(previous) = self.previous.take().filter(comparable) {
            if sample.frame != previous.frame + 1 {
                self.gaps += 1;
            }
            let shown = |t: &Transition| t.is_running().then_some((t.from, t.to));
            let (before, now) = (shown(&previous.transition), shown(&sample.transition));
            if self.open.is_some() && before != now {
                // Ended (or replaced by the next queued one): the jump of this frame is the next's.
                let (_, pops) = self.open.take().expect("checked");
                self.last = Some(pops);
                self.transitions += 1;
                completed = true;
            }
            if let (Some(key), None) = (now, &self.open) {
                self.open = Some((key, vec![Pop::default(); sample.views.len()]));
            }
            let grow_into = self.open.as_mut().map(|(_, pops)| pops);
            let closing = if completed { self.last.as_mut() } else { None };
            // The frame a transition ends on still belongs to it (the last step to the new level).
            for pops in grow_into.into_iter().chain(closing) {
                let frames = previous.views.iter().zip(&sample.views).zip(&sample.steps);
                for (pop, ((a, b), step)) in pops.iter_mut().zip(frames) {
                    pop.grow(a, b, step);
                }
            }
        } else {
            self.open = None;
        }
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(sample.clone());
        self.previous = Some(sample);
        completed
    }

    /// How each view's difference from the reference changed from frame to frame over the
    /// history (consecutive frames of one scene only): the mean and the largest `|Δ|` per
    /// channel, and their sum per second of viewer time (what changes on screen per second). This is the
    /// crowd's meter, where many transitions overlap and none is "the last": popping's changes
    /// land in single frames (a high peak), a geomorph's are spread over many (a low one), and the
    /// animation's own motion adds the same to every view.
    pub fn changes(&self) -> Vec<Change> {
        let views = self.history.back().map_or(0, |s| s.views.len());
        let mut out = vec![Change::default(); views];
        let mut pairs = 0usize;
        let mut seconds = 0.0f64;
        for (a, b) in self.history.iter().zip(self.history.iter().skip(1)) {
            if b.frame != a.frame + 1
                || a.scene != b.scene
                || a.views.len() != views
                || b.views.len() != views
            {
                continue;
            }
            pairs += 1;
            seconds += (b.time - a.time).max(0.0);
            for (c, (x, y)) in out.iter_mut().zip(a.views.iter().zip(&b.views)) {
                let (ds, dc) = ((y.silhouette - x.silhouette).abs(), (y.shading - x.shading).abs());
                c.silhouette_mean += ds;
                c.shading_mean += dc;
                c.silhouette_peak = c.silhouette_peak.max(ds);
                c.shading_peak = c.shading_peak.max(dc);
            }
        }
        for c in &mut out {
            let per_second = if seconds > 0.0 { pairs as f32 / seconds as f32 } else { 0.0 };
            c.silhouette_mean /= pairs.max(1) as f32;
            c.shading_mean /= pairs.max(1) as f32;
            c.silhouette_per_second = c.silhouette_mean * per_second;
            c.shading_per_second = c.shading_mean * per_second;
        }
        out
    }
}

/// Measured frames whose pictures may still come back: readbacks that fail never do, and a
/// few in flight cover the one or two frames the pictures arrive late.
pub const IN_FLIGHT: usize = 8;

/// The viewer's side of measuring: what it drew in each measured frame whose pictures are not
/// back yet, each view's control for the next measured frame, and the pixels per degree of the
/// last FLIP.
#[derive(Clone, Debug, Default)]
pub struct MeterFrames {
    /// The frames sent, oldest first, at most [`IN_FLIGHT`].
    pending: VecDeque<SentFrame>,
    /// The plans of the last measured frame: each view's control in the next one (see the module
    /// docs); `None` until a frame is measured, and after the levels change.
    pub controls: Option<[ViewPlan; 3]>,
    /// Pixels per degree of the last FLIP computed (`None` until one was).
    pub flip_ppd: Option<f32>,
}

/// A measured frame whose pictures are on their way back: what its sample needs besides them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SentFrame {
    pub frame: u64,
    /// Dolly seconds.
    pub time: f64,
    pub transition: Transition,
    pub scene: u64,
}

impl MeterFrames {
    /// Frame `frame` of `scene` was measured at dolly time `time` showing `transition`, with
    /// `plans` (the next measured frame's controls).
    pub fn sent(&mut self, frame: u64, time: f64, transition: Transition, scene: u64, plans: [ViewPlan; 3]) {
        self.controls = Some(plans);
        self.pending.push_back(SentFrame { frame, time, transition, scene });
        while self.pending.len() > IN_FLIGHT {
            self.pending.pop_front();
        }
    }

    /// Frame `frame`, whose pictures came back; frames sent before it whose pictures never will
    /// are forgotten. `None` for a frame not (or no longer) in flight.
    pub fn returned(&mut self, frame: u64) -> Option<SentFrame> {
        while self.pending.front().is_some_and(|s| s.frame < frame) {
            self.pending.pop_front();
        }
        self.pending.front().filter(|s| s.frame == frame)?;
        self.pending.pop_front()
    }
}

/// Frame-to-frame change of one view's difference from the reference (see
/// [`TransitionMeter::changes`]): silhouette as a share of the view (0..1), shading in mean
/// `|ΔRGB|` (0..765).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Change {
    pub silhouette_mean: f32,
    pub silhouette_peak: f32,
    /// `Σ |Δ silhouette|` over the consecutive pairs divided by the seconds they span.
    pub silhouette_per_second: f32,
    pub shading_mean: f32,
    pub shading_peak: f32,
    pub shading_per_second: f32,
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn frames_in_flight_come_back_in_order_or_not_at_all() {
        let mut frames = MeterFrames::default();
        let plans = || std::array::from_fn(|_| ViewPlan { draws: Vec::new(), transition: Transition::at(0) });
        for f in 0..12u64 {
            frames.sent(f, f as f64 / 10.0, Transition::at(f as usize), f / 6, plans());
        }
        assert!(frames.controls.is_some());
        // Only the last IN_FLIGHT are kept: 4..12.
        assert_eq!(frames.returned(2), None);
        let sent = |frame: u64| SentFrame {
            frame,
            time: frame as f64 / 10.0,
            transition: Transition::at(frame as usize),
            scene: frame / 6,
        };
        assert_eq!(frames.returned(5), Some(sent(5)), "4 never came back");
        assert_eq!(frames.returned(5), None, "each frame comes back once");
        assert_eq!(frames.returned(9), Some(sent(9)));
        assert_eq!(frames.returned(20), None);
        assert_eq!(frames.returned(11), None, "everything before 20 was forgotten");
    }

    fn rgba(pixels: &[(u8, u8)]) -> Vec<u8> {
        pixels.iter().flat_map(|&(g, alpha)| [g, g, g, alpha]).collect()
    }

    #[test]
    fn silhouette_sums_coverage_that_differs_and_shading_the_rest() {
        let reference = rgba(&[(10, 255), (10, 255), (0, 0), (50, 0), (7, 255)]);
        let view = rgba(&[(20, 255), (10, 0), (0, 255), (90, 0), (9, 51)]);
        let d = frame_difference(&reference, &view);
        assert!((d.silhouette - 2.8 / 5.0).abs() < 1e-6, "pixels 1 and 2 whole, 4 by 0.8: {}", d.silhouette);
        assert_eq!(
            d.shading,
            30.0 / 5.0,
            "|Δ| 10 in three channels over five pixels; partly covered and background ignored"
        );
        assert_eq!(frame_difference(&[], &[]), FrameDifference::default());
    }

    fn sample(frame: u64, transition: Transition, silhouette: [f32; 2]) -> MeterSample {
        stepped(frame, transition, silhouette, [0.0; 2])
    }

    fn stepped(frame: u64, transition: Transition, silhouette: [f32; 2], steps: [f32; 2]) -> MeterSample {
        let differences = |v: [f32; 2]| {
            v.iter().map(|&s| FrameDifference { silhouette: s, shading: 10.0 * s, flip: s / 2.0 }).collect()
        };
        MeterSample {
            frame,
            time: frame as f64 / 60.0,
            transition,
            scene: 0,
            views: differences(silhouette),
            steps: differences(steps),
        }
    }

    #[test]
    fn a_pop_is_the_largest_step_from_the_switch_to_the_frame_after_the_end() {
        let mut meter = TransitionMeter::default();
        let rest = Transition::at(0);
        let run = |t| Transition { from: 0, to: 2, t };
        // View 0 pops at the switch (its step is the whole change); view 1 steps by 0.1 a frame.
        // Both differences from the reference also drift with the animation, which the steps
        // (against the controls) leave out and the uncontrolled pops keep.
        assert!(!meter.push(stepped(1, rest, [0.0, 0.0], [0.0, 0.0])));
        assert!(!meter.push(stepped(2, run(0.0), [0.5, 0.15], [0.45, 0.1])));
        assert!(!meter.push(stepped(3, run(0.5), [0.55, 0.3], [0.0, 0.1])));
        assert!(meter.push(stepped(4, Transition::at(2), [0.6, 0.5], [0.0, 0.12])), "ends at rest");
        // Frames at rest after the end belong to no transition: a large change there is ignored.
        assert!(!meter.push(stepped(5, Transition::at(2), [0.9, 0.9], [0.0, 0.0])));
        let pops = meter.last.clone().unwrap();
        assert_eq!((pops[0].silhouette, pops[0].shading, pops[0].flip), (0.45, 4.5, 0.225));
        assert!((pops[1].silhouette - 0.12).abs() < 1e-6, "the last step counts: {:?}", pops[1]);
        assert_eq!(pops[0].uncontrolled.silhouette, 0.5);
        assert!((pops[1].uncontrolled.silhouette - 0.2).abs() < 1e-6, "{:?}", pops[1]);
        assert_eq!((meter.transitions, meter.gaps), (1, 0));
        // A queued transition follows at once: the first closes, the second opens.
        assert!(!meter.push(sample(6, Transition { from: 2, to: 3, t: 0.0 }, [0.6, 0.5])));
        assert!(meter.push(sample(8, Transition { from: 3, to: 1, t: 0.0 }, [0.6, 0.5])));
        assert_eq!((meter.transitions, meter.gaps), (2, 1));
        assert_eq!(meter.history.len(), 7);
    }

    #[test]
    fn a_view_whose_plan_holds_pops_zero_while_its_difference_moves() {
        // Both views' differences from the reference change every frame (the walk), only view 0
        // changes level: view 1's steps are 0, so its pop is 0 while its uncontrolled pop is not.
        let mut meter = TransitionMeter::default();
        let run = |t| Transition { from: 1, to: 2, t };
        meter.push(stepped(1, Transition::at(1), [0.1, 0.1], [0.0, 0.0]));
        for (k, frame) in (2..6).enumerate() {
            let drift = 0.02 * k as f32;
            meter.push(stepped(frame, run(0.25 * k as f32), [0.1 + drift, 0.1 + drift], [0.03, 0.0]));
        }
        assert!(meter.push(stepped(6, Transition::at(2), [0.3, 0.2], [0.03, 0.0])));
        let pops = meter.last.clone().unwrap();
        assert_eq!(pops[1].silhouette, 0.0);
        assert!(pops[1].uncontrolled.silhouette >= 0.02, "{:?}", pops[1]);
        assert_eq!(pops[0].silhouette, 0.03);
    }

    #[test]
    fn flip_compares_each_distinct_pair_once() {
        // At rest on level 0: every view is the reference and its own control: nothing to compare.
        assert!(flip_pairs(&[0, 0, 0], &[0, 0, 0]).is_empty());
        // At rest on a coarse level: one shared picture against the reference.
        assert_eq!(flip_pairs(&[1, 1, 1], &[1, 1, 1]), [(0, 1)]);
        // Mid-transition: popping (1) held, the blend (2) and the geomorph (3) against their
        // controls (4, 5) and the reference.
        assert_eq!(flip_pairs(&[1, 2, 3], &[1, 4, 5]), [(0, 1), (0, 2), (4, 2), (0, 3), (5, 3)]);
    }

    #[test]
    fn changes_are_the_frame_to_frame_steps_of_consecutive_frames() {
        let mut meter = TransitionMeter::default();
        let rest = Transition::at(0);
        for (frame, s) in
            [(1, [0.0, 0.0]), (2, [0.4, 0.1]), (3, [0.4, 0.2]), (5, [0.0, 0.0]), (6, [0.0, 0.3])]
        {
            meter.push(sample(frame, rest, s));
        }
        let c = meter.changes();
        // Pairs 1→2, 2→3 and 5→6 (3→5 skipped a frame).
        assert!((c[0].silhouette_mean - 0.4 / 3.0).abs() < 1e-6, "{c:?}");
        assert_eq!(c[0].silhouette_peak, 0.4);
        assert!((c[1].silhouette_mean - 0.5 / 3.0).abs() < 1e-6, "{c:?}");
        assert!((c[1].silhouette_peak - 0.3).abs() < 1e-6);
        assert!((c[1].shading_peak - 3.0).abs() < 1e-5);
        // Three pairs of 1/60 s each: the sums over 0.05 s.
        assert!((c[0].silhouette_per_second - 0.4 / 0.05).abs() < 1e-3, "{c:?}");
        assert!(TransitionMeter::default().changes().is_empty());
    }

    #[test]
    fn frames_of_different_scenes_are_never_compared() {
        // Crowd mode turned on between frames 2 and 3: every view's difference from the reference
        // jumps alike (0.1 → 0.6), which is no change a transition made.
        let mut meter = TransitionMeter::default();
        let run = |t| Transition { from: 0, to: 1, t };
        let frames =
            [(1, run(0.0), 0, 0.1), (2, run(0.5), 0, 0.1), (3, run(0.75), 1, 0.6), (4, run(0.9), 1, 0.62)];
        for (frame, transition, scene, s) in frames {
            meter.push(MeterSample { scene, ..sample(frame, transition, [s, s]) });
        }
        let c = meter.changes();
        assert!((c[0].silhouette_peak - 0.02).abs() < 1e-6, "only 3 → 4 counts: {c:?}");
        assert!((c[0].silhouette_mean - 0.01).abs() < 1e-6, "2 pairs, 1 → 2 and 3 → 4: {c:?}");
        // The transition running across the change restarts with the new scene: its pops so far
        // saw no jump.
        assert_eq!(meter.gaps, 0);
        let open = meter.open.as_ref().map(|(_, pops)| pops[0].uncontrolled.silhouette);
        assert!(open.is_some_and(|u| (u - 0.02).abs() < 1e-6), "{open:?}");
    }
}
