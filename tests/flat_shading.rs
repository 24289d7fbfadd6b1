//! Flat shading: a faceted mesh simplifies along its faces (normal seams are not constraints), and
//! the renderer's levels carry each triangle's face normal at both ends of a geomorph.

use crate::common;

use clod_viewer::clod::{self, shading::face_normal, ClodOptions, SimplificationPose};
use clod_viewer::mesh::PrimitiveRange;
use clod_viewer::render::lod_source::LodSource;
use clod_viewer::skeleton::{Node, SkinJoint, Transform};
use clod_viewer::{Character, Skeleton, SkinnedMesh};
use glam::{Mat4, Vec3};

/// A flat-shaded box `4 × 1 × 1` of unit facets: every face has its own vertices (the long faces
/// 5 × 2 each, the end caps 4 each: 48 vertices), 36 triangles, normals the face normals, one
/// joint.
fn flat_box_strip() -> Character {
    let mut mesh = SkinnedMesh::default();
    // A face: origin, the long axis `u` (4 units, 4 facets) and the short axis `v` (1 unit).
    let mut face = |origin: Vec3, u: Vec3, v: Vec3, segments: u32| {
        let normal = u.cross(v).normalize();
        let base = mesh.positions.len() as u32;
        for i in 0..=segments {
            for j in 0..2 {
                mesh.positions.push(origin + u * (i as f32 / segments as f32) + v * j as f32);
                mesh.normals.push(normal);
            }
        }
        for i in 0..segments {
            let (a, b, c, d) = (base + 2 * i, base + 2 * i + 2, base + 2 * i + 3, base + 2 * i + 1);
            mesh.indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
    };
    let (x, y, z) = (Vec3::X * 4.0, Vec3::Y, Vec3::Z);
    face(Vec3::Y, x, -y, 4); // z = 0, normal −z
    face(Vec3::ZERO, x, z, 4); // y = 0, normal −y
    face(Vec3::Y + Vec3::Z, x, -z, 4); // y = 1, normal +y
    face(Vec3::Z, x, y, 4); // z = 1, normal +z
    face(Vec3::ZERO, z, y, 1); // x = 0, normal −x
    face(Vec3::X * 4.0, y, z, 1); // x = 4, normal +x
    let n = mesh.positions.len();
    mesh.joints = vec![[0; 4]; n];
    mesh.weights = vec![[1.0, 0.0, 0.0, 0.0]; n];
    mesh.primitives =
        vec![PrimitiveRange { first_index: 0, index_count: mesh.indices.len() as u32, material: None }];
    let rest = Transform { translation: Vec3::ZERO, rotation: glam::Quat::IDENTITY, scale: Vec3::ONE };
    let skeleton = Skeleton {
        nodes: vec![Node { name: "root".into(), parent: None, rest }],
        joints: vec![SkinJoint { node: 0, joint_from_bind: Mat4::IDENTITY }],
    };
    Character {
        mesh,
        skeleton,
        clips: Vec::new(),
        materials: Vec::new(),
        morph_targets: Vec::new(),
        warnings: Vec::new(),
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn flat_box_strip_collapses_along_its_faces_to_its_corners() {
    let character = flat_box_strip();
    assert_eq!((character.mesh.vertex_count(), character.mesh.triangle_count()), (48, 36));
    // Each normal really is its triangle's face normal (the fixture's winding is outward).
    for t in character.mesh.indices.chunks_exact(3) {
        let p = |k: usize| character.mesh.positions[t[k] as usize];
        assert_eq!(face_normal(p(0), p(1), p(2)), Some(character.mesh.normals[t[0] as usize]));
    }
    let options = ClodOptions {
        pose: SimplificationPose::Bind,
        level_triangles: Some(vec![36, 12]),
        ..ClodOptions::default()
    };
    let built = clod::build(&character, &options, &mut |_| {}).expect("the box simplifies");
    assert_eq!(built.levels.len(), 2);
    // The twelve vertices along the long edges cost nothing to remove (they lie on two planes'
    // line); the eight corners stay: the coarse level is the box itself.
    let coarse = &built.levels[1];
    assert_eq!(coarse.triangle_count(), 12);
    let mut corners: Vec<[i32; 3]> = coarse
        .indices
        .iter()
        .map(|&v| {
            built.apm.bind_positions[coarse.vertices[v as usize] as usize]
                .to_array()
                .map(|c| c.round() as i32)
        })
        .collect();
    corners.sort();
    corners.dedup();
    let expected: Vec<[i32; 3]> = (0..8).map(|i| [4 * (i >> 2 & 1), i >> 1 & 1, i & 1]).collect::<Vec<_>>();
    assert_eq!(corners, expected);
    for &v in &coarse.vertices {
        let p = built.apm.bind_positions[v as usize];
        assert_eq!(p, p.round(), "vertex {v} left the corners: {p}");
    }

    // The renderer's levels: every corner carries its triangle's face normal, at both ends; the
    // box keeps its planes, so a geomorph's ends agree.
    let source = LodSource::from_clod(&character, &built);
    for (i, level) in source.levels.iter().enumerate() {
        for t in level.indices.chunks_exact(3) {
            let fine = |k: usize| Vec3::from(level.vertices[t[k] as usize].fine.position);
            let normal = face_normal(fine(0), fine(1), fine(2)).expect("no degenerate triangle").to_array();
            for &v in t {
                let vertex = &level.vertices[v as usize];
                assert_eq!(vertex.fine.normal, normal, "level {i} vertex {v}");
                assert_eq!(vertex.coarse.normal, normal, "level {i} vertex {v}: coarse end");
                assert!(level.faceted[v as usize]);
            }
        }
        // One vertex per corner: 3 per triangle.
        assert_eq!(level.vertices.len(), level.indices.len(), "level {i}");
    }
    let skip = source.morph_vertices(0, 1).expect("two levels");
    assert!(skip.iter().zip(&source.levels[0].vertices).all(|(a, b)| a.coarse.normal == b.coarse.normal));
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn smooth_and_uv_seams_are_not_welded() {
    let mut character = flat_box_strip();
    let materials = vec![0; character.mesh.triangle_count()];
    let flat = clod::shading::ShadingWeld::new(&character.mesh, &materials);
    // Every vertex is on a facet edge: all flat, welded to 20 positions (5 rings of 4).
    assert!(flat.flat.iter().all(|&f| f));
    let mut reps = flat.representative.clone();
    reps.sort();
    reps.dedup();
    assert_eq!(reps.len(), 20);
    // Normals bent away from the faces (smooth groups meeting at creases): nothing is flat.
    let centre = Vec3::new(2.0, 0.5, 0.5);
    let mesh = &mut character.mesh;
    for (n, &p) in mesh.normals.iter_mut().zip(&mesh.positions) {
        *n = (*n + 0.3 * (p - centre)).normalize();
    }
    let smooth = clod::shading::ShadingWeld::new(&character.mesh, &materials);
    assert!(!smooth.any_flat());
    // Flat again, but the face z = 0 (vertices 0..10) has its own uvs: its vertices weld with
    // nothing (alone at their positions, so not flat either) and its border stays a seam: the 20
    // welded positions plus its 10 vertices.
    let mut flat_uv = flat_box_strip();
    let uvs = (0..48).map(|v| glam::Vec2::new(if v < 10 { 0.5 } else { 0.0 }, 0.0)).collect();
    flat_uv.mesh.uvs = Some(uvs);
    let weld = clod::shading::ShadingWeld::new(&flat_uv.mesh, &materials);
    let mut reps = weld.representative.clone();
    reps.sort();
    reps.dedup();
    assert_eq!(reps.len(), 30);
    assert!(!weld.flat[..10].iter().any(|&f| f));
}

/// Exporters that split a vertex per face renormalise each copy's weights, so the copies' weights
/// differ in the last bits (RiggedSimple.glb): they still weld. Copies whose weights really differ
/// (a step of 8-bit weights) do not, and neither do copies with other joints.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn copies_whose_weights_differ_by_rounding_are_welded() {
    let materials = vec![0; 36];
    let positions_welded = |weld: &clod::shading::ShadingWeld| {
        let mut reps = weld.representative.clone();
        reps.sort();
        reps.dedup();
        reps.len()
    };
    let skinned = |weight_of: &dyn Fn(usize) -> ([u16; 4], [f32; 4])| {
        let mut character = flat_box_strip();
        for v in 0..48 {
            (character.mesh.joints[v], character.mesh.weights[v]) = weight_of(v);
        }
        clod::shading::ShadingWeld::new(&character.mesh, &materials)
    };
    // Each copy's weights off by up to 48 ulps of 0.25, in either order of the influences, with
    // an unused third joint that varies: all 48 corners weld into the 20 positions.
    let rounding = skinned(&|v| {
        let w = 0.25 + v as f32 * 3e-8;
        let unused = (v % 3) as u16 + 2;
        if v % 2 == 0 {
            ([0, 1, unused, 0], [1.0 - w, w, 0.0, 0.0])
        } else {
            ([1, 0, 0, unused], [w, 1.0 - w, 0.0, 0.0])
        }
    });
    assert!(rounding.flat.iter().all(|&f| f));
    assert_eq!(positions_welded(&rounding), 20);
    // Weights a step of 1/255 apart at every other vertex: those stay apart from the rest.
    let steps = skinned(&|v| {
        let w = 0.25 + (v % 2) as f32 / 255.0;
        ([0, 1, 0, 0], [1.0 - w, w, 0.0, 0.0])
    });
    assert!(positions_welded(&steps) > 20);
    let reps = &steps.representative;
    assert!((0..48).all(|v| reps[v] as usize % 2 == v % 2), "a copy welded across a weight step");
    // Another joint: not welded to copies that use joint 1.
    let joints = skinned(&|v| ([0, if v % 2 == 0 { 1 } else { 2 }, 0, 0], [0.75, 0.25, 0.0, 0.0]));
    assert!((0..48).all(|v| joints.representative[v] as usize % 2 == v % 2));
}

/// Facet corners whose morph targets move them apart are not one vertex: a facet corner of a
/// morphing part that touches a still one keeps its own deltas (the generated robot's face plate
/// on its head). Normal deltas do not matter to a flat vertex.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn facet_corners_that_morph_apart_are_not_welded() {
    let materials = vec![0; 36];
    let mut character = flat_box_strip();
    let mut morph = clod_viewer::morph::MorphDeltas::default();
    // Vertex 0 (a corner of the face z = 0) moves with target 0, the other copies of its
    // position do not; the first half of the vertices have a normal delta of their own, the rest
    // no entry at all (the importer keeps non-zero deltas only).
    for v in 0..48 {
        let normal_delta = Vec3::splat(v as f32 * 0.01);
        let position_delta = if v == 0 { Vec3::Z } else { Vec3::ZERO };
        if v < 24 {
            morph.push_row([(0u16, position_delta, normal_delta)]);
        } else {
            morph.push_row([]);
        }
    }
    character.mesh.morph = morph;
    let weld = clod::shading::ShadingWeld::new(&character.mesh, &materials);
    assert_eq!(weld.representative[0], 0);
    assert!((1..48).all(|v| weld.representative[v] != 0), "a still copy welded into the morphing corner");
    let mut reps = weld.representative.clone();
    reps.sort();
    reps.dedup();
    assert_eq!(reps.len(), 21, "the 20 positions, and vertex 0 on its own");
}

/// An exporter that writes every triangle corner as its own vertex under an index buffer: every
/// edge is a seam of identical sides. The copies weld (they stay smooth), and the chain reaches as
/// far as the file's own (it stopped at 3,728 of CesiumMan's 4,672 triangles before).
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_mesh_split_per_corner_simplifies_like_the_original() {
    let Some(bytes) = common::model_bytes("CesiumMan.glb") else { return };
    let original = clod_viewer::import::from_glb(&bytes).expect("CesiumMan imports");
    let mut split = original.clone();
    let m = &original.mesh;
    let corners: Vec<usize> = m.indices.iter().map(|&v| v as usize).collect();
    split.mesh.positions = corners.iter().map(|&v| m.positions[v]).collect();
    split.mesh.normals = corners.iter().map(|&v| m.normals[v]).collect();
    split.mesh.uvs = m.uvs.as_ref().map(|uvs| corners.iter().map(|&v| uvs[v]).collect());
    split.mesh.colors = m.colors.as_ref().map(|colors| corners.iter().map(|&v| colors[v]).collect());
    split.mesh.joints = corners.iter().map(|&v| m.joints[v]).collect();
    split.mesh.weights = corners.iter().map(|&v| m.weights[v]).collect();
    split.mesh.indices = (0..corners.len() as u32).collect();
    assert!(m.morph.is_empty(), "CesiumMan has no morph targets to split");
    // The 14,016 corners weld back into no more vertices than the file has (its own copies
    // along uv seams stay apart).
    let weld = clod::shading::ShadingWeld::of_character(&split);
    let mut reps = weld.representative.clone();
    reps.sort();
    reps.dedup();
    assert!(
        reps.len() <= m.vertex_count(),
        "{} welded vertices, the file has {}",
        reps.len(),
        m.vertex_count()
    );
    let levels = |c: &Character| -> Vec<usize> {
        let built = clod::build(c, &ClodOptions::default(), &mut |_| {}).expect("CesiumMan simplifies");
        built.levels.iter().map(|l| l.triangle_count()).collect()
    };
    let (got, want) = (levels(&split), levels(&original));
    assert_eq!(got.len(), want.len(), "split {got:?}, original {want:?}");
    assert!(
        got.last() <= Some(&(want.last().unwrap() + want.last().unwrap() / 4)),
        "split {got:?}, original {want:?}"
    );
}

/// A unit cube of 8 shared corners and 12 triangles with no NORMAL attribute, as a `.gltf`.
fn cube_without_normals() -> Vec<u8> {
    use base64::Engine;
    let mut buffer = Vec::new();
    for i in 0..8u32 {
        for axis in 0..3 {
            buffer.extend((((i >> axis) & 1) as f32).to_le_bytes());
        }
    }
    // Corner i = x + 2y + 4z; each face two counter-clockwise triangles seen from outside.
    let faces: [[u16; 4]; 6] =
        [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    for [a, b, c, d] in faces {
        for i in [a, b, c, a, c, d] {
            buffer.extend(i.to_le_bytes());
        }
    }
    let uri = base64::engine::general_purpose::STANDARD.encode(&buffer);
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
        "buffers": [{{"byteLength": 168, "uri": "data:application/octet-stream;base64,{uri}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 96}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 72}}],
        "accessors": [
          {{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}},
          {{"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}}
        ]}}"#
    )
    .into_bytes()
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_mesh_without_normals_imports_flat_shaded_as_the_spec_asks() {
    let c = clod_viewer::import::from_gltf(&cube_without_normals(), &mut |_| None).expect("the cube imports");
    let mesh = &c.mesh;
    // Every face keeps its own four corners (its two triangles share two of them): 24, not 8 or 36.
    assert_eq!((mesh.triangle_count(), mesh.vertex_count()), (12, 24));
    for tri in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize]);
        let face = (b - a).cross(c - a).normalize();
        // Outward and axis-aligned: the cube's centre is behind every face.
        assert!(face.dot(a - Vec3::splat(0.5)) > 0.0, "{face} faces out");
        for &v in tri {
            assert_eq!(mesh.normals[v as usize], face, "each corner carries its face's normal");
        }
    }
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

/// A bumpy grid of 12 × 12 quads as low-poly exports often write one: every triangle has its own
/// three vertices, there is no NORMAL (so it is flat-shaded), and TEXCOORD_0 gives every triangle
/// its own uv island, so every edge is a uv seam. `textured`: a base colour texture samples them.
fn per_face_uv_grid(textured: bool) -> Vec<u8> {
    use base64::Engine;
    const N: u32 = 12;
    let corner = |i: u32, j: u32| Vec3::new(i as f32, j as f32, ((i * 7 + j * 3) % 5) as f32 * 0.2);
    let (mut positions, mut uvs) = (Vec::new(), Vec::new());
    for j in 0..N {
        for i in 0..N {
            let quad = [corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)];
            for tri in [[0, 1, 2], [0, 2, 3]] {
                // Each triangle's island: its own cell of a 24 × 12 atlas.
                let island = (positions.len() / 3) as f32;
                for (k, &q) in tri.iter().enumerate() {
                    positions.extend(quad[q].to_array());
                    uvs.extend([(island % 24.0 + [0.1, 0.9, 0.9][k]) / 24.0, ([0.1, 0.1, 0.9][k]) / 12.0]);
                }
            }
        }
    }
    let count = positions.len() / 3;
    let mut buffer: Vec<u8> = positions.iter().chain(&uvs).flat_map(|x: &f32| x.to_le_bytes()).collect();
    let indices_at = buffer.len();
    buffer.extend((0..count as u32).flat_map(u32::to_le_bytes));
    let uri = base64::engine::general_purpose::STANDARD.encode(&buffer);
    let material = if textured {
        r#""materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}], "images": [{"uri": "atlas.png"}],"#
    } else {
        r#""materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.2, 1]}}],"#
    };
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], {material}
        "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "indices": 2, "material": 0}}]}}],
        "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{uri}"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": {}}}, {{"buffer": 0, "byteOffset": {}, "byteLength": {}}},
                        {{"buffer": 0, "byteOffset": {indices_at}, "byteLength": {}}}],
        "accessors": [
          {{"bufferView": 0, "componentType": 5126, "count": {count}, "type": "VEC3", "min": [0, 0, 0], "max": [12, 12, 0.8]}},
          {{"bufferView": 1, "componentType": 5126, "count": {count}, "type": "VEC2"}},
          {{"bufferView": 2, "componentType": 5125, "count": {count}, "type": "SCALAR"}}
        ]}}"#,
        buffer.len(),
        12 * count,
        12 * count,
        8 * count,
        4 * count,
    )
    .into_bytes()
}

