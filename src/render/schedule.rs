//! The LOD schedule shared by every view: which level the screen-space error asks for, and the
//! one transition that every view shows at the same moment.
//!
//! A level's geometric error `e` (model units) seen from distance `d` covers
//! `e · H / (2 d tan(fovy/2))` pixels on a view `H` pixels tall. The schedule picks the coarsest
//! level whose projected error stays within a pixel tolerance, i.e. level `i` is allowed from the
//! *switch distance* `Dᵢ = e · H / (2 tan(fovy/2) · tolerance)` on. Hysteresis keeps a camera
//! hovering at a switch distance from flickering: coarsening waits until `d ≥ Dᵢ (1 + h)`,
//! refining happens as soon as `d < Dᵢ`.
//!
//! What the views show is one [`Transition`] `{ from, to, t }`: when the selection moves from level
//! `a` to level `b` (one level or several), popping shows `b` from that moment on, and the blending
//! views run one transition from `a` straight to `b` (Houle & Poulin 2001, Fig. 4: the ancestor
//! tables chain, so a vertex of `a` morphs to its ancestor in `b`). Transitions are driven either
//! over time (one duration per transition, started by the switch) or by distance (a morph zone
//! before each switch distance, as in Hoppe's geomorphs driven by view distance). Level indices
//! grow coarser: a higher index has fewer triangles.

/// How transitions are driven.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TransitionMode {
    /// Each transition takes this many seconds after the switch, whatever the number of levels it
    /// crosses; 0 pops.
    Time { seconds: f32 },
    /// The level coordinate follows the distance: the last `zone` fraction before each switch
    /// distance morphs.
    Distance { zone: f32 },
}

/// Pixels on a view `view_height_px` tall covered by a length `error` at `distance`.
///
/// A distance that is not positive projects to infinity (the eye is at the model).
pub fn projected_error_px(error: f32, distance: f32, view_height_px: f32, fovy: f32) -> f32 {
    if distance <= 0.0 {
        return f32::INFINITY;
    }
    error * view_height_px / (2.0 * distance * (fovy * 0.5).tan())
}

/// The switch distance of every level (see the module docs): 0 for the finest, non-decreasing
/// when errors are. A level with zero error is allowed everywhere (distance 0); a tolerance that
/// is not positive allows no coarse level (infinite distances).
pub fn switch_distances(errors: &[f32], view_height_px: f32, fovy: f32, tolerance_px: f32) -> Vec<f32> {
    errors
        .iter()
        .enumerate()
        .map(|(i, &e)| {
            if i == 0 || e <= 0.0 {
                0.0
            } else if tolerance_px <= 0.0 {
                f32::INFINITY
            } else {
                e * view_height_px / (2.0 * (fovy * 0.5).tan() * tolerance_px)
            }
        })
        .collect()
}

/// The level to show at `distance` when `current` is shown, with hysteresis `h` (a fraction,
/// e.g. 0.1) on coarsening. Several levels may be skipped in one call (a fast camera).
pub fn select_level(current: usize, distance: f32, switch: &[f32], hysteresis: f32) -> usize {
    if switch.is_empty() {
        return 0;
    }
    let mut level = current.min(switch.len() - 1);
    while level + 1 < switch.len() && distance >= switch[level + 1] * (1.0 + hysteresis.max(0.0)) {
        level += 1;
    }
    while level > 0 && distance < switch[level] {
        level -= 1;
    }
    level
}

/// How far level `i`'s morph zone has progressed at `distance`: 0 before
/// `Dᵢ (1 − zone)`, 1 from `Dᵢ` on, linear in between.
fn zone_ramp(distance: f32, switch: f32, zone: f32) -> f32 {
    let start = switch * (1.0 - zone);
    if distance >= switch {
        1.0
    } else if distance <= start || switch <= start {
        0.0
    } else {
        (distance - start) / (switch - start)
    }
}

/// The level coordinate for distance-driven transitions: the sum of every coarse level's zone
/// ramp (`zone_ramp`), so `i + t` inside the zone `[Dᵢ₊₁ (1 − zone), Dᵢ₊₁)` of separate zones and
/// whole levels between them.
///
/// It is a continuous, non-decreasing function of the distance for any zone width and any switch
/// distances: where zones overlap (`Dᵢ > Dᵢ₊₁ (1 − zone)`) or switch distances are equal, the
/// ramps add up instead of one cutting the other short. Its slope is at most
/// `Σ 1 / (Dᵢ · zone)`. `zone` is clamped to `[0, 1]`; 0 pops at each switch distance.
pub fn distance_coordinate(distance: f32, switch: &[f32], zone: f32) -> f32 {
    let zone = zone.clamp(0.0, 1.0);
    switch.iter().skip(1).map(|&d| zone_ramp(distance, d, zone)).sum()
}

/// A change of level that every view shows: level `from` becoming level `to`, `t` of the way
/// (`0` shows `from`, `1` would show `to`). A view not in a transition has `from == to`, `t = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition {
    pub from: usize,
    pub to: usize,
    pub t: f32,
}

