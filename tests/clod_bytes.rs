//! The LOD chain as bytes (`clod::bytes`): round trips on the built-in character and the shared
//! models, the cursor over a decoded chain, every truncation and seeded mutations of a small
//! chain's bytes, tampered chains and a mismatched character.

use crate::common;

use clod_viewer::character::Character;
use clod_viewer::clod::bytes::{decode, encode, ClodBytesError, FORMAT_VERSION, SOURCE_TAG};
use clod_viewer::clod::{self, Clod, ClodOptions, SimplificationPose};
use clod_viewer::mesh::{compute_normals, PrimitiveRange, SkinnedMesh};
use clod_viewer::render::lod_source::LodSource;
use clod_viewer::skeleton::{Node, Skeleton, SkinJoint, Transform};
use clod_viewer::{import, PmCursor};
use glam::{Mat4, Vec2, Vec3, Vec4};

const BUILTIN: &[u8] = include_bytes!("../assets/character.glb");
const MODELS: [&str; 3] = ["CesiumMan.glb", "Fox.glb", "RiggedSimple.glb"];

fn build(character: &Character, options: &ClodOptions) -> Clod {
    clod::build(character, options, &mut |_| {}).expect("the test characters simplify")
}

/// A `size × size`-quad wavy grid with uvs, colours and two joints (left half on joint 0, right
/// half on joint 1, a blend in the middle column): small enough to decode every prefix of.
fn small_character(size: usize) -> Character {
    let side = size + 1;
    let mut positions = Vec::new();
    let (mut uvs, mut colors, mut joints, mut weights) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for j in 0..side {
        for i in 0..side {
            let (x, y) = (i as f32, j as f32);
            positions.push(Vec3::new(x, y, 0.3 * (x * 0.9).sin() * (y * 0.7).cos()));
            uvs.push(Vec2::new(x / size as f32, y / size as f32));
            colors.push(Vec4::new(x / size as f32, 0.5, y / size as f32, 1.0));
            let right = (i as f32 / size as f32).clamp(0.0, 1.0);
            joints.push([0, 1, 0, 0]);
            weights.push([1.0 - right, right, 0.0, 0.0]);
        }
    }
    let mut indices = Vec::new();
    for j in 0..size as u32 {
        for i in 0..size as u32 {
            let v = j * side as u32 + i;
            indices.extend([v, v + 1, v + side as u32 + 1, v, v + side as u32 + 1, v + side as u32]);
        }
    }
    let normals = compute_normals(&positions, &indices);
    let primitives =
        vec![PrimitiveRange { first_index: 0, index_count: indices.len() as u32, material: None }];
    let mesh = SkinnedMesh {
        positions,
        normals,
        uvs: Some(uvs),
        colors: Some(colors),
        joints,
        weights,
        indices,
        primitives,
        morph: Default::default(),
    };
    let node = |name: &str, parent| Node { name: name.into(), parent, rest: Transform::IDENTITY };
    let skeleton = Skeleton {
        nodes: vec![node("root", None), node("right", Some(0))],
        joints: vec![
            SkinJoint { node: 0, joint_from_bind: Mat4::IDENTITY },
            SkinJoint { node: 1, joint_from_bind: Mat4::IDENTITY },
        ],
    };
    let (clips, materials, morph_targets, warnings) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    Character { mesh, skeleton, clips, materials, morph_targets, warnings }
}

fn small_clod() -> (Character, Clod) {
    let character = small_character(6);
    let options = ClodOptions { level_triangles: Some(vec![72, 36, 16]), ..ClodOptions::default() };
    let clod = build(&character, &options);
    (character, clod)
}

