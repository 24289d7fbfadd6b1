//! Morph targets from import to the LOD chain, on a hand-made glTF: a flat 3 × 3-vertex grid
//! (8 triangles) on a rigid node scaled by 2, with a sparse target (the centre vertex lifted by
//! one unit) and a dense one whose deltas are a linear field (`Δp = (0, 0, x)`, `Δn = (0.1 x, 0,
//! 0)` in the file's units), node and mesh default weights, and one clip per interpolation of
//! the `weights` path. Exact expected values; then every level of the chain built from it.
//! Last, invariants on shared models given seeded random sparse targets.

use crate::common;

use clod_viewer::clod::bytes::{decode, encode, ClodBytesError};
use clod_viewer::clod::{self, Clod, ClodOptions, SimplificationPose};
use clod_viewer::import::from_gltf;
use clod_viewer::morph::{MorphDeltas, MorphTarget};
use clod_viewer::render::crowd::PosePalette;
use clod_viewer::simplify::CollapseMode;
use clod_viewer::{import, Character};
use glam::Vec3;
use std::collections::HashMap;

/// The grid's buffer: positions, normals, indices, the dense target, the sparse target's index
/// and value, key times, linear weights and cubic-spline weights, in that order.
fn buffer() -> Vec<u8> {
    let mut out = Vec::new();
    let f32s = |out: &mut Vec<u8>, xs: &[f32]| xs.iter().for_each(|x| out.extend(x.to_le_bytes()));
    let grid: Vec<[f32; 2]> = (0..3).flat_map(|j| (0..3).map(move |i| [i as f32, j as f32])).collect();
    for [x, y] in &grid {
        f32s(&mut out, &[*x, *y, 0.0]); // 0..108
    }
    for _ in &grid {
        f32s(&mut out, &[0.0, 0.0, 1.0]); // 108..216
    }
    for j in 0..2u16 {
        for i in 0..2u16 {
            let v = 3 * j + i;
            for c in [v, v + 1, v + 4, v, v + 4, v + 3] {
                out.extend(c.to_le_bytes()); // 216..264
            }
        }
    }
    for [x, _] in &grid {
        f32s(&mut out, &[0.0, 0.0, *x]); // 264..372
    }
    for [x, _] in &grid {
        f32s(&mut out, &[0.1 * x, 0.0, 0.0]); // 372..480
    }
    out.extend(4u16.to_le_bytes()); // 480..482, padded to 484
    out.extend([0, 0]);
    f32s(&mut out, &[0.0, 0.0, 1.0]); // 484..496
    f32s(&mut out, &[0.0, 1.0]); // 496..504
    f32s(&mut out, &[0.0, 0.0, 1.0, 0.5]); // 504..520: two keys of two weights
                                           // 520..568: per key in-tangents, values, out-tangents of two weights.
    f32s(&mut out, &[0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0]);
    assert_eq!(out.len(), 568);
    out
}