impl Transition {
    /// Resting at `level`.
    pub const fn at(level: usize) -> Self {
        Self { from: level, to: level, t: 0.0 }
    }

    /// Whether a change is under way.
    pub fn is_running(&self) -> bool {
        self.from != self.to
    }

    /// The finer and the coarser of the two levels and how far the picture is from the finer
    /// towards the coarser (`t` when coarsening, `1 − t` when refining): what a geomorph or a
    /// cross-fade between the two draws. `(level, level, 0)` at rest.
    pub fn fine_coarse(&self) -> (usize, usize, f32) {
        if !self.is_running() {
            (self.to, self.to, 0.0)
        } else if self.to > self.from {
            (self.from, self.to, self.t)
        } else {
            (self.to, self.from, 1.0 - self.t)
        }
    }
}

/// The selected level and the transition every view shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schedule {
    /// Level selected by the screen-space error.
    pub selected: usize,
    /// What every view shows; popping shows `transition.to`.
    pub transition: Transition,
}

impl Schedule {
    /// Starts at the finest level.
    pub const FINEST: Self = Self { selected: 0, transition: Transition::at(0) };

    /// Advances by `dt` seconds with the camera at `distance`.
    ///
    /// Time mode: when the selection differs from the level shown, one transition starts from
    /// the level shown straight to the selected one, and runs for the duration. A selection that
    /// changes while it runs waits for it to end (then the next transition starts at once), except
    /// a selection going back to where the transition started, which turns it around smoothly.
    /// Distance mode: the transition is the distance's level coordinate
    /// ([`distance_coordinate`]), `from = ⌊x⌋`, `to = ⌊x⌋ + 1` inside a zone.
    pub fn step(&mut self, mode: TransitionMode, distance: f32, switch: &[f32], hysteresis: f32, dt: f32) {
        let last = switch.len().saturating_sub(1);
        match mode {
            TransitionMode::Time { seconds } => {
                self.selected = select_level(self.selected, distance, switch, hysteresis);
                self.transition = advance_time(self.transition, self.selected, seconds, dt);
            }
            TransitionMode::Distance { zone } => {
                let x = distance_coordinate(distance, switch, zone).clamp(0.0, last as f32);
                let from = (x.floor() as usize).min(last);
                let t = x - from as f32;
                self.transition = if t > 0.0 && from < last {
                    Transition { from, to: from + 1, t }
                } else {
                    Transition::at(from)
                };
                self.selected = self.transition.to;
            }
        }
        let clamp = |l: usize| l.min(last);
        self.selected = clamp(self.selected);
        let t = &mut self.transition;
        (t.from, t.to) = (clamp(t.from), clamp(t.to));
        if !t.is_running() {
            *t = Transition::at(t.to);
        }
    }
}

