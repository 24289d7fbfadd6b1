//! `KHR_draco_mesh_compression`: primitives whose geometry is a Draco stream (what gltf-transform
//! `draco`, gltf-pipeline and Blender's exporter with compression on write). Each stream is
//! decoded by a [`DracoDecoder`] — the `clod-draco` crate (`crates/clod-draco`, over draco-core,
//! a pure Rust port of Google's Draco decoder) linked in with the `draco` feature, or the same
//! crate's separate wasm module, which the viewer page loads only for such files — into the
//! bytes of the primitive's own accessors, in their declared component type, tightly packed:
//! the indices from the decoded faces, and each attribute the extension maps from its semantic
//! to a Draco attribute id. `accessor` then reads those accessors like any other, so quantized,
//! normalized and sparse handling stays in one place.
//!
//! The extension's accessors keep `count`, `type` and `componentType` but have no buffer view
//! (or one with uncompressed fallback data, which is ignored here). Draco reconstructs
//! quantized positions, octahedral normals and texture coordinates as floats and keeps joint
//! indices as integers; a float attribute stored into a normalized integer accessor is scaled
//! to its range. A decoded point or face count that differs from the accessor's is an error
//! naming the primitive, as is a stream that does not decode. Decoded sizes are capped by the
//! importer's own vertex and index limits, and in bytes, all streams together, by
//! [`MAX_EXPANSION`] times the file (at least [`MIN_BUDGET`]).

use clod_draco::{Attribute, DecodeError, Decoded, Request};
use serde_json::Value;

use super::document::{ComponentType, Root};

use super::container::{view_bytes, Buffers, DecodedAccessors};
use super::meshopt::MAX_EXPANSION;
use super::{ImportError, MAX_INDICES, MAX_VERTICES};

/// The smallest decoding budget, for tiny files: 1 MiB.
const MIN_BUDGET: usize = 1 << 20;

/// The extension's name in `extensionsUsed` and on a primitive.
pub(crate) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// Decodes one Draco stream as `request` asks (see `clod_draco::decode`).
pub type DracoDecoder<'a> = dyn FnMut(&[u8], &Request) -> Result<Decoded, DecodeError> + 'a;

/// `clod_draco::decode`'s signature.
type DecodeFn = fn(&[u8], &Request) -> Result<Decoded, DecodeError>;

/// The decoder linked into this build (feature `draco`), if any.
#[cfg(feature = "draco")]
pub(crate) const BUILT_IN: Option<DecodeFn> = Some(clod_draco::decode);
/// The decoder linked into this build (feature `draco`), if any.
#[cfg(not(feature = "draco"))]
pub(crate) const BUILT_IN: Option<DecodeFn> = None;

/// Whether the glTF JSON `json` declares Draco-compressed primitives (`extensionsUsed`): a
/// caller without the built-in decoder then loads one before importing.
pub(crate) fn declared(json: &[u8]) -> bool {
    let Ok(document) = serde_json::from_slice::<Value>(json) else { return false };
    let used = document.get("extensionsUsed").and_then(Value::as_array);
    used.is_some_and(|used| used.iter().any(|e| e.as_str() == Some(EXTENSION)))
}

/// Decodes every Draco-compressed primitive of `root`.
///
/// # Errors
/// [`ImportError::Invalid`] naming the primitive: a malformed extension object, a stream that
/// does not decode or is over the limits, or decoded counts that disagree with the accessors.
pub(crate) fn decode_primitives(
    root: &Root,
    buffers: &Buffers,
    mut decoder: Option<&mut DracoDecoder>,
) -> Result<DecodedAccessors, ImportError> {
    let mut decoded = DecodedAccessors::new();
    // What all streams together may decode to: primitives may share one stream, so each decode
    // gets what the ones before it left.
    let mut budget = buffers.file_bytes().saturating_mul(MAX_EXPANSION).max(MIN_BUDGET);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let Some(extension) = primitive.extensions.get(EXTENSION) else { continue };
            let bad =
                |problem: String| ImportError::Invalid(format!("meshes[{m}].primitives[{p}]: {problem}"));
            let view = extension
                .get("bufferView")
                .and_then(Value::as_u64)
                .ok_or_else(|| bad(format!("{EXTENSION} has no bufferView")))?;
            let stream = view_bytes(root, buffers, view as usize)?;
            let attributes = extension
                .get("attributes")
                .and_then(Value::as_object)
                .ok_or_else(|| bad(format!("{EXTENSION} has no attributes")))?;
            // The attributes the primitive lists (one compressed but not listed is never read),
            // each with its accessor and Draco id.
            let mut wanted = Vec::new();
            for (semantic, id) in attributes {
                let id = id.as_u64().ok_or_else(|| bad(format!("attribute {semantic} has no Draco id")))?;
                let Some(accessor) =
                    primitive.attributes.iter().find(|(s, _)| s.to_string() == *semantic).map(|&(_, a)| a)
                else {
                    continue;
                };
                let id = u32::try_from(id)
                    .map_err(|_| bad(format!("its Draco stream has no attribute {id} ({semantic})")))?;
                let components = layout(root, accessor).map_err(|p| bad(format!("{semantic}: {p}")))?.3;
                wanted.push((semantic, accessor, id, components));
            }
            let request = Request {
                max_points: MAX_VERTICES as u64,
                max_faces: (MAX_INDICES / 3) as u64,
                max_decoded_bytes: budget as u64,
                attributes: wanted.iter().map(|w| (w.2, w.3)).collect(),
            };
            let too_large = || {
                bad(format!("the file's Draco streams decode to more than {MAX_EXPANSION} times its size"))
            };
            let decode = decoder.as_deref_mut().ok_or_else(|| ImportError::UnsupportedExtension {
                name: EXTENSION.into(),
                what: "Draco-compressed geometry".into(),
                advice: "this build decodes it with the separate Draco module (crates/clod-draco, \
                         www/pkg-draco/), which was not given"
                    .into(),
            })?;
            let mesh = decode(stream, &request).map_err(|e| match e {
                DecodeError::LimitExceeded => too_large(),
                DecodeError::Invalid(e) => bad(format!("its Draco stream does not decode ({e})")),
            })?;
            let mut spend = |bytes: Vec<u8>| match budget.checked_sub(bytes.len()) {
                Some(left) => {
                    budget = left;
                    Ok(bytes)
                }
                None => Err(too_large()),
            };
            if let Some(indices) = primitive.indices {
                let bytes = spend(index_bytes(root, indices, &mesh).map_err(bad)?)?;
                decoded.entry(indices).or_insert(bytes);
            }
            for ((semantic, accessor, id, _), attribute) in wanted.iter().zip(&mesh.attributes) {
                let attribute = attribute
                    .as_ref()
                    .ok_or_else(|| bad(format!("its Draco stream has no attribute {id} ({semantic})")))?;
                let bytes = attribute_bytes(root, *accessor, &mesh, attribute)
                    .map_err(|problem| bad(format!("{semantic}: {problem}")))?;
                decoded.entry(*accessor).or_insert(spend(bytes)?);
            }
        }
    }
    Ok(decoded)
}

