//! The built-in character (assets/character.glb, made by tools/make-character) through the
//! project's importer: it imports cleanly, matches the counts and clips stated in
//! assets/README.md (parsed from its tables, so the document and the asset cannot drift apart),
//! carries normalized skin weights, a closed surface, a UV seam and vertex colours, and stays in
//! one piece when skinned through every clip.

use crate::common;

use clod_viewer::import::from_glb;
use clod_viewer::Character;
use glam::Vec3;

const GLB: &[u8] = include_bytes!("../assets/character.glb");
const README: &str = include_str!("../assets/README.md");

fn character() -> Character {
    from_glb(GLB).unwrap_or_else(|e| panic!("the built-in character does not import: {e}"))
}

/// The body rows of every Markdown table in the README with `columns` cells, trimmed.
fn table_rows(columns: usize) -> Vec<Vec<&'static str>> {
    README
        .lines()
        .filter(|l| l.starts_with('|'))
        .map(|l| l.trim().trim_matches('|').split('|').map(str::trim).collect::<Vec<_>>())
        .filter(|cells| cells.len() == columns && !cells[0].starts_with("---"))
        .collect()
}

/// The value of a row of the README's "Quantity | Value" table.
fn quantity(name: &str) -> f64 {
    let row = table_rows(2).into_iter().find(|r| r[0] == name);
    let value = row.unwrap_or_else(|| panic!("assets/README.md states no `{name}`"))[1];
    value.parse().unwrap_or_else(|_| panic!("`{name}` in assets/README.md is not a number: {value}"))
}

/// Number of distinct vertex positions (bit-identical positions counted once).
fn welded(positions: &[Vec3], indices: &[u32]) -> (Vec<u32>, usize) {
    let key = |v: u32| positions[v as usize].to_array().map(f32::to_bits);
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_by_key(|&v| (key(v), v));
    let mut canonical = vec![0u32; positions.len()];
    let mut distinct = 0;
    for (i, &v) in order.iter().enumerate() {
        if i == 0 || key(order[i - 1]) != key(v) {
            distinct += 1;
            canonical[v as usize] = v;
        } else {
            canonical[v as usize] = canonical[order[i - 1] as usize];
        }
    }
    (indices.iter().map(|&i| canonical[i as usize]).collect(), distinct)
}