/// Uses a chain as the viewer does, so a decoded chain that passed validation but breaks an
/// invariant panics here: every triangle count down and back up, the level source, the cursor
/// level and skinned positions of every level.
fn walk(character: &Character, clod: &Clod) {
    let pm = &clod.apm.pm;
    let mut cursor = pm.cursor();
    let full = pm.triangle_count_after(0);
    for triangles in (0..=full).rev().chain(0..=full) {
        cursor.set_triangle_count(triangles);
        let (indices, vertices) = (cursor.indices(), cursor.vertices());
        assert!(indices.iter().all(|&i| (i as usize) < vertices.len()));
        assert!(vertices.iter().all(|&v| (v as usize) < pm.vertex_total()));
    }
    // The slider's geomorph: a state paired with its ancestors in the coarsest state.
    let last = pm.collapse_count();
    let mut coarse_cursor = pm.cursor();
    coarse_cursor.set_collapses(last);
    let coarse = LodSource::from_cursor(character, clod, &coarse_cursor, last);
    let coarse_vertices: std::collections::HashSet<_> =
        coarse.vertices.iter().map(|v| bytemuck::bytes_of(&v.fine).to_vec()).collect();
    cursor.set_triangle_count(full / 2);
    let fine = LodSource::from_cursor(character, clod, &cursor, last);
    assert_eq!(fine.indices, LodSource::from_cursor(character, clod, &cursor, 0).indices, "one index buffer");
    assert!(
        fine.vertices.iter().all(|v| coarse_vertices.contains(bytemuck::bytes_of(&v.coarse))),
        "every ancestor is a vertex of the coarser state"
    );
    let source = LodSource::from_clod(character, clod);
    assert_eq!(source.levels.len(), clod.levels.len());
    // Geomorphs that skip levels chain the ancestor tables; one step is the level's own pairs.
    for i in 0..source.levels.len() - 1 {
        // Bytes, not floats: a mutated input may carry NaN weights, which compare unequal.
        let step = source.morph_vertices(i, i + 1).expect("the next level");
        let own: &[u8] = bytemuck::cast_slice(&source.levels[i].vertices);
        assert!(bytemuck::cast_slice::<_, u8>(&step) == own, "level {i}: one step is the level's own pairs");
        let last = source.levels.len() - 1;
        let skip = source.morph_vertices(i, last).expect("a coarser level");
        for (k, pair) in skip.iter().enumerate() {
            let a = clod.levels[i..last].iter().fold(k as u32, |v, level| level.ancestors[v as usize]);
            let expected = &source.levels[last].vertices[a as usize].fine;
            assert!(bytemuck::bytes_of(&pair.coarse) == bytemuck::bytes_of(expected), "level {i} vertex {k}");
        }
    }
    assert_eq!(source.morph_vertices(1, 1), None);
    let skin = vec![Mat4::IDENTITY; character.skeleton.joints.len()];
    for level in 0..clod.levels.len() {
        assert_eq!(clod.level_skinned_positions(level, &skin).len(), clod.levels[level].vertices.len());
    }
}

/// The same mesh at several triangle counts from the decoded and the original chain.
fn same_cursor_meshes(original: &Clod, decoded: &Clod) {
    let full = original.apm.pm.triangle_count_after(0);
    let (mut a, mut b): (PmCursor, PmCursor) = (original.apm.pm.cursor(), decoded.apm.pm.cursor());
    for triangles in [full, full * 3 / 4, full / 3, full / 10, 0, full / 2] {
        assert_eq!(a.set_triangle_count(triangles), b.set_triangle_count(triangles));
        assert_eq!(a.indices(), b.indices(), "indices at {triangles} triangles");
        assert_eq!(a.vertices(), b.vertices(), "vertices at {triangles} triangles");
    }
}

/// Checks the round trip and prints the encoded size (against the `.glb`'s, if there is one).
fn round_trip(name: &str, glb_len: Option<usize>, character: &Character, clod: &Clod) {
    let bytes = encode(clod);
    assert_eq!(&bytes[..4], b"CLOD");
    assert_eq!(bytes[4..8], FORMAT_VERSION.to_le_bytes());
    let decoded = decode(&bytes, character).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(decoded == *clod, "{name}: the decoded chain differs from the built one");
    assert_eq!(encode(&decoded), bytes, "{name}: re-encoding gives other bytes");
    same_cursor_meshes(clod, &decoded);
    assert_eq!(LodSource::from_clod(character, &decoded), LodSource::from_clod(character, clod));
    let versus_glb = glb_len.map_or(String::new(), |glb| {
        // Issue 15: the transferred (and cached) chain is at most twice its file.
        let ratio = bytes.len() as f64 / glb as f64;
        assert!(ratio <= 2.0, "{name}: the chain is {ratio:.2} × its .glb");
        format!(" ({ratio:.2} × the {glb} byte glb)")
    });
    println!(
        "{name}: {} triangles, {} vertex ids, {} collapses, {} levels: {} bytes encoded{versus_glb}",
        character.mesh.triangle_count(),
        clod.apm.pm.vertex_total(),
        clod.apm.pm.collapse_count(),
        clod.levels.len(),
        bytes.len(),
    );
}