/// One time step of a transition towards `goal` (see [`Schedule::step`]); also drives the
/// continuous slider's morphs between progressive-mesh states.
pub fn advance_time(mut transition: Transition, goal: usize, seconds: f32, dt: f32) -> Transition {
    if seconds <= 0.0 {
        return Transition::at(goal);
    }
    if transition.is_running() {
        if goal == transition.from {
            // Turned around: the same picture, now heading back.
            transition = Transition { from: transition.to, to: transition.from, t: 1.0 - transition.t };
        }
        transition.t += dt.max(0.0) / seconds;
        if transition.t < 1.0 {
            return transition;
        }
        transition = Transition::at(transition.to);
    }
    if goal != transition.to {
        // The switch: popping shows `goal` from this frame on, the others start from `to`.
        transition = Transition { from: transition.to, to: goal, t: 0.0 };
    }
    transition
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    const FOVY_90: f32 = std::f32::consts::FRAC_PI_2;

    #[test]
    fn projection_of_a_level_error() {
        // tan(45°) = 1: an error of 0.01 at distance 1 on a 1000 px view covers 5 px.
        assert!((projected_error_px(0.01, 1.0, 1000.0, FOVY_90) - 5.0).abs() < 1e-4);
        assert_eq!(projected_error_px(0.01, 0.0, 1000.0, FOVY_90), f32::INFINITY);
    }

    #[test]
    fn switch_distance_projects_to_the_tolerance() {
        let d = switch_distances(&[0.0, 0.01, 0.04], 1000.0, FOVY_90, 2.0);
        assert_eq!(d[0], 0.0);
        assert!((d[1] - 2.5).abs() < 1e-5 && (d[2] - 10.0).abs() < 1e-4);
        assert!((projected_error_px(0.04, d[2], 1000.0, FOVY_90) - 2.0).abs() < 1e-4);
        assert_eq!(switch_distances(&[0.0, 0.01], 1000.0, FOVY_90, 0.0)[1], f32::INFINITY);
    }

    #[test]
    fn hysteresis_holds_the_level_between_thresholds() {
        let switch = [0.0, 10.0, 20.0];
        assert_eq!(select_level(0, 10.5, &switch, 0.1), 0, "not yet 10 % past the switch");
        assert_eq!(select_level(0, 11.0, &switch, 0.1), 1);
        assert_eq!(select_level(1, 10.5, &switch, 0.1), 1, "holds while above the switch");
        assert_eq!(select_level(1, 9.99, &switch, 0.1), 0);
        assert_eq!(select_level(0, 50.0, &switch, 0.1), 2, "skips levels for a fast camera");
        assert_eq!(select_level(2, 1.0, &switch, 0.1), 0);
        assert_eq!(select_level(7, 15.0, &switch, 0.1), 1, "an out-of-range level is clamped first");
        assert_eq!(select_level(3, 15.0, &[], 0.1), 0);
    }

    #[test]
    fn a_jump_of_several_levels_is_one_transition() {
        let switch = [0.0, 10.0, 20.0, 40.0];
        let mode = TransitionMode::Time { seconds: 0.5 };
        let mut s = Schedule::FINEST;
        s.step(mode, 50.0, &switch, 0.0, 0.1);
        assert_eq!(s.selected, 3);
        assert_eq!(s.transition, Transition { from: 0, to: 3, t: 0.0 }, "starts at the switch");
        s.step(mode, 50.0, &switch, 0.0, 0.25);
        assert_eq!(s.transition, Transition { from: 0, to: 3, t: 0.5 });
        assert_eq!(s.transition.fine_coarse(), (0, 3, 0.5));
        s.step(mode, 50.0, &switch, 0.0, 0.25);
        assert_eq!(s.transition, Transition::at(3), "one duration, whatever the levels crossed");
    }

    #[test]
    fn a_reversal_turns_around_and_a_new_goal_waits() {
        let switch = [0.0, 10.0, 20.0, 40.0];
        let mode = TransitionMode::Time { seconds: 1.0 };
        let mut s = Schedule::FINEST;
        s.step(mode, 15.0, &switch, 0.0, 0.0);
        s.step(mode, 15.0, &switch, 0.0, 0.25);
        assert_eq!(s.transition, Transition { from: 0, to: 1, t: 0.25 });
        // Back to where it started: the same picture, heading back.
        s.step(mode, 5.0, &switch, 0.0, 0.0);
        assert_eq!(s.transition, Transition { from: 1, to: 0, t: 0.75 });
        assert_eq!(s.transition.fine_coarse(), (0, 1, 0.25));
        // A new goal while running: waits for the running one, then starts at once.
        s.step(mode, 50.0, &switch, 0.0, 0.125);
        assert_eq!((s.selected, s.transition.to), (3, 0));
        s.step(mode, 50.0, &switch, 0.0, 0.125);
        assert_eq!(s.transition, Transition { from: 0, to: 3, t: 0.0 });
        let mut pop = Schedule::FINEST;
        pop.step(TransitionMode::Time { seconds: 0.0 }, 15.0, &switch, 0.0, 0.0);
        assert_eq!(pop.transition, Transition::at(1));
    }

    #[test]
    fn distance_transition_morphs_inside_the_zone() {
        let switch = [0.0, 10.0, 20.0];
        assert_eq!(distance_coordinate(7.0, &switch, 0.2), 0.0);
        assert!((distance_coordinate(9.0, &switch, 0.2) - 0.5).abs() < 1e-6);
        assert_eq!(distance_coordinate(10.0, &switch, 0.2), 1.0);
        assert!((distance_coordinate(19.0, &switch, 0.2) - 1.75).abs() < 1e-6);
        assert_eq!(distance_coordinate(25.0, &switch, 0.2), 2.0);
        assert_eq!(distance_coordinate(9.99, &switch, 0.0), 0.0, "no zone pops");
        assert_eq!(distance_coordinate(10.0, &switch, 0.0), 1.0);
        let mut s = Schedule::FINEST;
        s.step(TransitionMode::Distance { zone: 0.2 }, 9.0, &switch, 0.5, 0.0);
        assert_eq!((s.selected, s.transition), (1, Transition { from: 0, to: 1, t: 0.5 }));
        s.step(TransitionMode::Distance { zone: 0.2 }, 10.0, &switch, 0.5, 0.0);
        assert_eq!((s.selected, s.transition), (1, Transition::at(1)));
    }

    #[test]
    fn overlapping_zones_do_not_jump() {
        // The cases: [0, 10, 20, 40] at zone 0.6 and [0, 10, 12, 40] at zone 0.25 used
        // to jump 0.17 and 0.33 levels at D₁.
        for (switch, zone) in [([0.0, 10.0, 20.0, 40.0], 0.6), ([0.0, 10.0, 12.0, 40.0], 0.25)] {
            let below = distance_coordinate(10.0 - 1e-3, &switch, zone);
            let at = distance_coordinate(10.0, &switch, zone);
            assert!((at - below).abs() < 1e-3, "{switch:?} zone {zone}: {below} → {at}");
        }
        let equal = [0.0, 10.0, 10.0, 40.0];
        assert!((distance_coordinate(9.0, &equal, 0.2) - 1.0).abs() < 1e-5, "equal switches morph together");
        assert_eq!(distance_coordinate(10.0, &equal, 0.2), 2.0);
    }
}
