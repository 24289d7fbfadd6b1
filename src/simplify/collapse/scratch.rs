//! The collapse engine's scratch space: buffers that one step fills and the next reuses, grown
//! once and never shrunk, so the loop allocates nothing once it is warm. Nothing here outlives
//! the step that wrote it, with one exception: the [`Pairing`] a plan leaves is what the collapse
//! of that plan reads (`apply.rs`), so a plan must be the latest made before it is applied. Part
//! of the collapse engine in `mod.rs`.

use super::checks::ProbeTriangle;

/// Scratch buffers of the collapse engine (see the module docs).
#[derive(Default)]
pub(super) struct Scratch {
    /// Per-class marks of the current question (neighbour sets, the link condition, parked
    /// partners).
    pub(super) marks: Marks,
    /// The wedge pairing of the latest plan.
    pub(super) pairing: Pairing,
    /// The neighbours of a class, and of one of those (`requeue_neighbours` in `apply.rs`).
    pub(super) neighbours: Vec<u32>,
    pub(super) second_neighbours: Vec<u32>,
    /// The attributes of a vertex a collapse creates, one per channel.
    pub(super) new_attributes: Vec<f32>,
    /// The surviving triangles of the collapse being checked (`checks.rs`, `Probes`).
    pub(super) probe_triangles: Vec<ProbeTriangle>,
}

impl Scratch {
    /// Scratch for `classes` position classes and `channels` attribute channels.
    pub(super) fn new(classes: usize, channels: usize) -> Scratch {
        Scratch { marks: Marks::new(classes), new_attributes: vec![0.0; channels], ..Scratch::default() }
    }
}

/// One mark per class, set to the current stamp: a new stamp clears every mark at once.
///
/// Invariant: no mark is above `stamp`, so after [`Marks::next_stamp`] no class is marked. When
/// the stamp wraps, the marks are cleared and counting starts again at 1.
#[derive(Default)]
pub(super) struct Marks {
    mark: Vec<u32>,
    stamp: u32,
}

impl Marks {
    pub(super) fn new(classes: usize) -> Marks {
        Marks { mark: vec![0; classes], stamp: 0 }
    }

    /// A fresh stamp, under which no class is marked.
    pub(super) fn next_stamp(&mut self) -> u32 {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
        self.stamp
    }

    /// Marks class `c` with `stamp`.
    #[inline]
    pub(super) fn set(&mut self, c: u32, stamp: u32) {
        self.mark[c as usize] = stamp;
    }

    /// Whether class `c` carries `stamp`.
    #[inline]
    pub(super) fn is_set(&self, c: u32, stamp: u32) -> bool {
        self.mark[c as usize] == stamp
    }
}

/// The wedge pairing of a planned collapse `u → v` (`Pricing::plan` in `plan.rs`): which wedge of
/// `v` each wedge of `u` merges with.
#[derive(Default)]
pub(super) struct Pairing {
    /// Per wedge of `u`: index into `v`'s wedges (NONE: none yet).
    pub(super) u_pair: Vec<u32>,
    /// Per wedge of `u`: whether a live triangle uses it.
    pub(super) u_seen: Vec<bool>,
    /// Per wedge of `v`: index into `u`'s wedges, or NONE.
    pub(super) v_partner: Vec<u32>,
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_new_stamp_clears_every_mark_even_when_it_wraps() {
        let mut marks = Marks::new(3);
        let first = marks.next_stamp();
        marks.set(1, first);
        assert!(marks.is_set(1, first) && !marks.is_set(0, first));
        let second = marks.next_stamp();
        assert_ne!(first, second);
        assert!(!marks.is_set(1, second));
        // Just before the wrap: a mark at the last stamp must not survive into stamp 1.
        marks.stamp = u32::MAX - 1;
        let last = marks.next_stamp();
        assert_eq!(last, u32::MAX);
        marks.set(2, last);
        marks.set(0, 1);
        let wrapped = marks.next_stamp();
        assert_eq!(wrapped, 1, "counting starts again at 1 (0 is every mark's cleared value)");
        assert!((0..3).all(|c| !marks.is_set(c, wrapped)), "the wrap clears the marks");
    }
}
