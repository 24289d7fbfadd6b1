//! Flat shading and normal seams: which vertices are faceted, and the welded mesh the simplifier
//! sees.
//!
//! A flat-shaded mesh (normals = face normals) duplicates every vertex once per face, so every
//! edge is an attribute seam to the simplifier (Hoppe 1999's wedges) and every vertex where seams
//! meet is pinned: such a mesh hardly simplifies. Its normals carry no information the positions
//! do not: a *normal seam*, an edge whose two sides differ only in the normal, is not a constraint
//! when both sides are faceted. So:
//! - a vertex is **flat** when its normal is its face's normal at every (non-degenerate) triangle
//!   that uses it and another such vertex shares its position and other attributes (a facet
//!   corner: a smooth mesh shares one vertex there), or when all its triangles' corners are such
//!   vertices and one is flat (inside a subdivided facet); a lone vertex on a planar patch of a
//!   smooth mesh stays smooth;
//! - flat vertices that share position, uv, colour, skin and material are **welded** into their
//!   lowest-index vertex, whose normal the simplifier does not price (see
//!   [`ShadingWeld::simplifier_normals`]). The simplifier collapses the welded mesh; uv, colour
//!   and material borders stay constraints, and so do creases between smooth groups (non-flat
//!   vertices are never welded: a crease that survives stays sharp);
//! - the renderer gives every corner of a flat vertex its triangle's face normal at each level
//!   (both ends of a geomorph), so the faceted look survives simplification
//!   ([`crate::render::lod_source`]).
//!
//! Normals are unit vectors in the mesh's (bind) space; welding compares the other attributes by
//! their bits.

use std::collections::HashMap;

use glam::Vec3;

use crate::mesh::SkinnedMesh;

/// A normal within 2° of its face's normal is that face's normal: exporters quantise normals
/// (8-bit normalised components are off by up to about 0.5°) and face normals recomputed from f32
/// positions round too, while the smallest deliberate smoothing of a low-poly mesh bends a normal
/// by far more than 2° away from the faces around it.
const FLAT_COS: f32 = 0.999_39;

/// The unit normal of triangle `(a, b, c)` (counter-clockwise front), `None` when degenerate.
pub fn face_normal(a: Vec3, b: Vec3, c: Vec3) -> Option<Vec3> {
    (b - a).cross(c - a).try_normalize()
}

/// Flat vertices and the weld of a mesh; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingWeld {
    /// Per input vertex: faceted (its normal is the face normal wherever it is used, on a facet
    /// edge).
    pub flat: Vec<bool>,
    /// Per input vertex: the vertex it is welded into (itself when it is not welded); always the
    /// lowest index of its group.
    pub representative: Vec<u32>,
}