fn mean_edge_length(positions: &[Vec3], indices: &[u32]) -> f64 {
    let mut sum = 0.0f64;
    for t in indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            sum += f64::from(positions[a as usize].distance(positions[b as usize]));
        }
    }
    sum / indices.len() as f64
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn imports_with_the_counts_stated_in_the_readme() {
    let c = character();
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    assert_eq!(GLB.len() as f64, quantity("file size (bytes)"));
    assert_eq!(c.mesh.vertex_count() as f64, quantity("vertices"));
    assert_eq!(c.mesh.triangle_count() as f64, quantity("triangles"));
    assert_eq!(c.skeleton.joints.len() as f64, quantity("joints"));
    assert_eq!(c.mesh.primitives.len() as f64, quantity("primitives"));
    assert_eq!(c.materials.len() as f64, quantity("materials"));
    assert_eq!(c.clips.len() as f64, quantity("clips"));
    let (_, distinct) = welded(&c.mesh.positions, &c.mesh.indices);
    assert_eq!(distinct as f64, quantity("distinct positions"));
    let (lo, hi) = c.mesh.bounds();
    assert!((hi.y - lo.y - quantity("height (m)") as f32).abs() < 5e-3, "height {}", hi.y - lo.y);
    assert!(lo.y.abs() < 1e-3, "the character stands on y = 0, not {}", lo.y);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn primitives_and_materials_match_the_readme() {
    let c = character();
    let rows = table_rows(4).into_iter().filter(|r| r[0] != "Material").collect::<Vec<_>>();
    assert_eq!(rows.len(), c.mesh.primitives.len());
    for (row, prim) in rows.iter().zip(&c.mesh.primitives) {
        let material = &c.materials[prim.material.expect("every primitive has a material")];
        assert_eq!(material.name, row[0]);
        let colour: Vec<f32> = row[1].split(' ').map(|v| v.parse().unwrap()).collect();
        let factor = material.base_color_factor;
        assert!(Vec3::from_slice(&colour).abs_diff_eq(factor.truncate(), 1e-6), "{}: {factor}", row[0]);
        assert_eq!(prim.index_count / 3, row[2].parse::<u32>().unwrap(), "{} triangles", row[0]);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn clips_match_the_readme() {
    let c = character();
    let rows = table_rows(6).into_iter().filter(|r| r[0] != "Clip").collect::<Vec<_>>();
    assert_eq!(rows.len(), c.clips.len());
    for row in rows {
        let clip = c.clip(row[0]).unwrap_or_else(|| panic!("no clip {}", row[0]));
        assert!((clip.duration() - row[1].parse::<f32>().unwrap()).abs() < 1e-5, "{} duration", row[0]);
        assert_eq!(clip.channels().len(), row[4].parse::<usize>().unwrap(), "{} channels", row[0]);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn skin_weights_are_normalized_and_in_range() {
    let c = character();
    let joints = c.skeleton.joints.len();
    for (v, (w, j)) in c.mesh.weights.iter().zip(&c.mesh.joints).enumerate() {
        let sum: f32 = w.iter().sum();
        assert!((sum - 1.0).abs() < 1e-5, "vertex {v}: weights sum to {sum}");
        assert!(w.iter().all(|&x| x >= 0.0), "vertex {v}: negative weight {w:?}");
        assert!(j.iter().zip(w).all(|(&j, &w)| w == 0.0 || (j as usize) < joints), "vertex {v}: {j:?}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn surface_is_closed_once_welded_and_has_a_uv_seam() {
    let c = character();
    let (indices, _) = welded(&c.mesh.positions, &c.mesh.indices);
    // Closed and consistently oriented: every directed edge appears once, and so does its reverse.
    let mut edges: Vec<(u32, u32)> =
        indices.chunks_exact(3).flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]).collect();
    edges.sort_unstable();
    assert!(edges.windows(2).all(|w| w[0] != w[1]), "an edge is used twice in the same direction");
    let open = edges.iter().filter(|&&(a, b)| edges.binary_search(&(b, a)).is_err()).count();
    assert_eq!(open, 0, "edges without a reverse twin");

    // The seam is in TEXCOORD_0, which no material of the file samples: the importer leaves it
    // out (it draws nothing), so the seam is read from a copy whose materials sample it.
    assert!(c.mesh.uvs.is_none(), "no texture samples TEXCOORD_0");
    assert!(c.mesh.colors.is_some(), "COLOR_0 is imported");
    let (mut json, bin) = common::split_glb(GLB);
    for material in json["materials"].as_array_mut().expect("materials") {
        material["pbrMetallicRoughness"]["baseColorTexture"] = value(r#"{"index": 0}"#);
    }
    json["textures"] = value(r#"[{"source": 0}]"#);
    json["images"] = value(r#"[{"uri": "data:image/png;base64,iVBORw0KGgo="}]"#);
    let textured = from_glb(&common::TinyModel { json, bin }.glb()).expect("the textured copy imports");
    assert_eq!(textured.mesh.positions, c.mesh.positions);
    // The seam: within a primitive, vertices sharing a position whose u differs by exactly 1.
    let uvs = textured.mesh.uvs.as_ref().expect("TEXCOORD_0 is imported under a texture");
    let mut seam = 0;
    for prim in &c.mesh.primitives {
        let range = prim.first_index as usize..(prim.first_index + prim.index_count) as usize;
        let mut verts: Vec<u32> = c.mesh.indices[range].to_vec();
        verts.sort_unstable();
        verts.dedup();
        verts.sort_by_key(|&v| (c.mesh.positions[v as usize].to_array().map(f32::to_bits), v));
        for w in verts.windows(2) {
            let (a, b) = (w[0] as usize, w[1] as usize);
            let du = (uvs[a].x - uvs[b].x).abs();
            if c.mesh.positions[a] == c.mesh.positions[b] && (du - 1.0).abs() < 1e-6 {
                seam += 1;
            }
        }
    }
    assert_eq!(seam as f64, quantity("seam vertices"));
}

fn value(json: &str) -> serde_json::Value {
    serde_json::from_str(json).expect("valid JSON")
}

/// Frames sampled per clip: enough to catch a bad key anywhere in a few-second clip.
const FRAMES: usize = 24;

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_clip_samples_finite_transforms() {
    let c = character();
    for clip in &c.clips {
        for f in 0..=FRAMES {
            let time = clip.duration() * f as f32 / FRAMES as f32;
            let pose = c.pose_at(clip, time);
            for (n, t) in pose.local.iter().enumerate() {
                let finite = t.translation.is_finite() && t.rotation.is_finite() && t.scale.is_finite();
                assert!(finite, "{} at {time}s: node {n} has {t:?}", clip.name);
                assert!((t.rotation.length() - 1.0).abs() < 1e-4, "{} at {time}s: node {n}", clip.name);
            }
            let skin = c.skeleton.pose_skin_matrices(&pose);
            assert!(skin.iter().all(|m| m.is_finite()), "{} at {time}s", clip.name);
        }
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn skinning_through_every_clip_keeps_the_body_in_one_piece() {
    let c = character();
    let (lo, hi) = c.mesh.bounds();
    let height = hi.y - lo.y;
    let bind_edge = mean_edge_length(&c.mesh.positions, &c.mesh.indices);
    // The rest pose reproduces the bind positions (inverse bind matrices match the nodes).
    let rest = c.skinned_positions(&c.skeleton.rest_pose());
    let drift = rest.iter().zip(&c.mesh.positions).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    assert!(drift < 1e-4, "rest pose moves a vertex by {drift} m");
    for clip in &c.clips {
        let mut moved = 0.0f32;
        for f in 0..=FRAMES {
            let time = clip.duration() * f as f32 / FRAMES as f32;
            let posed = c.skinned_positions(&c.pose_at(clip, time));
            for (p, q) in posed.iter().zip(&c.mesh.positions) {
                assert!(p.is_finite(), "{} at {time}s", clip.name);
                let d = p.distance(*q);
                assert!(d < height, "{} at {time}s: a vertex moved {d} m", clip.name);
                moved = moved.max(d);
            }
            let ratio = mean_edge_length(&posed, &c.mesh.indices) / bind_edge;
            assert!((0.5..=2.0).contains(&ratio), "{} at {time}s: mean edge length ×{ratio}", clip.name);
        }
        // Every clip visibly moves something (more than 10 cm somewhere).
        assert!(moved > 0.1, "{} barely moves: {moved} m", clip.name);
    }
}
