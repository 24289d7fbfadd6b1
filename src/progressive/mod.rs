//! Progressive meshes (Hoppe 1996) recorded as a collapse forest, with an incremental cursor.
//!
//! Vertex ids `0..input_vertex_count` are the input vertices. Every collapse creates new vertex
//! ids (one per merged wedge pair, and one per unmerged wedge that moved) with their own position
//! and attributes; `parent[x]` is the vertex `x` merged into and `born_at[x]` the 1-based collapse
//! step that created `x` (0 for input vertices). The mesh after `k` collapses is the first
//! [`ProgressiveMesh::triangle_count_after`]`(k)` base triangles with every corner replaced by its
//! active ancestor ([`ProgressiveMesh::ancestor_at`]); the dropped triangles are exactly those
//! that became degenerate. Refining fully gives back the input triangles (in the base order,
//! see [`ProgressiveMesh::triangle_source`]).
//!
//! For streaming and GPU upload the mesh also has Hoppe's prefix property: base triangles are
//! ordered by the step that removes them (latest first), and vertices live in *slots* — a new
//! vertex takes the slot of the vertex whose identity it inherits (`survivor_source`) — ordered
//! the same way, so at every level the live triangles and live slots are prefixes.
//! [`PmCursor`] moves between levels by applying or undoing only the recorded corner changes of
//! each step.

mod validate;

pub use validate::BrokenInvariant;

use glam::Vec3;

/// "No vertex, slot or step" in the u32 index arrays of a progressive mesh and of the code that
/// builds and encodes one.
pub(crate) const NONE: u32 = u32::MAX;

/// Why simplification ended (recorded in the progressive mesh it built; re-exported by
/// `simplify`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// `target_triangles` was reached.
    TargetReached,
    /// Every collapse left would cost more than `max_mean_squared_error` or leave an input
    /// vertex farther than `max_distance` from the surface.
    MaxErrorReached,
    /// No valid collapse is left (everything remaining is locked or would fold); the mesh may
    /// still have more triangles than asked for.
    NoValidCollapse,
}

/// One corner change of the raw log: input corner `corner` switched vertices.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RawCornerChange {
    pub corner: u32,
    pub from_vertex: u32,
    pub to_vertex: u32,
}

/// One step of the raw log.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RawStep {
    pub cost: f64,
    pub distance: f64,
    pub triangles_after: u32,
    pub first_new_vertex: u32,
    pub new_vertex_count: u32,
    pub corner_changes_end: u32,
}

/// What the collapse engine records, in input order (see `simplify::collapse`).
#[derive(Clone, Debug)]
pub(crate) struct CollapseLog {
    pub positions: Vec<Vec3>,
    pub attributes: Vec<f32>,
    pub parent: Vec<u32>,
    pub born_at: Vec<u32>,
    pub survivor_source: Vec<u32>,
    /// Per input triangle, the 1-based step that removed it, or NONE.
    pub triangle_death: Vec<u32>,
    pub corner_changes: Vec<RawCornerChange>,
    pub steps: Vec<RawStep>,
    pub stop: StopReason,
}

/// One edge collapse of a [`ProgressiveMesh`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollapseRecord {
    /// The collapse's quadric cost: mean squared error in position units², attribute errors
    /// included (weighted as the caller asked).
    pub cost: f32,
    /// Square root of the geometric part of the cost (face and penalty planes): an RMS distance
    /// in position units.
    pub distance: f32,
    /// Running maximum of `cost` up to and including this step (non-decreasing).
    pub error: f32,
    /// Running maximum of `distance` up to and including this step (non-decreasing).
    pub max_distance: f32,
    /// Live triangles after this step.
    pub triangles_after: u32,
    /// Live vertex slots after this step.
    pub vertices_after: u32,
    /// The vertices this step created are `first_new_vertex..first_new_vertex + new_vertex_count`.
    pub first_new_vertex: u32,
    pub new_vertex_count: u32,
    /// This step's corner changes are `corner_changes[corner_changes_start..corner_changes_end]`
    /// (see [`ProgressiveMesh::corner_change`]).
    pub corner_changes_start: u32,
    pub corner_changes_end: u32,
}

/// A corner of the base triangle list that moves to another vertex slot at some step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerChange {
    /// Index into [`ProgressiveMesh::indices`] (3 × triangle + k).
    pub corner: u32,
    /// Slot before the step.
    pub from_slot: u32,
    /// Slot after the step.
    pub to_slot: u32,
}