/// The tag of the sources that the page's chain cache keys on (`build.rs`).
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_source_tag_is_sixteen_lowercase_hex_digits() {
    assert_eq!(SOURCE_TAG.len(), 16, "{SOURCE_TAG}");
    assert!(SOURCE_TAG.bytes().all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b)), "{SOURCE_TAG}");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn builtin_character_round_trips() {
    let character = import::from_glb(BUILTIN).expect("the built-in character imports");
    let clod = build(&character, &ClodOptions::default());
    round_trip("assets/character.glb", Some(BUILTIN.len()), &character, &clod);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn generated_robot_and_parts_round_trip() {
    // The robot's closed parts go away whole (tetrahedron, two-sided sheet, nothing) and its
    // facet corners are welded; the parts' plates have open borders.
    for (name, glb) in [
        ("assets/robot.glb", include_bytes!("../assets/robot.glb").as_slice()),
        ("assets/parts.glb", include_bytes!("../assets/parts.glb").as_slice()),
    ] {
        let character = import::from_glb(glb).expect("the generated characters import");
        let clod = build(&character, &ClodOptions::default());
        round_trip(name, Some(glb.len()), &character, &clod);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_shared_model_round_trips() {
    for name in MODELS {
        let Some(glb) = common::model_bytes(name) else { continue };
        let character = import::from_glb(&glb).expect("shared models import");
        // One model simplified in a clip frame, so the pose's clip name goes through the bytes.
        let pose = match name {
            "RiggedSimple.glb" => {
                SimplificationPose::ClipFrame { clip: character.clips[0].name.clone(), time: 0.4 }
            }
            _ => ClodOptions::default().pose,
        };
        let clod = build(&character, &ClodOptions { pose, ..ClodOptions::default() });
        round_trip(name, Some(glb.len()), &character, &clod);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn small_chain_round_trips_and_walks() {
    let (character, clod) = small_clod();
    let (levels, collapses) = (clod.levels.len(), clod.apm.pm.collapse_count());
    assert!(levels == 3 && collapses > 25, "a chain worth encoding: {levels} levels, {collapses} collapses");
    round_trip("6 × 6 grid", None, &character, &clod);
    walk(&character, &decode(&encode(&clod), &character).unwrap());
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_truncation_is_an_error() {
    let (character, clod) = small_clod();
    let bytes = encode(&clod);
    for end in 0..bytes.len() {
        match decode(&bytes[..end], &character) {
            Err(ClodBytesError::Truncated { .. }) => {}
            other => panic!("{end} of {} bytes: expected Truncated, got {other:?}", bytes.len()),
        }
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert_eq!(decode(&longer, &character).unwrap_err(), ClodBytesError::TrailingBytes { count: 1 });
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn seeded_mutations_never_panic() {
    let (character, clod) = small_clod();
    let bytes = encode(&clod);
    let mut rng = common::SplitMix(0x0C10_DB17);
    let (mut accepted, mut rejected) = (0, 0);
    for _ in 0..400 {
        let mut mutated = bytes.clone();
        for _ in 0..1 + rng.below(3) {
            // Words at 4-byte offsets are the fields (everything is 4-byte aligned except joints);
            // small values make plausible but wrong ids, single bits wrong floats and lengths.
            let at = 4 * rng.below(mutated.len() / 4);
            let word = u32::from_le_bytes(mutated[at..at + 4].try_into().unwrap());
            let new = match rng.below(4) {
                0 => rng.below(200) as u32,
                1 => word ^ (1 << rng.below(32)),
                2 => word.wrapping_add(1),
                _ => word.wrapping_sub(1),
            };
            mutated[at..at + 4].copy_from_slice(&new.to_le_bytes());
        }
        match decode(&mutated, &character) {
            Ok(decoded) => {
                walk(&character, &decoded);
                accepted += 1;
            }
            Err(_) => rejected += 1,
        }
    }
    println!("mutations: {accepted} decoded (and walked), {rejected} rejected");
    assert!(rejected > 100, "most mutations of ids and counts are caught, got {rejected} of 400");
}

/// Encodes a tampered copy of the small chain and returns the decoder's answer.
fn decode_tampered(tamper: impl FnOnce(&mut Clod)) -> ClodBytesError {
    let (character, mut clod) = small_clod();
    tamper(&mut clod);
    decode(&encode(&clod), &character).expect_err("the tampered chain is rejected")
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn tampered_chains_name_their_problem() {
    use ClodBytesError::*;
    let (character, clod) = small_clod();
    let bytes = encode(&clod);
    let n = clod.apm.pm.input_vertex_count;
    let total = clod.apm.pm.vertex_total();

    let mut bad = bytes.clone();
    bad[0] = b'X';
    assert_eq!(decode(&bad, &character).unwrap_err(), BadMagic { found: *b"XLOD" });
    let mut bad = bytes.clone();
    bad[4..8].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    let error = decode(&bad, &character).unwrap_err();
    assert_eq!(error, UnsupportedVersion { found: FORMAT_VERSION + 1, supported: FORMAT_VERSION });
    assert!(
        error.to_string().contains(&format!("version {} is not supported", FORMAT_VERSION + 1)),
        "{error}"
    );

    // An array count far beyond the bytes: refused before anything is allocated.
    let mut bad = bytes.clone();
    // Header (8), character (16), multi-pose tag and u64 (12), weight rule (4), level requests
    // (4 + 8 each), three progressive-mesh scalars (12).
    let triangle_source = 8 + 16 + 12 + 4 + 4 + 8 * clod.levels.len() + 12;
    let triangles = character.mesh.triangle_count() as u32;
    assert_eq!(bad[triangle_source..triangle_source + 4], triangles.to_le_bytes());
    bad[triangle_source..triangle_source + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(decode(&bad, &character).unwrap_err(), Truncated { field: "triangle_source", .. }));

    // The build's choices.
    let error = decode_tampered(|c| c.levels.swap(1, 2));
    let reason = "requests are positive and decreasing";
    assert_eq!(error, Inconsistent { field: "level requests", index: 2, reason });
    let error = decode_tampered(|c| c.levels[2].requested_triangles = 0);
    assert_eq!(error, Inconsistent { field: "level requests", index: 2, reason });
    let error = decode_tampered(|c| c.levels.clear());
    assert_eq!(error, LengthMismatch { field: "level requests", found: 0, expected: 1 });
    let error =
        decode_tampered(|c| c.pose = SimplificationPose::ClipFrame { clip: "Nope".into(), time: 0.0 });
    assert_eq!(error, UnknownClip { name: "Nope".into() });

    // The progressive mesh's decisions.
    let error = decode_tampered(|c| c.apm.pm.positions[n + 1].y = f32::NAN);
    assert_eq!(error, NonFinite { field: "positions", index: n + 1 });
    // (In the bytes: the fingerprint is computed from the chain's own triangles.)
    let mut bad = bytes.clone();
    let first = triangle_source + 4;
    bad.copy_within(first..first + 4, first + 4);
    let error = decode(&bad, &character).unwrap_err();
    assert_eq!(
        error,
        Inconsistent { field: "triangle_source", index: 1, reason: "an input triangle appears twice" }
    );
    let error = decode_tampered(|c| {
        let x = c.apm.pm.input_vertex_count + 3;
        c.apm.pm.survivor_source[x] =
            (0..x as u32).find(|&v| c.apm.pm.parent[v as usize] != x as u32).unwrap();
    });
    assert!(matches!(error, Inconsistent { field: "survivor_source", .. }), "{error}");
    // A parent pointing back down would make ancestor walks loop forever.
    let error = decode_tampered(|c| {
        let child = c.apm.pm.parent.iter().position(|&p| p != u32::MAX).unwrap();
        let p = c.apm.pm.parent[child] as usize;
        c.apm.pm.parent[p] = child as u32;
    });
    assert!(matches!(error, Inconsistent { field: "parent", .. }), "{error}");
    let error = decode_tampered(|c| c.apm.pm.survivor_source[n] = n as u32);
    let reason = "created vertices inherit from a smaller id";
    assert_eq!(error, Inconsistent { field: "survivor_source", index: n, reason });
    let error = decode_tampered(|c| c.apm.pm.vertex_slot[1] = c.apm.pm.vertex_slot[0]);
    assert_eq!(
        error,
        Inconsistent { field: "vertex_slot", index: 1, reason: "two input vertices share a slot" }
    );
    // The last corner change sends its corner to the last input slot, dead by then: it is the
    // last word of the bytes.
    let mut bad = bytes.clone();
    let at = bad.len() - 4;
    assert_eq!(bad[at..], clod.apm.pm.corner_changes().last().unwrap().to_slot.to_le_bytes());
    bad[at..].copy_from_slice(&(n as u32 - 1).to_le_bytes());
    let error = decode(&bad, &character).unwrap_err();
    assert!(matches!(error, Inconsistent { field: "collapses", .. }), "a corner on a dead slot: {error}");
    let error = decode_tampered(|c| c.apm.pm.collapses[3].triangles_after += 10);
    assert!(matches!(error, Inconsistent { field: "collapses", index: 3, .. }), "{error}");
    let error = decode_tampered(|c| c.apm.pm.collapses[0].vertices_after = 0);
    let reason = "triangle and slot counts never grow";
    assert_eq!(error, Inconsistent { field: "collapses", index: 1, reason });
    // A slot dropped one step early, while its vertex is still in use.
    let collapses = &clod.apm.pm.collapses;
    let drop = (1..collapses.len()).find(|&s| collapses[s].vertices_after < collapses[s - 1].vertices_after);
    let drop = drop.expect("some step merges two chains");
    let error = decode_tampered(|c| {
        c.apm.pm.collapses[drop - 1].vertices_after = c.apm.pm.collapses[drop].vertices_after
    });
    let reason = "a live triangle uses a slot past the live ones";
    assert_eq!(error, Inconsistent { field: "collapses", index: drop - 1, reason });
    // One more created vertex claimed by the first step than there are.
    let error = decode_tampered(|c| c.apm.pm.collapses[0].new_vertex_count += (total - n) as u32);
    let reason = "more created vertices than survivors";
    assert_eq!(error, Inconsistent { field: "collapses", index: 0, reason });
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn another_character_is_named_as_the_mismatch() {
    let (character, clod) = small_clod();
    let bytes = encode(&clod);
    let bigger = small_character(7);
    let error = decode(&bytes, &bigger).unwrap_err();
    assert_eq!(error, ClodBytesError::CharacterMismatch { what: "vertices", bytes: 49, character: 64 });
    assert!(error.to_string().contains("49 vertices; this character has 64"), "{error}");

    // Same counts, different data: one vertex moved, one triangle flipped, the colours gone.
    let mut moved = character.clone();
    moved.mesh.positions[5].z += 0.5;
    let mut flipped = character.clone();
    flipped.mesh.indices.swap(0, 1);
    let mut no_colours = character.clone();
    no_colours.mesh.colors = None;
    for other in [moved, flipped, no_colours] {
        let error = decode(&bytes, &other).unwrap_err();
        assert_eq!(error, ClodBytesError::OtherCharacter);
        assert!(error.to_string().contains("built for another character"), "{error}");
    }

    // A real model's chain against the built-in character.
    if let Some(glb) = common::model_bytes("RiggedSimple.glb") {
        let simple = import::from_glb(&glb).unwrap();
        let options = ClodOptions { level_triangles: Some(vec![892, 200]), ..ClodOptions::default() };
        let bytes = encode(&build(&simple, &options));
        let builtin = import::from_glb(BUILTIN).unwrap();
        let error = decode(&bytes, &builtin).unwrap_err();
        assert!(
            matches!(error, ClodBytesError::CharacterMismatch { what: "vertices", bytes: 960, .. }),
            "{error}"
        );
    }
}
