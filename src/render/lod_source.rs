//! The levels the renderer draws, as GPU-ready arrays: each level's vertices carry their own
//! attributes and those of their ancestor in the next coarser level (for geomorphs), and its
//! triangles are grouped by material.
//!
//! Built from the full mesh alone (one level, every vertex its own ancestor) or from a level chain
//! whose vertex ids index per-id attribute arrays (the articulated progressive mesh). Attributes
//! are in bind space; skinning happens on the GPU.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};

use crate::character::Character;
use crate::clod::shading::face_normal;
use crate::clod::{ArticulatedPm, Clod};
use crate::mesh::PrimitiveRange;
use crate::morph::MorphDeltas;
use crate::progressive::PmCursor;

/// One vertex's attributes as the shader reads them (`LevelVertex` in `skin.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct VertexRaw {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    /// Linear RGBA.
    pub color: [f32; 4],
    pub joints: [u16; 4],
    pub weights: [f32; 4],
    /// Its morph deltas: `(first entry, entry count)` in [`LodSource::morph_texels`] (`(0, 0)`
    /// when it has none).
    pub morph: [u32; 2],
}

/// A vertex and its ancestor (`LevelVertex` and `AncestorVertex` in `skin.wgsl`, locations 0..5
/// and 6..11).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GeomorphVertexRaw {
    pub fine: VertexRaw,
    pub coarse: VertexRaw,
}

/// Per-id attribute arrays (input vertices first, then any the simplifier created).
#[derive(Clone, Copy, Debug)]
pub struct Attributes<'a> {
    pub positions: &'a [Vec3],
    pub normals: &'a [Vec3],
    pub uvs: Option<&'a [Vec2]>,
    pub colors: Option<&'a [Vec4]>,
    pub joints: &'a [[u16; 4]],
    pub weights: &'a [[f32; 4]],
    /// Per id: flat-shaded, drawn with each triangle's face normal ([`crate::clod::shading`]);
    /// `None` when no vertex is.
    pub flat: Option<&'a [bool]>,
    /// Morph deltas by id (empty: none).
    pub morph: &'a MorphDeltas,
}

impl<'a> Attributes<'a> {
    /// The bind-space attributes of an articulated progressive mesh, by vertex id.
    fn of_clod(clod: &'a Clod) -> Self {
        let apm: &ArticulatedPm = &clod.apm;
        Self {
            flat: clod.flat.contains(&true).then_some(&clod.flat[..]),
            positions: &apm.bind_positions,
            normals: &apm.bind_normals,
            uvs: apm.uvs.as_deref(),
            colors: apm.colors.as_deref(),
            joints: &apm.joints,
            weights: &apm.weights,
            morph: &apm.morph,
        }
    }

    fn vertex(&self, id: usize) -> VertexRaw {
        VertexRaw {
            position: self.positions[id].to_array(),
            normal: self.normals[id].to_array(),
            uv: self.uvs.map_or([0.0; 2], |u| u[id].to_array()),
            color: self.colors.map_or([1.0; 4], |c| c[id].to_array()),
            joints: self.joints[id],
            weights: self.weights[id],
            morph: self.morph.row_range(id),
        }
    }
}

/// One level ready for upload.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelData {
    pub vertices: Vec<GeomorphVertexRaw>,
    /// Triangle list into `vertices`, grouped by material in the order of `ranges`.
    pub indices: Vec<u32>,
    /// Material ranges of `indices`.
    pub ranges: Vec<PrimitiveRange>,
    /// Geometric error in model units (0 for the full mesh).
    pub error: f32,
    /// For each vertex, its ancestor's index in the next coarser level (empty for the coarsest):
    /// chained, they join this level to any coarser one.
    pub next: Vec<u32>,
    /// Per vertex: faceted (a flat id: its fine normal is its triangle's face normal). A vertex
    /// that is faceted or whose ancestor is (its coarse normal is then the face normal at the
    /// ancestors' positions) is used by one triangle only.
    pub faceted: Vec<bool>,
}

