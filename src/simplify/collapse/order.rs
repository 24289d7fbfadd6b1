//! The order of candidates: the strict order's heap (`queue.rs`) with its bulk purges, the
//! batched passes' candidates, pending edges and rank keys, and the parked classes whose failed
//! edges wait for a change nearby. Part of the collapse engine in `mod.rs`.
//!
//! Invariants: an entry is current while its classes' versions match its stamp
//! (`Mesh::is_current`); stale entries may stay anywhere and are dropped when met. The strict
//! heap holds exact entries and bounds, a bound never above the exact key of any collapse along
//! its edge; the passes hold exact entries only.

use super::super::quadric::Quadric;
use super::super::queue::{Candidate, Queue};
use super::super::topology::NONE;
use super::super::Schedule;
use super::costs::Costs;
use super::mesh::Mesh;
use super::{Placement, Plan, PricingStats};

/// The candidates in their order (see the module docs).
pub(super) struct Order {
    pub(super) schedule: Schedule,
    /// The heap of [`Schedule::Strict`].
    queue: Queue,
    /// Queue length after the last purge of stale entries.
    purged_length: usize,
    /// The priced candidates of [`Schedule::Passes`], in no particular order between passes.
    pub(super) candidates: Vec<Candidate>,
    /// Edges (lower class first) to price at the end of the pass.
    pub(super) pending: Vec<(u32, u32)>,
    /// Scratch of the pass threshold: the candidates' cost bits.
    pub(super) keys: Vec<u32>,
    /// Scratch of [`Order::queue_bounds`].
    bound_sums: Vec<(Quadric, u32)>,
    /// The classes whose collapses failed a check, and with which partners.
    pub(super) parked: Parked,
}

impl Order {
    /// An empty order of `schedule` over `classes` classes, none parked.
    pub(super) fn new(schedule: Schedule, classes: usize) -> Order {
        Order {
            schedule,
            queue: Queue::default(),
            purged_length: 0,
            candidates: Vec::new(),
            pending: Vec::new(),
            keys: Vec::new(),
            bound_sums: Vec::new(),
            parked: Parked::new(classes),
        }
    }

    /// Queues `plan` (as it stands on `mesh`): in the heap or among the pass's candidates.
    pub(super) fn push(&mut self, mesh: &Mesh, plan: &Plan) {
        let (u, v) = (plan.u, plan.v);
        let (u, v) = if matches!(plan.placement, Placement::Fixed) {
            (u, v)
        } else {
            // Symmetric placements: both directions give the same point and cost; the end nearer
            // the new point survives (it keeps its skin weights), ties to the lower class id.
            let du = (plan.p - mesh.position[u as usize]).length_squared();
            let dv = (plan.p - mesh.position[v as usize]).length_squared();
            if du < dv || (du == dv && u < v) {
                (v, u)
            } else {
                (u, v)
            }
        };
        let candidate = Candidate::new(plan.cost as f32, u, v, mesh.stamp_of(u, v));
        match self.schedule {
            Schedule::Passes => self.candidates.push(candidate),
            Schedule::Strict => self.queue.push(candidate),
        }
    }

    /// Defers pricing the edges from `v` to `others` in the strict order: queues each under a
    /// lower bound of its cost, to be priced when that reaches the top of the queue (most
    /// re-priced edges change again before then, see `pricing_stats`).
    pub(super) fn queue_bounds(
        &mut self,
        mesh: &Mesh,
        costs: &Costs,
        stats: &mut PricingStats,
        v: u32,
        others: &[u32],
    ) {
        // Two loops: the first only gathers the neighbours' quadrics and versions, independent
        // loads that miss the caches together instead of one after another behind each bound's
        // solve.
        let mut sums = std::mem::take(&mut self.bound_sums);
        sums.clear();
        let relaxed_v = costs.relaxed[v as usize];
        for &x in others {
            let mut sum = relaxed_v;
            sum += &costs.relaxed[x as usize];
            sums.push((sum, mesh.stamp_of(v.min(x), v.max(x))));
        }
        for (&x, (sum, stamp)) in others.iter().zip(&sums) {
            // Where the pair's planes leave a direction free (a flat or cylindrical patch, every
            // plate of an armour), the least value over all of space is 0 and would have the
            // edge priced at the next pop. Every placement lies within one edge length of the
            // midpoint (`price` in `plan.rs`; the f32 rounding of the point within 1e-6 of its
            // coordinates), so the least value within that ball is a bound too.
            let mut error_bound = sum.minimum_lower_bound();
            if error_bound == 0.0 {
                let (a, b) = (mesh.position[v as usize], mesh.position[x as usize]);
                let (center, length) = (0.5 * (a + b), a.distance(b));
                let radius = length + 1e-6 * (length + center.abs().max_element());
                error_bound = sum.lower_bound_within(center, radius);
            }
            // The pair's area is the sum's (relaxing drops attribute planes, not area), so the
            // bound scales like the key.
            let bound = costs.order_key(error_bound, sum.weight) as f32;
            self.queue.push(Candidate::bound(bound, v.min(x), v.max(x), *stamp));
        }
        stats.bounds += others.len() as u64;
        self.bound_sums = sums;
    }