/// A progressive mesh: the input mesh, the collapse forest over vertex ids, and the data to move
/// between levels. See the module docs for the conventions.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgressiveMesh {
    /// Position of every vertex id (input vertices first).
    pub positions: Vec<Vec3>,
    /// `attribute_count` floats per vertex id.
    pub attributes: Vec<f32>,
    pub attribute_count: usize,
    pub input_vertex_count: usize,
    /// The vertex each vertex merged into, `u32::MAX` for roots.
    pub parent: Vec<u32>,
    /// The 1-based collapse step that created each vertex, 0 for input vertices.
    pub born_at: Vec<u32>,
    /// For every created vertex, the vertex it inherits identity (and skin weights) from: the
    /// survivor of its merge, or the vertex it moved from. `u32::MAX` for input vertices.
    pub survivor_source: Vec<u32>,
    /// The slot of every vertex id; slots of live vertices at step `k` are
    /// `0..vertex_count_after(k)`.
    pub vertex_slot: Vec<u32>,
    /// Base triangles (input vertex ids), latest-removed first: the live triangles at step `k`
    /// are the first `triangle_count_after(k)`.
    pub indices: Vec<u32>,
    /// Input triangle index of each base triangle.
    pub triangle_source: Vec<u32>,
    /// The collapses, in order.
    pub collapses: Vec<CollapseRecord>,
    /// Why simplification ended: if not [`StopReason::TargetReached`] the last level may have
    /// more triangles than asked for.
    pub stop: StopReason,
    /// Live slots before any collapse (input vertices some triangle uses).
    pub base_vertex_count: u32,
    /// Private so that only the simplifier and the validated decoder (`clod::bytes`) fill it.
    pub(crate) corner_changes: Vec<CornerChange>,
}

/// The indices of `deaths` (collapse steps, [`NONE`] for never), never first, then latest first,
/// ties in index order: a counting sort, as the steps are at most the collapse count.
fn latest_death_first(deaths: &[u32]) -> Vec<u32> {
    let latest = deaths.iter().filter(|&&d| d != NONE).max().map_or(0, |&d| d as usize);
    // Bucket 0 holds never, bucket 1 + latest − d step d.
    let bucket = |d: u32| if d == NONE { 0 } else { 1 + latest - d as usize };
    let mut start = vec![0usize; latest + 3];
    for &d in deaths {
        start[bucket(d) + 1] += 1;
    }
    for b in 1..start.len() {
        start[b] += start[b - 1];
    }
    let mut order = vec![0u32; deaths.len()];
    for (i, &d) in deaths.iter().enumerate() {
        let at = &mut start[bucket(d)];
        order[*at] = i as u32;
        *at += 1;
    }
    order
}