/// The accessor's count, component type and normalized flag, and its component count.
fn layout(root: &Root, accessor: usize) -> Result<(usize, ComponentType, bool, usize), String> {
    let a = root.accessors.get(accessor).ok_or_else(|| format!("accessor {accessor} does not exist"))?;
    Ok((a.count as usize, a.component_type, a.normalized, a.type_.multiplicity()))
}

/// The decoded faces as the bytes of index accessor `accessor`.
fn index_bytes(root: &Root, accessor: usize, mesh: &Decoded) -> Result<Vec<u8>, String> {
    let (count, ct, _, _) = layout(root, accessor)?;
    let faces = mesh.faces.len() / 3;
    if count != faces * 3 {
        return Err(format!("accessor {accessor} has {count} indices, its Draco stream {faces} triangles"));
    }
    let max = match ct {
        ComponentType::U8 => u32::from(u8::MAX),
        ComponentType::U16 => u32::from(u16::MAX),
        ComponentType::U32 => u32::MAX,
        _ => return Err(format!("index accessor {accessor} is not unsigned")),
    };
    let mut bytes = Vec::with_capacity(count * ct.size());
    for &index in &mesh.faces {
        if index > max {
            return Err(format!("index {index} does not fit accessor {accessor}'s {ct:?}"));
        }
        match ct {
            ComponentType::U8 => bytes.push(index as u8),
            ComponentType::U16 => bytes.extend((index as u16).to_le_bytes()),
            _ => bytes.extend(index.to_le_bytes()),
        }
    }
    Ok(bytes)
}

/// A decoded attribute as the bytes of accessor `accessor`.
fn attribute_bytes(
    root: &Root,
    accessor: usize,
    mesh: &Decoded,
    attribute: &Attribute,
) -> Result<Vec<u8>, String> {
    let (count, ct, normalized, components) = layout(root, accessor)?;
    let points = mesh.points;
    if count != points {
        return Err(format!("accessor {accessor} has {count} elements, its Draco stream {points} points"));
    }
    if attribute.values.len() != count * components {
        return Err(format!(
            "its Draco decoder gave {} values for {count} points of {components} components",
            attribute.values.len()
        ));
    }
    let mut bytes = Vec::with_capacity(count * components * ct.size());
    for &value in &attribute.values {
        push_component(&mut bytes, ct, normalized && attribute.float, value);
    }
    Ok(bytes)
}

/// Appends `value` as one component of type `ct`: floats as they are, integers rounded into their
/// range, scaled to it first when `scale` (a float in a normalized accessor, glTF §3.11).
fn push_component(out: &mut Vec<u8>, ct: ComponentType, scale: bool, value: f32) {
    let integer = |min: f32, max: f32| (if scale { value * max } else { value }).round().clamp(min, max);
    match ct {
        ComponentType::F32 => out.extend(value.to_le_bytes()),
        ComponentType::U8 => out.push(integer(0.0, 255.0) as u8),
        ComponentType::I8 => out.push(integer(-128.0, 127.0) as i8 as u8),
        ComponentType::U16 => out.extend((integer(0.0, 65535.0) as u16).to_le_bytes()),
        ComponentType::I16 => out.extend((integer(-32768.0, 32767.0) as i16).to_le_bytes()),
        ComponentType::U32 => out.extend((integer(0.0, u32::MAX as f32) as u32).to_le_bytes()),
    }
}
