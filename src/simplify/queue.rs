//! The collapse queue: a 4-ary min-heap of candidates keyed by (cost, u, v), with lazy
//! invalidation by version stamps. A candidate is either an exact collapse `u → v` or a *bound*:
//! an edge not priced yet, keyed by a lower bound of its cost, priced when it reaches the top.
//!
//! Four children per node put a node's children in one 64-byte cache line (16-byte entries) and
//! halve the depth of a binary heap; popping is what dominates a heap of hundreds of thousands of
//! mostly stale entries. [`Queue::purge`] drops stale entries in bulk when they pile up.

/// A queued collapse of class `u` into class `v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Candidate {
    /// `f32::to_bits` of the non-negative cost in the high half (integer order is numeric order
    /// for non-negative floats), `u` in the low half: one compare orders by (cost, u).
    key: u64,
    pub v: u32,
    /// Low bits of both classes' versions when queued (see `Engine::stamp_of`), and
    /// [`BOUND_FLAG`] for a bound.
    stamp: u32,
}

/// The stamp bit that marks a bound (versions keep the other 31 bits, see `Engine::stamp_of`).
pub(crate) const BOUND_FLAG: u32 = 1 << 31;

impl Candidate {
    /// The collapse `u → v`, priced exactly at `cost`.
    pub fn new(cost: f32, u: u32, v: u32, stamp: u32) -> Candidate {
        debug_assert_eq!(stamp & BOUND_FLAG, 0);
        Candidate { key: (u64::from(cost.to_bits()) << 32) | u64::from(u), v, stamp }
    }

    /// The edge `u`–`v` (`u < v`), not priced yet: every collapse along it costs at least
    /// `bound`. Its order key is at most that of either direction's exact entry, so it reaches
    /// the top before they would.
    pub fn bound(bound: f32, u: u32, v: u32, stamp: u32) -> Candidate {
        debug_assert!(u < v);
        Candidate { stamp: stamp | BOUND_FLAG, ..Candidate::new(bound, u, v, stamp) }
    }

    /// Whether this is a bound rather than an exact collapse.
    pub fn is_bound(&self) -> bool {
        self.stamp & BOUND_FLAG != 0
    }

    /// The versions' stamp (without the bound flag).
    pub fn stamp(&self) -> u32 {
        self.stamp & !BOUND_FLAG
    }

    pub fn cost(&self) -> f32 {
        f32::from_bits((self.key >> 32) as u32)
    }

    pub fn u(&self) -> u32 {
        self.key as u32
    }

    /// The total order of candidates: (cost, u, v).
    pub fn order(&self) -> (u64, u32) {
        (self.key, self.v)
    }

    #[inline]
    fn before(&self, other: &Candidate) -> bool {
        (self.key, self.v) < (other.key, other.v)
    }
}

const ARITY: usize = 4;

#[derive(Default)]
pub(crate) struct Queue {
    items: Vec<Candidate>,
}

impl Queue {
    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn push(&mut self, candidate: Candidate) {
        self.items.push(candidate);
        let mut at = self.items.len() - 1;
        while at > 0 {
            let parent = (at - 1) / ARITY;
            if !candidate.before(&self.items[parent]) {
                break;
            }
            self.items[at] = self.items[parent];
            at = parent;
        }
        self.items[at] = candidate;
    }

    /// Removes and returns the smallest candidate.
    pub fn pop(&mut self) -> Option<Candidate> {
        let last = self.items.pop()?;
        if self.items.is_empty() {
            return Some(last);
        }
        let top = self.items[0];
        self.sift_down(0, last);
        Some(top)
    }

    /// Places `item` at hole `at` or below, moving smaller children up.
    fn sift_down(&mut self, mut at: usize, item: Candidate) {
        let len = self.items.len();
        loop {
            let first = at * ARITY + 1;
            if first >= len {
                break;
            }
            let mut best = first;
            for child in first + 1..(first + ARITY).min(len) {
                if self.items[child].before(&self.items[best]) {
                    best = child;
                }
            }
            if !self.items[best].before(&item) {
                break;
            }
            self.items[at] = self.items[best];
            at = best;
        }
        self.items[at] = item;
    }

    /// Keeps only the candidates for which `keep` holds and restores the heap order.
    pub fn purge(&mut self, keep: impl Fn(&Candidate) -> bool) {
        self.items.retain(|c| keep(c));
        if self.items.len() < 2 {
            return;
        }
        for at in (0..=(self.items.len() - 2) / ARITY).rev() {
            let item = self.items[at];
            self.sift_down(at, item);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_in_cost_then_id_order_after_purge() {
        let mut queue = Queue::default();
        let mut state = 17u32;
        for i in 0..500u32 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            queue.push(Candidate::new((state >> 24) as f32 * 0.25, i % 7, i, 0));
        }
        queue.purge(|c| c.v % 3 != 0);
        let mut last = (0.0f32, 0u32, 0u32);
        let mut count = 0;
        while let Some(c) = queue.pop() {
            let now = (c.cost(), c.u(), c.v);
            assert!(now >= last, "{now:?} after {last:?}");
            assert!(c.v % 3 != 0);
            last = now;
            count += 1;
        }
        assert_eq!(count, (0..500).filter(|v| v % 3 != 0).count());
    }
}
