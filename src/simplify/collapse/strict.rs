//! The strict order ([`super::super::Schedule::Strict`]): one collapse at a time, always the
//! cheapest valid one, from a 4-ary heap with lazy invalidation (`queue.rs`). Edges wait in the
//! heap under a lower bound of their cost (`Order::queue_bounds`) and are priced when the bound
//! reaches the top; since a bound never exceeds the exact key, the collapses come in exactly the
//! order eager pricing gives, and most edges change again, and are bounded again, before they
//! would have been due. Part of the collapse engine in `mod.rs`.

use super::super::StopReason;
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
            if !self.mesh.is_current(&entry) {
                continue;
            }
            if entry.is_bound() {
                // A deferred edge is due: price it; its exact entries take their place in order.
                self.queue_edge(entry.u(), entry.v, entry.cost());
                continue;
            }
            self.try_collapse(&entry, max_mean_squared_error);
        }
    }
}
