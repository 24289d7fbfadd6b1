//! The collapse queue: a 4-ary min-heap of candidates keyed by (cost, u, v), `u` scrambled so
//! that equal costs do not go in the file's vertex order ([`TIE_SCRAMBLE`]), with lazy
//! invalidation by version stamps. A candidate is either an exact collapse `u → v` or a *bound*:
//! an edge not priced yet, keyed by a lower bound of its cost, priced when it reaches the top.
//!
//! Four children per node put a node's children in one 64-byte cache line (16-byte entries) and
//! halve the depth of a binary heap; popping is what dominates a heap of hundreds of thousands of
//! mostly stale entries. [`Queue::purge`] drops stale entries in bulk when they pile up.
//!
//! Most entries are never popped: a collapse nearby makes them stale first. So only the near
//! future is a heap: entries keyed above a *horizon* wait unordered in `later`, and when the heap
//! runs dry the cheapest eighth of them (stale ones dropped) moves in and the horizon rises to the
//! last of those. Every heap entry is at or below the horizon and every waiting one above it, so
//! pops come in exactly the order one heap would give, from a heap a fraction of the size.

/// A queued collapse of class `u` into class `v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Candidate {
    /// `f32::to_bits` of the non-negative cost in the high half (integer order is numeric order
    /// for non-negative floats), `u` scrambled ([`TIE_SCRAMBLE`]) in the low half: one compare
    /// orders by (cost, scrambled u).
    key: u64,
    pub v: u32,
    /// Low bits of both classes' versions when queued (see `Mesh::stamp_of`), and
    /// [`BOUND_FLAG`] for a bound.
    stamp: u32,
}

/// The stamp bit that marks a bound (versions keep the other 31 bits, see `Mesh::stamp_of`).
pub(crate) const BOUND_FLAG: u32 = 1 << 31;

impl Candidate {
    /// The collapse `u → v`, priced exactly at `cost`.
    pub fn new(cost: f32, u: u32, v: u32, stamp: u32) -> Candidate {
        debug_assert_eq!(stamp & BOUND_FLAG, 0);
        let tie_rank = u.wrapping_mul(TIE_SCRAMBLE);
        Candidate { key: (u64::from(cost.to_bits()) << 32) | u64::from(tie_rank), v, stamp }
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
        (self.key as u32).wrapping_mul(TIE_UNSCRAMBLE)
    }

    /// The total order of candidates: (cost, scrambled u, v).
    pub fn order(&self) -> (u64, u32) {
        (self.key, self.v)
    }

    /// Whether this comes first in [`Candidate::order`]. With `|` and `&` rather than `||` and
    /// `&&`: compared without a branch (see [`least_of_four`]).
    #[inline]
    fn before(&self, other: &Candidate) -> bool {
        (self.key < other.key) | ((self.key == other.key) & (self.v < other.v))
    }
}

/// Equal costs are ordered by `u` through this bijection (multiplication by an odd number mod
/// 2³², Knuth's golden-ratio constant), not by `u` itself. Mirrored parts of a model cost exactly
/// the same, and an exporter numbers its vertices part by part, ring by ring, so ties broken by
/// ascending id collapse the same corner of every part first, in a pattern the file's numbering
/// makes. On robot.glb that pattern cost its coarse levels: its 82-triangle level was 0.712 % of the
/// diagonal off (skinned, mean over 3 frames), against 0.605–0.658 % for the same robot with its
/// vertices shuffled by 7 seeds; with the scrambled tie-break it is 0.613 % in the file's order,
/// inside the 0.601–0.668 % of the shuffles (`bench/README.md`, 2026-11-26 morning). The shared
/// models, which have no exact ties, build byte for byte as before.
const TIE_SCRAMBLE: u32 = 0x9E37_79B1;
/// The inverse of [`TIE_SCRAMBLE`] mod 2³² by Newton's iteration: an odd number is its own
/// inverse mod 8 (3 correct low bits), and every step doubles the correct bits (3 → 48 in four
/// steps; the fifth changes nothing).
const TIE_UNSCRAMBLE: u32 = {
    let mut x: u32 = TIE_SCRAMBLE;
    let mut step = 0;
    while step < 5 {
        x = x.wrapping_mul(2u32.wrapping_sub(TIE_SCRAMBLE.wrapping_mul(x)));
        step += 1;
    }
    x
};

