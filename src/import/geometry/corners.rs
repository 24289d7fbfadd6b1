//! Corners of one primitive made into shared vertices: [`weld`] merges the corners of a
//! non-indexed primitive that agree in everything, and [`flat_shaded`] gives a primitive without
//! normals the flat normals the spec asks for, one corner per triangle corner, for `weld` to merge.

use std::collections::HashMap;

use glam::Vec3;

use super::{Influences, Primitive};
use crate::mesh::compute_normals;

/// Merges corners that are bit-identical in every attribute (position, normal, uv, colour, joints,
/// weights), keeping first occurrences in order. Non-indexed files store each triangle corner
/// separately; welding makes the mesh connected for simplification.
pub(super) fn weld(prim: Primitive, influences: Influences) -> (Primitive, Influences) {
    let n = prim.positions.len();
    let mut key_len = 3 + 4 + 4;
    key_len += prim.normals.as_ref().map_or(0, |_| 3) + prim.uvs.as_ref().map_or(0, |_| 2);
    key_len += prim.colors.as_ref().map_or(0, |_| 4);
    // Keys have different lengths when morph rows do: key `v` is `keys[key_at[v]..key_at[v + 1]]`.
    let mut keys: Vec<u32> = Vec::with_capacity(n * key_len);
    let mut key_at = Vec::with_capacity(n + 1);
    for v in 0..n {
        key_at.push(keys.len());
        keys.extend(prim.positions[v].to_array().map(f32::to_bits));
        if let Some(normals) = &prim.normals {
            keys.extend(normals[v].to_array().map(f32::to_bits));
        }
        if let Some(uvs) = &prim.uvs {
            keys.extend(uvs[v].to_array().map(f32::to_bits));
        }
        if let Some(colors) = &prim.colors {
            keys.extend(colors[v].to_array().map(f32::to_bits));
        }
        keys.extend(influences.joints[v].map(u32::from));
        keys.extend(influences.weights[v].map(f32::to_bits));
        // Corners with different morph deltas are different vertices.
        for (t, dp, dn) in prim.morph.get(v).into_iter().flatten() {
            keys.push(u32::from(*t));
            keys.extend(dp.to_array().map(f32::to_bits));
            keys.extend(dn.to_array().map(f32::to_bits));
        }
    }
    key_at.push(keys.len());
    let mut first: HashMap<&[u32], u32> = HashMap::with_capacity(n);
    let mut kept: Vec<usize> = Vec::new();
    let remap: Vec<u32> = key_at
        .windows(2)
        .map(|w| &keys[w[0]..w[1]])
        .enumerate()
        .map(|(v, key)| {
            *first.entry(key).or_insert_with(|| {
                kept.push(v);
                (kept.len() - 1) as u32
            })
        })
        .collect();
    let pick = |values: &[Vec3]| kept.iter().map(|&v| values[v]).collect::<Vec<_>>();
    let welded = Primitive {
        positions: pick(&prim.positions),
        normals: prim.normals.as_deref().map(pick),
        uvs: prim.uvs.as_ref().map(|uvs| kept.iter().map(|&v| uvs[v]).collect()),
        colors: prim.colors.as_ref().map(|c| kept.iter().map(|&v| c[v]).collect()),
        influence_sets: Vec::new(),
        indices: prim.indices.iter().map(|&i| remap[i as usize]).collect(),
        indexed: true,
        target_count: prim.target_count,
        file_count: prim.file_count,
        rows: None,
        morph: if prim.morph.is_empty() {
            Vec::new()
        } else {
            kept.iter().map(|&v| prim.morph[v].clone()).collect()
        },
    };
    let influences = Influences {
        joints: kept.iter().map(|&v| influences.joints[v]).collect(),
        weights: kept.iter().map(|&v| influences.weights[v]).collect(),
    };
    (welded, influences)
}

/// A primitive without normals as the spec draws it (§3.7.2.1: "client implementations MUST
/// calculate flat normals"): one corner per triangle corner, each with its face's normal, as an
/// unindexed primitive that [`weld`] then merges wherever corners agree in everything (a flat
/// quad keeps four vertices). The LOD build sees a flat-shaded mesh and keeps it faceted
/// (`clod::shading`). A degenerate triangle's corners get the area-weighted vertex normals.
pub(super) fn flat_shaded(prim: Primitive, influences: Influences) -> (Primitive, Influences) {
    let corners = &prim.indices;
    let mut smooth: Option<Vec<Vec3>> = None;
    let mut normals = Vec::with_capacity(corners.len());
    for tri in corners.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| prim.positions[tri[k] as usize]);
        let face = (b - a).cross(c - a).try_normalize();
        for &v in tri {
            let fallback =
                || smooth.get_or_insert_with(|| compute_normals(&prim.positions, corners))[v as usize];
            normals.push(face.unwrap_or_else(fallback));
        }
    }
    let at = |v: &u32| *v as usize;
    let flat = Primitive {
        positions: corners.iter().map(|v| prim.positions[at(v)]).collect(),
        normals: Some(normals),
        uvs: prim.uvs.as_ref().map(|uvs| corners.iter().map(|v| uvs[at(v)]).collect()),
        colors: prim.colors.as_ref().map(|c| corners.iter().map(|v| c[at(v)]).collect()),
        influence_sets: Vec::new(),
        indices: (0..corners.len() as u32).collect(),
        indexed: false,
        target_count: prim.target_count,
        file_count: prim.file_count,
        rows: None,
        morph: if prim.morph.is_empty() {
            Vec::new()
        } else {
            corners.iter().map(|v| prim.morph[at(v)].clone()).collect()
        },
    };
    let influences = Influences {
        joints: corners.iter().map(|v| influences.joints[at(v)]).collect(),
        weights: corners.iter().map(|v| influences.weights[at(v)]).collect(),
    };
    (flat, influences)
}
