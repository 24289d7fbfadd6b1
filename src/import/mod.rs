//! glTF 2.0 import: `.glb` bytes, or `.gltf` JSON plus a resolver for external files, become one
//! [`Character`] — a merged [`crate::SkinnedMesh`], the [`crate::Skeleton`] that drives it, its
//! animation clips and materials.
//!
//! The pipeline, in the order of this module's files:
//! 1. `container`: split GLB chunks; `document`: read the JSON into checked types (every index in
//!    range, every enum known, every required field present); `container` again: load buffers
//!    (GLB binary chunk, base64 `data:` URIs, the caller's resolver for anything else) and decode
//!    the buffer views stored meshopt-compressed (`meshopt`: `EXT_` and `KHR_meshopt_compression`);
//!    then `draco` decodes the Draco-compressed primitives (`KHR_draco_mesh_compression`) from
//!    those buffers into their accessors' bytes. A file that requires an extension we cannot read
//!    is an [`ImportError::UnsupportedExtension`] naming it; `KHR_mesh_quantization` and
//!    `KHR_texture_transform` (gltfpack's output) are read; a required texture format we do not
//!    decode (KTX2, WebP, …) only drops those textures, with a warning.
//! 2. `scene`: the node tree of the default scene (scene 0 if none is marked): parents, cycle
//!    checks, rest transforms, and the skeleton nodes (joints, mesh nodes, their ancestors).
//! 3. `geometry`: every triangle primitive of every mesh node merged into one indexed mesh in bind
//!    space. Skinned primitives keep the file's bind-space vertices and remap their joints into
//!    [`crate::Skeleton::joints`]; rigid meshes get a joint of their own node and are moved into
//!    bind space (model space at rest), so skinning at rest puts every vertex where the file does.
//!    Texture coordinates are the set the base colour texture samples, and none where no texture
//!    samples them (they would draw nothing, and their seams would hold the levels).
//! 4. `clips`: animations as [`crate::Clip`]s over the skeleton nodes and the morph weights.
//! 5. `material`: materials in file order with their base-colour image bytes.
//!
//! Accessors are read by our own code (`accessor`) with every bound checked before allocating.
//! Bad input yields an [`ImportError`] naming the object at fault; the importer never panics, caps
//! every count it allocates by, and cannot loop on cyclic node graphs. What it drops or changes on
//! purpose (points and lines, TANGENT morph deltas, channels of nodes we do not draw, …) is listed in
//! [`Character::warnings`].

mod accessor;
mod clips;
mod container;
mod document;
mod draco;
pub use draco::DracoDecoder;
mod geometry;
mod material;
mod meshopt;
mod scene;

use thiserror::Error;

use crate::animation::CurveError;
use crate::character::Character;
use accessor::Source;

/// Most vertices (and most indices per accessor) the importer accepts: 2^26 ≈ 67M, far above any
/// character a browser can draw, and low enough that a forged count cannot exhaust memory.
pub(crate) const MAX_VERTICES: usize = 1 << 26;
/// Most indices of the merged mesh (three per triangle).
pub(crate) const MAX_INDICES: usize = 3 << 26;
/// Joint indices are `u16` in [`crate::SkinnedMesh::joints`].
pub(crate) const MAX_JOINTS: usize = 1 << 16;
/// Most keys of one animation sampler: 2^24 is over 3 days of 60 Hz keys.
pub(crate) const MAX_KEYS: usize = 1 << 24;