const ARITY: usize = 4;

#[derive(Default)]
pub(crate) struct Queue {
    /// The heap: every entry keyed at or below `horizon`.
    items: Vec<Candidate>,
    /// Unordered: every entry keyed above `horizon`.
    later: Vec<Candidate>,
    horizon: u64,
}

/// Entries that move into the heap when it runs dry, at least (unless fewer wait) and as a
/// fraction of those waiting: few enough to keep the heap small, many enough that the linear scans
/// of `later` cost a few nanoseconds per pop.
const MIN_MOVED: usize = 1024;
const MOVED_FRACTION: usize = 8;

impl Queue {
    /// Entries in the heap (not counting those waiting beyond the horizon).
    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn push(&mut self, candidate: Candidate) {
        if candidate.key > self.horizon {
            self.later.push(candidate);
            return;
        }
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

    /// Removes and returns the smallest candidate; `keep` tells which of those waiting beyond the
    /// horizon are still wanted when they move into the heap.
    pub fn pop_kept(&mut self, keep: impl Fn(&Candidate) -> bool) -> Option<Candidate> {
        if self.items.is_empty() {
            self.advance(keep);
        }
        self.pop()
    }

    /// Moves the cheapest waiting entries into the (empty) heap and raises the horizon to them.
    fn advance(&mut self, keep: impl Fn(&Candidate) -> bool) {
        self.later.retain(|c| keep(c));
        if self.later.is_empty() {
            return;
        }
        let moved = (self.later.len() / MOVED_FRACTION).max(MIN_MOVED).min(self.later.len());
        self.later.select_nth_unstable_by_key(moved - 1, |c| c.key);
        self.horizon = self.later[moved - 1].key;
        let (items, horizon) = (&mut self.items, self.horizon);
        self.later.retain(|c| {
            // Entries after the selected one may share its key: they move too.
            let inside = c.key <= horizon;
            if inside {
                items.push(*c);
            }
            !inside
        });
        self.heapify();
    }

    /// Removes and returns the smallest candidate of the heap.
    fn pop(&mut self) -> Option<Candidate> {
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
            let best = if first + ARITY <= len {
                first + least_of_four(&self.items[first..first + ARITY])
            } else {
                let mut best = first;
                for child in first + 1..len {
                    if self.items[child].before(&self.items[best]) {
                        best = child;
                    }
                }
                best
            };
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
        self.later.retain(|c| keep(c));
        self.items.retain(|c| keep(c));
        self.heapify();
    }

    /// Restores the heap order of `items` from scratch.
    fn heapify(&mut self) {
        if self.items.len() < 2 {
            return;
        }
        for at in (0..=(self.items.len() - 2) / ARITY).rev() {
            let item = self.items[at];
            self.sift_down(at, item);
        }
    }
}

/// The index of the first least of four children (a full node, [`ARITY`] being 4), by a
/// tournament of selects rather than a loop of branches: which child is least is what the branch
/// predictor cannot guess, and most sifts go down a full node (cachegrind on the built-in
/// character: about a million fewer mispredicted branches per build, in its model).
#[inline]
fn least_of_four(children: &[Candidate]) -> usize {
    let left = usize::from(children[1].before(&children[0]));
    let right = 2 + usize::from(children[3].before(&children[2]));
    if children[right].before(&children[left]) {
        right
    } else {
        left
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip_through_the_tie_scramble() {
        assert_eq!(TIE_SCRAMBLE.wrapping_mul(TIE_UNSCRAMBLE), 1);
        for u in [0, 1, 2, 12_345, u32::MAX - 1, u32::MAX] {
            assert_eq!(Candidate::new(1.5, u, 7, 0).u(), u);
            assert_eq!(Candidate::bound(0.5, u.min(u32::MAX - 1), u32::MAX, 3).u(), u.min(u32::MAX - 1));
        }
        // Equal costs: not in id order (0, 1, 2 rank 0, 0x9E3779B1, 0x3C6EF362).
        let ranks: Vec<u64> = (0..3).map(|u| Candidate::new(1.0, u, 0, 0).order().0).collect();
        assert!(ranks[2] < ranks[1]);
    }

    #[test]
    fn the_least_of_four_is_the_first_least() {
        let node = |costs: [f32; 4]| costs.map(|cost| Candidate::new(cost, 1, 2, 0));
        for (costs, least) in
            [([1.0, 2.0, 3.0, 4.0], 0), ([4.0, 3.0, 2.0, 1.0], 3), ([2.0, 1.0, 1.0, 3.0], 1)]
        {
            assert_eq!(least_of_four(&node(costs)), least, "{costs:?}");
        }
        let mut tied = node([5.0; 4]);
        assert_eq!(least_of_four(&tied), 0, "ties go to the first");
        tied[2].v = 1;
        assert_eq!(least_of_four(&tied), 2, "then by v");
    }

    #[test]
    fn pops_in_order_after_purge() {
        let mut queue = Queue::default();
        let mut state = 17u32;
        for i in 0..500u32 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            queue.push(Candidate::new((state >> 24) as f32 * 0.25, i % 7, i, 0));
        }
        queue.purge(|c| c.v % 3 != 0);
        let mut last = (0u64, 0u32);
        let mut count = 0;
        while let Some(c) = queue.pop_kept(|_| true) {
            let now = c.order();
            assert!(now >= last, "{now:?} after {last:?}");
            assert!(c.u() < 7);
            assert!(c.v % 3 != 0);
            last = now;
            count += 1;
        }
        assert_eq!(count, (0..500).filter(|v| v % 3 != 0).count());
    }

    /// Pushes and pops interleaved, ties included, entries pushed below the horizon after it rose,
    /// and stale entries (odd `v`) dropped when they move in: the kept pops come in exactly the
    /// order of one sorted list of everything pushed so far.
    #[test]
    fn the_horizon_keeps_the_order_of_one_heap() {
        let mut queue = Queue::default();
        let mut reference: Vec<(u64, u32)> = Vec::new();
        let mut state = 5u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            state >> 8
        };
        let keep = |c: &Candidate| c.v % 2 == 0;
        let mut popped = 0;
        for round in 0..40u32 {
            for i in 0..400u32 {
                let cost = (next() % 50) as f32 * 0.5 + round as f32 * 2.0 - 40.0;
                let candidate = Candidate::new(cost.max(0.0), next() % 13, round * 400 + i, 0);
                queue.push(candidate);
                if keep(&candidate) {
                    reference.push(candidate.order());
                }
            }
            for _ in 0..300 {
                let Some(c) = queue.pop_kept(keep) else { break };
                if !keep(&c) {
                    continue;
                }
                let smallest = reference.iter().enumerate().min_by_key(|(_, o)| **o).map(|(k, _)| k).unwrap();
                assert_eq!(c.order(), reference.swap_remove(smallest), "pop {popped}");
                popped += 1;
            }
        }
        while let Some(c) = queue.pop_kept(keep) {
            if keep(&c) {
                let smallest = reference.iter().enumerate().min_by_key(|(_, o)| **o).map(|(k, _)| k).unwrap();
                assert_eq!(c.order(), reference.swap_remove(smallest));
            }
        }
        assert!(reference.is_empty());
        assert!(popped > 5_000);
    }
}
