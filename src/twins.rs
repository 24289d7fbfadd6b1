//! Twin triangles: triangles on the same three positions as another, and the *layers* that keep
//! each copy a surface of its own.
//!
//! Files repeat triangles on purpose: a mesh drawn by two nodes lies on itself, and a
//! double-sided card (hair, cloth, leaves) is often a sheet plus a reversed copy of it, so that a
//! back-face-culled material shows it from both sides. Welded by position, such copies put four
//! triangles on every edge, which no edge collapse may touch: the whole copy stayed at full
//! detail, and the rest of the mesh paid for every level's triangle count. Numbered instead by
//! how many earlier triangles (in index order) lie on the same positions, the `k`-th is in layer
//! `k`, and welding vertices only within a layer lets each copy simplify like the original.
//!
//! Positions compare bit for bit, with −0.0 the same as +0.0, as everywhere the mesh is welded.

use std::collections::HashMap;

use glam::Vec3;

use crate::mesh::SkinnedMesh;

/// "No layer yet" in [`vertex_layers`]' scratch.
const UNSEEN: u32 = u32::MAX;

/// Per vertex, the lowest vertex with a bit-identical position (−0.0 = +0.0).
pub fn position_ids(positions: &[Vec3]) -> Vec<u32> {
    lowest_of_equal_keys(positions.len(), |v| {
        let [x, y, z] = position_bits(positions[v]);
        Some([x, y, z, 0])
    })
}

