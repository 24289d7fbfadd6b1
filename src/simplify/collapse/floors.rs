//! The floors a collapse must stay within besides the error limit, and what they remember: the
//! distance floor ([`super::super::SimplifyOptions::max_distance`]) with the input vertex each
//! class tracks (`Probes` in `checks.rs`), the clearance of the input's parts (`clearance.rs`),
//! how far the level has reached, and the open parts waiting for it to reach farther
//! ([`Waiting`]). Part of the collapse engine in `mod.rs`.
//!
//! An open part's last triangle goes once every point of the part lies within the distance the
//! level has already reached (`open_part_vanishing_error` in `plan.rs`); until then it waits, and
//! the level's reach growing past it (`Engine::reach` in `apply.rs`) prices it again.
//!
//! Invariants: `reached_distance` never decreases; a waiting part is listed once, by the edge of
//! its last triangle (lower class first), at the last distance found for it.

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::clearance::Clearance;
use super::super::topology::PositionClasses;
use super::super::{Rule, SimplifyInput, SimplifyOptions, StopReason};
use super::mesh::Mesh;
use crate::metrics::closest_point_on_triangle_f64;
use glam::{DVec3, Vec3};

/// Live classes whose triangles [`Floors::squared_to_level`] remembers having tested: enough for
/// the few that stand for a coarse neighbourhood, few enough that looking them up stays cheap.
const SEEN_CLASSES: usize = 64;
/// Points whose distance from the live triangles [`Floors::open_part_within`] keeps to vouch for
/// their neighbours (as `clearance.rs` does for the input's).
const MAX_VOUCHERS: usize = 32;

/// The floors and their memory (see the module docs).
pub(super) struct Floors<'a> {
    /// [`super::super::SimplifyOptions::max_distance`].
    pub(super) max_distance: f64,
    /// Whether a collapse that leaves a tracked input vertex farther than `max_distance` is
    /// refused ([`Rule::DistanceFloor`]); the distances are measured either way, for the level's
    /// reach.
    pub(super) distance_floor: bool,
    /// Whether an open part's last triangle goes only within the level's reach
    /// ([`Rule::OpenPartsWithinReach`]; `plan.rs`, `checks.rs`).
    pub(super) open_parts_within_reach: bool,
    /// Whether a collapse was skipped for exceeding the error limit or the distance floor.
    pub(super) over_floor: bool,
    /// Per class: of the input vertices it stands for, the one farthest from the surface after
    /// its last collapse (its representative until then); see `Probes` in `checks.rs`.
    pub(super) farthest_input: Vec<u32>,
    /// The input positions ([`SimplifyInput::positions`]).
    pub(super) input_positions: &'a [Vec3],
    /// How far the input's other parts are, for pricing a part that vanishes.
    pub(super) clearance: Clearance<'a>,
    /// The farthest a committed collapse has left an input point from the level so far, in the
    /// simplification pose (an upper bound, see `Probes` in `checks.rs`), or the distance the
    /// level was let reach when nothing else could collapse (`Engine::reach_nearest_waiting`).
    pub(super) reached_distance: f64,
    /// Open parts whose vanishing would leave a point farther than `reached_distance`.
    pub(super) waiting: Waiting,
    /// The last [`Floors::open_part_within`] asked: (class, steps logged, bound's bits) and its
    /// answer.
    last_open_part_within: Option<OpenPartWithin>,
}

/// A question [`Floors::open_part_within`] answered, and its answer.
type OpenPartWithin = ((u32, usize, u64), Result<(), Option<f64>>);

impl<'a> Floors<'a> {
    /// The floors of a run over `input` (whose position classes are `classes`), nothing reached.
    pub(super) fn new(
        input: &SimplifyInput<'a>,
        options: &SimplifyOptions,
        classes: &PositionClasses,
    ) -> Self {
        Floors {
            max_distance: f64::from(options.max_distance),
            distance_floor: options.rules.has(Rule::DistanceFloor),
            open_parts_within_reach: options.rules.has(Rule::OpenPartsWithinReach),
            over_floor: false,
            farthest_input: classes.representative.clone(),
            input_positions: input.positions,
            clearance: Clearance::new(input.positions, input.indices),
            reached_distance: 0.0,
            waiting: Waiting::default(),
            last_open_part_within: None,
        }
    }
}

