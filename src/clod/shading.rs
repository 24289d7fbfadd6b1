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
//! - flat vertices that share position, uv, colour, skin, morph position deltas and material are
//!   **welded** into their lowest-index vertex (skin weights within [`SKIN_WELD_TOLERANCE`],
//!   since exporters that split a vertex per face renormalise each copy's weights), whose normal
//!   the simplifier does not price (see [`ShadingWeld::simplifier_normals`]). The simplifier
//!   collapses the welded mesh; uv, colour and material borders stay constraints, and so do
//!   creases between smooth groups (non-flat vertices with different normals are never welded:
//!   a crease that survives stays sharp);
//! - smooth vertices that are copies of each other, normal and morph normal deltas included, are
//!   welded the same way but stay smooth: an exporter that writes every triangle corner as its
//!   own vertex under an index buffer makes every edge a seam of identical sides, and CesiumMan
//!   split so simplified to 3,728 of its 4,672 triangles and stopped (non-indexed primitives are
//!   welded by the importer);
//! - the renderer gives every corner of a flat vertex its triangle's face normal at each level
//!   (both ends of a geomorph), so the faceted look survives simplification
//!   ([`crate::render::lod_source`]).
//!
//! Normals are unit vectors in the mesh's (bind) space; welding compares the other attributes by
//! their bits, skin weights within a tolerance.

use glam::Vec3;

use crate::mesh::SkinnedMesh;
use crate::morph::MorphDeltas;
use crate::twins::{position_ids, triangle_layers, vertex_layers};

/// A normal within 2° of its face's normal is that face's normal: exporters quantise normals
/// (8-bit normalised components are off by up to about 0.5°) and face normals recomputed from f32
/// positions round too, while the smallest deliberate smoothing of a low-poly mesh bends a normal
/// by far more than 2° away from the faces around it.
const FLAT_COS: f32 = 0.999_39;

/// What vertices of one position must share exactly to be welded, as bits: uv, colour (zero when
/// the mesh has none), material, whether they are flat candidates, and for the others the
/// normal. Their skins must agree within [`SKIN_WELD_TOLERANCE`], their morph deltas exactly.
const WELD_KEY_LENGTH: usize = 11;
type WeldKey = [u32; WELD_KEY_LENGTH];

/// Two copies of a vertex skin alike when each joint's weight differs by at most this. Exporters
/// that split a vertex per face renormalise each copy's weights in f32, so the copies differ in
/// the last bits (RiggedSimple.glb: 0.015826821 and 0.015826799 at one facet corner; compared by
/// bits, 19 of its 960 vertices welded, every edge along its length stayed a normal seam and its
/// levels kept every ring). A weight off by 1e-4 moves the vertex by 1e-4 of its joints'
/// relative motion, far under a pixel; weights quantised to 8 bits that differ by a step
/// (1/255) still keep their copies apart.
pub const SKIN_WELD_TOLERANCE: f32 = 1e-4;

/// The weight `joints`/`weights` give `joint` (summed, should a joint repeat).
fn influence(joints: [u16; 4], weights: [f32; 4], joint: u16) -> f32 {
    joints.iter().zip(&weights).filter(|(&j, _)| j == joint).map(|(_, &w)| w).sum()
}

/// Whether two vertices' skins agree within [`SKIN_WELD_TOLERANCE`] for every joint either uses
/// (the order of the influences and the joints of zero weights do not matter).
fn same_skin(a: ([u16; 4], [f32; 4]), b: ([u16; 4], [f32; 4])) -> bool {
    // Copies of one vertex mostly carry the very same influences: eight compares instead of
    // eight lookups. (Equal is equal within the tolerance; a NaN weight is equal to nothing.)
    if a == b {
        return true;
    }
    a.0.iter().chain(&b.0).all(|&joint| {
        // A NaN weight compares false: its vertex never welds.
        let d = (influence(a.0, a.1, joint) - influence(b.0, b.1, joint)).abs();
        d <= SKIN_WELD_TOLERANCE
    })
}