/// Why a file could not be imported. Messages name the glTF object at fault for a user.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ImportError {
    /// The GLB header or chunk layout is broken (usually a truncated download).
    #[error("broken GLB file: {0}")]
    Glb(String),
    /// The file itself could not be read from disk ([`from_file`]).
    #[error("cannot read {path}: {reason}")]
    Unreadable { path: String, reason: String },
    /// The JSON does not parse as a glTF document.
    #[error("the glTF JSON does not parse: {0}")]
    Json(String),
    /// The document breaks a rule of the glTF spec.
    #[error("invalid glTF: {0}")]
    Invalid(String),
    /// A URI that cannot be decoded.
    #[error("bad URI '{uri}': {reason}")]
    BadUri { uri: String, reason: String },
    /// The resolver had no bytes for an external file.
    #[error("external file '{0}' was not provided")]
    MissingResource(String),
    /// A buffer without URI in a file without GLB binary chunk.
    #[error("buffer {0} has no URI and there is no GLB binary chunk")]
    MissingBinChunk(usize),
    /// A buffer's data is shorter than its declared `byteLength`.
    #[error("buffer {buffer} declares {declared} bytes but its data has only {actual}")]
    ShortBuffer { buffer: usize, declared: u64, actual: usize },
    /// An accessor that cannot be read for its use.
    #[error("accessor {index} ({usage}) {problem}")]
    Accessor { index: usize, usage: String, problem: String },
    /// A node that cannot be placed in the skeleton.
    #[error("node {node} ('{name}') {problem}")]
    Node { node: usize, name: String, problem: String },
    /// A mesh primitive with bad vertex, index or skin data.
    #[error("{primitive}: {problem}")]
    Primitive { primitive: String, problem: String },
    /// An animation channel whose keys do not form a valid curve.
    #[error("animation '{clip}' channel {channel} ({target}): {source}")]
    Animation { clip: String, channel: usize, target: String, source: CurveError },
    /// The merged character would be too large to hold.
    #[error("{what}: {count} exceeds the limit of {limit}")]
    TooLarge { what: String, count: u64, limit: u64 },
    /// The default scene draws no triangles; `skipped` says why for each primitive left out
    /// (no triangle with an area, points or lines, no positions), if any.
    #[error("the scene has no triangle meshes to show{}", skipped_list(skipped))]
    NoTriangles { skipped: Vec<String> },
    /// The file requires an extension the importer cannot read (compressed geometry, …).
    #[error("the file needs the glTF extension {name} ({what}), which this viewer cannot read; {advice}")]
    UnsupportedExtension { name: String, what: String, advice: String },
}

/// Extensions a file may require that the importer reads: quantized attributes
/// (`KHR_mesh_quantization`, gltfpack's default) are integer or normalized accessors, which
/// `accessor` reads like any other; the base colour texture's `KHR_texture_transform` is applied
/// to the primitive's uvs (`geometry`); compressed buffer views are decoded by `meshopt`, and
/// Draco-compressed primitives by `draco`.
const READ_EXTENSIONS: [&str; 5] = [
    "KHR_mesh_quantization",
    "KHR_texture_transform",
    "EXT_meshopt_compression",
    "KHR_meshopt_compression",
    draco::EXTENSION,
];

/// Texture formats the viewer does not decode. A file may require them: the geometry, skins and
/// clips are all there, so it imports and `material` drops each texture that has no core
/// (PNG/JPEG) image, with a warning; its material keeps its colour factor.
pub(crate) const TEXTURE_FORMAT_EXTENSIONS: [&str; 4] =
    ["KHR_texture_basisu", "EXT_texture_webp", "EXT_texture_avif", "MSFT_texture_dds"];

/// The error for a required extension that is neither in [`READ_EXTENSIONS`] nor a texture
/// format, saying what it is and what a user can do.
fn unsupported_extension(name: &str) -> ImportError {
    ImportError::UnsupportedExtension {
        name: name.to_string(),
        what: "an extension the viewer does not know".to_string(),
        advice: "export the file without it".to_string(),
    }
}

/// The first required extension the importer cannot read, if any.
fn first_unreadable(required: &[String]) -> Option<ImportError> {
    required
        .iter()
        .find(|name| {
            !READ_EXTENSIONS.contains(&name.as_str()) && !TEXTURE_FORMAT_EXTENSIONS.contains(&name.as_str())
        })
        .map(|name| unsupported_extension(name))
}

