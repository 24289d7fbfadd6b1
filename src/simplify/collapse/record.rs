//! What a run hands back: the collapse log (`progressive.rs` turns it into the progressive mesh),
//! the vertex id each wedge has in it now, and the run's counts (`stats.rs`). Part of the
//! collapse engine in `mod.rs`.
//!
//! Invariants: the log's first vertices are the input's, in its order; every collapse appends
//! its new vertices and then its step, so `log.steps.len()` counts the collapses made and names
//! the state of the mesh (the floors remember answers by it); `vertex_id[w]` is the newest
//! vertex of wedge `w`.

use super::super::topology::NONE;
use super::super::{SimplifyInput, StopReason};
use super::stats::PricingStats;
use crate::progressive::CollapseLog;

/// The log, the wedges' vertex ids in it, and the counts (see the module docs).
pub(super) struct Record {
    pub(super) log: CollapseLog,
    /// Per wedge, the id of its newest vertex in the log (its input vertex until a collapse
    /// gives it a new one).
    pub(super) vertex_id: Vec<u32>,
    /// This run's counts, added to the process-wide ones at the end.
    pub(super) stats: PricingStats,
}

impl Record {
    /// The record of no collapse over `input`.
    pub(super) fn new(input: &SimplifyInput<'_>) -> Record {
        let n = input.positions.len();
        let log = CollapseLog {
            positions: input.positions.to_vec(),
            attributes: input.attributes.to_vec(),
            parent: vec![NONE; n],
            born_at: vec![0; n],
            survivor_source: vec![NONE; n],
            triangle_death: vec![NONE; input.indices.len() / 3],
            corner_changes: Vec::new(),
            steps: Vec::new(),
            stop: StopReason::NoValidCollapse,
        };
        Record { log, vertex_id: (0..n as u32).collect(), stats: PricingStats::default() }
    }

    /// The collapses logged so far.
    #[inline]
    pub(super) fn steps(&self) -> usize {
        self.log.steps.len()
    }
}
