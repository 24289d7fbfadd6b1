//! Import of the three shared real models: counts, clip names and durations, skin invariants,
//! rest-pose skinning, and skinned positions at one animation time checked against an
//! independent computation.
//!
//! Expected counts come from /work/shared/models/README.md (read from the files' accessors) and
//! were re-checked by hand. Expected skinned positions come from tests/reference/skin_reference.py,
//! a numpy script that parses the GLB bytes itself and applies the glTF spec's sampling and
//! linear-blend-skinning formulas (see its docstring); it was run once and its output pasted here.

// The reference values are pasted verbatim from the script's output (6 decimals, some beyond f32).
#![allow(clippy::excessive_precision)]

use crate::common;

use clod_viewer::character::AlphaMode;
use clod_viewer::import::{from_bytes, from_glb, from_gltf};
use clod_viewer::Character;
use glam::Vec3;

fn load(name: &str) -> Option<Character> {
    let bytes = common::model_bytes(name)?;
    Some(from_glb(&bytes).unwrap_or_else(|e| panic!("{name}: {e}")))
}

fn bbox_diagonal(c: &Character) -> f32 {
    let (lo, hi) = c.mesh.bounds();
    (hi - lo).length()
}

/// Invariants every imported character satisfies.
fn check_invariants(name: &str, c: &Character) {
    let mesh = &c.mesh;
    let n = mesh.vertex_count();
    assert_eq!(mesh.normals.len(), n, "{name}");
    assert_eq!(mesh.joints.len(), n, "{name}");
    assert_eq!(mesh.weights.len(), n, "{name}");
    assert!(mesh.indices.iter().all(|&i| (i as usize) < n), "{name}: index out of range");
    assert!(mesh.positions.iter().all(|p| p.is_finite()), "{name}");
    assert!(mesh.normals.iter().all(|v| (v.length() - 1.0).abs() < 1e-4), "{name}: normals not unit");
    for (v, (w, j)) in mesh.weights.iter().zip(&mesh.joints).enumerate() {
        let sum: f32 = w.iter().sum();
        assert!((sum - 1.0).abs() < 1e-5, "{name}: vertex {v} weights sum to {sum}");
        assert!(w.windows(2).all(|p| p[0] >= p[1]), "{name}: vertex {v} weights not sorted: {w:?}");
        assert!(j.iter().all(|&j| (j as usize) < c.skeleton.joints.len()), "{name}: vertex {v} joints {j:?}");
    }
    // Material ranges cover the indices in order, without gaps.
    let mut next = 0;
    for range in &mesh.primitives {
        assert_eq!(range.first_index, next, "{name}");
        assert_eq!(range.index_count % 3, 0, "{name}");
        next += range.index_count;
        assert!(range.material.is_none_or(|m| m < c.materials.len()), "{name}");
    }
    assert_eq!(next as usize, mesh.indices.len(), "{name}");
    // Parent-first node order.
    for (i, node) in c.skeleton.nodes.iter().enumerate() {
        assert!(node.parent.is_none_or(|p| p < i), "{name}: node {i} before its parent");
    }
    assert!(c.skeleton.joints.iter().all(|j| j.node < c.skeleton.nodes.len()), "{name}");
}

/// Skinning at the rest pose reproduces the bind positions: for these three files the nodes'
/// rest transforms are the pose the inverse bind matrices were taken in.
fn check_rest_pose_is_bind_pose(name: &str, c: &Character) {
    let skinned = c.skinned_positions(&c.skeleton.rest_pose());
    // f32 round-off through a few matrix products: relative to the model's size.
    let tolerance = 1e-5 * bbox_diagonal(c);
    for (v, (s, p)) in skinned.iter().zip(&c.mesh.positions).enumerate() {
        assert!(s.distance(*p) <= tolerance, "{name}: vertex {v} moves at rest: {s} vs {p}");
    }
}