impl LevelData {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// All levels, finest first.
#[derive(Clone, Debug, PartialEq)]
pub struct LodSource {
    pub levels: Vec<LevelData>,
    /// Every morph delta of the source, by vertex id, two RGBA32F texels per entry: `(Δp, target)`
    /// and `(Δn, 0)`; a vertex's [`VertexRaw::morph`] range indexes entries (empty: no morphs).
    /// The GPU reads them from a texture ([`MORPH_TEXTURE_WIDTH`] texels wide).
    pub morph_texels: Vec<[f32; 4]>,
}

/// Width of the morph-delta texture (texels): WebGL2's smallest guaranteed texture size, so rows
/// of it hold 1,024 entries.
pub const MORPH_TEXTURE_WIDTH: u32 = 2048;

/// The texels of `deltas` (see [`LodSource::morph_texels`]).
pub fn morph_texels(deltas: &MorphDeltas) -> Vec<[f32; 4]> {
    let mut texels = Vec::with_capacity(2 * deltas.entry_count());
    for ((&t, p), n) in deltas.targets.iter().zip(&deltas.positions).zip(&deltas.normals) {
        texels.push([p.x, p.y, p.z, f32::from(t)]);
        texels.push([n.x, n.y, n.z, 0.0]);
    }
    texels
}

impl LodSource {
    /// The full mesh as the only level; every vertex is its own ancestor.
    pub fn full_mesh(character: &Character) -> Self {
        let mesh = &character.mesh;
        let attributes = Attributes {
            positions: &mesh.positions,
            normals: &mesh.normals,
            uvs: mesh.uvs.as_deref(),
            colors: mesh.colors.as_deref(),
            joints: &mesh.joints,
            weights: &mesh.weights,
            // The full mesh draws its own normals, faceted or not.
            flat: None,
            morph: &mesh.morph,
        };
        let ids: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
        let materials = mesh.triangle_materials();
        let level = build_level(&attributes, &ids, &ids, &mesh.indices, &materials, 0.0, &[]);
        Self { levels: vec![level], morph_texels: morph_texels(&mesh.morph) }
    }

    /// The discrete levels of an articulated progressive mesh built from `character`. Each
    /// vertex's ancestor is its vertex in the next coarser level (itself in the coarsest).
    ///
    /// A level triangle takes the material of the input vertex its first corner descends from
    /// (the simplifier keeps material borders, so all three corners agree).
    pub fn from_clod(character: &Character, clod: &Clod) -> Self {
        let attributes = Attributes::of_clod(clod);
        let materials_of = clod_materials(character, clod);
        let levels = clod
            .levels
            .iter()
            .enumerate()
            .map(|(i, level)| {
                let ancestor_ids: Vec<u32> = match clod.levels.get(i + 1) {
                    Some(coarse) => level.ancestors.iter().map(|&a| coarse.vertices[a as usize]).collect(),
                    None => level.vertices.clone(),
                };
                let materials = materials_of(&level.vertices, &level.indices);
                build_level(
                    &attributes,
                    &level.vertices,
                    &ancestor_ids,
                    &level.indices,
                    &materials,
                    level.error,
                    &level.ancestors,
                )
            })
            .collect();
        Self { levels, morph_texels: morph_texels(&clod.apm.morph) }
    }

