//! Morph targets (glTF 2.0 §3.7.2.2): per-vertex position and normal displacements, blended by
//! per-target weights and added to the bind-space vertex *before* skinning:
//! `p = b + Σ wₜ · Δpₜ`, `n = normalize(nb + Σ wₜ · Δnₜ)`.
//!
//! Targets of every primitive of every mesh instance are separate targets of the character,
//! numbered globally in import order; a glTF weight index `k` of a node drives target `k` of each
//! of its primitives. Deltas are stored sparsely by vertex ([`MorphDeltas`], compressed rows):
//! most targets (a face's expressions) move a small part of a character, and a vertex lists only
//! the targets that move it. Deltas are in bind space, in the character's units.

use glam::Vec3;

/// Most morph targets of one character. Face rigs use 50-150 blend shapes (the ARKit set is 52),
/// and a target index is a `u16` on the GPU side; 1,024 targets × 4 bytes of weights stays far
/// inside any uniform or storage limit, and bounds the weights a clip sample writes.
pub const MAX_MORPH_TARGETS: usize = 1024;

/// Most stored `(vertex, target)` deltas of one character or chain: 2^22 entries of 26 bytes
/// (≈ 110 MB) — 80 targets each moving 50,000 vertices — so a forged file cannot exhaust memory,
/// while real face rigs (tens of targets moving a few thousand vertices each) stay far below.
pub const MAX_MORPH_DELTAS: usize = 1 << 22;

/// One morph target of the character.
#[derive(Clone, Debug, PartialEq)]
pub struct MorphTarget {
    /// `mesh 3 ('Face') primitive 0 target 2`.
    pub name: String,
    /// The weight when no clip animates it: the node's `weights`, else the mesh's, else 0.
    pub default_weight: f32,
}

/// Sparse per-vertex deltas: vertex `v`'s entries are `offsets[v]..offsets[v + 1]` of the other
/// arrays, targets increasing. An empty `offsets` means no vertex has any delta.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphDeltas {
    pub offsets: Vec<u32>,
    /// Global target index of each entry.
    pub targets: Vec<u16>,
    /// Position delta of each entry.
    pub positions: Vec<Vec3>,
    /// Normal delta of each entry (zero when the target has none).
    pub normals: Vec<Vec3>,
}

impl MorphDeltas {
    /// Whether no vertex has a delta.
    pub fn is_empty(&self) -> bool {
        self.targets.is_empty()
    }

    /// Vertex `v`'s entries as `(first, count)` (`(0, 0)` past the rows).
    pub fn row_range(&self, v: usize) -> [u32; 2] {
        match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&a), Some(&b)) => [a, b - a],
            _ => [0, 0],
        }
    }

    /// Number of stored entries.
    pub fn entry_count(&self) -> usize {
        self.targets.len()
    }

    /// The entries of vertex `v` as `(target, position delta, normal delta)`; none for a vertex
    /// past the rows (a chain or mesh without morph targets).
    pub fn of(&self, v: usize) -> impl Iterator<Item = (u16, Vec3, Vec3)> + '_ {
        let range = match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&a), Some(&b)) => a as usize..b as usize,
            _ => 0..0,
        };
        range.map(move |e| (self.targets[e], self.positions[e], self.normals[e]))
    }

    /// Appends the row of the next vertex. Entries must have increasing targets.
    pub fn push_row(&mut self, entries: impl IntoIterator<Item = (u16, Vec3, Vec3)>) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        for (t, dp, dn) in entries {
            self.targets.push(t);
            self.positions.push(dp);
            self.normals.push(dn);
        }
        self.offsets.push(self.targets.len() as u32);
    }

    /// Rows so far (0 for an empty set, which stands for any number of delta-free vertices).
    pub fn row_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// `Σ wₜ · Δpₜ` of vertex `v`; targets past `weights` weigh 0.
    pub fn position_offset(&self, v: usize, weights: &[f32]) -> Vec3 {
        self.of(v).map(|(t, dp, _)| weights.get(t as usize).copied().unwrap_or(0.0) * dp).sum()
    }

    /// `Σ wₜ · Δnₜ` of vertex `v`; targets past `weights` weigh 0.
    pub fn normal_offset(&self, v: usize, weights: &[f32]) -> Vec3 {
        self.of(v).map(|(t, _, dn)| weights.get(t as usize).copied().unwrap_or(0.0) * dn).sum()
    }

    /// `positions[v] + Σ wₜ · Δpₜ(v)` for every vertex; `positions` unchanged when every weight
    /// is zero or there are no deltas.
    pub fn morph_positions(&self, positions: &[Vec3], weights: &[f32]) -> Vec<Vec3> {
        if self.is_empty() || weights.iter().all(|&w| w == 0.0) {
            return positions.to_vec();
        }
        positions.iter().enumerate().map(|(v, &p)| p + self.position_offset(v, weights)).collect()
    }

    /// The rows of `ids`, in that order, as a new set (a level's vertices out of a chain's ids).
    pub fn select(&self, ids: impl IntoIterator<Item = usize>) -> MorphDeltas {
        if self.is_empty() {
            return MorphDeltas::default();
        }
        let mut out = MorphDeltas::default();
        for v in ids {
            out.push_row(self.of(v));
        }
        out
    }

    /// Whether every delta is finite.
    pub fn all_finite(&self) -> bool {
        self.positions.iter().chain(&self.normals).all(|d| d.is_finite())
    }
}