/// Skinned positions at `time` of `clip` at the given index-list corners, against the reference.
fn check_pinned(name: &str, c: &Character, clip: &str, time: f32, expected: &[(usize, [f32; 3])]) {
    let clip = c.clip(clip).unwrap_or_else(|| panic!("{name}: no clip {clip}"));
    let skinned = c.skinned_positions(&c.pose_at(clip, time));
    // The reference prints 6 decimals and computes in f64; f32 skinning differs by round-off.
    let tolerance = 2e-5 * bbox_diagonal(c) + 1e-5;
    for &(corner, want) in expected {
        let got = skinned[c.mesh.indices[corner] as usize];
        let want = Vec3::from_array(want);
        assert!(got.distance(want) <= tolerance, "{name} corner {corner}: {got} vs reference {want}");
    }
}

fn clip_summary(c: &Character) -> Vec<(String, f32)> {
    c.clips.iter().map(|clip| (clip.name.clone(), clip.duration())).collect()
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn cesium_man() {
    let Some(c) = load("CesiumMan.glb") else { return };
    assert_eq!(c.mesh.triangle_count(), 4672);
    assert_eq!(c.mesh.vertex_count(), 3273);
    assert_eq!(c.skeleton.joints.len(), 19);
    assert_eq!(clip_summary(&c), vec![("Anim_0".to_string(), 2.0)]);
    assert!(c.mesh.uvs.is_some() && c.mesh.colors.is_none());
    assert_eq!(c.materials.len(), 1);
    let texture = c.materials[0].base_color_texture.as_ref().expect("CesiumMan has a texture");
    assert_eq!(texture.mime_type, "image/jpeg");
    assert_eq!(&texture.bytes[..3], &[0xFF, 0xD8, 0xFF]);
    assert_eq!(c.materials[0].alpha_mode, AlphaMode::Opaque);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    check_invariants("CesiumMan", &c);
    check_rest_pose_is_bind_pose("CesiumMan", &c);
    // python3 tests/reference/skin_reference.py ../shared/models
    check_pinned(
        "CesiumMan",
        &c,
        "Anim_0",
        0.9,
        &[
            (0, [0.018380, 0.926506, 0.107029]),
            (7028, [0.082139, 0.587657, -0.377841]),
            (8778, [0.068970, 0.571363, -0.387915]),
        ],
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn fox_is_flat_shaded_and_its_corners_are_welded_where_they_agree() {
    let Some(c) = load("Fox.glb") else { return };
    assert_eq!(c.mesh.triangle_count(), 576);
    // 1,728 corners in the file and no NORMAL: each corner gets its face's normal (glTF
    // §3.7.2.1, flat normals), and no two faces are coplanar neighbours, so every corner stays
    // its own vertex. 434 distinct (position, uv, joints, weights) tuples (skin_reference.py):
    // the shading weld of the LOD build finds them again.
    assert_eq!(c.mesh.vertex_count(), 1728);
    for tri in c.mesh.indices.chunks_exact(3) {
        let [a, b, d] = [0, 1, 2].map(|k| c.mesh.positions[tri[k] as usize]);
        let face = (b - a).cross(d - a).normalize();
        assert!(tri.iter().all(|&v| c.mesh.normals[v as usize].abs_diff_eq(face, 1e-6)));
    }
    let materials = vec![0; 576];
    let weld = clod_viewer::clod::shading::ShadingWeld::new(&c.mesh, &materials);
    let mut welded = weld.representative.clone();
    welded.sort_unstable();
    welded.dedup();
    assert_eq!(welded.len(), 434);
    assert_eq!(c.skeleton.joints.len(), 24);
    let clips = clip_summary(&c);
    let names: Vec<&str> = clips.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["Survey", "Walk", "Run"]);
    // Last key times of the three clips (accessor max of their inputs).
    for ((_, got), want) in clips.iter().zip([3.4166667, 0.7083333, 1.1583333]) {
        assert!((got - want).abs() < 1e-6, "{got} vs {want}");
    }
    assert_eq!(c.materials[0].base_color_texture.as_ref().map(|t| t.mime_type.as_str()), Some("image/png"));
    check_invariants("Fox", &c);
    check_rest_pose_is_bind_pose("Fox", &c);
    check_pinned(
        "Fox",
        &c,
        "Walk",
        0.3,
        &[
            (0, [1.949880, 33.140650, -21.893862]),
            (1477, [-5.657524, 16.148934, 45.158279]),
            (1610, [-4.641578, 17.033455, 46.737293]),
        ],
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn rigged_simple() {
    let Some(c) = load("RiggedSimple.glb") else { return };
    assert_eq!(c.mesh.triangle_count(), 892);
    assert_eq!(c.mesh.vertex_count(), 960);
    assert_eq!(c.skeleton.joints.len(), 4);
    let clips = clip_summary(&c);
    assert_eq!(clips.len(), 1);
    assert_eq!(clips[0].0, "Anim_0_Armature");
    assert!((clips[0].1 - 6.6666665).abs() < 1e-6);
    // No materials: the primitive uses glTF's default material.
    assert!(c.materials.is_empty());
    assert_eq!(c.mesh.primitives[0].material, None);
    check_invariants("RiggedSimple", &c);
    check_rest_pose_is_bind_pose("RiggedSimple", &c);
    check_pinned(
        "RiggedSimple",
        &c,
        "Anim_0_Armature",
        1.3,
        &[
            (0, [1.000000, -0.019181, 0.030317]),
            (1267, [0.195090, 3.971054, -0.085955]),
            (2436, [-0.382683, 2.157554, -6.016068]),
        ],
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn gltf_json_with_external_buffer_matches_the_glb() {
    let Some(bytes) = common::model_bytes("CesiumMan.glb") else { return };
    let from_binary = from_glb(&bytes).unwrap();
    let (mut json, bin) = common::split_glb(&bytes);
    json["buffers"][0]["uri"] = serde_json::Value::from("Cesium%20Man.bin");
    let text = serde_json::to_vec(&json).unwrap();
    let mut asked = Vec::new();
    let mut resolve = |uri: &str| {
        asked.push(uri.to_string());
        (uri == "Cesium Man.bin").then(|| bin.clone())
    };
    let from_text = from_gltf(&text, &mut resolve).unwrap();
    assert_eq!(asked, ["Cesium Man.bin"], "the resolver gets the percent-decoded URI");
    assert_eq!(from_text, from_binary);
    // `from_bytes` sniffs JSON and GLB alike.
    assert_eq!(from_bytes(&text, &mut |_| Some(bin.clone())).unwrap(), from_binary);
    assert_eq!(from_bytes(&bytes, &mut |_| None).unwrap(), from_binary);
    // Without the file, the error names it.
    let err = from_gltf(&text, &mut |_| None).unwrap_err().to_string();
    assert!(err.contains("Cesium Man.bin"), "{err}");
}

/// `from_file` reads a `.gltf`'s buffer from its folder (native only: wasm32 has no files).
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn a_gltf_file_on_disk_reads_its_buffer_from_its_folder() {
    use clod_viewer::import::{from_file, ImportError};
    let Some(bytes) = common::model_bytes("CesiumMan.glb") else { return };
    let (mut json, bin) = common::split_glb(&bytes);
    json["buffers"][0]["uri"] = serde_json::Value::from("data/Cesium%20Man.bin");
    let folder = std::env::temp_dir().join(format!("clod-from-file-{}", std::process::id()));
    std::fs::create_dir_all(folder.join("data")).unwrap();
    let gltf = folder.join("man.gltf");
    std::fs::write(&gltf, serde_json::to_vec(&json).unwrap()).unwrap();
    std::fs::write(folder.join("data/Cesium Man.bin"), &bin).unwrap();
    std::fs::write(folder.join("man.glb"), &bytes).unwrap();

    let from_binary = from_glb(&bytes).unwrap();
    assert_eq!(from_file(&gltf).unwrap(), from_binary);
    assert_eq!(from_file(&folder.join("man.glb")).unwrap(), from_binary);
    std::fs::remove_file(folder.join("data/Cesium Man.bin")).unwrap();
    let missing = from_file(&gltf).unwrap_err();
    assert!(
        matches!(&missing, ImportError::MissingResource(uri) if uri.contains("Cesium Man.bin")),
        "{missing}"
    );
    let absent = from_file(&folder.join("absent.glb")).unwrap_err();
    assert!(
        matches!(&absent, ImportError::Unreadable { path, .. } if path.ends_with("absent.glb")),
        "{absent}"
    );
    std::fs::remove_dir_all(&folder).unwrap();
}