fn grid_gltf() -> Vec<u8> {
    use base64::Engine;
    let uri = base64::engine::general_purpose::STANDARD.encode(buffer());
    let json = r#"{
      "asset": {"version": "2.0"},
      "scene": 0,
      "scenes": [{"nodes": [0]}],
      "nodes": [{"name": "grid", "mesh": 0, "scale": [2, 2, 2], "weights": [0.5, 0]}],
      "meshes": [{"name": "face", "weights": [0.25, 0], "primitives": [{
        "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
        "targets": [{"POSITION": 3}, {"POSITION": 4, "NORMAL": 5}]
      }]}],
      "animations": [
        {"name": "linear", "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
         "samplers": [{"input": 6, "output": 7}]},
        {"name": "cubic", "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
         "samplers": [{"input": 6, "output": 8, "interpolation": "CUBICSPLINE"}]}
      ],
      "buffers": [{"byteLength": 568, "uri": "data:application/octet-stream;base64,URI"}],
      "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 108},
        {"buffer": 0, "byteOffset": 108, "byteLength": 108},
        {"buffer": 0, "byteOffset": 216, "byteLength": 48},
        {"buffer": 0, "byteOffset": 264, "byteLength": 108},
        {"buffer": 0, "byteOffset": 372, "byteLength": 108},
        {"buffer": 0, "byteOffset": 480, "byteLength": 2},
        {"buffer": 0, "byteOffset": 484, "byteLength": 12},
        {"buffer": 0, "byteOffset": 496, "byteLength": 8},
        {"buffer": 0, "byteOffset": 504, "byteLength": 16},
        {"buffer": 0, "byteOffset": 520, "byteLength": 48}
      ],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 9, "type": "VEC3", "min": [0, 0, 0], "max": [2, 2, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 9, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": 24, "type": "SCALAR"},
        {"componentType": 5126, "count": 9, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 1],
         "sparse": {"count": 1, "indices": {"bufferView": 5, "componentType": 5123},
                    "values": {"bufferView": 6}}},
        {"bufferView": 3, "componentType": 5126, "count": 9, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 2]},
        {"bufferView": 4, "componentType": 5126, "count": 9, "type": "VEC3"},
        {"bufferView": 7, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
        {"bufferView": 8, "componentType": 5126, "count": 4, "type": "SCALAR"},
        {"bufferView": 9, "componentType": 5126, "count": 12, "type": "SCALAR"}
      ]
    }"#;
    json.replace("URI", &uri).into_bytes()
}

fn grid() -> Character {
    from_gltf(&grid_gltf(), &mut |_| None).expect("the grid imports")
}

fn close(a: Vec3, b: Vec3) -> bool {
    // f32 round-off of the node's scale and its inverse.
    a.abs_diff_eq(b, 1e-6)
}

/// Some exporters write one vertex buffer per mesh and let each primitive index part of it. Each
/// primitive then gets the vertices it uses, with their attributes and morph deltas: the grid's
/// two rows of quads as two primitives over the same accessors import to 6 + 6 vertices (the
/// middle row in both), not 9 + 9, each equal to the file vertex it was read from.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn primitives_sharing_a_vertex_buffer_read_only_their_vertices() {
    let whole = grid();
    let mut json: serde_json::Value = serde_json::from_slice(&grid_gltf()).unwrap();
    let accessors = json["accessors"].as_array_mut().unwrap();
    for offset in [0, 24] {
        let text = format!(
            r#"{{"bufferView": 2, "byteOffset": {offset}, "componentType": 5123, "count": 12, "type": "SCALAR"}}"#
        );
        accessors.push(serde_json::from_str(&text).unwrap());
    }
    let rows = [accessors.len() - 2, accessors.len() - 1];
    let primitive = json["meshes"][0]["primitives"][0].clone();
    let primitives = json["meshes"][0]["primitives"].as_array_mut().unwrap();
    primitives.clear();
    for row in rows {
        let mut split = primitive.clone();
        split["indices"] = serde_json::Value::from(row);
        primitives.push(split);
    }
    let split = from_gltf(&serde_json::to_vec(&json).unwrap(), &mut |_| None).unwrap();
    // Merged vertex → the file's vertex: the first row uses 0..6, the second 3..9.
    let file_vertex: Vec<usize> = (0..6).chain(3..9).collect();
    assert_eq!(split.mesh.vertex_count(), file_vertex.len());
    for (v, &f) in file_vertex.iter().enumerate() {
        assert_eq!(split.mesh.positions[v], whole.mesh.positions[f], "vertex {v}");
        assert_eq!(split.mesh.normals[v], whole.mesh.normals[f], "vertex {v}");
        // Each primitive numbers its own two targets (the second's are 2 and 3).
        let split_row: Vec<_> = split.mesh.morph.of(v).map(|(t, dp, dn)| (t % 2, dp, dn)).collect();
        assert_eq!(split_row, whole.mesh.morph.of(f).collect::<Vec<_>>(), "vertex {v}");
    }
    let triangles = |c: &Character| -> Vec<[Vec3; 3]> {
        let p = &c.mesh.positions;
        c.mesh
            .indices
            .chunks_exact(3)
            .map(|t| [p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]])
            .collect()
    };
    assert_eq!(triangles(&split), triangles(&whole));
    // A message names the file's vertex: file vertex 7 is the second primitive's fifth.
    use base64::Engine;
    let mut bytes = buffer();
    bytes[108 + 7 * 12..108 + 7 * 12 + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let uri = base64::engine::general_purpose::STANDARD.encode(bytes);
    json["buffers"][0]["uri"] =
        serde_json::Value::from(format!("data:application/octet-stream;base64,{uri}"));
    let error = from_gltf(&serde_json::to_vec(&json).unwrap(), &mut |_| None).err().unwrap();
    let message = error.to_string();
    assert!(
        message.contains("primitive 1") && message.contains("vertex 7 has a non-finite normal"),
        "{message}"
    );
}