impl ProgressiveMesh {
    /// Assembles the mesh from the engine's log: orders triangles and slots, renumbers corners.
    pub(crate) fn from_log(
        log: CollapseLog,
        input_indices: &[u32],
        attribute_count: usize,
        input_vertex_count: usize,
    ) -> ProgressiveMesh {
        let n = input_vertex_count;
        let vertex_total = log.positions.len();
        let triangle_count = input_indices.len() / 3;
        // Triangles: never removed first, then latest removed first; ties by input order.
        let order = latest_death_first(&log.triangle_death);
        let mut rank = vec![0u32; triangle_count];
        for (i, &t) in order.iter().enumerate() {
            rank[t as usize] = i as u32;
        }
        let mut indices = Vec::with_capacity(input_indices.len());
        for &t in &order {
            indices.extend_from_slice(&input_indices[3 * t as usize..3 * t as usize + 3]);
        }

        // Slots: one chain of survivors per input vertex. A chain dies when its vertex merges as
        // the non-survivor; chains of unreferenced vertices are dead from the start.
        let mut chain = vec![0u32; vertex_total];
        for x in 0..vertex_total {
            chain[x] = if x < n { x as u32 } else { chain[log.survivor_source[x] as usize] };
        }
        let mut referenced = vec![false; n];
        for &i in input_indices {
            referenced[i as usize] = true;
        }
        let mut chain_death: Vec<u32> = referenced.iter().map(|&r| if r { NONE } else { 0 }).collect();
        for y in 0..vertex_total {
            let p = log.parent[y];
            if p != NONE && log.survivor_source[p as usize] != y as u32 {
                chain_death[chain[y] as usize] = log.born_at[p as usize];
            }
        }
        let chains = latest_death_first(&chain_death);
        let mut slot_of_chain = vec![0u32; n];
        for (slot, &c) in chains.iter().enumerate() {
            slot_of_chain[c as usize] = slot as u32;
        }
        let vertex_slot: Vec<u32> = chain.iter().map(|&c| slot_of_chain[c as usize]).collect();
        let mut deaths_at = vec![0u32; log.steps.len() + 1];
        for &d in &chain_death {
            if d != NONE && (d as usize) < deaths_at.len() {
                deaths_at[d as usize] += 1;
            }
        }
        let base_vertex_count = chain_death.iter().filter(|&&d| d != 0).count() as u32;

        let corner_changes: Vec<CornerChange> = log
            .corner_changes
            .iter()
            .map(|c| CornerChange {
                corner: rank[c.corner as usize / 3] * 3 + c.corner % 3,
                from_slot: vertex_slot[c.from_vertex as usize],
                to_slot: vertex_slot[c.to_vertex as usize],
            })
            .collect();
        let mut collapses = Vec::with_capacity(log.steps.len());
        let (mut error, mut max_distance, mut vertices, mut start) = (0.0f32, 0.0f32, base_vertex_count, 0);
        for (s, step) in log.steps.iter().enumerate() {
            error = error.max(step.cost as f32);
            max_distance = max_distance.max(step.distance as f32);
            vertices -= deaths_at[s + 1];
            collapses.push(CollapseRecord {
                cost: step.cost as f32,
                distance: step.distance as f32,
                error,
                max_distance,
                triangles_after: step.triangles_after,
                vertices_after: vertices,
                first_new_vertex: step.first_new_vertex,
                new_vertex_count: step.new_vertex_count,
                corner_changes_start: start,
                corner_changes_end: step.corner_changes_end,
            });
            start = step.corner_changes_end;
        }
        ProgressiveMesh {
            positions: log.positions,
            attributes: log.attributes,
            attribute_count,
            input_vertex_count: n,
            parent: log.parent,
            born_at: log.born_at,
            survivor_source: log.survivor_source,
            vertex_slot,
            indices,
            triangle_source: order,
            collapses,
            stop: log.stop,
            base_vertex_count,
            corner_changes,
        }
    }

    /// Number of recorded collapses (levels are `0..=collapse_count()`).
    pub fn collapse_count(&self) -> usize {
        self.collapses.len()
    }

    /// Number of vertex ids (input and created).
    pub fn vertex_total(&self) -> usize {
        self.positions.len()
    }

    /// Live triangles after `k` collapses (`k` is clamped to the collapse count).
    pub fn triangle_count_after(&self, k: usize) -> usize {
        match k.min(self.collapses.len()) {
            0 => self.indices.len() / 3,
            k => self.collapses[k - 1].triangles_after as usize,
        }
    }

    /// Live vertex slots after `k` collapses (`k` is clamped).
    pub fn vertex_count_after(&self, k: usize) -> usize {
        match k.min(self.collapses.len()) {
            0 => self.base_vertex_count as usize,
            k => self.collapses[k - 1].vertices_after as usize,
        }
    }

    /// The error after `k` collapses: the running maximum of collapse costs (mean squared error,
    /// position units²), 0 for `k = 0`. Non-decreasing in `k`.
    pub fn error_after(&self, k: usize) -> f32 {
        match k.min(self.collapses.len()) {
            0 => 0.0,
            k => self.collapses[k - 1].error,
        }
    }

    /// The geometric error after `k` collapses as a distance (running maximum of the collapses'
    /// RMS plane distances), 0 for `k = 0`. Non-decreasing in `k`.
    pub fn distance_after(&self, k: usize) -> f32 {
        match k.min(self.collapses.len()) {
            0 => 0.0,
            k => self.collapses[k - 1].max_distance,
        }
    }

    /// The fewest collapses that leave at most `triangles` triangles, or all of them when even
    /// the coarsest level has more.
    pub fn collapses_for_triangle_count(&self, triangles: usize) -> usize {
        if self.triangle_count_after(0) <= triangles {
            return 0;
        }
        // triangles_after is non-increasing: find the first step at or below the target; when
        // none is, every collapse (not one past the last).
        let above = self.collapses.partition_point(|c| c.triangles_after as usize > triangles);
        (above + 1).min(self.collapses.len())
    }

    /// The vertex that stands for `v` after `k` collapses: follow `parent` while the parent was
    /// born by step `k`.
    ///
    /// # Panics
    /// If `v` is not a vertex id.
    pub fn ancestor_at(&self, v: u32, k: usize) -> u32 {
        let mut a = v;
        loop {
            let p = self.parent[a as usize];
            if p == NONE || self.born_at[p as usize] as usize > k {
                return a;
            }
            a = p;
        }
    }

