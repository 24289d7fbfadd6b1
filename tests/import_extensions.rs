//! Required glTF extensions on the tiny skinned triangle (tests/common `TinyModel`): those the
//! importer reads (`KHR_mesh_quantization`: integer and normalized attributes, as gltfpack writes
//! them; `KHR_texture_transform` on the base colour texture, gltfpack's uv dequantization) import
//! to exact values, and every other one is an error that names it and says what to do.

use crate::common;

use clod_viewer::import::from_gltf;
use clod_viewer::{Character, ImportError};
use common::TinyModel;
use glam::{Vec2, Vec3};
use serde_json::Value;

fn import(model: &TinyModel) -> Result<Character, ImportError> {
    from_gltf(&model.gltf(), &mut |_| None)
}

fn require(model: &mut TinyModel, names: &[&str]) {
    model.json["extensionsUsed"] = Value::from(names.to_vec());
    model.json["extensionsRequired"] = Value::from(names.to_vec());
}

/// Appends `bytes` (padded to 4) to the buffer as a new buffer view and returns its index.
fn add_view(model: &mut TinyModel, bytes: &[u8]) -> usize {
    let offset = model.bin.len();
    model.bin.extend_from_slice(bytes);
    model.bin.resize(model.bin.len().next_multiple_of(4), 0);
    model.json["buffers"][0]["byteLength"] = Value::from(model.bin.len());
    let views = model.json["bufferViews"].as_array_mut().unwrap();
    views.push(view_json(offset, bytes.len()));
    views.len() - 1
}

fn view_json(offset: usize, length: usize) -> Value {
    let text = format!(r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {length}}}"#);
    serde_json::from_str(&text).unwrap()
}

/// Adds an accessor of `count` elements over buffer view `view` and returns its index.
fn add_accessor(
    model: &mut TinyModel,
    view: usize,
    component_type: u32,
    normalized: bool,
    ty: &str,
) -> usize {
    let text = format!(
        r#"{{"bufferView": {view}, "componentType": {component_type}, "normalized": {normalized},
            "count": 3, "type": "{ty}"}}"#
    );
    let accessors = model.json["accessors"].as_array_mut().unwrap();
    accessors.push(serde_json::from_str(&text).unwrap());
    accessors.len() - 1
}