/// Imports a binary glTF (`.glb`) file.
///
/// Buffers and images must be inside the file (binary chunk or `data:` URIs): an external URI
/// yields [`ImportError::MissingResource`]. Use [`from_bytes`] with a resolver for those.
///
/// # Errors
/// Any [`ImportError`]: broken container, invalid JSON, out-of-range data, …
pub fn from_glb(bytes: &[u8]) -> Result<Character, ImportError> {
    let glb = container::split_glb(bytes)?;
    import(glb.json, glb.bin, &mut |_| None, None)
}

/// Imports a JSON glTF (`.gltf`) file.
///
/// `resolve` is called with each external URI as written in the file, percent-decoded (relative
/// paths stay relative: the caller knows what they are relative to), and returns the file's bytes
/// or `None` when it has none. `data:` URIs are decoded here and never passed to it.
///
/// # Errors
/// Any [`ImportError`]; a URI the resolver cannot serve gives [`ImportError::MissingResource`].
pub fn from_gltf(
    json: &[u8],
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<Character, ImportError> {
    import(json, None, resolve, None)
}

/// A resolver over files dropped or picked together, as a browser hands them over (names, no
/// folders): asks `lookup` for a URI's path as [`from_gltf`] passes it (percent-decoded), and
/// when it has none, for the path's last segment, the name a file keeps when dropped
/// (`textures/skin.png` → `skin.png`; `\` separates segments too, as some exporters write).
pub fn by_path_or_name(
    mut lookup: impl FnMut(&str) -> Option<Vec<u8>>,
) -> impl FnMut(&str) -> Option<Vec<u8>> {
    move |path| {
        lookup(path).or_else(|| {
            let name = path.rsplit(['/', '\\']).next().filter(|name| !name.is_empty() && *name != path)?;
            lookup(name)
        })
    }
}

/// Imports either form, telling GLB (magic `glTF`) from JSON by the first bytes.
///
/// # Errors
/// As [`from_glb`] and [`from_gltf`].
pub fn from_bytes(
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<Character, ImportError> {
    from_bytes_with(bytes, resolve, None)
}

/// [`from_bytes`] with the Draco decoder `draco` (else the built-in one of feature `draco`, if
/// any): the viewer page's build has none built in, and passes the separate module's for the files
/// [`uses_draco`] finds.
///
/// # Errors
/// As [`from_bytes`]; a Draco-compressed file without any decoder is
/// [`ImportError::UnsupportedExtension`].
pub fn from_bytes_with(
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
    draco: Option<&mut DracoDecoder>,
) -> Result<Character, ImportError> {
    if bytes.starts_with(container::GLB_MAGIC) {
        let glb = container::split_glb(bytes)?;
        import(glb.json, glb.bin, resolve, draco)
    } else {
        import(bytes, None, resolve, draco)
    }
}

/// Whether a `.glb` or `.gltf` declares Draco-compressed geometry (`KHR_draco_mesh_compression`
/// in `extensionsUsed`): what a caller without the built-in decoder checks before importing. Bytes
/// that are not a glTF answer `false` (the import then says what is wrong).
pub fn uses_draco(bytes: &[u8]) -> bool {
    let json = match bytes.starts_with(container::GLB_MAGIC) {
        true => container::split_glb(bytes).map(|glb| glb.json).ok(),
        false => Some(bytes),
    };
    json.is_some_and(draco::declared)
}

/// Imports a `.glb` or `.gltf` file from disk, reading the external buffers and images its URIs
/// name from paths relative to the file's folder. For native programs: in a browser (wasm32)
/// there is no file system and every call gives [`ImportError::Unreadable`]; there, pass the
/// bytes and a resolver to [`from_bytes`].
///
/// # Errors
/// [`ImportError::Unreadable`] when the file cannot be read; a URI naming no readable file gives
/// [`ImportError::MissingResource`]; otherwise as [`from_bytes`].
pub fn from_file(path: &std::path::Path) -> Result<Character, ImportError> {
    let unreadable = |e: std::io::Error| ImportError::Unreadable {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    let bytes = std::fs::read(path).map_err(unreadable)?;
    let folder = path.parent().unwrap_or(std::path::Path::new("."));
    from_bytes(&bytes, &mut |uri| std::fs::read(folder.join(uri)).ok())
}

/// `": a; b; c"` for [`ImportError::NoTriangles`], the first three and how many more.
fn skipped_list(skipped: &[String]) -> String {
    match skipped.len() {
        0 => String::new(),
        n @ 1..=3 => format!(": {}", skipped[..n].join("; ")),
        n => format!(": {} (and {} more)", skipped[..3].join("; "), n - 3),
    }
}

/// Reads the JSON into checked types (`document`), refusing a file that requires an extension
/// the importer cannot read.
fn parse_document(json: &[u8], warnings: &mut Vec<String>) -> Result<document::Root, ImportError> {
    let root = document::Root::read(json, warnings)?;
    match first_unreadable(&root.extensions_required) {
        Some(error) => Err(error),
        None => Ok(root),
    }
}

/// The whole pipeline; see the module docs.
fn import(
    json: &[u8],
    bin: Option<&[u8]>,
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
    draco: Option<&mut DracoDecoder>,
) -> Result<Character, ImportError> {
    let mut warnings = Vec::new();
    let root = parse_document(json, &mut warnings)?;
    let mut buffers = container::load_buffers(&root, bin, resolve)?;
    let mut built_in = draco::BUILT_IN;
    let draco = draco.or(built_in.as_mut().map(|f| f as &mut DracoDecoder));
    buffers.set_draco(draco::decode_primitives(&root, &buffers, draco)?);
    let src = Source { root: &root, buffers: &buffers };

    let graph = scene::SceneGraph::new(&root)?;
    if let Some(s) = graph.chosen_scene {
        warnings
            .push(format!("scene 0 has no mesh and no scene is marked as the default: scene {s} is shown"));
    }
    let (mut skeleton, slots) = graph.skeleton(&root)?;
    let mut morph = geometry::MorphIndex::default();
    let mut mesh = geometry::merge_meshes(src, &graph, &slots, &mut skeleton, &mut morph, &mut warnings)?;
    crate::twins::unshare_layers(&mut mesh, MAX_VERTICES);
    let clips = clips::read_clips(src, &slots, &morph.by_node, &mut warnings)?;
    let materials = material::read_materials(src, resolve, &mut warnings)?;
    Ok(Character { mesh, skeleton, clips, materials, morph_targets: morph.targets, warnings })
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// `by_path_or_name` over files named `names`, recording what it was asked.
    fn ask(path: &str, names: &[&str]) -> (Option<Vec<u8>>, Vec<String>) {
        let mut asked = Vec::new();
        let found = by_path_or_name(|name: &str| {
            asked.push(name.to_string());
            names.iter().position(|&n| n == name).map(|i| vec![i as u8])
        })(path);
        (found, asked)
    }

    #[test]
    fn a_dropped_file_is_found_by_its_path_then_its_name() {
        assert_eq!(
            ask("textures/skin.png", &["textures/skin.png"]),
            (Some(vec![0]), vec!["textures/skin.png".into()])
        );
        assert_eq!(
            ask("textures/skin.png", &["body.bin", "skin.png"]),
            (Some(vec![1]), vec!["textures/skin.png".into(), "skin.png".into()])
        );
        assert_eq!(ask(r"maps\a b.png", &["a b.png"]).0, Some(vec![0]));
        // A bare name is asked once; a path ending in a separator has no name to ask for.
        assert_eq!(ask("skin.png", &[]), (None, vec!["skin.png".into()]));
        assert_eq!(ask("textures/", &[]), (None, vec!["textures/".into()]));
    }
}