impl Floors<'_> {
    /// Why the run ended when no candidate is left: the error limit if it refused one.
    pub(super) fn exhausted(&self) -> StopReason {
        if self.over_floor {
            StopReason::MaxErrorReached
        } else {
            StopReason::NoValidCollapse
        }
    }

    /// Whether a part vanishing with its last classes (`sheet`) leaves its input points within
    /// the distance floor of the parts left, in every pose (`clearance.rs`): the floor for a part
    /// that goes away whole. Its price (`vanishing_error` in `plan.rs`) is a mean over the
    /// sheet's corners, which lets a thin part reaching out go while its tip stands farther than
    /// the floor from everything left.
    pub(super) fn vanishes_within_floor(&mut self, mesh: &Mesh, sheet: [u32; 3]) -> bool {
        self.clearance.leaves_within(&mesh.classes, sheet[0], self.max_distance as f32)
    }

    /// Whether every input point of class `class`'s open part (its own and those left to it) lies
    /// within `bound` of the live triangles of the other parts, in the simplification pose:
    /// `Ok`, or `Err` with the distance of the first point found farther (a lower bound of the
    /// farthest one's), `None` when that one is beyond the floor. `steps`: the collapses logged
    /// so far, which name the state of `mesh`.
    pub(super) fn open_part_within(
        &mut self,
        mesh: &Mesh,
        steps: usize,
        class: u32,
        bound: f64,
    ) -> Result<(), Option<f64>> {
        // A vanishing is priced and then checked with nothing changed in between: ask once.
        let key = (class, steps, bound.to_bits());
        if let Some((known, answer)) = self.last_open_part_within {
            if known == key {
                return answer;
            }
        }
        let answer = self.search_open_part_within(mesh, class, bound);
        self.last_open_part_within = Some((key, answer));
        answer
    }

    fn search_open_part_within(&mut self, mesh: &Mesh, class: u32, bound: f64) -> Result<(), Option<f64>> {
        // As in `Clearance::leaves_within`: a point within `d` of a live triangle puts every
        // point within `bound − d` of it within `bound` too, and a search may stop at any
        // triangle within `bound`.
        let mut found: Vec<(DVec3, f64)> = Vec::new();
        for vertex in self.clearance.points_of_part(&mesh.classes, class) {
            let q = self.input_positions[vertex as usize].as_dvec3();
            if found.iter().any(|&(p, d)| d + p.distance(q) <= bound) {
                continue;
            }
            let distance =
                self.squared_to_level(mesh, class, q, self.max_distance, bound).ok_or(None)?.sqrt();
            if distance > bound {
                return Err(Some(distance));
            }
            if found.len() < MAX_VOUCHERS {
                found.push((q, distance));
            }
        }
        Ok(())
    }

    /// The squared distance from `q` (in the simplification pose) to the nearest live triangle of
    /// another part than class `class`'s among those that now stand for the input triangles near
    /// `q` (the triangles around their corners' live classes), if one is within `radius`; the
    /// search may stop at one within `enough`. An upper bound of the distance to the level: a live
    /// triangle that stands for input farther from `q` than the nearest found is not looked at.
    pub(super) fn squared_to_level(
        &mut self,
        mesh: &Mesh,
        class: u32,
        q: DVec3,
        radius: f64,
        enough: f64,
    ) -> Option<f64> {
        let mut best = f64::INFINITY;
        // Near input triangles share corners, and at coarse levels live classes: each class's
        // triangles are tested once (of the first few classes; later ones are rarely repeats).
        let mut seen: Vec<u32> = Vec::new();
        self.clearance.visit_near(&mesh.classes, class, q.as_vec3(), radius as f32, &mut |t| {
            for k in 0..3 {
                let live = mesh.live_class(mesh.corner_class[3 * t as usize + k]);
                if seen.contains(&live) {
                    continue;
                }
                if seen.len() < SEEN_CLASSES {
                    seen.push(live);
                }
                for corner in mesh.lists.iter(live) {
                    let first = 3 * (corner / 3) as usize;
                    let [a, b, c] = [0, 1, 2].map(|j| mesh.position[mesh.corner_class[first + j] as usize]);
                    best = best.min(closest_point_on_triangle_f64(q, a, b, c).distance_squared(q));
                }
            }
            if best <= enough * enough {
                0.0
            } else {
                best as f32
            }
        });
        (best.is_finite() && best <= radius * radius).then_some(best)
    }
}