/// uvs that no texture samples draw nothing, so they do not hold the levels: the untextured grid,
/// every edge of which is a uv seam, simplifies as far as its shape allows (before, the importer
/// kept its uvs and it kept all 288 triangles). The same grid under a texture keeps its seams, and
/// where islands meet nothing may move: it stops within a few collapses, and says why.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn uvs_no_texture_samples_do_not_hold_the_levels() {
    let build = |textured: bool| {
        let png = b"\x89PNG\r\n\x1a\n".to_vec();
        let c = clod_viewer::import::from_gltf(&per_face_uv_grid(textured), &mut |_| Some(png.clone()))
            .expect("the grid imports");
        assert_eq!(c.mesh.triangle_count(), 288);
        assert_eq!(c.mesh.uvs.is_some(), textured);
        let options = ClodOptions { level_triangles: Some(vec![144, 72, 36]), ..ClodOptions::default() };
        clod::build(&c, &options, &mut |_| {}).expect("builds")
    };
    let untextured = build(false);
    let counts: Vec<usize> = untextured.levels.iter().map(|l| l.triangle_count()).collect();
    // Each level at most its count (a collapse removes two triangles, or one on a border).
    assert!(
        counts.len() == 3 && counts.iter().zip([144, 72, 36]).all(|(&n, want)| n <= want && n + 2 >= want)
    );
    assert_eq!(untextured.stopped_short(), None);
    let textured = build(true);
    let coarsest = textured.levels.last().expect("a level").triangle_count();
    assert!(coarsest > 250, "{coarsest}: only a few collapses at the grid's rim can keep every island");
    let stop = textured.stopped_short().expect("the textured grid stops short").to_string();
    assert!(stop.starts_with(&format!("the levels stop at {coarsest} of 288")), "{stop}");
}
