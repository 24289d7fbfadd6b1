//! The importer on a tiny hand-built skinned triangle (tests/common `TinyModel`): the valid file
//! imports to exact numbers, and each kind of broken input is an `Err` whose message names the
//! problem.

use crate::common;

use clod_viewer::import::{from_bytes, from_glb, from_gltf};
use clod_viewer::{Character, ImportError};
use common::{tiny, SplitMix, TinyModel};
use glam::{Mat4, Vec3};
use serde_json::Value;

fn import(model: &TinyModel) -> Result<Character, ImportError> {
    from_gltf(&model.gltf(), &mut |_| None)
}

/// Imports `model` and returns the error message, failing if it imports.
fn error_of(model: &TinyModel) -> String {
    match import(model) {
        Ok(_) => panic!("the broken model imported"),
        Err(e) => e.to_string(),
    }
}

fn assert_mentions(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "message {message:?} does not mention {part:?}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn tiny_model_imports_exactly() {
    let model = TinyModel::new();
    let c = import(&model).unwrap();
    assert_eq!(from_glb(&model.glb()).unwrap(), c);
    assert_eq!(c.mesh.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(c.mesh.indices, vec![0, 1, 2]);
    assert_eq!(c.mesh.weights, vec![[1.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]);
    assert_eq!(c.mesh.joints, vec![[0, 0, 0, 0], [0, 1, 0, 0], [1, 0, 0, 0]]);
    // No NORMAL in the file: the face normal of a counter-clockwise triangle in the xy plane.
    assert_eq!(c.mesh.normals, vec![Vec3::Z; 3]);
    let names: Vec<&str> = c.skeleton.nodes.iter().map(|n| n.name.as_str()).collect();
    assert_eq!(names, ["root", "tip", "tri"]);
    assert_eq!(c.skeleton.nodes[1].parent, Some(0));
    assert_eq!(c.skeleton.joints[1].joint_from_bind, Mat4::from_translation(-Vec3::Y));
    assert_eq!(c.clips[0].name, "clip 0");
    // Half-way through the clip `tip` is at (0.5, 1, 0): vertex 2 (all `tip`) follows it, vertex 1
    // (half `tip`) moves half as far.
    let skinned = c.skinned_positions(&c.pose_at(&c.clips[0], 0.5));
    assert_eq!(skinned, vec![Vec3::ZERO, Vec3::new(1.25, 0.0, 0.0), Vec3::new(0.5, 1.0, 0.0)]);
}

/// The tiny model with a second mesh, its triangle again without a skin, on a node `prop` under
/// `tip` with the node properties `transform` (glTF JSON members).
fn with_prop(transform: &str) -> TinyModel {
    let mut model = TinyModel::new();
    model.json["nodes"][1]["children"] = Value::from(vec![3]);
    let prop = format!(r#"{{"name": "prop", "mesh": 1, {transform}}}"#);
    model.json["nodes"].as_array_mut().unwrap().push(serde_json::from_str(&prop).unwrap());
    let mesh = r#"{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}"#;
    model.json["meshes"].as_array_mut().unwrap().push(serde_json::from_str(mesh).unwrap());
    model
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn unskinned_mesh_under_a_joint_is_bound_rigidly() {
    // The mesh moves under `tip` without skin: its vertices go to bind (model) space at rest, with
    // a joint of its own node, and skinning at rest puts them back.
    let c = import(&with_prop(r#""translation": [2, 0, 0], "scale": [1, -1, 1]"#)).unwrap();
    assert_eq!(c.mesh.vertex_count(), 6);
    // Depth-first scene order: `prop` (under root/tip) comes before `tri`.
    assert_eq!(c.mesh.primitives.len(), 2);
    // prop's rest model_from_node: translate (2, 1, 0), mirror y. The mirror flips the winding
    // back so the face keeps facing the same way: the file's corners 0, 1, 2 are drawn 0, 2, 1.
    // (Without NORMAL the primitive gets flat normals, one vertex per corner in drawing order.)
    let corners: Vec<Vec3> = c.mesh.indices[..3].iter().map(|&i| c.mesh.positions[i as usize]).collect();
    assert_eq!(corners, [Vec3::new(2.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 0.0)]);
    // Its face normal: the mirrored triangle still faces +z.
    assert!(c.mesh.indices[..3].iter().all(|&i| c.mesh.normals[i as usize] == Vec3::Z));
    let joint = c.mesh.joints[0][0] as usize;
    assert!(c.mesh.joints[..3].iter().all(|j| *j == [joint as u16, 0, 0, 0]));
    assert_eq!(c.mesh.weights[0], [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(c.skeleton.nodes[c.skeleton.joints[joint].node].name, "prop");
    assert_eq!(c.skeleton.joints.len(), 3);
    let rest = c.skinned_positions(&c.skeleton.rest_pose());
    for (a, b) in rest.iter().zip(&c.mesh.positions) {
        assert!(a.distance(*b) < 1e-6, "{a} vs {b}");
    }
    // Half-way through the clip `tip` moved by +0.5 in x, and the prop with it.
    let mid = c.skinned_positions(&c.pose_at(&c.clips[0], 0.5));
    assert!(mid[0].distance(Vec3::new(2.5, 1.0, 0.0)) < 1e-6, "{}", mid[0]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn unskinned_mesh_on_a_quantization_grid_is_bound_too() {
    // gltfpack stores a rigid mesh's positions on an integer grid and scales them back on its
    // node: here 2e-5 per axis (a 0.33 m prop on 16,383 steps), a determinant of 8e-15. The node
    // is not singular; it used to be skipped as if it were.
    let c = import(&with_prop(r#""translation": [2, 0, 0], "scale": [2e-5, 2e-5, 2e-5]"#)).unwrap();
    assert_eq!(c.warnings, Vec::<String>::new());
    assert_eq!(c.mesh.primitives.len(), 2);
    let corners: Vec<Vec3> = c.mesh.indices[..3].iter().map(|&i| c.mesh.positions[i as usize]).collect();
    let expected = [Vec3::new(2.0, 1.0, 0.0), Vec3::new(2.00002, 1.0, 0.0), Vec3::new(2.0, 1.00002, 0.0)];
    for (a, b) in corners.iter().zip(expected) {
        assert!(a.distance(b) < 1e-6, "{a} vs {b}");
    }
    assert!(c.mesh.indices[..3].iter().all(|&i| c.mesh.normals[i as usize] == Vec3::Z));
    let rest = c.skinned_positions(&c.skeleton.rest_pose());
    for (a, b) in rest.iter().zip(&c.mesh.positions) {
        assert!(a.distance(*b) < 1e-6, "{a} vs {b}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn strips_points_and_morph_targets() {
    let mut model = TinyModel::new();
    model.json["meshes"][0]["primitives"][0]["mode"] = Value::from(5); // TRIANGLE_STRIP
    let mut points = model.json["meshes"][0]["primitives"][0].clone();
    points["mode"] = Value::from(0);
    model.json["meshes"][0]["primitives"].as_array_mut().unwrap().push(points);
    let target: Value = serde_json::from_str(r#"[{"POSITION": 0}]"#).unwrap();
    model.json["meshes"][0]["primitives"][0]["targets"] = target;
    let c = import(&model).unwrap();
    assert_eq!(c.mesh.indices, vec![0, 1, 2]);
    // The morph target (the positions themselves as deltas) is imported, not dropped: vertex 0's
    // delta is zero and not stored.
    assert_eq!(c.morph_targets.len(), 1);
    let rows: Vec<Vec<_>> = (0..3).map(|v| c.mesh.morph.of(v).map(|e| e.1).collect()).collect();
    assert_eq!(rows, vec![vec![], vec![Vec3::X], vec![Vec3::Y]]);
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    assert_mentions(&c.warnings[0], &["primitive 1", "Points", "skipped"]);
}

/// With no scene marked as the default and nothing in scene 0, the first scene with a mesh is
/// shown, with a warning; a marked empty scene is still an error.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_empty_first_scene_gives_way_when_none_is_marked() {
    let mut model = TinyModel::new();
    model.json.as_object_mut().unwrap().remove("scene");
    let scenes = serde_json_value(r#"[{"nodes": []}, {"name": "props", "nodes": []}, {"nodes": [0, 2]}]"#);
    model.json["scenes"] = scenes;
    let c = import(&model).unwrap();
    assert_eq!(c.mesh.indices, vec![0, 1, 2]);
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    assert_mentions(&c.warnings[0], &["scene 0 has no mesh", "scene 2 is shown"]);
    model.json["scene"] = Value::from(0);
    assert_mentions(&error_of(&model), &["no triangle"]);
}

/// Triangles without area draw nothing and would stop the simplifier early: they are left out
/// with a warning, and a primitive of nothing else is skipped.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn triangles_without_area_are_left_out() {
    let mut model = TinyModel::new();
    let offset = model.bin.len();
    model.bin.extend([0u16, 1, 2, 0, 0, 1, 2, 2, 2].iter().flat_map(|i| i.to_le_bytes()));
    model.json["buffers"][0]["byteLength"] = Value::from(model.bin.len());
    let view = format!(r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": 18}}"#);
    model.json["bufferViews"].as_array_mut().unwrap().push(serde_json_value(&view));
    let accessor = r#"{"bufferView": 7, "componentType": 5123, "count": 9, "type": "SCALAR"}"#;
    model.json["accessors"].as_array_mut().unwrap().push(serde_json_value(accessor));
    model.json["meshes"][0]["primitives"][0]["indices"] = Value::from(7);
    let c = import(&model).unwrap();
    assert_eq!(c.mesh.indices, vec![0, 1, 2]);
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    assert_mentions(&c.warnings[0], &["primitive 0", "2 of its 3 triangles have no area", "left out"]);
    // Vertex 2 on the line through 0 and 1: nothing is left to show, and the message says why.
    model.put_f32s(tiny::POSITIONS + 24, &[2.0, 0.0, 0.0]);
    let message = error_of(&model);
    assert_mentions(&message, &["no triangle meshes to show", "primitive 0 has no triangle with an area"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn truncated_glb() {
    let glb = TinyModel::new().glb();
    for len in [0, 5, 12, 20, glb.len() / 2, glb.len() - 1] {
        let err = from_glb(&glb[..len]).unwrap_err().to_string();
        assert_mentions(&err, &["GLB"]);
    }
    let err = from_glb(&glb[..glb.len() - 1]).unwrap_err().to_string();
    assert_mentions(&err, &["truncated"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn random_bytes_and_bad_json() {
    let mut rng = SplitMix(7);
    for len in [1, 10, 100, 1000] {
        let bytes: Vec<u8> = (0..len).map(|_| rng.next_u64() as u8).collect();
        let err = from_bytes(&bytes, &mut |_| None).unwrap_err().to_string();
        assert_mentions(&err, &["JSON"]);
    }
    let err = from_gltf(br#"{"asset": {"version": "2.0"}, "nodes": [{"#, &mut |_| None).unwrap_err();
    assert_mentions(&err.to_string(), &["does not parse"]);
    let err =
        from_gltf(br#"{"asset": {"version": "2.0"}, "nodes": [{"mesh": 3}]}"#, &mut |_| None).unwrap_err();
    assert_mentions(&err.to_string(), &["invalid glTF", "nodes[0].mesh"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn out_of_range_vertex_index() {
    let mut model = TinyModel::new();
    model.bin[tiny::INDICES + 2..tiny::INDICES + 4].copy_from_slice(&7u16.to_le_bytes());
    assert_mentions(&error_of(&model), &["mesh 0 ('tri') primitive 0", "index 7", "out of range"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn out_of_range_joint_index() {
    let mut model = TinyModel::new();
    model.bin[tiny::JOINTS + 5] = 9; // vertex 1's second influence (weight 0.5)
    assert_mentions(&error_of(&model), &["primitive 0", "vertex 1", "joint 9", "2 joints"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn accessor_larger_than_its_buffer_view() {
    let mut model = TinyModel::new();
    model.json["accessors"][0]["count"] = Value::from(1000);
    let msg = error_of(&model);
    assert_mentions(
        &msg,
        &["accessor 0 (POSITION of mesh 0 ('tri') primitive 0)", "needs 12000 bytes", "has 36"],
    );
    // A stride larger than the view, and a stride smaller than an element.
    let mut model = TinyModel::new();
    model.json["bufferViews"][0]["byteStride"] = Value::from(16);
    assert_mentions(&error_of(&model), &["needs 44 bytes but buffer view 0 has 36"]);
    let mut model = TinyModel::new();
    model.json["bufferViews"][3]["byteStride"] = Value::from(8);
    assert_mentions(&error_of(&model), &["WEIGHTS_0", "byte stride of 8"]);
    // A buffer view past the end of its buffer.
    let mut model = TinyModel::new();
    model.json["bufferViews"][6]["byteLength"] = Value::from(64);
    assert_mentions(&error_of(&model), &["buffer view 6", "264 bytes"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn non_finite_values() {
    let mut model = TinyModel::new();
    model.put_f32s(tiny::POSITIONS + 12, &[f32::NAN]);
    assert_mentions(&error_of(&model), &["vertex 1", "non-finite position"]);
    let mut model = TinyModel::new();
    model.put_f32s(tiny::WEIGHTS + 16, &[f32::INFINITY]);
    assert_mentions(&error_of(&model), &["vertex 1", "weight inf"]);
    let mut model = TinyModel::new();
    model.put_f32s(tiny::INVERSE_BINDS + 64, &[f32::NAN]);
    assert_mentions(&error_of(&model), &["inverse bind matrices of skin 0", "non-finite"]);
    let mut model = TinyModel::new();
    model.put_f32s(tiny::TRANSLATIONS + 12, &[f32::NAN]);
    assert_mentions(
        &error_of(&model),
        &["animation 'clip 0' channel 0", "translation of node 'tip'", "non-finite"],
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn all_zero_weights() {
    let mut model = TinyModel::new();
    model.put_f32s(tiny::WEIGHTS, &[0.0]);
    assert_mentions(&error_of(&model), &["mesh 0 ('tri') primitive 0", "vertex 0", "all zero"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn node_cycles() {
    // tip -> root -> tip, reachable from the scene.
    let mut model = TinyModel::new();
    model.json["nodes"][1]["children"] = Value::from(vec![0]);
    assert_mentions(&error_of(&model), &["cycle"]);
    // A node that is its own child.
    let mut model = TinyModel::new();
    model.json["nodes"][1]["children"] = Value::from(vec![1]);
    assert_mentions(&error_of(&model), &["node 1 ('tip')", "its own child"]);
    // A cycle outside the scene that a skin joint hangs from.
    let mut model = TinyModel::new();
    let extra: Value = serde_json::from_str(r#"[{"children": [4]}, {"children": [3]}]"#).unwrap();
    model.json["nodes"].as_array_mut().unwrap().extend(extra.as_array().unwrap().iter().cloned());
    model.json["nodes"][4]["children"] = Value::from(vec![3, 0]);
    assert_mentions(&error_of(&model), &["cycle"]);
    // A node with two parents.
    let mut model = TinyModel::new();
    model.json["nodes"][2]["children"] = Value::from(vec![1]);
    assert_mentions(&error_of(&model), &["node 1 ('tip')", "child of both node 0 and node 2"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn absurd_counts() {
    for accessor in 0..7 {
        let mut model = TinyModel::new();
        // 2^30 fits a 32-bit usize (wasm32), so our own limit, not the JSON layer, must catch it.
        model.json["accessors"][accessor]["count"] = Value::from(1u64 << 30);
        let msg = error_of(&model);
        assert_mentions(&msg, &[&format!("accessor {accessor} ("), "more than the limit"]);
        // 2^40 does not fit in wasm32's usize: the JSON layer rejects it there, we do natively.
        model.json["accessors"][accessor]["count"] = Value::from(1u64 << 40);
        let msg = error_of(&model);
        assert!(msg.contains("count") || msg.contains("limit"), "{msg}");
    }
    // A sparse accessor without buffer view: zeros that no file bytes back.
    let mut model = TinyModel::new();
    let sparse: Value = serde_json::from_str(
        r#"{"count": 1, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 0}}"#,
    )
    .unwrap();
    model.json["accessors"][6] =
        serde_json::from_str(r#"{"componentType": 5126, "count": 10000000, "type": "VEC3"}"#).unwrap();
    model.json["accessors"][6]["sparse"] = sparse;
    assert_mentions(
        &error_of(&model),
        &["accessor 6 (key values of animation 'clip 0' channel 0)", "no buffer view"],
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn sparse_accessors_substitute_and_check_their_indices() {
    // Replace key value 1 of the animation with (0, 1, 0), the value at key 0, via sparse data
    // that reuses the position view (vertex 2 is (0, 1, 0)) and an index buffer of one u16 = 1.
    let mut model = TinyModel::new();
    let sparse: Value = serde_json::from_str(
        r#"{"count": 1, "indices": {"bufferView": 1, "byteOffset": 2, "componentType": 5123},
            "values": {"bufferView": 0, "byteOffset": 24}}"#,
    )
    .unwrap();
    model.json["accessors"][6]["sparse"] = sparse.clone();
    let c = import(&model).unwrap();
    let mid = c.skinned_positions(&c.pose_at(&c.clips[0], 0.5));
    assert_eq!(mid[2], Vec3::Y, "the clip no longer moves the tip");
    // Sparse index 2 is out of range for a two-key accessor.
    model.json["accessors"][6]["sparse"]["indices"]["byteOffset"] = Value::from(4);
    assert_mentions(&error_of(&model), &["accessor 6", "sparse index 2", "out of range"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn bad_animation_keys_and_missing_resources() {
    let mut model = TinyModel::new();
    model.put_f32s(tiny::TIMES, &[2.0]);
    model.json["animations"][0]["name"] = Value::from("wave");
    assert_mentions(
        &error_of(&model),
        &["animation 'wave' channel 0 (translation of node 'tip')", "backwards"],
    );
    let mut model = TinyModel::new();
    model.json["accessors"][6]["count"] = Value::from(1);
    assert_mentions(&error_of(&model), &["animation 'clip 0' channel 0", "2 key times but 1 values"]);
    // An external buffer the resolver does not have.
    let mut json = TinyModel::new().json;
    json["buffers"][0]["uri"] = Value::from("missing%20file.bin");
    let text = serde_json::to_vec(&json).unwrap();
    let err = from_gltf(&text, &mut |_| None).unwrap_err();
    assert_eq!(err, ImportError::MissingResource("missing file.bin".into()));
    assert_mentions(&err.to_string(), &["'missing file.bin'"]);
    // A buffer shorter than it says.
    let mut model = TinyModel::new();
    model.bin.truncate(100);
    assert_mentions(&error_of(&model), &["buffer 0 declares 264 bytes", "only 100"]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn two_skins_share_joints_and_keep_their_own_inverse_binds() {
    // A second node draws the same mesh with a second skin over the same joints, but without
    // inverse bind matrices (identity): (root, I) is shared, (tip, I) is a new skin joint.
    let mut model = TinyModel::new();
    model.json["scenes"][0]["nodes"] = serde_json_value("[0, 2, 3]");
    model.json["nodes"]
        .as_array_mut()
        .unwrap()
        .push(serde_json_value(r#"{"name": "tri2", "mesh": 0, "skin": 1}"#));
    model.json["skins"].as_array_mut().unwrap().push(serde_json_value(r#"{"joints": [0, 1]}"#));
    let c = import(&model).unwrap();
    assert_eq!(c.skeleton.joints.len(), 3, "{:?}", c.skeleton.joints);
    assert_eq!(c.mesh.vertex_count(), 6);
    assert_eq!(c.mesh.triangle_count(), 2);
    // The second copy's joints are remapped into the merged list: tip with identity is joint 2.
    assert_eq!(&c.mesh.joints[3..], &[[0, 0, 0, 0], [0, 2, 0, 0], [2, 0, 0, 0]]);
    let rest = c.skinned_positions(&c.skeleton.rest_pose());
    assert_eq!(&rest[..3], &c.mesh.positions[..3], "the first skin reproduces its bind pose");
    // Identity inverse bind on tip (at y = 1): the tip-bound corner lands one unit higher.
    assert_eq!(rest[5], Vec3::new(0.0, 2.0, 0.0));
}

fn serde_json_value(text: &str) -> Value {
    serde_json::from_str(text).unwrap()
}
