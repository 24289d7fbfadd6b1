//! Discrete levels of a progressive mesh and the ancestor tables that join them (for geomorphs,
//! Hoppe 1996 §4.2; Houle & Poulin 2001 §5).
//!
//! Level `i` is the progressive mesh after `kᵢ` collapses, compacted to the vertices its triangles
//! use, with triangles ordered for the vertex cache (Tipsify) and vertices numbered in first-use
//! order. Tipsify reads each fan's triangles by number, so it is given them coherently: the finest
//! level in the input's triangle order, each coarser one in the finer level's drawing order (on an
//! 820k-triangle character the levels' extraction takes 0.54× the time it took in the progressive
//! mesh's own order, by collapse, natively; in wasm its Tipsify and renumbering went from about 700
//! to 350 ms). Its ancestor table gives, for every vertex of level `i`, the index of the vertex of
//! level `i + 1` it collapses into: the same vertex for position and for attributes, since the
//! collapse forest merges wedges (position + attributes) as units. Tables chain: composing
//! `i → i+1` and `i+1 → i+2` gives `i → i+2`.

use std::fmt;

use crate::progressive::{ProgressiveMesh, StopReason, NONE};
use crate::vertex_cache::{first_use_order, tipsify};

/// One discrete level.
#[derive(Clone, Debug, PartialEq)]
pub struct LodLevel {
    /// Collapses applied to reach this level.
    pub collapses: usize,
    /// The triangle count that was asked for.
    pub requested_triangles: usize,
    /// Triangle list indexing `vertices`, ordered for the vertex cache.
    pub indices: Vec<u32>,
    /// The progressive-mesh vertex id of each level vertex. Vertices past those the triangles use
    /// are kept only as ancestors of the finer level (rare: their triangles all degenerated).
    pub vertices: Vec<u32>,
    /// For each vertex, its ancestor's index in the next coarser level; empty for the coarsest.
    pub ancestors: Vec<u32>,
    /// Geometric error: the running maximum RMS plane distance of the collapses so far
    /// (position units), non-decreasing from level to level.
    pub error: f32,
}

