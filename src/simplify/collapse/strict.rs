//! The strict order ([`super::super::Schedule::Strict`]): one collapse at a time, always the
//! cheapest valid one, from a 4-ary heap with lazy invalidation (`queue.rs`). Edges wait in the
//! heap under a lower bound of their cost (`Engine::queue_bounds`) and are priced when the bound
//! reaches the top; since a bound never exceeds the exact key, the collapses come in exactly the
//! order eager pricing gives, and most edges change again, and are bounded again, before they
//! would have been due. Part of the collapse engine in `mod.rs`.

use super::super::StopReason;
use super::checks::check;
use super::{Candidate, Engine, Progress};

impl Engine<'_> {
    /// Pops collapses in order until the target or the end of the queue, skipping those over the
    /// error limit.
    pub(super) fn collapse_until(
        &mut self,
        target: usize,
        max_mean_squared_error: f32,
        progress: &mut dyn FnMut(f32),
    ) -> StopReason {
        let mut reporter = Progress::new(self.mesh.live_triangles, target);
        loop {
            reporter.update(self.mesh.live_triangles, progress);
            if target > 0 && self.mesh.live_triangles <= target {
                return StopReason::TargetReached;
            }
            let mesh = &self.mesh;
            let Some(entry) = self.order.pop(|c: &Candidate| mesh.is_current(c)) else {
                if self.reach_nearest_waiting() {
                    continue;
                }
                return self.floors.exhausted();
            };
            let (u, v) = (entry.u(), entry.v);
            if !self.mesh.is_current(&entry) {
                continue;
            }
            if entry.is_bound() {
                // A deferred edge is due: price it; its exact entries take their place in order.
                self.queue_edge(u, v, entry.cost());
                continue;
            }
            // The stamp keeps 16 and 15 bits of the versions; a wrapped stamp is caught by the
            // cost, which a current entry reproduces exactly, unless a part near it vanished
            // (see `requeue_repriced`).
            let Some(plan) = self.current_plan(u, v, entry.cost()) else {
                continue;
            };
            if plan.mean_squared as f32 > max_mean_squared_error {
                self.floors.over_floor = true;
                continue;
            }
            let Some((farthest, distance)) =
                check(&self.mesh, &mut self.floors, &mut self.scratch, self.record.steps(), &plan)
            else {
                self.order.parked.park(u, v);
                self.order.parked.park(v, u);
                continue;
            };
            if distance > self.floors.max_distance {
                self.floors.over_floor = true;
                continue;
            }
            self.commit(&plan, farthest, distance);
        }
    }
}