    /// The vertices of level `fine` paired with their ancestors in level `coarse` (any coarser
    /// level: the ancestor tables are chained), for a geomorph that skips levels. `None` unless
    /// `fine < coarse < levels`.
    pub fn morph_vertices(&self, fine: usize, coarse: usize) -> Option<Vec<GeomorphVertexRaw>> {
        if fine >= coarse || coarse >= self.levels.len() {
            return None;
        }
        let chain = &self.levels[fine..coarse];
        let target = &self.levels[coarse].vertices;
        let mut vertices: Vec<GeomorphVertexRaw> = (0..self.levels[fine].vertices.len())
            .map(|k| {
                let a = chain.iter().fold(k as u32, |v, level| level.next[v as usize]);
                GeomorphVertexRaw {
                    fine: self.levels[fine].vertices[k].fine,
                    coarse: target[a as usize].fine,
                }
            })
            .collect();
        // A corner whose ancestor is faceted in the coarse level takes its triangle's face normal
        // at the coarse positions (the ancestor's own normal belongs to one of its coarse
        // triangles, maybe another). A fine vertex that its own level shares (neither it nor its
        // next ancestor flat) gets the normal of the last of its triangles.
        let faceted_ancestor: Vec<bool> = (0..vertices.len())
            .map(|k| {
                let a = chain.iter().fold(k as u32, |v, level| level.next[v as usize]);
                self.levels[coarse].faceted[a as usize]
            })
            .collect();
        let level = &self.levels[fine];
        for tri in level.indices.chunks_exact(3) {
            if tri.iter().any(|&v| faceted_ancestor[v as usize]) {
                let at = |k: usize, coarse: bool| {
                    let v = &vertices[tri[k] as usize];
                    Vec3::from(if coarse { v.coarse.position } else { v.fine.position })
                };
                let fine_normal = face_normal(at(0, false), at(1, false), at(2, false));
                let normal = face_normal(at(0, true), at(1, true), at(2, true)).or(fine_normal);
                for &v in tri.iter().filter(|&&v| faceted_ancestor[v as usize]) {
                    if let Some(n) = normal {
                        vertices[v as usize].coarse.normal = n.to_array();
                    }
                }
            }
        }
        Some(vertices)
    }

    /// The progressive mesh at a cursor's position as one level, each vertex paired with its
    /// ancestor after `coarse_collapses` collapses (itself when that is not coarser): the
    /// continuous LOD slider's meshes, which geomorph from one state to another (Hoppe 1996
    /// §3.2). Vertex order and triangles depend on the cursor alone, so the same state paired
    /// with different ancestors shares its index buffer.
    pub fn from_cursor(
        character: &Character,
        clod: &Clod,
        cursor: &PmCursor,
        coarse_collapses: usize,
    ) -> LevelData {
        let apm = &clod.apm;
        let attributes = Attributes::of_clod(clod);
        let materials = clod_materials(character, clod)(cursor.vertices(), cursor.indices());
        let error = apm.pm.distance_after(cursor.level());
        let ancestors: Vec<u32> = if coarse_collapses > cursor.level() {
            cursor.vertices().iter().map(|&v| apm.pm.ancestor_at(v, coarse_collapses)).collect()
        } else {
            cursor.vertices().to_vec()
        };
        build_level(&attributes, cursor.vertices(), &ancestors, cursor.indices(), &materials, error, &[])
    }

    /// Geometric error of every level, finest first.
    pub fn errors(&self) -> Vec<f32> {
        self.levels.iter().map(|l| l.error).collect()
    }
}

/// Per-triangle materials of a mesh over progressive-mesh vertex ids: a triangle takes the
/// material of the input vertex its first corner descends from.
fn clod_materials<'a>(
    character: &Character,
    clod: &'a Clod,
) -> impl Fn(&[u32], &[u32]) -> Vec<Option<usize>> + 'a {
    let input_material = vertex_materials(character);
    let pm = &clod.apm.pm;
    move |vertices, indices| {
        indices
            .chunks_exact(3)
            .map(|t| {
                let mut v = vertices[t[0] as usize] as usize;
                while v >= pm.input_vertex_count {
                    v = pm.survivor_source[v] as usize;
                }
                input_material.get(v).copied().flatten()
            })
            .collect()
    }
}

/// Material of every input vertex: that of the first primitive whose triangles use it.
fn vertex_materials(character: &Character) -> Vec<Option<usize>> {
    let mesh = &character.mesh;
    let mut out = vec![None; mesh.vertex_count()];
    let mut seen = vec![false; mesh.vertex_count()];
    for range in &mesh.primitives {
        let start = range.first_index as usize;
        let end = (start + range.index_count as usize).min(mesh.indices.len());
        for &v in &mesh.indices[start.min(end)..end] {
            if !seen[v as usize] {
                seen[v as usize] = true;
                out[v as usize] = range.material;
            }
        }
    }
    out
}