/// One mesh on two nodes at the same place lies on itself: the import keeps both copies, the
/// LOD build keeps their vertices apart and simplifies each as a surface of its own
/// (`clod_viewer::twins`), so the doubled grid goes down to twice the single grid's coarsest
/// level instead of staying whole.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_mesh_drawn_twice_simplifies_copy_by_copy() {
    // On a second node (its own rigid joint), and as a second primitive of the same mesh (the
    // same joint, as one skin drawn by two nodes has: the copies' vertices agree in everything).
    let mut on_two_nodes: serde_json::Value = serde_json::from_slice(&grid_gltf()).unwrap();
    let twin = on_two_nodes["nodes"][0].clone();
    on_two_nodes["nodes"].as_array_mut().unwrap().push(twin);
    on_two_nodes["scenes"][0]["nodes"] = serde_json::Value::from(vec![0, 1]);
    let mut two_primitives: serde_json::Value = serde_json::from_slice(&grid_gltf()).unwrap();
    let twin = two_primitives["meshes"][0]["primitives"][0].clone();
    two_primitives["meshes"][0]["primitives"].as_array_mut().unwrap().push(twin);
    for (json, mode) in [
        (&on_two_nodes, CollapseMode::Full),
        (&two_primitives, CollapseMode::Full),
        (&two_primitives, CollapseMode::HalfEdge),
    ] {
        let twice = from_gltf(&serde_json::to_vec(json).unwrap(), &mut |_| None).unwrap();
        assert_eq!(twice.mesh.triangle_count(), 16);
        let once = chain(&grid(), mode);
        let levels = once.levels.iter().map(|l| 2 * l.triangle_count()).collect();
        let options = ClodOptions { level_triangles: Some(levels), ..chain_options(mode) };
        let twice = clod::build(&twice, &options, &mut |_| {}).unwrap();
        let counts = |c: &Clod| c.levels.iter().map(|l| l.triangle_count()).collect::<Vec<_>>();
        assert_eq!(counts(&twice), counts(&once).iter().map(|n| 2 * n).collect::<Vec<_>>(), "{mode:?}");
        let error = |c: &Clod| c.levels.last().unwrap().error;
        assert!(
            error(&twice) <= 1.001 * error(&once),
            "{mode:?}: {} against {}",
            error(&twice),
            error(&once)
        );
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn targets_deltas_and_default_weights_import_exactly() {
    let c = grid();
    assert!(c.warnings.is_empty(), "nothing is dropped: {:?}", c.warnings);
    assert_eq!(c.morph_targets.len(), 2);
    assert_eq!(c.morph_targets[0].name, "mesh 0 ('face') primitive 0 target 0");
    // The node's weights override the mesh's.
    assert_eq!(c.default_morph_weights(), vec![0.5, 0.0]);
    let morph = &c.mesh.morph;
    assert_eq!(morph.row_count(), 9);
    // Vertex 0 (x = 0) moves with neither target: nothing is stored for it.
    assert_eq!(morph.of(0).count(), 0);
    // The centre (file (1, 1)): the sparse target's (0, 0, 1) and the dense target's (0, 0, 1),
    // scaled by the node into bind space; the normal delta keeps its length (uniform scale).
    let centre: Vec<_> = morph.of(4).collect();
    assert_eq!(centre.len(), 2);
    assert_eq!((centre[0].0, centre[1].0), (0, 1));
    assert!(close(centre[0].1, Vec3::new(0.0, 0.0, 2.0)) && centre[0].2 == Vec3::ZERO);
    assert!(close(centre[1].1, Vec3::new(0.0, 0.0, 2.0)) && close(centre[1].2, Vec3::new(0.1, 0.0, 0.0)));
    // Every other vertex: the dense target only, Δp = (0, 0, bind x).
    for v in [1, 2, 5, 8] {
        let row: Vec<_> = morph.of(v).collect();
        assert_eq!(row.len(), 1, "vertex {v}");
        let x = c.mesh.positions[v].x;
        assert!(close(row[0].1, Vec3::new(0.0, 0.0, x)), "vertex {v}: {:?}", row[0]);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn crowd_palette_rows_carry_the_clips_weights_at_their_time() {
    let c = grid();
    let linear = c.clips.iter().position(|clip| clip.name == "linear").unwrap();
    let palette = PosePalette::sample(&c, Some(linear));
    assert_eq!((palette.targets, palette.rows), (2, 30));
    assert_eq!(palette.weights.len(), 2 * 30);
    // Row 15 is the clip at 0.5 s, as `morph_weights_at` samples it.
    assert_eq!(&palette.weights[30..32], &[0.5, 0.25]);
    for r in 0..palette.rows {
        let time = r as f32 / 30.0;
        assert_eq!(
            &palette.weights[2 * r..2 * r + 2],
            c.morph_weights_at(&c.clips[linear], time).as_slice(),
            "row {r}"
        );
    }
    // One texel per row holds both weights; switched off, zeros.
    assert_eq!(palette.weight_texels_per_row(), 1);
    let texels = palette.weight_texels(true);
    assert_eq!(texels.len(), 30);
    assert_eq!(texels[15], [0.5, 0.25, 0.0, 0.0]);
    assert!(palette.weight_texels(false).iter().all(|t| *t == [0.0; 4]));
    // The rest pose: one row of the default weights (the node's).
    let rest = PosePalette::sample(&c, None);
    assert_eq!((rest.rows, rest.weights.as_slice()), (1, [0.5, 0.0].as_slice()));
    assert_eq!(rest.weight_texels(true), vec![[0.5, 0.0, 0.0, 0.0]]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn clips_sample_weights_in_every_interpolation_and_cpu_skinning_applies_them() {
    let c = grid();
    let linear = c.clip("linear").unwrap();
    let cubic = c.clip("cubic").unwrap();
    assert_eq!(linear.duration(), 1.0);
    assert_eq!(c.morph_weights_at(linear, 0.5), vec![0.5, 0.25]);
    // Hermite at s = 0.5 with tangents 2 (out of key 0) and 1 (into key 1): 0.25 + 0.5 - 0.125.
    assert_eq!(c.morph_weights_at(cubic, 0.5), vec![0.625, 0.5]);
    let skinned = c.clip_skinned_positions(linear, 0.5);
    // The centre (2, 2, 0) lifted by 0.5 · 2 + 0.25 · 2.
    assert!(close(skinned[4], Vec3::new(2.0, 2.0, 1.5)), "{}", skinned[4]);
    // Vertex 2 at x = 4: 0.25 · 4.
    assert!(close(skinned[2], Vec3::new(4.0, 0.0, 1.0)), "{}", skinned[2]);
    // Weights 0: the bind pose.
    let rest = c.morphed_skinned_positions(&c.skeleton.rest_pose(), &[0.0, 0.0]);
    assert!(rest.iter().zip(&c.mesh.positions).all(|(a, b)| close(*a, *b)));
}

fn chain_options(mode: CollapseMode) -> ClodOptions {
    ClodOptions {
        pose: SimplificationPose::Bind,
        level_triangles: Some(vec![8, 4, 2]),
        mode,
        max_relative_error: f32::INFINITY,
        ..ClodOptions::default()
    }
}

fn chain(c: &Character, mode: CollapseMode) -> Clod {
    clod::build(c, &chain_options(mode), &mut |_| {}).expect("the grid simplifies")
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_level_carries_the_deltas_and_the_linear_field_exactly() {
    let c = grid();
    for mode in [CollapseMode::Full, CollapseMode::HalfEdge] {
        let clod = chain(&c, mode);
        assert!(clod.levels.len() >= 2, "{mode:?}: the grid collapses");
        // Deltas carried through collapses: the coarsest level is made of created vertices.
        let inputs = clod.apm.pm.input_vertex_count as u32;
        let coarsest = clod.levels.last().unwrap();
        assert!(coarsest.vertices.iter().any(|&v| v >= inputs), "{mode:?}: {:?}", coarsest.vertices);
        assert!(clod.apm.morph.all_finite());
        assert_eq!(clod.apm.morph.row_count(), clod.apm.pm.vertex_total());
        for (i, level) in clod.levels.iter().enumerate() {
            let deltas = clod.level_morph_deltas(i);
            assert_eq!(deltas.row_count(), level.vertices.len());
            for (k, &v) in level.vertices.iter().enumerate() {
                let p = clod.apm.bind_positions[v as usize];
                // The grid is flat and every new vertex lies on its collapsed edge, so the linear
                // field's blend is the field at the new vertex.
                let dense: Vec<_> = deltas.of(k).filter(|e| e.0 == 1).collect();
                let expected = Vec3::new(0.0, 0.0, p.x);
                let found = dense.first().map_or(Vec3::ZERO, |e| e.1);
                assert!(found.abs_diff_eq(expected, 1e-5), "{mode:?} level {i} vertex {v}: {found} at {p}");
                let normal = dense.first().map_or(Vec3::ZERO, |e| e.2);
                assert!(normal.abs_diff_eq(Vec3::new(0.05 * p.x, 0.0, 0.0), 1e-6));
            }
        }
        // Level 0 at weights 0 is the bind pose, and with weights the character's own morph.
        let identity = c.skin_matrices(&c.skeleton.rest_pose());
        let level0 = clod.level_morphed_skinned_positions(0, &identity, &[0.0, 0.0]);
        let vertices = &clod.levels[0].vertices;
        for (p, &v) in level0.iter().zip(vertices) {
            assert!(close(*p, c.mesh.positions[v as usize]));
        }
        let weights = [1.0, 0.5];
        let morphed = c.morphed_skinned_positions(&c.skeleton.rest_pose(), &weights);
        let level0 = clod.level_morphed_skinned_positions(0, &identity, &weights);
        for (p, &v) in level0.iter().zip(vertices) {
            assert!(close(*p, morphed[v as usize]));
        }
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn chain_bytes_keep_the_deltas_and_reject_another_characters() {
    let c = grid();
    let clod = chain(&c, CollapseMode::Full);
    let bytes = encode(&clod);
    assert_eq!(decode(&bytes, &c).expect("round trip"), clod);
    // The same mesh without its targets is another character.
    let mut plain = c.clone();
    plain.mesh.morph = Default::default();
    plain.morph_targets.clear();
    let error = decode(&bytes, &plain).unwrap_err();
    assert_eq!(error, ClodBytesError::OtherCharacter);
    // A changed delta of an input vertex: built for another character.
    let mut other = c.clone();
    other.mesh.morph.positions[0].z += 1.0;
    let error = decode(&bytes, &other).unwrap_err();
    assert_eq!(error, ClodBytesError::OtherCharacter);
}

/// `character` with three seeded random sparse targets: each position moves with each target
/// with probability 1/3, by up to 5 % of the diagonal, and every vertex there with it, as an
/// exporter's copies of one vertex do (normals by up to 0.1, per vertex).
fn with_random_targets(mut character: Character, seed: u64) -> Character {
    let mut rng = common::SplitMix(seed);
    let scale = 0.05 * clod_viewer::metrics::bounds_diagonal(&character.mesh.positions);
    let mut deltas = MorphDeltas::default();
    let mut moves: HashMap<[u32; 3], Vec<(u16, Vec3)>> = HashMap::new();
    for v in 0..character.mesh.vertex_count() {
        let key = character.mesh.positions[v].to_array().map(f32::to_bits);
        let moved = moves
            .entry(key)
            .or_insert_with(|| {
                let mut row = Vec::new();
                for t in 0..3u16 {
                    if rng.below(3) == 0 {
                        row.push((t, Vec3::new(rng.signed(), rng.signed(), rng.signed()) * scale));
                    }
                }
                row
            })
            .clone();
        let mut row = Vec::new();
        for (t, dp) in moved {
            row.push((t, dp, Vec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.1));
        }
        deltas.push_row(row);
    }
    character.mesh.morph = deltas;
    character.morph_targets =
        (0..3).map(|t| MorphTarget { name: format!("random {t}"), default_weight: 0.0 }).collect();
    character
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn random_targets_on_shared_models_keep_every_level_finite_and_bounded() {
    for (name, seed) in [("Fox.glb", 7), ("RiggedSimple.glb", 11)] {
        let Some(bytes) = common::model_bytes(name) else { continue };
        let c = with_random_targets(import::from_glb(&bytes).unwrap(), seed);
        let clip = &c.clips[0];
        let frame = SimplificationPose::ClipFrame { clip: clip.name.clone(), time: 0.5 * clip.duration() };
        for pose in [SimplificationPose::MultiPose { frames_per_clip: 4 }, frame] {
            let options = ClodOptions { pose: pose.clone(), ..ClodOptions::default() };
            let clod = clod::build(&c, &options, &mut |_| {}).unwrap();
            assert!(clod.levels.len() >= 3, "{name} {pose:?}");
            assert!(clod.apm.morph.all_finite(), "{name} {pose:?}");
            assert_eq!(decode(&encode(&clod), &c).unwrap(), clod);
            // Multi-pose simplifies in bind space: every created row blends its children's
            // convexly, so no target's delta grows past the largest input delta of that target.
            if let SimplificationPose::MultiPose { .. } = pose {
                let inputs = c.mesh.vertex_count();
                for t in 0..3u16 {
                    let largest = |range: std::ops::Range<usize>| {
                        range
                            .flat_map(|v| clod.apm.morph.of(v).filter(|e| e.0 == t).map(|e| e.1.length()))
                            .fold(0.0f32, f32::max)
                    };
                    let created = largest(inputs..clod.apm.pm.vertex_total());
                    assert!(created <= largest(0..inputs) * (1.0 + 1e-5), "{name}: target {t}");
                }
            }
            // Level 0 at weights 0 is the bind pose (skinned at rest), exactly; with weights, in
            // a clip's pose, the character's own morphed skinning.
            let rest = c.skeleton.rest_pose();
            let level0 = clod.level_morphed_skinned_positions(0, &c.skin_matrices(&rest), &[0.0; 3]);
            let bind = c.skinned_positions(&rest);
            let ids = &clod.levels[0].vertices;
            assert!(level0.iter().zip(ids).all(|(p, &v)| *p == bind[v as usize]), "{name}");
            let (pose_now, weights) = (c.pose_at(clip, 0.3), [0.7, -0.4, 1.0]);
            let level0 = clod.level_morphed_skinned_positions(0, &c.skin_matrices(&pose_now), &weights);
            let full = c.morphed_skinned_positions(&pose_now, &weights);
            assert!(level0.iter().zip(ids).all(|(p, &v)| *p == full[v as usize]), "{name}");
            for i in 0..clod.levels.len() {
                let positions =
                    clod.level_morphed_skinned_positions(i, &c.skin_matrices(&pose_now), &weights);
                assert!(positions.iter().all(|p| p.is_finite()), "{name} level {i}");
                assert_eq!(clod.level_morph_deltas(i).row_count(), clod.levels[i].vertices.len());
            }
        }
    }
}
