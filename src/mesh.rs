//! The merged, indexed triangle mesh of a character: one vertex array for every primitive, with
//! per-primitive index ranges that keep each primitive's material.
//!
//! Positions and normals are in *bind space* (the space the inverse bind matrices expect, which for
//! rigid parts is the scene's model space at rest). Every vertex has exactly four skin influences:
//! `joints[v][k]` indexes [`crate::Skeleton::joints`] and the weights of a vertex sum to 1 (unused
//! slots have weight 0 and joint 0).

use glam::{Vec2, Vec3, Vec4};

use crate::morph::MorphDeltas;

/// A contiguous range of [`SkinnedMesh::indices`] drawn with one material.
#[derive(Clone, Debug, PartialEq)]
pub struct PrimitiveRange {
    /// First index (not triangle) of the range.
    pub first_index: u32,
    /// Number of indices, a multiple of 3.
    pub index_count: u32,
    /// Index into [`crate::Character::materials`], `None` for glTF's default material.
    pub material: Option<usize>,
}

/// An indexed triangle list with skin data; see the module docs for spaces and invariants.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SkinnedMesh {
    /// Bind-space positions.
    pub positions: Vec<Vec3>,
    /// Unit bind-space normals (computed from the triangles when the file has none).
    pub normals: Vec<Vec3>,
    /// First texture coordinate set, when any primitive has one (zeros elsewhere).
    pub uvs: Option<Vec<Vec2>>,
    /// First vertex colour set as linear RGBA, when any primitive has one (white elsewhere).
    pub colors: Option<Vec<Vec4>>,
    /// Four joint indices per vertex into [`crate::Skeleton::joints`].
    pub joints: Vec<[u16; 4]>,
    /// Four weights per vertex, summing to 1, sorted by decreasing weight.
    pub weights: Vec<[f32; 4]>,
    /// Triangle list, three indices per triangle, every index `< positions.len()`.
    pub indices: Vec<u32>,
    /// Material ranges covering `indices` in order, without gaps.
    pub primitives: Vec<PrimitiveRange>,
    /// Bind-space morph target deltas per vertex (empty when the file has no morph targets);
    /// target indices are those of [`crate::Character::morph_targets`].
    pub morph: MorphDeltas,
}

impl SkinnedMesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The material of every triangle, from the primitive ranges (`None`: glTF's default
    /// material). A range that reaches past the index list is cut at its end.
    pub fn triangle_materials(&self) -> Vec<Option<usize>> {
        let triangles = self.triangle_count();
        let mut out = vec![None; triangles];
        for range in &self.primitives {
            let first = (range.first_index / 3) as usize;
            let end = (first + (range.index_count / 3) as usize).min(triangles);
            for m in &mut out[first.min(end)..end] {
                *m = range.material;
            }
        }
        out
    }

    /// Axis-aligned bounds of the bind positions as `(min, max)`; `(0, 0)` for an empty mesh.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        if self.positions.is_empty() {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        self.positions.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }
}

/// Area-weighted vertex normals of an indexed triangle list.
///
/// Vertices that touch no triangle, or only degenerate ones, get `+Y` so the result is always unit
/// length. Indices must be in range (the importer checks them first).
pub fn compute_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut sums = vec![Vec3::ZERO; positions.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        // The cross product's length is twice the area: larger faces weigh more.
        let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        sums[a] += n;
        sums[b] += n;
        sums[c] += n;
    }
    sums.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::Y)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn normals_of_a_quad_face_up() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0), Vec3::new(0.0, 0.0, -1.0)];
        let normals = compute_normals(&positions, &[0, 1, 2, 0, 2, 3]);
        assert_eq!(normals, vec![Vec3::Y; 4]);
    }

    #[test]
    fn isolated_vertex_gets_a_unit_normal() {
        let normals = compute_normals(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z], &[0, 0, 1]);
        assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-6));
    }

    #[test]
    fn primitive_ranges_become_triangle_materials() {
        let mesh = SkinnedMesh {
            indices: vec![0; 9],
            primitives: vec![
                PrimitiveRange { first_index: 0, index_count: 6, material: Some(0) },
                PrimitiveRange { first_index: 6, index_count: 6, material: Some(2) },
            ],
            ..SkinnedMesh::default()
        };
        // The second range reaches one triangle past the indices: it is cut there.
        assert_eq!(mesh.triangle_materials(), [Some(0), Some(0), Some(2)]);
    }
}