/// Open parts whose vanishing would leave a point farther from the level than it has reached:
/// per part, that distance and the edge of its last triangle (lower class first), in the order
/// they began waiting. A part is priced again when the level reaches its distance
/// ([`Waiting::take_due`]), or, when nothing else can collapse, the nearest is let go first
/// ([`Waiting::nearest`]).
#[derive(Default)]
pub(super) struct Waiting {
    parts: Vec<(f64, u32, u32)>,
}

impl Waiting {
    /// The part whose last triangle has edge `edge` (lower class first) would leave a point
    /// `farther` from the level: it waits until the level reaches that far (a part already
    /// waiting takes the new distance and keeps its place).
    pub(super) fn wait(&mut self, edge: (u32, u32), farther: f64) {
        match self.parts.iter_mut().find(|w| (w.1, w.2) == edge) {
            Some(known) => known.0 = farther,
            None => self.parts.push((farther, edge.0, edge.1)),
        }
    }

    /// The nearest distance a part waits for, of those whose edge's classes are both `alive`
    /// (the others are dropped); `None` when none waits.
    pub(super) fn nearest(&mut self, alive: &[bool]) -> Option<f64> {
        self.parts.retain(|&(_, a, b)| alive[a as usize] && alive[b as usize]);
        self.parts.iter().map(|&(reach, ..)| reach).min_by(f64::total_cmp)
    }

    /// Takes out the parts that wait for no more than `distance`, in the order they began
    /// waiting; the others keep waiting.
    pub(super) fn take_due(&mut self, distance: f64) -> Vec<(f64, u32, u32)> {
        let (due, still): (Vec<_>, Vec<_>) =
            std::mem::take(&mut self.parts).into_iter().partition(|&(reach, ..)| reach <= distance);
        self.parts = still;
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn waiting_parts_are_due_when_the_level_reaches_them() {
        let mut waiting = Waiting::default();
        waiting.wait((1, 2), 0.5);
        waiting.wait((3, 4), 0.2);
        waiting.wait((5, 6), 0.9);
        // Found farther later: the new distance, the old place.
        waiting.wait((1, 2), 0.3);
        assert_eq!(waiting.parts, [(0.3, 1, 2), (0.2, 3, 4), (0.9, 5, 6)]);
        assert_eq!(waiting.take_due(0.3), [(0.3, 1, 2), (0.2, 3, 4)], "in the order they began waiting");
        assert_eq!(waiting.take_due(0.3), [], "each part is due once");
        assert_eq!(waiting.parts, [(0.9, 5, 6)]);
    }

    #[test]
    fn the_nearest_waiting_part_is_of_live_classes() {
        let mut waiting = Waiting::default();
        assert_eq!(waiting.nearest(&[true; 4]), None);
        waiting.wait((0, 1), 0.4);
        waiting.wait((2, 3), 0.7);
        assert_eq!(waiting.nearest(&[true; 4]), Some(0.4));
        // Class 1 died (its part vanished another way): its entry goes.
        assert_eq!(waiting.nearest(&[true, false, true, true]), Some(0.7));
        assert_eq!(waiting.parts, [(0.7, 2, 3)]);
    }
}
