//! The invariants of a [`ProgressiveMesh`] that [`PmCursor`](super::PmCursor), the level
//! accessors and the GPU upload rely on, checked in linear time: the collapse forest (parents are
//! created vertices with larger ids, triangle and slot counts never grow), and a replay of every
//! collapse (each new vertex replaces its survivor, what merges is live until its step, and every
//! live corner points at a live slot at every level). The simplifier's meshes hold them by
//! construction and the tests check that they do; decoding bytes (`clod::bytes`) checks them,
//! since the bytes may come from anywhere, and restores each corner change's `from_slot` from the
//! replay.

use thiserror::Error;

use super::{ProgressiveMesh, NONE};

/// A broken invariant of a [`ProgressiveMesh`]: the array, the index in it, and what is wrong.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("{field}[{index}]: {reason}")]
pub struct BrokenInvariant {
    pub field: &'static str,
    pub index: usize,
    pub reason: &'static str,
}

impl ProgressiveMesh {
    /// Checks the invariants of the module docs, and that every corner change starts from the
    /// slot its corner has at that step.
    ///
    /// # Errors
    /// The first [`BrokenInvariant`] found.
    pub fn validate(&self) -> Result<(), BrokenInvariant> {
        check_forest(self)?;
        let from_slots = replay(self)?;
        match self.corner_changes.iter().zip(&from_slots).position(|(c, &from)| c.from_slot != from) {
            Some(index) => Err(inconsistent("corner_changes", index, "a change starts from another slot")),
            None => Ok(()),
        }
    }

    /// Checks the invariants as [`ProgressiveMesh::validate`] does and sets every corner change's
    /// `from_slot` from the replay (the bytes store only where a corner goes).
    pub(crate) fn restore_from_slots(&mut self) -> Result<(), BrokenInvariant> {
        check_forest(self)?;
        let from_slots = replay(self)?;
        for (change, from) in self.corner_changes.iter_mut().zip(from_slots) {
            change.from_slot = from;
        }
        Ok(())
    }
}

fn inconsistent(field: &'static str, index: usize, reason: &'static str) -> BrokenInvariant {
    BrokenInvariant { field, index, reason }
}

/// The collapse forest: parents, and step counts that never grow.
fn check_forest(pm: &ProgressiveMesh) -> Result<(), BrokenInvariant> {
    let (n, total) = (pm.input_vertex_count, pm.vertex_total());
    for (v, &p) in pm.parent.iter().enumerate() {
        if p != NONE && (p as usize >= total || (p as usize) < n.max(v + 1)) {
            // Ancestor walks stop because ids grow towards the roots; parents are created ids.
            return Err(inconsistent("parent", v, "a parent must be a created vertex with a larger id"));
        }
    }
    let (mut triangles, mut vertices) = (pm.indices.len() as u64 / 3, u64::from(pm.base_vertex_count));
    for (s, c) in pm.collapses.iter().enumerate() {
        if u64::from(c.triangles_after) > triangles || u64::from(c.vertices_after) > vertices {
            return Err(inconsistent("collapses", s, "triangle and slot counts never grow"));
        }
        (triangles, vertices) = (c.triangles_after.into(), c.vertices_after.into());
    }
    Ok(())
}