/// Whether vertices `a` and `b` have the same morph deltas: targets and position deltas, and the
/// normal deltas too when `normals` (a flat vertex's normal follows from its positions).
fn same_morph(morph: &MorphDeltas, a: usize, b: usize, normals: bool) -> bool {
    // A flat vertex's entry that only bends its normal does not move it.
    let moving = |&(_, dp, _): &(u16, Vec3, Vec3)| normals || dp != Vec3::ZERO;
    let (mut da, mut db) = (morph.of(a).filter(moving), morph.of(b).filter(moving));
    loop {
        match (da.next(), db.next()) {
            (None, None) => return true,
            (Some((ta, pa, na)), Some((tb, pb, nb))) if ta == tb && pa == pb && (!normals || na == nb) => {}
            _ => return false,
        }
    }
}

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
            // A degenerate triangle has no normal to compare and renders nothing.
            let normal = face_normal(a, b, c);
            for &v in tri {
                let v = v as usize;
                match material[v] {
                    None => material[v] = Some(m),
                    Some(old) if old != m => mixed[v] = true,
                    _ => {}
                }
                if let Some(f) = normal {
                    let same = mesh.normals[v].dot(f) >= FLAT_COS;
                    matches[v] = Some(matches[v].unwrap_or(true) && same);
                }
            }
        }
        let candidate: Vec<bool> = (0..n).map(|v| matches[v] == Some(true) && !mixed[v]).collect();
        // Group the vertices used by triangles of one material: by position, then each run
        // of one position (a handful of facet corners or copies) by its key (flat candidates
        // without their normal, the others with it), and within a run of equal keys each vertex
        // joins the first earlier one it skins and morphs like. (A hash map of the keys took
        // 8–15 % of the whole build on Fox, RiggedSimple and robot.glb, most of whose vertices
        // are candidates; one sort of the full keys, 4–12 %.)
        let key = |v: usize| -> WeldKey {
            let mut key = [0; WELD_KEY_LENGTH];
            if let Some(uvs) = &mesh.uvs {
                key[..2].copy_from_slice(&uvs[v].to_array().map(f32::to_bits));
            }
            if let Some(colors) = &mesh.colors {
                key[2..6].copy_from_slice(&colors[v].to_array().map(f32::to_bits));
            }
            key[6] = material[v].unwrap_or(0);
            if !candidate[v] {
                key[7] = 1;
                key[8..11].copy_from_slice(&mesh.normals[v].to_array().map(f32::to_bits));
            }
            key
        };
        let skin = |v: u32| (mesh.joints[v as usize], mesh.weights[v as usize]);
        // A copy of a triangle (a mesh drawn twice, a sheet doubled by a reversed copy) keeps its
        // own vertices, so that the simplifier can layer it apart (`crate::twins`).
        let ids = position_ids(&mesh.positions);
        let layers = triangle_layers(|v| ids[v as usize], &mesh.indices, n)
            .map(|t| vertex_layers(&t, &mesh.indices, n));
        let same_layer = |a: u32, b: u32| layers.as_ref().is_none_or(|l| l[a as usize] == l[b as usize]);
        let alike = |a: u32, b: u32| {
            let flat_candidate = candidate[a as usize];
            same_layer(a, b)
                && same_skin(skin(a), skin(b))
                && same_morph(&mesh.morph, a as usize, b as usize, !flat_candidate)
        };
        // The weldable vertices grouped by position id, in vertex order within a group (a
        // counting sort: a sort of 128-bit keys was 1–2 % of a build natively).
        let weldable = |v: usize| material[v].is_some() && !mixed[v];
        let mut group_start = vec![0u32; n + 1];
        for v in (0..n).filter(|&v| weldable(v)) {
            group_start[ids[v] as usize + 1] += 1;
        }
        for id in 0..n {
            group_start[id + 1] += group_start[id];
        }
        let mut fill = group_start.clone();
        let mut by_position = vec![0u32; group_start[n] as usize];
        for v in (0..n).filter(|&v| weldable(v)) {
            by_position[fill[ids[v] as usize] as usize] = v as u32;
            fill[ids[v] as usize] += 1;
        }
        let mut flat = vec![false; n];
        let mut representative: Vec<u32> = (0..n as u32).collect();
        let mut by_key: Vec<(WeldKey, u32)> = Vec::new();
        for run in group_start.windows(2).map(|w| &by_position[w[0] as usize..w[1] as usize]) {
            // A lone vertex has no copy to weld with, and a lone candidate is no evidence of
            // facets (a smooth mesh's planar patch); two or more are facet corners or copies.
            if run.len() < 2 {
                continue;
            }
            by_key.clear();
            by_key.extend(run.iter().map(|&v| (key(v as usize), v)));
            by_key.sort_unstable();
            for same_key in by_key.chunk_by(|a, b| a.0 == b.0).filter(|run| run.len() >= 2) {
                // A flat candidate with a copy that skins like it is a facet corner, whatever
                // their morph targets do. In vertex order, each vertex joins the first earlier
                // one it skins and morphs like (its group's lowest vertex), else starts a group:
                // copies that morph apart stay apart, so level 0 morphs as the file does.
                for (k, &(_, v)) in same_key.iter().enumerate() {
                    if candidate[v as usize] {
                        let copy = same_key.iter().any(|&(_, w)| w != v && same_skin(skin(w), skin(v)));
                        flat[v as usize] |= copy;
                    }
                    let first =
                        same_key[..k].iter().find(|&&(_, w)| representative[w as usize] == w && alike(w, v));
                    if let Some(&(_, first)) = first {
                        representative[v as usize] = first;
                    }
                }
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
        Self::new(&character.mesh, &super::material_ids(character))
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