impl LodLevel {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// `active[v]`: the vertex that stands for vertex id `v` after `k` collapses.
///
/// One pass over ids in decreasing order works because a parent is always created after its
/// children, so it has a larger id.
pub fn active_ancestors(pm: &ProgressiveMesh, k: usize) -> Vec<u32> {
    let total = pm.vertex_total();
    let mut active = vec![0u32; total];
    for v in (0..total).rev() {
        let p = pm.parent[v];
        active[v] =
            if p != NONE && pm.born_at[p as usize] as usize <= k { active[p as usize] } else { v as u32 };
    }
    active
}

/// Extracts the levels closest to `requested` triangle counts (finest first) and links them.
///
/// A count the progressive mesh cannot reach gives its coarsest level; requests that land on the
/// same collapse count are merged, so every level differs from the next.
pub fn build_levels(pm: &ProgressiveMesh, requested: &[usize]) -> Vec<LodLevel> {
    let mut levels: Vec<LodLevel> = Vec::new();
    let mut new_from_id: Vec<Vec<u32>> = Vec::new();
    let mut actives: Vec<Vec<u32>> = Vec::new();
    // The last level's triangles, as progressive-mesh slots, in drawing order. A coarser level's
    // triangles are a prefix of the slots; listed in this order they come coherently, where the
    // slots' own order (by collapse) is scattered over the mesh.
    let mut drawn: Vec<u32> = Vec::new();
    for &triangles in requested {
        let k = pm.collapses_for_triangle_count(triangles);
        if levels.last().is_some_and(|l| l.collapses == k) {
            continue;
        }
        let active = active_ancestors(pm, k);
        let live = pm.triangle_count_after(k);
        let (slots, by_id) = match levels.last() {
            None => in_input_order(pm, &active, live),
            Some(finer) => in_drawing_order(finer, &drawn, &active, live),
        };
        // Tipsify over vertices numbered as they come, then the level's own first-use numbering.
        let (coherent, ids) = first_use_order(&by_id, pm.vertex_total());
        let order = tipsify(&coherent, ids.len());
        let mut ordered = Vec::with_capacity(coherent.len());
        for &t in &order {
            ordered.extend_from_slice(&coherent[3 * t as usize..3 * t as usize + 3]);
        }
        let (indices, used) = first_use_order(&ordered, ids.len());
        let vertices: Vec<u32> = used.iter().map(|&c| ids[c as usize]).collect();
        drawn = order.iter().map(|&t| slots[t as usize]).collect();
        let mut slot = vec![NONE; pm.vertex_total()];
        for (i, &v) in vertices.iter().enumerate() {
            slot[v as usize] = i as u32;
        }
        new_from_id.push(slot);
        actives.push(active);
        levels.push(LodLevel {
            collapses: k,
            requested_triangles: triangles,
            indices,
            vertices,
            ancestors: Vec::new(),
            error: pm.distance_after(k),
        });
    }
    // Link fine to coarse; an ancestor the coarser level's triangles no longer use is appended
    // to it, so it gets its own ancestor when that level is linked in turn.
    for i in 0..levels.len().saturating_sub(1) {
        let active = &actives[i + 1];
        let (fine, coarse) = levels.split_at_mut(i + 1);
        let (fine, coarse) = (&mut fine[i], &mut coarse[0]);
        let slots = &mut new_from_id[i + 1];
        fine.ancestors = fine
            .vertices
            .iter()
            .map(|&v| {
                let a = active[v as usize] as usize;
                if slots[a] == NONE {
                    slots[a] = coarse.vertices.len() as u32;
                    coarse.vertices.push(a as u32);
                }
                slots[a]
            })
            .collect();
    }
    levels
}

/// The first `live` triangle slots in the input's triangle order (which exporters write part by
/// part, often already for the vertex cache), and their corners as the vertices that stand for
/// them (`active`). One scattered write per triangle, then reads in order.
fn in_input_order(pm: &ProgressiveMesh, active: &[u32], live: usize) -> (Vec<u32>, Vec<u32>) {
    let mut by_source = vec![(NONE, [0u32; 3]); pm.triangle_source.len()];
    for (s, corners) in pm.indices.chunks_exact(3).enumerate().take(live) {
        by_source[pm.triangle_source[s] as usize] = (s as u32, [corners[0], corners[1], corners[2]]);
    }
    let mut slots = Vec::with_capacity(live);
    let mut by_id = Vec::with_capacity(3 * live);
    for (s, corners) in by_source.into_iter().filter(|&(s, _)| s != NONE) {
        slots.push(s);
        by_id.extend(corners.map(|v| active[v as usize]));
    }
    (slots, by_id)
}

/// The first `live` triangle slots in the drawing order of `finer` (`drawn`: its triangles'
/// slots), and their corners as the vertices that stand for them (`active`), read through
/// `finer`'s own corners: a vertex's ancestor is its finer ancestor's.
fn in_drawing_order(finer: &LodLevel, drawn: &[u32], active: &[u32], live: usize) -> (Vec<u32>, Vec<u32>) {
    let ancestor: Vec<u32> = finer.vertices.iter().map(|&v| active[v as usize]).collect();
    let mut slots = Vec::with_capacity(live);
    let mut by_id = Vec::with_capacity(3 * live);
    for (&s, corners) in drawn.iter().zip(finer.indices.chunks_exact(3)) {
        if (s as usize) < live {
            slots.push(s);
            by_id.extend(corners.iter().map(|&c| ancestor[c as usize]));
        }
    }
    (slots, by_id)
}

/// Why a chain's coarsest level has more triangles than its build asked for: the simplifier
/// stopped first ([`StopReason::MaxErrorReached`] or [`StopReason::NoValidCollapse`]). Its
/// `Display` is a sentence for the reader of the page.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StoppedShort {
    pub reason: StopReason,
    /// Triangles of the coarsest level.
    pub triangles: usize,
    /// Triangles of the full mesh.
    pub full: usize,
}

impl StoppedShort {
    /// Whether the simplification of `pm` stopped before its target, and where; `None` when it
    /// reached it.
    pub fn of(pm: &ProgressiveMesh) -> Option<StoppedShort> {
        (pm.stop != StopReason::TargetReached).then(|| StoppedShort {
            reason: pm.stop,
            triangles: pm.triangle_count_after(pm.collapse_count()),
            full: pm.triangle_count_after(0),
        })
    }
}

impl fmt::Display for StoppedShort {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let percent = 100.0 * self.triangles as f64 / self.full.max(1) as f64;
        write!(f, "the levels stop at {} of {} triangles ({percent:.0} %): ", self.triangles, self.full)?;
        f.write_str(match self.reason {
            StopReason::MaxErrorReached => {
                "every further collapse would move the surface more than the error limit allows"
            }
            StopReason::NoValidCollapse | StopReason::TargetReached => {
                "every edge left is locked (where seams, creases or material borders meet) or would fold \
                 a triangle over"
            }
        })
    }
}