/// Replays every collapse as [`PmCursor::set_collapses`](super::PmCursor::set_collapses) does,
/// returning each corner change's slot before its step (what `from_slot` must be, so that undoing
/// restores exactly), and checks that the vertices that
/// merge into a new one are live until then, the new vertex takes its survivor's slot and the
/// others' slots die with the step; and the live corners only use live slots at every level.
/// Linear in corners, slots and changes: the live-slot bound only shrinks, so a per-slot count
/// of live corners and a running count of those past the bound suffice.
fn replay(pm: &ProgressiveMesh) -> Result<Vec<u32>, BrokenInvariant> {
    let n = pm.input_vertex_count;
    let mut corner_slots: Vec<u32> = pm.indices.iter().map(|&v| pm.vertex_slot[v as usize]).collect();
    let mut slot_vertex = vec![0u32; n];
    for v in 0..n {
        slot_vertex[pm.vertex_slot[v] as usize] = v as u32;
    }
    let mut live_corners = pm.indices.len();
    let mut live_slots = pm.base_vertex_count as usize;
    let mut corners_at = vec![0u32; n];
    corner_slots.iter().for_each(|&s| corners_at[s as usize] += 1);
    let mut past_bound: u64 = corners_at[live_slots..].iter().map(|&c| u64::from(c)).sum();
    // Children of each created vertex, grouped by parent (counting sort).
    let mut child_start = vec![0u32; pm.vertex_total() - n + 1];
    for &p in &pm.parent {
        if p != NONE {
            child_start[p as usize - n + 1] += 1;
        }
    }
    for i in 1..child_start.len() {
        child_start[i] += child_start[i - 1];
    }
    let mut children = vec![0u32; child_start[child_start.len() - 1] as usize];
    let mut fill = child_start.clone();
    for (v, &p) in pm.parent.iter().enumerate() {
        if p != NONE {
            let at = &mut fill[p as usize - n];
            children[*at as usize] = v as u32;
            *at += 1;
        }
    }
    if past_bound > 0 {
        return Err(inconsistent("base_vertex_count", 0, "a triangle uses a slot past the live ones"));
    }
    let mut from_slots = Vec::with_capacity(pm.corner_changes.len());
    for (s, record) in pm.collapses.iter().enumerate() {
        let range = record.corner_changes_start as usize..record.corner_changes_end as usize;
        for change in &pm.corner_changes[range] {
            let corner = change.corner as usize;
            let from_slot = corner_slots[corner];
            from_slots.push(from_slot);
            corner_slots[corner] = change.to_slot;
            if corner < live_corners {
                let (from, to) = (from_slot as usize, change.to_slot as usize);
                corners_at[from] -= 1;
                corners_at[to] += 1;
                past_bound = past_bound - u64::from(from >= live_slots) + u64::from(to >= live_slots);
            }
        }
        let created =
            record.first_new_vertex as usize..(record.first_new_vertex + record.new_vertex_count) as usize;
        // The merge tree agrees with the slots: what merges is live until this step...
        for x in created.clone() {
            let survivor = pm.survivor_source[x];
            if pm.parent[survivor as usize] as usize != x {
                return Err(inconsistent(
                    "survivor_source",
                    x,
                    "the survivor is not a vertex that merged into it",
                ));
            }
            for &child in &children[child_start[x - n] as usize..child_start[x - n + 1] as usize] {
                if slot_vertex[pm.vertex_slot[child as usize] as usize] != child {
                    return Err(inconsistent(
                        "parent",
                        child as usize,
                        "a vertex merges while it is not live",
                    ));
                }
            }
        }
        for x in created.clone() {
            let slot = pm.vertex_slot[x] as usize;
            slot_vertex[slot] = x as u32;
        }
        // ... and afterwards only its survivor's slot goes on (in the new vertex).
        for x in created {
            for &child in &children[child_start[x - n] as usize..child_start[x - n + 1] as usize] {
                let slot = pm.vertex_slot[child as usize] as usize;
                if slot_vertex[slot] != x as u32 && slot < record.vertices_after as usize {
                    return Err(inconsistent("parent", child as usize, "a merged vertex keeps its slot"));
                }
            }
        }
        let triangles_after = record.triangles_after as usize;
        for &slot in &corner_slots[3 * triangles_after..live_corners] {
            corners_at[slot as usize] -= 1;
            past_bound -= u64::from(slot as usize >= live_slots);
        }
        live_corners = 3 * triangles_after;
        let vertices_after = record.vertices_after as usize;
        past_bound += corners_at[vertices_after..live_slots].iter().map(|&c| u64::from(c)).sum::<u64>();
        live_slots = vertices_after;
        if past_bound > 0 {
            return Err(inconsistent("collapses", s, "a live triangle uses a slot past the live ones"));
        }
    }
    Ok(from_slots)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simplify::{simplify, SimplifyInput, SimplifyOptions};
    use glam::Vec3;

    /// A 4×4 grid of unit squares with a bump, simplified down to 4 triangles.
    fn grid_pm() -> ProgressiveMesh {
        let positions: Vec<Vec3> = (0..25)
            .map(|i| {
                let (x, y) = ((i % 5) as f32, (i / 5) as f32);
                Vec3::new(x, y, if i == 12 { 0.5 } else { 0.0 })
            })
            .collect();
        let mut indices = Vec::new();
        for y in 0..4u32 {
            for x in 0..4u32 {
                let a = 5 * y + x;
                indices.extend_from_slice(&[a, a + 1, a + 6, a, a + 6, a + 5]);
            }
        }
        let input = SimplifyInput {
            positions: &positions,
            attributes: &[],
            attribute_weights: &[],
            indices: &indices,
            triangle_materials: &[],
            vertex_quadrics: None,
        };
        simplify(&input, &SimplifyOptions { target_triangles: 4, ..SimplifyOptions::default() }).unwrap()
    }

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn a_simplified_mesh_is_valid_and_restoring_its_slots_changes_nothing() {
        let pm = grid_pm();
        assert!(pm.collapse_count() > 0);
        assert_eq!(pm.validate(), Ok(()));
        let mut restored = pm.clone();
        restored.corner_changes.iter_mut().for_each(|c| c.from_slot = NONE);
        assert_eq!(restored.restore_from_slots(), Ok(()));
        assert_eq!(restored, pm);
    }

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn each_broken_invariant_is_named() {
        let pm = grid_pm();
        let field_of = |break_it: &dyn Fn(&mut ProgressiveMesh)| {
            let mut broken = pm.clone();
            break_it(&mut broken);
            broken.validate().map_err(|e| e.field)
        };
        // A parent that is an input vertex: ancestor walks would not end.
        let child = pm.parent.iter().position(|&p| p != NONE).unwrap();
        assert_eq!(field_of(&|m| m.parent[child] = 0), Err("parent"));
        // A step that gives back a triangle.
        assert_eq!(
            field_of(&|m| m.collapses[1].triangles_after = m.collapses[0].triangles_after + 1),
            Err("collapses")
        );
        // A change that claims to start from another slot.
        assert_eq!(field_of(&|m| m.corner_changes[0].from_slot ^= 1), Err("corner_changes"));
        // A corner that stays live sent to a slot that is dead after its step.
        let (change, dead) = pm
            .collapses
            .iter()
            .find_map(|c| {
                let changes = c.corner_changes_start as usize..c.corner_changes_end as usize;
                let live = changes.clone().find(|&i| pm.corner_changes[i].corner < 3 * c.triangles_after)?;
                Some((live, c.vertices_after))
            })
            .expect("some step moves a corner that stays live");
        assert_eq!(field_of(&|m| m.corner_changes[change].to_slot = dead), Err("collapses"));
    }
}
