//! The batched order ([`super::super::Schedule::Passes`], opt-in), after meshoptimizer's
//! `simplifyEdge` loop (Kapoulkine, meshoptimizer `src/simplifier.cpp`; the idea, not the code):
//! each pass
//! 1. **picks** the live candidates (stale ones, whose classes changed, are dropped);
//! 2. **ranks** them: the pass's error goal is 1.5× the cost of the k-th cheapest (k = a sixth of
//!    the live triangles), and never below the costliest collapse so far;
//! 3. **sorts** the candidates under the goal by (cost, u, v);
//! 4. **performs** them in that order, each checked against the current mesh; a class that
//!    took part in a collapse is locked for the rest of the pass (its candidates went stale with
//!    its version), so every candidate committed in a pass still has its exact, priced cost;
//! 5. **updates**: the edges the pass changed are priced again in bulk, sorted by class, so the
//!    pricings walk the class arrays in order instead of jumping around the mesh.
//!
//! The result is an ordered collapse sequence like the strict one's (vertex splits, ancestors and
//! the running-maximum error keep their meaning), but a collapse's cost is no longer monotone: it
//! rises within a pass and may drop at the next. The goal depends on the mesh state only, never
//! on the target or the error limit; the run stops at the first collapse that reaches the target
//! and skips those over the limit, so a targeted run is a prefix of an untargeted one.

use super::super::queue::Candidate;
use super::super::StopReason;
use super::apply::Step;
use super::order::Order;
use super::{Engine, Progress};

/// The pass's error goal is this many times the k-th cheapest candidate's cost: meshoptimizer's
/// factor (commit bb419200, "tradeoff between quality … and number of passes"). Measured here
/// (`animated_error`, `clod_timing`): 1.1× brings CesiumMan's static error within 5–8 % of the
/// strict order's, but makes the character's build no faster than the strict one (twice the
/// passes, each filtering every candidate); 1.5× is 10–25 % faster natively.
const GOAL_FACTOR: f32 = 1.5;
/// k = live triangles / this: the goal sits near the 11th percentile of the candidates' costs
/// (about 1.5 candidates per triangle); the character takes 30–40 passes. 12 and 20 measured no
/// better in animated error on CesiumMan and the character.
const RANK_DIVISOR: usize = 6;

impl Engine<'_> {
    /// Runs passes until the target, the error limit, or no candidate is left.
    pub(super) fn collapse_in_passes(
        &mut self,
        target: usize,
        max_mean_squared_error: f32,
        progress: &mut dyn FnMut(f32),
    ) -> StopReason {
        let mut reporter = Progress::new(self.mesh.live_triangles, target);
        // The costliest collapse so far (the running maximum the levels report).
        let mut running_max = 0.0f32;
        loop {
            let mesh = &self.mesh;
            self.order.pick(|c| mesh.is_current(c));
            if self.order.candidates.is_empty() {
                if self.reach_nearest_waiting() {
                    self.update();
                    continue;
                }
                return self.floors.exhausted();
            }
            let goal = self.order.rank(self.mesh.live_triangles, running_max);
            let first = self.order.sort(goal);
            let mut batch = std::mem::take(&mut self.order.candidates);
            let stop = self.perform(
                &batch[first..],
                target,
                max_mean_squared_error,
                &mut running_max,
                &mut |live| reporter.update(live, progress),
            );
            if let Some(stop) = stop {
                return stop;
            }
            batch.truncate(first);
            self.order.candidates = batch;
            self.update();
        }
    }

    /// Commits `batch` in order, skipping collapses over `max_mean_squared_error`; `Some` when the target is
    /// reached.
    fn perform(
        &mut self,
        batch: &[Candidate],
        target: usize,
        max_mean_squared_error: f32,
        running_max: &mut f32,
        report: &mut dyn FnMut(usize),
    ) -> Option<StopReason> {
        for entry in batch {
            report(self.mesh.live_triangles);
            if target > 0 && self.mesh.live_triangles <= target {
                return Some(StopReason::TargetReached);
            }
            // A class that took part in a collapse of this pass is locked: its version moved on.
            if !self.mesh.is_current(entry) {
                continue;
            }
            // Re-planning fills the pairing scratch `apply` uses; the cost is still exact (no end
            // changed, no part near it vanished), and a wrapped 16-bit stamp shows here as a
            // different cost.
            if self.try_collapse(entry, max_mean_squared_error) == Step::Committed {
                *running_max = running_max.max(entry.cost());
            }
        }
        report(self.mesh.live_triangles);
        None
    }

    /// Prices the edges the pass changed, once each, in class order.
    fn update(&mut self) {
        let mut pending = std::mem::take(&mut self.order.pending);
        pending.sort_unstable();
        pending.dedup();
        for &(a, b) in &pending {
            self.queue_edge(a, b, 0.0);
        }
        pending.clear();
        self.order.pending = pending;
    }
}

impl Order {
    /// Drops the candidates whose classes died or changed since they were priced (not
    /// `current`).
    fn pick(&mut self, current: impl Fn(&Candidate) -> bool) {
        self.candidates.retain(|c| current(c));
    }

    /// The pass's error goal, with `live_triangles` left: `GOAL_FACTOR` × the k-th cheapest
    /// candidate's cost, at least the
    /// running maximum (collapsing an edge no costlier than one already collapsed never raises
    /// the reported error; meshoptimizer PR #770).
    fn rank(&mut self, live_triangles: usize, running_max: f32) -> f32 {
        self.keys.clear();
        self.keys.extend(self.candidates.iter().map(|c| c.cost().to_bits()));
        let k = (live_triangles / RANK_DIVISOR).clamp(1, self.keys.len()) - 1;
        // Non-negative f32 bits order like the numbers.
        let (_, kth, _) = self.keys.select_nth_unstable(k);
        (f32::from_bits(*kth) * GOAL_FACTOR).max(running_max)
    }

    /// Moves the candidates at or under `goal` to the end of the list, sorted by (cost, u, v);
    /// returns where they start.
    fn sort(&mut self, goal: f32) -> usize {
        let list = &mut self.candidates;
        let mut end = list.len();
        let mut at = 0;
        while at < end {
            // `!(cost > goal)` also takes NaN, which no candidate has (pricing drops it).
            if list[at].cost() <= goal {
                end -= 1;
                list.swap(at, end);
            } else {
                at += 1;
            }
        }
        list[end..].sort_unstable_by_key(Candidate::order);
        end
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::Schedule;
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_pass_takes_the_candidates_up_to_its_goal_in_order() {
        let mut order = Order::new(Schedule::Passes, 0);
        // Costs 12, 11, …, 1, and a stale one.
        order.candidates = (0..12u32).map(|k| Candidate::new((12 - k) as f32, k, k + 1, 0)).collect();
        order.candidates.push(Candidate::new(0.5, 20, 21, 1));
        order.pick(|c| c.stamp() == 0);
        assert_eq!(order.candidates.len(), 12);
        // 12 live triangles: k = 12 / RANK_DIVISOR = 2, the 2nd cheapest (2) × GOAL_FACTOR.
        assert_eq!(order.rank(12, 0.0), 2.0 * GOAL_FACTOR);
        assert_eq!(order.rank(12, 7.0), 7.0, "never below the running maximum");
        let first = order.sort(3.0);
        assert_eq!(first, 9);
        let taken: Vec<f32> = order.candidates[first..].iter().map(Candidate::cost).collect();
        assert_eq!(taken, [1.0, 2.0, 3.0]);
        assert!(order.candidates[..first].iter().all(|c| c.cost() > 3.0));
    }
}