    /// The triangles after `k` collapses as vertex ids, rebuilt from scratch (for checking and
    /// one-off use; [`PmCursor`] is the incremental way).
    pub fn indices_at(&self, k: usize) -> Vec<u32> {
        let count = self.triangle_count_after(k);
        self.indices[..3 * count].iter().map(|&v| self.ancestor_at(v, k)).collect()
    }

    /// The corner changes of all steps; step `k`'s are the range in its [`CollapseRecord`].
    pub fn corner_change(&self, index: usize) -> CornerChange {
        self.corner_changes[index]
    }

    /// Every corner change, in step order.
    pub fn corner_changes(&self) -> &[CornerChange] {
        &self.corner_changes
    }

    /// A cursor at level 0 (the full mesh).
    pub fn cursor(&self) -> PmCursor<'_> {
        PmCursor::new(self)
    }
}

/// Moves a [`ProgressiveMesh`] between levels incrementally and exposes the current mesh in
/// compact form: `indices()` index `vertices()`, which lists the vertex id in each live slot.
#[derive(Clone, Debug)]
pub struct PmCursor<'a> {
    pm: &'a ProgressiveMesh,
    level: usize,
    corner_slots: Vec<u32>,
    slot_vertex: Vec<u32>,
}

impl<'a> PmCursor<'a> {
    /// A cursor at level 0.
    pub fn new(pm: &'a ProgressiveMesh) -> PmCursor<'a> {
        let corner_slots = pm.indices.iter().map(|&v| pm.vertex_slot[v as usize]).collect();
        let mut slot_vertex = vec![0u32; pm.input_vertex_count];
        for v in 0..pm.input_vertex_count {
            slot_vertex[pm.vertex_slot[v] as usize] = v as u32;
        }
        PmCursor { pm, level: 0, corner_slots, slot_vertex }
    }

    /// Number of collapses currently applied.
    pub fn level(&self) -> usize {
        self.level
    }

    /// Applies or undoes collapses until `k` are applied (`k` is clamped to the collapse count).
    /// Costs time proportional to the changed corners and vertices only.
    pub fn set_collapses(&mut self, k: usize) {
        let k = k.min(self.pm.collapses.len());
        let pm = self.pm;
        while self.level < k {
            let record = &pm.collapses[self.level];
            for change in
                &pm.corner_changes[record.corner_changes_start as usize..record.corner_changes_end as usize]
            {
                self.corner_slots[change.corner as usize] = change.to_slot;
            }
            for x in record.first_new_vertex..record.first_new_vertex + record.new_vertex_count {
                self.slot_vertex[pm.vertex_slot[x as usize] as usize] = x;
            }
            self.level += 1;
        }
        while self.level > k {
            self.level -= 1;
            let record = &pm.collapses[self.level];
            for x in (record.first_new_vertex..record.first_new_vertex + record.new_vertex_count).rev() {
                self.slot_vertex[pm.vertex_slot[x as usize] as usize] = pm.survivor_source[x as usize];
            }
            for change in pm.corner_changes
                [record.corner_changes_start as usize..record.corner_changes_end as usize]
                .iter()
                .rev()
            {
                self.corner_slots[change.corner as usize] = change.from_slot;
            }
        }
    }

    /// Moves to the finest level with at most `triangles` triangles (or the coarsest level) and
    /// returns its collapse count.
    pub fn set_triangle_count(&mut self, triangles: usize) -> usize {
        let k = self.pm.collapses_for_triangle_count(triangles);
        self.set_collapses(k);
        k
    }

    /// Triangle list of the current level, indexing [`PmCursor::vertices`].
    pub fn indices(&self) -> &[u32] {
        &self.corner_slots[..3 * self.pm.triangle_count_after(self.level)]
    }

    /// Vertex id in each live slot of the current level (look up positions and attributes in the
    /// [`ProgressiveMesh`]). Rarely a slot holds a vertex no triangle uses any more.
    pub fn vertices(&self) -> &[u32] {
        &self.slot_vertex[..self.pm.vertex_count_after(self.level)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn deaths_order_never_first_then_latest_first_ties_by_index() {
        assert_eq!(latest_death_first(&[3, NONE, 0, 5, 3, NONE, 1]), [1, 5, 3, 0, 4, 6, 2]);
        assert_eq!(latest_death_first(&[NONE, NONE]), [0, 1]);
        assert_eq!(latest_death_first(&[]), Vec::<u32>::new());
    }
}