    /// The strict order's next entry, which may be stale (`current` tells), or `None` when the
    /// heap is empty.
    pub(super) fn pop(&mut self, current: impl Fn(&Candidate) -> bool + Copy) -> Option<Candidate> {
        // Stale entries pile up (several per collapse). Dropping them in one linear pass
        // costs a few ns each, popping them one by one a cache-missing sift each: purge
        // whenever the queue has grown by a quarter since the last purge (amortised O(1) per
        // push). Measured on the built-in character (cachegrind), growth of 2× left 9 of 10
        // pops stale; a quarter leaves 1 in 2 and saves more sifting than the purges cost.
        if self.queue.len() > self.purged_length.max(2048) * 5 / 4 {
            self.queue.purge(current);
            self.purged_length = self.queue.len();
        }
        self.queue.pop_kept(current)
    }
}

/// The classes parked by a failed check, each with the partners it failed with: when a later
/// collapse changes a parked class's neighbourhood, its failed edges are priced again
/// (`requeue_neighbours` in `apply.rs`).
///
/// Per class a singly linked list, newest first, of records in one array; records are never
/// freed (a run parks a few times per collapse at most).
pub(super) struct Parked {
    /// Per class, the head of its list of failed partners in `records` (NONE: not parked).
    head: Vec<u32>,
    /// Failed-edge records: (partner class, next record or NONE).
    records: Vec<(u32, u32)>,
}

impl Parked {
    fn new(classes: usize) -> Parked {
        Parked { head: vec![NONE; classes], records: Vec::new() }
    }

    /// Marks `c` parked, remembering that its collapse with `partner` failed a check.
    pub(super) fn park(&mut self, c: u32, partner: u32) {
        let record = self.records.len() as u32;
        self.records.push((partner, self.head[c as usize]));
        self.head[c as usize] = record;
    }

    pub(super) fn is_parked(&self, c: u32) -> bool {
        self.head[c as usize] != NONE
    }

    /// Forgets `c`'s failed partners: it is no longer parked.
    pub(super) fn clear(&mut self, c: u32) {
        self.head[c as usize] = NONE;
    }

    /// Calls `visit` with each of `c`'s failed partners, newest first, and forgets them.
    pub(super) fn take(&mut self, c: u32, mut visit: impl FnMut(u32)) {
        let mut record = std::mem::replace(&mut self.head[c as usize], NONE);
        while record != NONE {
            let (partner, next) = self.records[record as usize];
            visit(partner);
            record = next;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// An order whose heap takes every entry pushed after it, up to a cost of 1e6: one entry
    /// has gone through the heap, and the horizon is up at its key.
    fn raised_order() -> Order {
        let mut order = Order::new(Schedule::Strict, 0);
        order.queue.push(Candidate::new(1e6, 0, 1, 0));
        assert_eq!(order.pop(|_| true).map(|c| c.cost()), Some(1e6));
        order
    }

    #[test]
    fn pops_come_cheapest_first_and_a_grown_heap_is_purged() {
        let mut order = raised_order();
        // 3,000 entries (more than the first purge's 2,048 × 5/4), every third one stale.
        for k in 0..3000u32 {
            let cost = ((k * 7919) % 3000) as f32;
            order.queue.push(Candidate::new(cost, k, k + 1, u32::from(k % 3 == 0)));
        }
        let current = |c: &Candidate| c.stamp() == 0;
        let first = order.pop(current).unwrap();
        assert_eq!(order.purged_length, 2000, "the stale thousand went in one purge");
        assert_eq!(order.queue.len(), 1999);
        let mut last = first.cost();
        let mut count = 1;
        while let Some(entry) = order.pop(current) {
            assert!(current(&entry), "nothing stale is left");
            assert!(entry.cost() >= last, "{} after {last}", entry.cost());
            last = entry.cost();
            count += 1;
        }
        assert_eq!(count, 2000);
    }

    #[test]
    fn a_small_heap_is_not_purged() {
        let mut order = raised_order();
        order.queue.push(Candidate::new(1.0, 0, 1, 1));
        order.queue.push(Candidate::new(2.0, 1, 2, 0));
        // The stale entry comes back: the caller tells it from a current one.
        assert_eq!(order.pop(|c| c.stamp() == 0).map(|c| c.cost()), Some(1.0));
        assert_eq!(order.purged_length, 0);
        assert_eq!(order.pop(|c| c.stamp() == 0).map(|c| c.cost()), Some(2.0));
        assert_eq!(order.pop(|c| c.stamp() == 0), None);
    }

    #[test]
    fn a_parked_class_gives_its_failed_partners_back_once() {
        let mut parked = Parked::new(4);
        assert!(!parked.is_parked(1));
        parked.park(1, 2);
        parked.park(3, 0);
        parked.park(1, 3);
        assert!(parked.is_parked(1) && parked.is_parked(3) && !parked.is_parked(0));
        let mut partners = Vec::new();
        parked.take(1, |p| partners.push(p));
        assert_eq!(partners, [3, 2], "newest first");
        assert!(!parked.is_parked(1));
        parked.take(1, |_| panic!("taken already"));
        parked.clear(3);
        assert!(!parked.is_parked(3));
        parked.take(3, |_| panic!("cleared"));
    }
}