/// Builds one level: `ids[k]` is the attribute id of level vertex `k` and `ancestor_ids[k]` that
/// of its ancestor; `indices` index level vertices; `materials` has one entry per triangle; `next`
/// is the level's ancestor table (or empty). Triangles are grouped by material (stably, so a
/// vertex-cache order within a material stays).
///
/// Every corner of a flat id, or of an id whose ancestor is flat, gets a vertex of its own (the
/// vertex's first such corner keeps it, later ones get copies appended, with the same `next`
/// entry). A flat end's normal is its triangle's face normal: at the level's positions for the
/// fine end, at the ancestors' for the coarse end (the fine one where that triangle has
/// degenerated).
///
/// # Panics
/// If the arrays disagree in length or an id or index is out of range (callers build them from
/// one validated source).
pub fn build_level(
    attributes: &Attributes,
    ids: &[u32],
    ancestor_ids: &[u32],
    indices: &[u32],
    materials: &[Option<usize>],
    error: f32,
    next: &[u32],
) -> LevelData {
    assert_eq!(ids.len(), ancestor_ids.len(), "one ancestor per vertex");
    assert_eq!(indices.len(), 3 * materials.len(), "one material per triangle");
    let mut vertices: Vec<GeomorphVertexRaw> = ids
        .iter()
        .zip(ancestor_ids)
        .map(|(&v, &a)| GeomorphVertexRaw {
            fine: attributes.vertex(v as usize),
            coarse: attributes.vertex(a as usize),
        })
        .collect();
    let mut next = next.to_vec();
    let mut faceted = vec![false; vertices.len()];
    let mut indices = std::borrow::Cow::Borrowed(indices);
    if let Some(flat) = attributes.flat {
        let indices = indices.to_mut();
        let fine_flat: Vec<bool> = ids.iter().map(|&v| flat[v as usize]).collect();
        let coarse_flat: Vec<bool> = ancestor_ids.iter().map(|&a| flat[a as usize]).collect();
        let split = |v: u32| fine_flat[v as usize] || coarse_flat[v as usize];
        // Whether a triangle already took the vertex (later ones get copies).
        let mut claimed = vec![false; vertices.len()];
        for t in 0..indices.len() / 3 {
            let tri = [indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]];
            if !tri.iter().any(|&v| split(v)) {
                continue;
            }
            let end = |k: usize, coarse: bool| {
                let v = &vertices[tri[k] as usize];
                Vec3::from(if coarse { v.coarse.position } else { v.fine.position })
            };
            let fine_normal = face_normal(end(0, false), end(1, false), end(2, false));
            let coarse_normal = face_normal(end(0, true), end(1, true), end(2, true)).or(fine_normal);
            for (k, &v) in tri.iter().enumerate() {
                if !split(v) {
                    continue;
                }
                let slot = if claimed[v as usize] {
                    vertices.push(vertices[v as usize]);
                    claimed.push(true);
                    faceted.push(fine_flat[v as usize]);
                    if let Some(&n) = next.get(v as usize) {
                        next.push(n);
                    }
                    vertices.len() - 1
                } else {
                    claimed[v as usize] = true;
                    faceted[v as usize] = fine_flat[v as usize];
                    v as usize
                };
                let vertex = &mut vertices[slot];
                if let (true, Some(n)) = (fine_flat[v as usize], fine_normal) {
                    vertex.fine.normal = n.to_array();
                }
                if let (true, Some(n)) = (coarse_flat[v as usize], coarse_normal) {
                    vertex.coarse.normal = n.to_array();
                }
                indices[3 * t + k] = slot as u32;
            }
        }
    }
    let mut order: Vec<usize> = (0..materials.len()).collect();
    // Default material (None) first, then by index: a fixed order, so every level draws alike.
    order.sort_by_key(|&t| materials[t].map_or(0, |m| m + 1));
    let mut sorted = Vec::with_capacity(indices.len());
    let mut ranges: Vec<PrimitiveRange> = Vec::new();
    for t in order {
        match ranges.last_mut() {
            Some(r) if r.material == materials[t] => r.index_count += 3,
            _ => ranges.push(PrimitiveRange {
                first_index: sorted.len() as u32,
                index_count: 3,
                material: materials[t],
            }),
        }
        sorted.extend_from_slice(&indices[3 * t..3 * t + 3]);
    }
    LevelData { vertices, indices: sorted, ranges, error, next, faceted }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn vertex_layout_matches_the_shader_locations() {
        // src/render/gpu/pipelines.rs declares these offsets for locations 0..5 (and the morph
        // range at 12 and 13); 80 bytes per vertex, 160 with ancestor.
        assert_eq!(std::mem::size_of::<VertexRaw>(), 80);
        assert_eq!(std::mem::offset_of!(VertexRaw, joints), 48);
        assert_eq!(std::mem::offset_of!(VertexRaw, weights), 56);
        assert_eq!(std::mem::offset_of!(VertexRaw, morph), 72);
        assert_eq!(std::mem::size_of::<GeomorphVertexRaw>(), 160);
    }

    #[test]
    fn level_vertices_carry_their_morph_rows_at_both_ends() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let normals = [Vec3::Y; 4];
        let joints = [[0u16; 4]; 4];
        let weights = [[1.0, 0.0, 0.0, 0.0]; 4];
        let mut morph = MorphDeltas::default();
        morph.push_row([]);
        morph.push_row([(0, Vec3::X, Vec3::ZERO), (2, Vec3::Y, Vec3::Z)]);
        morph.push_row([]);
        morph.push_row([(1, Vec3::Z, Vec3::X)]);
        let attributes = Attributes {
            positions: &positions,
            normals: &normals,
            uvs: None,
            colors: None,
            joints: &joints,
            weights: &weights,
            flat: None,
            morph: &morph,
        };
        let level = build_level(&attributes, &[3, 1, 2], &[1, 1, 2], &[0, 1, 2], &[None], 0.0, &[]);
        let ends: Vec<_> = level.vertices.iter().map(|v| (v.fine.morph, v.coarse.morph)).collect();
        assert_eq!(ends, [([2, 1], [0, 2]), ([0, 2], [0, 2]), ([2, 0], [2, 0])]);
        // Two texels per entry: (Δp, target) then (Δn, 0), in entry order.
        let texels = morph_texels(&morph);
        assert_eq!(texels.len(), 6);
        assert_eq!(texels[2], [0.0, 1.0, 0.0, 2.0]);
        assert_eq!(texels[3], [0.0, 0.0, 1.0, 0.0]);
        assert_eq!(texels[4], [0.0, 0.0, 1.0, 1.0]);
    }

    #[test]
    fn level_groups_triangles_by_material_and_pairs_ancestors() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let normals = [Vec3::Y; 4];
        let joints = [[0u16, 0, 0, 0], [1, 0, 0, 0], [2, 0, 0, 0], [3, 0, 0, 0]];
        let weights = [[1.0, 0.0, 0.0, 0.0]; 4];
        let attributes = Attributes {
            positions: &positions,
            normals: &normals,
            uvs: None,
            colors: None,
            joints: &joints,
            weights: &weights,
            flat: None,
            morph: &MorphDeltas::default(),
        };
        let level = build_level(
            &attributes,
            &[3, 1, 2],
            &[1, 1, 2],
            &[0, 1, 2, 2, 1, 0, 1, 2, 0],
            &[Some(1), None, Some(1)],
            0.5,
            &[],
        );
        assert_eq!(level.indices, [2, 1, 0, 0, 1, 2, 1, 2, 0]);
        assert_eq!(
            level.ranges,
            [
                PrimitiveRange { first_index: 0, index_count: 3, material: None },
                PrimitiveRange { first_index: 3, index_count: 6, material: Some(1) },
            ]
        );
        assert_eq!(level.vertices[0].fine.position, [0.0, 0.0, 1.0]);
        assert_eq!(level.vertices[0].coarse.position, [1.0, 0.0, 0.0]);
        assert_eq!(level.vertices[0].coarse.joints, [1, 0, 0, 0]);
        assert_eq!(level.vertices[2].fine, level.vertices[2].coarse);
        assert_eq!(level.vertices[1].fine.color, [1.0; 4], "no colours: white");
        assert_eq!(level.triangle_count(), 3);
    }
}