/// A position as welding compares it: bit for bit, with −0.0 the same as +0.0.
pub(crate) fn position_bits(p: Vec3) -> [u32; 3] {
    p.to_array().map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

/// For each of `count` vertices that `key` gives a key, the lowest such vertex with the same key;
/// `u32::MAX` for the others. An open-addressing table of vertex ids (twice as many slots as
/// vertices, linear probing, keys recomputed to compare), so linear in the vertices: sorting
/// 128-bit keys instead was 1.5–3 % of a build natively, more in wasm32.
pub(crate) fn lowest_of_equal_keys(count: usize, key: impl Fn(usize) -> Option<[u32; 4]>) -> Vec<u32> {
    let bits = (2 * count).max(16).next_power_of_two().trailing_zeros();
    let mask = (1usize << bits) - 1;
    const EMPTY: u32 = u32::MAX;
    let mut slots = vec![EMPTY; 1 << bits];
    let mut lowest = vec![EMPTY; count];
    for (v, lowest) in lowest.iter_mut().enumerate() {
        let Some(k) = key(v) else { continue };
        let low = u64::from(k[0]) | u64::from(k[1]) << 32;
        let high = u64::from(k[2]) | u64::from(k[3]) << 32;
        let hash = (low.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ high).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        let mut slot = (hash >> (64 - bits)) as usize;
        *lowest = loop {
            match slots[slot] {
                EMPTY => {
                    slots[slot] = v as u32;
                    break v as u32;
                }
                other if key(other as usize) == Some(k) => break other,
                _ => slot = (slot + 1) & mask,
            }
        };
    }
    lowest
}

/// Per triangle, its layer: how many earlier triangles lie on the same three positions
/// (`position_of` maps a vertex to an id below `id_count`, equal for equal positions). `None` when
/// no triangle repeats another, the common case.
///
/// Linear in the triangles: they are grouped by their lowest position id (a counting sort, in
/// index order within a group) and compared within a group, which holds the few triangles a
/// vertex is the lowest corner of; a larger group (a fan's centre) is sorted instead. No 128-bit
/// sort: in wasm32 that took 5–9 % of the whole build.
pub fn triangle_layers(
    position_of: impl Fn(u32) -> u32,
    indices: &[u32],
    id_count: usize,
) -> Option<Vec<u32>> {
    let triples: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|c| {
            let mut k = [position_of(c[0]), position_of(c[1]), position_of(c[2])];
            k.sort_unstable();
            k
        })
        .collect();
    let mut start = vec![0u32; id_count + 1];
    for k in &triples {
        start[k[0] as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut fill = start.clone();
    let mut grouped = vec![0u32; triples.len()];
    for (t, k) in triples.iter().enumerate() {
        grouped[fill[k[0] as usize] as usize] = t as u32;
        fill[k[0] as usize] += 1;
    }
    let mut layer: Option<Vec<u32>> = None;
    let mut scratch: Vec<(u32, u32, u32)> = Vec::new();
    for group in start.windows(2).map(|w| &grouped[w[0] as usize..w[1] as usize]) {
        let rest = |t: u32| (triples[t as usize][1], triples[t as usize][2]);
        if group.len() <= 16 {
            for (i, &t) in group.iter().enumerate() {
                let earlier = group[..i].iter().filter(|&&e| rest(e) == rest(t)).count() as u32;
                if earlier > 0 {
                    layer.get_or_insert_with(|| vec![0; triples.len()])[t as usize] = earlier;
                }
            }
        } else {
            scratch.clear();
            scratch.extend(group.iter().map(|&t| (rest(t).0, rest(t).1, t)));
            scratch.sort_unstable();
            for run in scratch.chunk_by(|a, b| (a.0, a.1) == (b.0, b.1)).filter(|run| run.len() > 1) {
                let layer = layer.get_or_insert_with(|| vec![0; triples.len()]);
                for (k, &(_, _, t)) in run.iter().enumerate() {
                    layer[t as usize] = k as u32;
                }
            }
        }
    }
    layer
}

/// Per vertex, the layer of the triangles that use it: 0 for a vertex used in two layers (a copy
/// that shares the original's vertices, see [`unshare_layers`]) or by none.
pub fn vertex_layers(triangle_layers: &[u32], indices: &[u32], vertex_count: usize) -> Vec<u32> {
    let mut layer = vec![UNSEEN; vertex_count];
    for (corners, &t) in indices.chunks_exact(3).zip(triangle_layers) {
        for &v in corners {
            let l = &mut layer[v as usize];
            *l = if *l == UNSEEN || *l == t { t } else { 0 };
        }
    }
    layer.iter_mut().filter(|l| **l == UNSEEN).for_each(|l| *l = 0);
    layer
}

/// Gives the corners of a twin triangle their own vertices where they share one with a
/// triangle of another layer (a reversed copy written over the original's vertices), copying
/// every attribute; the mesh draws the same. Returns the number of vertices added: none when
/// no triangle repeats another, or when the copies would take the mesh past `max_vertices`.
pub fn unshare_layers(mesh: &mut SkinnedMesh, max_vertices: usize) -> usize {
    let ids = position_ids(&mesh.positions);
    let Some(triangle_layer) = triangle_layers(|v| ids[v as usize], &mesh.indices, ids.len()) else {
        return 0;
    };
    // The first layer to use each vertex keeps it; another layer gets one copy per vertex.
    let mut owner = vec![UNSEEN; mesh.vertex_count()];
    let mut copies: HashMap<(u32, u32), u32> = HashMap::new();
    let mut remapped = mesh.indices.clone();
    let mut sources = Vec::new();
    for (t, &layer) in triangle_layer.iter().enumerate() {
        for corner in &mut remapped[3 * t..3 * t + 3] {
            let v = *corner;
            let o = &mut owner[v as usize];
            if *o == UNSEEN {
                *o = layer;
            } else if *o != layer {
                let next = (mesh.vertex_count() + sources.len()) as u32;
                *corner = *copies.entry((v, layer)).or_insert_with(|| {
                    sources.push(v as usize);
                    next
                });
            }
        }
    }
    if sources.is_empty() || mesh.vertex_count() + sources.len() > max_vertices {
        return 0;
    }
    mesh.indices = remapped;
    copy_rows(&mut mesh.positions, &sources);
    copy_rows(&mut mesh.normals, &sources);
    copy_rows(&mut mesh.joints, &sources);
    copy_rows(&mut mesh.weights, &sources);
    if let Some(uvs) = &mut mesh.uvs {
        copy_rows(uvs, &sources);
    }
    if let Some(colors) = &mut mesh.colors {
        copy_rows(colors, &sources);
    }
    if !mesh.morph.is_empty() {
        for &v in &sources {
            let row: Vec<_> = mesh.morph.of(v).collect();
            mesh.morph.push_row(row);
        }
    }
    sources.len()
}

/// Appends a copy of `values[v]` for every `v` of `sources`.
fn copy_rows<T: Copy>(values: &mut Vec<T>, sources: &[usize]) {
    values.reserve(sources.len());
    for &v in sources {
        values.push(values[v]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec4};

    /// A unit quad (two triangles) and, on the same four vertices, its reversed copy.
    fn quad_with_shared_back() -> SkinnedMesh {
        SkinnedMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: vec![Vec3::Z; 4],
            uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
            colors: Some(vec![Vec4::ONE; 4]),
            joints: vec![[0, 1, 0, 0]; 4],
            weights: vec![[0.75, 0.25, 0.0, 0.0]; 4],
            indices: vec![0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2],
            ..SkinnedMesh::default()
        }
    }

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn copies_are_numbered_in_index_order() {
        // Vertex 4 lies on vertex 0: the third triangle repeats the first, reversed, and the
        // fourth repeats the first again.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ZERO];
        let ids = position_ids(&positions);
        assert_eq!(ids, [0, 1, 2, 3, 0]);
        let indices = [0, 1, 2, 0, 1, 3, 4, 2, 1, 1, 2, 0];
        let layers = triangle_layers(|v| ids[v as usize], &indices, ids.len()).unwrap();
        assert_eq!(layers, [0, 0, 1, 2]);
        // Vertex 4 only in layer 1; 1 and 2 in three layers, 0 in two and 3 in one: layer 0.
        assert_eq!(vertex_layers(&layers, &indices, 6), [0, 0, 0, 0, 1, 0]);
        assert_eq!(triangle_layers(|v| v, &[0, 1, 2, 0, 2, 3], 4), None);
        // A fan centre with more triangles than are compared pairwise: sorted, same answer.
        let fan: Vec<u32> = (1..=40).flat_map(|k| [0, k, k + 1]).chain([0, 8, 7, 0, 8, 7]).collect();
        let mut expected = vec![0; 42];
        expected[40] = 1;
        expected[41] = 2;
        assert_eq!(triangle_layers(|v| v, &fan, 42), Some(expected));
        // −0.0 is +0.0.
        assert_eq!(position_ids(&[Vec3::ZERO, Vec3::new(-0.0, 0.0, -0.0)]), [0, 0]);
    }

    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    fn a_copy_on_shared_vertices_gets_its_own() {
        let mut mesh = quad_with_shared_back();
        mesh.morph.push_row([(0, Vec3::Z, Vec3::ZERO)]);
        for _ in 1..4 {
            mesh.morph.push_row([]);
        }
        let before = mesh.clone();
        assert_eq!(unshare_layers(&mut mesh, 100), 4);
        assert_eq!(mesh.indices, [0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 7, 5]);
        // Each copy has every attribute of its source, so the mesh draws the same.
        let source = [0, 1, 2, 3, 0, 2, 1, 3];
        for (v, &s) in source.iter().enumerate() {
            assert_eq!(mesh.positions[v], before.positions[s]);
            assert_eq!(mesh.uvs.as_ref().unwrap()[v], before.uvs.as_ref().unwrap()[s]);
            assert_eq!((mesh.joints[v], mesh.weights[v]), (before.joints[s], before.weights[s]));
            assert_eq!(mesh.morph.of(v).collect::<Vec<_>>(), before.morph.of(s).collect::<Vec<_>>());
        }
        assert_eq!(mesh.colors.as_ref().map(Vec::len), Some(8));
        // Nothing left to unshare; and a cap that the copies would pass leaves the mesh alone.
        assert_eq!(unshare_layers(&mut mesh, 100), 0);
        let mut capped = before.clone();
        assert_eq!(unshare_layers(&mut capped, 7), 0);
        assert_eq!(capped, before);
    }
}