/// The entries of two rows blended `(1 - s) · a + s · b` over the union of their targets (a
/// target missing from one row has delta 0 there), targets increasing.
pub fn blend_rows(
    a: impl Iterator<Item = (u16, Vec3, Vec3)>,
    b: impl Iterator<Item = (u16, Vec3, Vec3)>,
    s: f32,
) -> Vec<(u16, Vec3, Vec3)> {
    let mut out: Vec<(u16, Vec3, Vec3)> = a.map(|(t, p, n)| (t, (1.0 - s) * p, (1.0 - s) * n)).collect();
    for (t, p, n) in b {
        match out.binary_search_by_key(&t, |e| e.0) {
            Ok(k) => {
                out[k].1 += s * p;
                out[k].2 += s * n;
            }
            Err(k) => out.insert(k, (t, s * p, s * n)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn rows_offset_by_their_weighted_deltas() {
        let mut d = MorphDeltas::default();
        d.push_row([(0, Vec3::X, Vec3::ZERO), (2, Vec3::Y, Vec3::Z)]);
        d.push_row([]);
        assert_eq!(d.row_count(), 2);
        assert_eq!(d.position_offset(0, &[0.5, 1.0, 2.0]), Vec3::new(0.5, 2.0, 0.0));
        assert_eq!(d.normal_offset(0, &[0.5, 1.0, 2.0]), Vec3::new(0.0, 0.0, 2.0));
        assert_eq!(d.position_offset(1, &[1.0; 3]), Vec3::ZERO);
        // Weights the caller does not have weigh 0; rows the set does not have are empty.
        assert_eq!(d.position_offset(0, &[1.0]), Vec3::X);
        assert_eq!(d.position_offset(7, &[1.0]), Vec3::ZERO);
        let moved = d.morph_positions(&[Vec3::ZERO, Vec3::ONE], &[1.0, 0.0, 1.0]);
        assert_eq!(moved, vec![Vec3::new(1.0, 1.0, 0.0), Vec3::ONE]);
    }

    #[test]
    fn blending_two_rows_takes_the_union_of_their_targets() {
        let a = [(1u16, Vec3::X, Vec3::ZERO), (3, Vec3::Y, Vec3::ZERO)];
        let b = [(0u16, Vec3::Z, Vec3::ZERO), (3, Vec3::X, Vec3::ZERO)];
        let out = blend_rows(a.into_iter(), b.into_iter(), 0.25);
        assert_eq!(
            out,
            vec![
                (0, Vec3::new(0.0, 0.0, 0.25), Vec3::ZERO),
                (1, Vec3::new(0.75, 0.0, 0.0), Vec3::ZERO),
                (3, Vec3::new(0.25, 0.75, 0.0), Vec3::ZERO),
            ]
        );
    }
}