/// `KHR_animation_pointer` animates other things than nodes (a material's colour, a light), and
/// its channels name no node: those channels are dropped with a warning naming the animation, and
/// the node channels still play.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn channels_that_target_no_node_are_dropped_and_the_rest_plays() {
    let mut model = TinyModel::new();
    model.json["extensionsUsed"] = Value::from(vec!["KHR_animation_pointer"]);
    model.json["animations"][0]["name"] = Value::from("wave");
    let pointer = r#"{"sampler": 0, "target": {"path": "pointer",
        "extensions": {"KHR_animation_pointer": {"pointer": "/materials/0/emissiveFactor"}}}}"#;
    let channels = model.json["animations"][0]["channels"].as_array_mut().unwrap();
    channels.push(serde_json::from_str(pointer).unwrap());
    let c = import(&model).expect("a file with pointer channels imports");
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    assert!(
        c.warnings[0].contains("KHR_animation_pointer") && c.warnings[0].contains("animation 0 ('wave'): 1")
    );
    let skinned = c.skinned_positions(&c.pose_at(&c.clips[0], 0.5));
    assert_eq!(skinned[2], Vec3::new(0.5, 1.0, 0.0), "the node channel still moves `tip`");
    // Another problem in the same file is still reported as itself.
    model.json["animations"][0]["channels"][0]["target"]["path"] = Value::from("size");
    let error = import(&model).err().unwrap().to_string();
    assert!(error.contains("channels[0].target.path: \"size\" is not one of translation"), "{error}");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn quantized_attributes_and_a_uv_transform_import_exactly() {
    let mut model = TinyModel::new();
    require(&mut model, &["KHR_mesh_quantization", "KHR_texture_transform"]);
    // POSITION as unnormalized u16 (gltfpack's integer grid), NORMAL as normalized i8, TEXCOORD_0
    // as normalized u16.
    let positions: Vec<u8> = [[0u16, 0, 0], [4, 0, 0], [0, 4, 0]]
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()).chain([0, 0]))
        .collect();
    let normals: Vec<u8> = [[0i8, 0, 127, 0]; 3].iter().flatten().map(|&c| c as u8).collect();
    let uvs: Vec<u8> =
        [[0u16, 0], [65535, 0], [0, 65535]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let view = add_view(&mut model, &positions);
    model.json["bufferViews"][view]["byteStride"] = Value::from(8);
    let position = add_accessor(&mut model, view, 5123, false, "VEC3");
    let view = add_view(&mut model, &normals);
    model.json["bufferViews"][view]["byteStride"] = Value::from(4);
    let normal = add_accessor(&mut model, view, 5120, true, "VEC3");
    let view = add_view(&mut model, &uvs);
    let uv = add_accessor(&mut model, view, 5123, true, "VEC2");
    let attributes = &mut model.json["meshes"][0]["primitives"][0]["attributes"];
    attributes["POSITION"] = Value::from(position);
    attributes["NORMAL"] = Value::from(normal);
    attributes["TEXCOORD_0"] = Value::from(uv);
    model.json["meshes"][0]["primitives"][0]["material"] = Value::from(0);
    // A quarter of the texture, offset to its middle: uv' = (0.5, 0.25) + 0.25 · uv.
    let material = r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions":
        {"KHR_texture_transform": {"offset": [0.5, 0.25], "scale": [0.25, 0.25]}}}}}]"#;
    model.json["materials"] = serde_json::from_str(material).unwrap();
    model.json["textures"] = serde_json::from_str(r#"[{"source": 0}]"#).unwrap();
    model.json["images"] = serde_json::from_str(r#"[{"uri": "texture.png"}]"#).unwrap();
    let resolve = &mut |uri: &str| (uri == "texture.png").then(|| b"\x89PNG\r\n\x1a\n".to_vec());
    let c = from_gltf(&model.gltf(), resolve).expect("a quantized file imports");
    assert_eq!(c.mesh.positions, vec![Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.0, 4.0, 0.0)]);
    assert_eq!(c.mesh.normals, vec![Vec3::Z; 3]);
    let expected = [Vec2::new(0.5, 0.25), Vec2::new(0.75, 0.25), Vec2::new(0.5, 0.5)];
    assert_eq!(c.mesh.uvs.as_deref(), Some(expected.as_slice()));
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_rotated_uv_transform_turns_counter_clockwise_in_uv_space() {
    // The extension's example: rotation π/2 maps (1, 0) to (0, −1) before the offset.
    let mut model = TinyModel::new();
    let uvs: Vec<u8> =
        [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let view = add_view(&mut model, &uvs);
    let uv = add_accessor(&mut model, view, 5126, false, "VEC2");
    model.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = Value::from(uv);
    model.json["meshes"][0]["primitives"][0]["material"] = Value::from(0);
    let material = r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions":
        {"KHR_texture_transform": {"offset": [0, 1], "rotation": 1.5707963}}}}}]"#;
    model.json["materials"] = serde_json::from_str(material).unwrap();
    model.json["textures"] = serde_json::from_str(r#"[{"source": 0}]"#).unwrap();
    model.json["images"] = serde_json::from_str(r#"[{"uri": "texture.png"}]"#).unwrap();
    let resolve = &mut |_: &str| Some(b"\x89PNG\r\n\x1a\n".to_vec());
    let c = from_gltf(&model.gltf(), resolve).expect("imports");
    let uvs = c.mesh.uvs.expect("uvs");
    for (got, want) in uvs.iter().zip([Vec2::new(0.0, 1.0), Vec2::new(0.0, 0.0), Vec2::new(1.0, 1.0)]) {
        assert!((*got - want).length() < 1e-6, "{got} != {want}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_unreadable_required_extension_is_named_with_what_to_do() {
    for (name, what) in [("EXT_made_up", "does not know"), ("KHR_gaussian_splatting", "does not know")] {
        let mut model = TinyModel::new();
        require(&mut model, &["KHR_mesh_quantization", name]);
        let error = import(&model).expect_err(name);
        assert!(matches!(&error, ImportError::UnsupportedExtension { name: n, .. } if n == name), "{error}");
        let message = error.to_string();
        assert!(message.contains(name) && message.contains(what), "{message}");
    }
    // Used but not required: the file is readable without it, and imports.
    let mut model = TinyModel::new();
    model.json["extensionsUsed"] = Value::from(vec!["KHR_materials_variants"]);
    import(&model).expect("an optional extension is ignored");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_required_texture_format_drops_the_texture_and_keeps_the_character() {
    // A KTX2 texture has its image in the extension, no core `source`: geometry, skin and clip
    // import, and the material keeps its colour factor with a warning naming the format.
    let mut model = TinyModel::new();
    require(&mut model, &["KHR_texture_basisu"]);
    model.json["meshes"][0]["primitives"][0]["material"] = Value::from(0);
    let json = r#"{
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1], "baseColorTexture": {"index": 0}}}],
        "textures": [{"extensions": {"KHR_texture_basisu": {"source": 0}}}],
        "images": [{"uri": "texture.ktx2", "mimeType": "image/ktx2"}]
    }"#;
    let extra: Value = serde_json::from_str(json).unwrap();
    for key in ["materials", "textures", "images"] {
        model.json[key] = extra[key].clone();
    }
    let c = import(&model).expect("a KTX2-textured file imports");
    assert_eq!(c.mesh.positions, from_gltf(&TinyModel::new().gltf(), &mut |_| None).unwrap().mesh.positions);
    assert_eq!(c.clips.len(), 1);
    assert!(c.materials[0].base_color_texture.is_none());
    assert_eq!(c.materials[0].base_color_factor, glam::Vec4::new(1.0, 0.5, 0.25, 1.0));
    assert!(
        c.warnings.iter().any(|w| w.contains("KHR_texture_basisu") && w.contains("keeps its colour")),
        "{:?}",
        c.warnings
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_base_colour_textures_uv_set_becomes_the_uvs() {
    // TEXCOORD_0 all zero (a lightmap's, say), TEXCOORD_1 the texture's.
    let with_sets = |material: &str| {
        let mut model = TinyModel::new();
        let set =
            |uvs: [[f32; 2]; 3]| uvs.iter().flatten().flat_map(|c| c.to_le_bytes()).collect::<Vec<u8>>();
        let view = add_view(&mut model, &set([[0.0; 2]; 3]));
        let zero = add_accessor(&mut model, view, 5126, false, "VEC2");
        let view = add_view(&mut model, &set([[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]]));
        let one = add_accessor(&mut model, view, 5126, false, "VEC2");
        let attributes = &mut model.json["meshes"][0]["primitives"][0]["attributes"];
        attributes["TEXCOORD_0"] = Value::from(zero);
        attributes["TEXCOORD_1"] = Value::from(one);
        model.json["meshes"][0]["primitives"][0]["material"] = Value::from(0);
        model.json["materials"] = serde_json::from_str(material).unwrap();
        model.json["textures"] = serde_json::from_str(r#"[{"source": 0}]"#).unwrap();
        model.json["images"] = serde_json::from_str(r#"[{"uri": "texture.png"}]"#).unwrap();
        from_gltf(&model.gltf(), &mut |_| Some(b"\x89PNG\r\n\x1a\n".to_vec())).expect("imports")
    };
    let texture_set = vec![Vec2::new(0.1, 0.2), Vec2::new(0.3, 0.4), Vec2::new(0.5, 0.6)];
    let c = with_sets(r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}]"#);
    assert_eq!(c.mesh.uvs, Some(texture_set.clone()));
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    // KHR_texture_transform's texCoord overrides the texture info's.
    let c = with_sets(
        r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 0,
            "extensions": {"KHR_texture_transform": {"texCoord": 1}}}}}]"#,
    );
    assert_eq!(c.mesh.uvs, Some(texture_set));
    // A set the primitive lacks: TEXCOORD_0, with a warning naming the one asked for.
    let c = with_sets(r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 3}}}]"#);
    assert_eq!(c.mesh.uvs, Some(vec![Vec2::ZERO; 3]));
    assert!(c.warnings.iter().any(|w| w.contains("TEXCOORD_3")), "{:?}", c.warnings);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn uvs_no_texture_samples_are_not_imported() {
    // The same triangle with TEXCOORD_0, under three materials: none, a plain colour, a texture.
    let with_material = |material: Option<&str>| {
        let mut model = TinyModel::new();
        let uvs: Vec<u8> =
            [[0.1f32, 0.2], [0.3, 0.4], [0.5, 0.6]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
        let view = add_view(&mut model, &uvs);
        let uv = add_accessor(&mut model, view, 5126, false, "VEC2");
        model.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = Value::from(uv);
        if let Some(material) = material {
            model.json["meshes"][0]["primitives"][0]["material"] = Value::from(0);
            model.json["materials"] = serde_json::from_str(material).unwrap();
            model.json["textures"] = serde_json::from_str(r#"[{"source": 0}]"#).unwrap();
            model.json["images"] = serde_json::from_str(r#"[{"uri": "t.png"}]"#).unwrap();
        }
        from_gltf(&model.gltf(), &mut |_| Some(b"\x89PNG\r\n\x1a\n".to_vec())).expect("imports")
    };
    for untextured in [None, Some(r#"[{"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}]"#)] {
        let c = with_material(untextured);
        assert_eq!(c.mesh.uvs, None, "{untextured:?}");
        // Nothing the viewer draws is dropped, so nothing is said.
        assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    }
    let c = with_material(Some(r#"[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]"#));
    assert_eq!(c.mesh.uvs, Some(vec![Vec2::new(0.1, 0.2), Vec2::new(0.3, 0.4), Vec2::new(0.5, 0.6)]));
}

/// A version 0 `EXT_meshopt_compression` attribute stream of `data` (`stride`-byte elements),
/// every group stored as raw bytes: the simplest valid encoding (the baseline is all zeros).
fn meshopt_raw_attributes(data: &[u8], stride: usize) -> Vec<u8> {
    let count = data.len() / stride;
    let per_block = ((8192 / stride) & !15).min(256);
    let mut out = vec![0xa0];
    let mut previous = vec![0u8; stride];
    for start in (0..count).step_by(per_block) {
        let n = per_block.min(count - start);
        let groups = n.div_ceil(16);
        for (k, last) in previous.iter_mut().enumerate() {
            out.extend(std::iter::repeat_n(0xff, groups.div_ceil(4))); // mode 3 for every group
            for i in 0..groups * 16 {
                let value = if i < n { data[(start + i) * stride + k] } else { *last };
                let delta = value.wrapping_sub(*last) as i8;
                out.push(((delta << 1) ^ (delta >> 7)) as u8); // zigzag
                *last = value;
            }
        }
    }
    out.resize(out.len() + stride.max(32), 0); // the tail: padding, then the zero baseline
    out
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_meshopt_compressed_buffer_view_decodes_into_a_placeholder_buffer() {
    // The positions move to a compressed stream in buffer 0; their view's own buffer becomes a
    // placeholder with no bytes (buffer 1, as gltfpack writes it).
    let plain = import(&TinyModel::new()).expect("imports");
    let mut model = TinyModel::new();
    let positions = model.bin[common::tiny::POSITIONS..common::tiny::POSITIONS + 36].to_vec();
    let stream = meshopt_raw_attributes(&positions, 12);
    let offset = model.bin.len();
    model.bin.extend_from_slice(&stream);
    model.json["buffers"][0]["byteLength"] = Value::from(model.bin.len());
    let placeholder = r#"{"byteLength": 36, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}"#;
    model.json["buffers"].as_array_mut().unwrap().push(serde_json::from_str(placeholder).unwrap());
    let extension = format!(
        r#"{{"EXT_meshopt_compression": {{"buffer": 0, "byteOffset": {offset}, "byteLength": {},
            "byteStride": 12, "count": 3, "mode": "ATTRIBUTES"}}}}"#,
        stream.len()
    );
    model.json["bufferViews"][0]["buffer"] = Value::from(1);
    model.json["bufferViews"][0]["extensions"] = serde_json::from_str(&extension).unwrap();
    require(&mut model, &["EXT_meshopt_compression"]);
    // The positions' bytes in buffer 0 are garbage now: only the decoded stream can give them.
    model.put_f32s(common::tiny::POSITIONS, &[9.0; 9]);
    let decoded = import(&model).expect("imports");
    assert_eq!(decoded.mesh.positions, plain.mesh.positions);

    // gltfpack -cf names a fallback file for loaders without the extension: never fetched (a
    // user who drops the .glb alone does not have it).
    model.json["buffers"][1]["uri"] = Value::from("out.fallback.bin");
    let decoded = import(&model).expect("imports without the fallback file");
    assert_eq!(decoded.mesh.positions, plain.mesh.positions);

    // Cut short by one byte, the stream is an error naming the view.
    model.json["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] =
        Value::from(stream.len() - 1);
    let error = import(&model).expect_err("a corrupt stream");
    assert!(error.to_string().contains("bufferViews[0]"), "{error}");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn compressed_views_cannot_decode_to_far_more_than_the_file() {
    // A valid stream of 5,461 all-equal 12-byte elements takes about 1 KiB (every group of 16 is
    // two header bits) and decodes to 64 KiB. A hundred views sharing it would make a 2 KiB file
    // allocate 6.4 MB: refused, naming the view that goes over.
    let (count, stride): (usize, usize) = (5_461, 12);
    let mut stream = vec![0xa0];
    for start in (0..count).step_by(256) {
        let groups = (count - start).min(256).div_ceil(16);
        stream.extend(std::iter::repeat_n(0, stride * groups.div_ceil(4)));
    }
    stream.resize(stream.len() + 32, 0);
    let mut model = TinyModel::new();
    let offset = model.bin.len();
    model.bin.extend_from_slice(&stream);
    model.json["buffers"][0]["byteLength"] = Value::from(model.bin.len());
    let placeholder =
        r#"{"byteLength": 65532, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}"#;
    model.json["buffers"].as_array_mut().unwrap().push(serde_json::from_str(placeholder).unwrap());
    let view = format!(
        r#"{{"buffer": 1, "byteLength": 65532, "extensions": {{"EXT_meshopt_compression": {{"buffer": 0,
            "byteOffset": {offset}, "byteLength": {}, "byteStride": 12, "count": {count}, "mode": "ATTRIBUTES"}}}}}}"#,
        stream.len()
    );
    let view: Value = serde_json::from_str(&view).unwrap();
    require(&mut model, &["EXT_meshopt_compression"]);
    let views = model.json["bufferViews"].as_array_mut().unwrap();
    views.push(view.clone());
    let one = views.len();
    import(&model).expect("one such view decodes");
    model.json["bufferViews"].as_array_mut().unwrap().extend(std::iter::repeat_n(view, 99));
    let error = import(&model).expect_err("a hundred");
    assert!(error.to_string().contains("times the file"), "{error}");
    assert!(
        !error.to_string().contains(&format!("bufferViews[{}]", one - 1)),
        "the first ones decode: {error}"
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_draco_stream_that_does_not_decode_names_its_primitive() {
    // Real Draco files (gltf-transform with Google's encoder) import in tests/js/draco.test.mjs;
    // here, streams no decoder can read. The accessors have no buffer view, as in real files.
    let mut model = TinyModel::new();
    require(&mut model, &["KHR_draco_mesh_compression"]);
    for accessor in 0..4 {
        model.json["accessors"][accessor].as_object_mut().unwrap().remove("bufferView");
    }
    let garbage = add_view(&mut model, &[0x44, 0x52, 0x41, 0x43, 0x4f, 2, 2, 1, 1, 0, 0, 9, 9, 9, 9, 9]);
    let empty = add_view(&mut model, &[]);
    for view in [garbage, empty] {
        let extension = format!(
            r#"{{"KHR_draco_mesh_compression": {{"bufferView": {view},
                "attributes": {{"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}}}}}}"#
        );
        model.json["meshes"][0]["primitives"][0]["extensions"] = serde_json::from_str(&extension).unwrap();
        let error = import(&model).expect_err("a stream that does not decode");
        let message = error.to_string();
        assert!(matches!(error, ImportError::Invalid(_)), "{message}");
        assert!(message.contains("meshes[0].primitives[0]") && message.contains("Draco"), "{message}");
    }
    // Seeded random streams behind a valid header (Draco 2.2, triangle mesh, each codec): an
    // error every time, never a panic or a runaway allocation.
    let mut state = 0x2545_f491_u32;
    for round in 0..300 {
        let mut stream = vec![b'D', b'R', b'A', b'C', b'O', 2, 2, 1, (round % 2) as u8, 0, 0];
        for _ in 0..(round % 64) {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            stream.push(state as u8);
        }
        let view = add_view(&mut model, &stream);
        let extension = format!(
            r#"{{"KHR_draco_mesh_compression": {{"bufferView": {view},
                "attributes": {{"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}}}}}}"#
        );
        model.json["meshes"][0]["primitives"][0]["extensions"] = serde_json::from_str(&extension).unwrap();
        import(&model).expect_err("a random stream");
    }
    // No stream at all.
    model.json["meshes"][0]["primitives"][0]["extensions"] = serde_json::from_str(
        r#"{"KHR_draco_mesh_compression": {"attributes": {"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}}}"#,
    )
    .unwrap();
    let message = import(&model).expect_err("no bufferView").to_string();
    assert!(message.contains("no bufferView"), "{message}");
}

/// A build without the built-in decoder (the viewer page's) imports a Draco file with the decoder
/// it is handed (`import::from_bytes_with`), which the separate module's answer reaches through
/// `clod_draco`'s wire format: the import asks for the attributes the extension maps with their
/// accessors' component counts, and builds the primitive from the answer. A decoder that gives a
/// wrong count is an error naming the primitive.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_draco_primitive_imports_with_the_decoder_it_is_handed() {
    use clod_draco::{read_answer, write_answer, Attribute, Decoded, Request};
    use clod_viewer::import::{from_bytes_with, uses_draco};
    let mut model = TinyModel::new();
    require(&mut model, &["KHR_draco_mesh_compression"]);
    for accessor in 0..4 {
        model.json["accessors"][accessor].as_object_mut().unwrap().remove("bufferView");
    }
    let stream = add_view(&mut model, b"DRACO stream the decoder below answers for");
    let extension = format!(
        r#"{{"KHR_draco_mesh_compression": {{"bufferView": {stream},
            "attributes": {{"POSITION": 7, "JOINTS_0": 8, "WEIGHTS_0": 9}}}}}}"#
    );
    model.json["meshes"][0]["primitives"][0]["extensions"] = serde_json::from_str(&extension).unwrap();
    let gltf = model.gltf();
    assert!(uses_draco(&gltf) && !uses_draco(&TinyModel::new().gltf()));
    // The tiny triangle, mirrored in x, as a decoder would answer it (across the wire format).
    let answer = |request: &Request, points: usize| {
        let values = |id: u32, components: usize| -> Vec<f32> {
            let all: Vec<f32> = match id {
                7 => vec![0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
                8 => vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
                _ => vec![1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
            };
            all[..points * components].to_vec()
        };
        let decoded = Decoded {
            faces: vec![0, 1, 2],
            points,
            attributes: request
                .attributes
                .iter()
                .map(|&(id, components)| Some(Attribute { float: id != 8, values: values(id, components) }))
                .collect(),
        };
        read_answer(&write_answer(&Ok(decoded))).unwrap()
    };
    let mut asked = Vec::new();
    let character = from_bytes_with(
        &gltf,
        &mut |_| None,
        Some(&mut |_: &[u8], request: &Request| {
            asked.push(request.attributes.clone());
            answer(request, 3)
        }),
    )
    .expect("the handed decoder's mesh");
    let mut wanted = asked[0].clone();
    wanted.sort();
    assert_eq!(wanted, [(7, 3), (8, 4), (9, 4)]);
    assert_eq!(character.mesh.positions[1], Vec3::new(-1.0, 0.0, 0.0));
    let error =
        from_bytes_with(&gltf, &mut |_| None, Some(&mut |_: &[u8], request: &Request| answer(request, 2)))
            .expect_err("two points for three");
    assert!(error.to_string().contains("meshes[0].primitives[0]"), "{error}");
}
