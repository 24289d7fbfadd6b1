//! The LOD schedule shared by the three views: which level the screen-space error asks for, and
//! where the transition towards it stands.
//!
//! A level's geometric error `e` (model units) seen from distance `d` covers
//! `e · H / (2 d tan(fovy/2))` pixels on a view `H` pixels tall. The schedule picks the coarsest
//! level whose projected error stays within a pixel tolerance, i.e. level `i` is allowed from the
//! *switch distance* `Dᵢ = e · H / (2 tan(fovy/2) · tolerance)` on. Hysteresis keeps a camera
//! hovering at a switch distance from flickering: coarsening waits until `d ≥ Dᵢ (1 + h)`,
//! refining happens as soon as `d < Dᵢ`.
//!
//! What the views show is a *level coordinate* `x` in `[0, levels − 1]`: an integer is that level,
//! `i + t` is the fine level `i` blending (or morphing) towards level `i + 1` by `t`. Transitions
//! move `x` towards the selected level either over time (a fixed duration per level, started by
//! the switch) or by distance (a morph zone just before each switch distance, as in Hoppe's
//! geomorphs driven by view distance). Popping always shows the selected level itself.

/// How transitions are driven.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TransitionMode {
    /// Each level step takes this many seconds after the switch; 0 pops.
    Time { seconds_per_level: f32 },
    /// `x` follows the distance: the last `zone` fraction before each switch distance morphs.
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

/// The level coordinate for distance-driven transitions: `i + t` inside the morph zone
/// `[Dᵢ₊₁ (1 − zone), Dᵢ₊₁)`, whole levels elsewhere. `zone` is clamped to `[0, 1]`; 0 pops.
pub fn distance_coordinate(distance: f32, switch: &[f32], zone: f32) -> f32 {
    let zone = zone.clamp(0.0, 1.0);
    let mut x = 0.0;
    for (i, &d) in switch.iter().enumerate().skip(1) {
        if distance >= d {
            x = i as f32;
            continue;
        }
        let start = d * (1.0 - zone);
        if distance > start && d > start {
            x = (i - 1) as f32 + (distance - start) / (d - start);
        }
        break;
    }
    x
}

/// The level coordinate shown by the blending views, and the level the popping view shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schedule {
    /// Level selected by the screen-space error (what popping shows).
    pub selected: usize,
    /// Level coordinate of the blending views, in `[0, levels − 1]`.
    pub coordinate: f32,
}

impl Schedule {
    /// Starts at the finest level.
    pub const FINEST: Self = Self { selected: 0, coordinate: 0.0 };

    /// Advances by `dt` seconds with the camera at `distance`.
    ///
    /// Time mode moves the coordinate towards the selected level at one level per
    /// `seconds_per_level` (it turns around at once when the selection goes back, so a reversal is
    /// smooth too); distance mode sets it from the distance and selects without hysteresis, so
    /// popping switches exactly where the morph ends.
    pub fn step(&mut self, mode: TransitionMode, distance: f32, switch: &[f32], hysteresis: f32, dt: f32) {
        let last = switch.len().saturating_sub(1);
        match mode {
            TransitionMode::Time { seconds_per_level } => {
                self.selected = select_level(self.selected, distance, switch, hysteresis);
                let goal = self.selected as f32;
                if seconds_per_level <= 0.0 {
                    self.coordinate = goal;
                } else {
                    let step = dt.max(0.0) / seconds_per_level;
                    self.coordinate = if self.coordinate < goal {
                        (self.coordinate + step).min(goal)
                    } else {
                        (self.coordinate - step).max(goal)
                    };
                }
            }
            TransitionMode::Distance { zone } => {
                self.selected = select_level(self.selected, distance, switch, 0.0);
                self.coordinate = distance_coordinate(distance, switch, zone);
            }
        }
        self.selected = self.selected.min(last);
        self.coordinate = self.coordinate.clamp(0.0, last as f32);
    }

    /// The fine level and blend `t` towards the next coarser one: `(i, t)` with `t` in `[0, 1)`,
    /// or `(last, 0)` at the coarsest level.
    pub fn blend(&self, levels: usize) -> (usize, f32) {
        let last = levels.saturating_sub(1);
        let fine = (self.coordinate.floor() as usize).min(last);
        let t = if fine == last { 0.0 } else { self.coordinate - fine as f32 };
        (fine, t)
    }
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
    fn time_transition_moves_one_level_per_duration_and_turns_around() {
        let switch = [0.0, 10.0, 20.0];
        let mode = TransitionMode::Time { seconds_per_level: 0.5 };
        let mut s = Schedule::FINEST;
        s.step(mode, 30.0, &switch, 0.0, 0.25);
        assert_eq!((s.selected, s.coordinate), (2, 0.5));
        s.step(mode, 30.0, &switch, 0.0, 0.5);
        assert_eq!(s.coordinate, 1.5);
        assert_eq!(s.blend(3), (1, 0.5));
        s.step(mode, 5.0, &switch, 0.0, 0.25);
        assert_eq!((s.selected, s.coordinate), (0, 1.0));
        s.step(mode, 5.0, &switch, 0.0, 10.0);
        assert_eq!(s.coordinate, 0.0);
        let mut pop = Schedule::FINEST;
        pop.step(TransitionMode::Time { seconds_per_level: 0.0 }, 15.0, &switch, 0.0, 0.0);
        assert_eq!((pop.selected, pop.coordinate), (1, 1.0));
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
        let mut s = Schedule::FINEST;
        s.step(TransitionMode::Distance { zone: 0.2 }, 9.0, &switch, 0.5, 0.0);
        assert_eq!(s.selected, 0);
        assert_eq!(s.blend(3), (0, 0.5));
        s.step(TransitionMode::Distance { zone: 0.2 }, 10.0, &switch, 0.5, 0.0);
        assert_eq!((s.selected, s.blend(3)), (1, (1, 0.0)), "popping switches where the morph ends");
    }

    #[test]
    fn coarsest_level_has_no_blend() {
        let s = Schedule { selected: 2, coordinate: 2.0 };
        assert_eq!(s.blend(3), (2, 0.0));
        assert_eq!(Schedule::FINEST.blend(1), (0, 0.0));
    }
}