impl ShadingWeld {
    /// Finds the flat vertices of `mesh` and welds them; `triangle_materials` has one id per
    /// triangle (vertices used by triangles of two materials are not welded).
    pub fn new(mesh: &SkinnedMesh, triangle_materials: &[u32]) -> Self {
        let n = mesh.vertex_count();
        // Per vertex: every face it is used by matches its normal (None: unused so far).
        let mut matches: Vec<Option<bool>> = vec![None; n];
        let mut material: Vec<Option<u32>> = vec![None; n];
        let mut mixed = vec![false; n];
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize]);
            let m = triangle_materials.get(t).copied().unwrap_or(0);
            for &v in tri {
                let v = v as usize;
                match material[v] {
                    None => material[v] = Some(m),
                    Some(old) if old != m => mixed[v] = true,
                    _ => {}
                }
                // A degenerate triangle has no normal to compare and renders nothing.
                if let Some(f) = face_normal(a, b, c) {
                    let same = mesh.normals[v].dot(f) >= FLAT_COS;
                    matches[v] = Some(matches[v].unwrap_or(true) && same);
                }
            }
        }
        let candidate: Vec<bool> = (0..n).map(|v| matches[v] == Some(true) && !mixed[v]).collect();
        // Group candidates by everything but the normal.
        let bits3 = |p: Vec3| p.to_array().map(|x| if x == 0.0 { 0 } else { x.to_bits() });
        let mut groups: HashMap<Vec<u32>, Vec<u32>> = HashMap::new();
        for v in (0..n).filter(|&v| candidate[v]) {
            let mut key: Vec<u32> = bits3(mesh.positions[v]).to_vec();
            if let Some(uvs) = &mesh.uvs {
                key.extend(uvs[v].to_array().map(f32::to_bits));
            }
            if let Some(colors) = &mesh.colors {
                key.extend(colors[v].to_array().map(f32::to_bits));
            }
            key.extend(mesh.joints[v].map(u32::from));
            key.extend(mesh.weights[v].map(f32::to_bits));
            key.push(material[v].unwrap_or(0));
            groups.entry(key).or_default().push(v as u32);
        }
        let mut flat = vec![false; n];
        let mut representative: Vec<u32> = (0..n as u32).collect();
        for group in groups.values() {
            // A lone vertex is no evidence of facets (a smooth mesh's planar patch); two or more
            // are facet corners (a smooth mesh would share one vertex). Vertices are pushed in
            // increasing order: group[0] is the lowest.
            if group.len() < 2 {
                continue;
            }
            for &v in group {
                flat[v as usize] = true;
                representative[v as usize] = group[0];
            }
        }
        // A lone candidate inside a faceted region (the middle of a subdivided facet) is flat
        // too: every triangle it is in has only candidate corners and one of them is flat.
        let mut inside = vec![true; n];
        let mut near_flat = vec![false; n];
        for tri in mesh.indices.chunks_exact(3) {
            let all = tri.iter().all(|&v| candidate[v as usize]);
            let any = tri.iter().any(|&v| flat[v as usize]);
            for &v in tri {
                inside[v as usize] &= all;
                near_flat[v as usize] |= any;
            }
        }
        for v in 0..n {
            if candidate[v] && !flat[v] && inside[v] && near_flat[v] {
                flat[v] = true;
            }
        }
        ShadingWeld { flat, representative }
    }

    /// [`ShadingWeld::new`] with the character's per-primitive materials, as the chain's build
    /// welds it.
    pub fn of_character(character: &crate::Character) -> Self {
        Self::new(&character.mesh, &super::triangle_materials(character))
    }

    /// Whether any vertex is flat.
    pub fn any_flat(&self) -> bool {
        self.flat.contains(&true)
    }

    /// `indices` with every vertex replaced by its representative.
    pub fn weld_indices(&self, indices: &[u32]) -> Vec<u32> {
        indices.iter().map(|&v| self.representative[v as usize]).collect()
    }

    /// `normals` with every flat vertex's normal zero: the value the simplifier prices for it. A
    /// facet's normal follows from its positions, so it carries no attribute error of its own (a
    /// face whose corners are all flat has a zero normal gradient, and a mesh that is flat
    /// everywhere has a constant, unpriced normal channel); the geometric quadric prices the
    /// shape. Created vertices then get their survivor's normal, which the renderer replaces.
    pub fn simplifier_normals(&self, normals: &[Vec3]) -> Vec<Vec3> {
        normals.iter().zip(&self.flat).map(|(&n, &flat)| if flat { Vec3::ZERO } else { n }).collect()
    }
}

/// Per progressive-mesh vertex id: flat. An input vertex is flat as [`ShadingWeld::flat`] says; a
/// vertex a collapse created is flat when the vertex it inherits identity from is.
pub fn flat_ids(weld: &ShadingWeld, pm: &crate::progressive::ProgressiveMesh) -> Vec<bool> {
    let mut flat = weld.flat.clone();
    flat.resize(pm.input_vertex_count, false);
    // Survivors have smaller ids than the vertices created from them: one forward pass.
    for x in pm.input_vertex_count..pm.vertex_total() {
        let survivor = pm.survivor_source[x] as usize;
        let inherited = flat.get(survivor).copied().unwrap_or(false);
        flat.push(inherited);
    }
    flat
}
