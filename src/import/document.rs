//! The part of the glTF 2.0 JSON document the importer reads (glTF 2.0 §3 and §5), as plain
//! types whose references are checked: every index is in range, every enum is a known value, and
//! every required field is present, so the importer indexes these arrays without further checks.
//!
//! The reader (`document/read.rs`) walks a parsed [`serde_json::Value`] by hand rather than
//! through serde's derived readers: the wasm then carries one JSON parser and this reader instead
//! of a derived reader, and a validator, for every glTF type (about 70 KB gzip of the viewer's
//! wasm). Fields the importer does not use (cameras, samplers' filters, accessors' bounds, …) are
//! not read; unknown fields are ignored, as the spec asks of extras and extensions.
//!
//! Conventions: an index is a `usize` into the array it names; byte offsets and lengths are
//! `u64` as written (the importer bounds them against the data); `byteOffset`, `normalized`,
//! `mode` and the material's factors take the spec's defaults when absent.

mod read;

use std::fmt;

use serde_json::{Map, Value};

use super::ImportError;

/// An object's `extensions`, by extension name (empty when it has none).
pub(crate) type Extensions = Map<String, Value>;

/// The root object of a glTF document: the arrays the importer reads.
#[derive(Clone, Debug, Default)]
pub(crate) struct Root {
    pub accessors: Vec<Accessor>,
    pub animations: Vec<Animation>,
    pub buffers: Vec<Buffer>,
    pub buffer_views: Vec<BufferView>,
    pub extensions_used: Vec<String>,
    pub extensions_required: Vec<String>,
    pub images: Vec<Image>,
    pub materials: Vec<Material>,
    pub meshes: Vec<Mesh>,
    pub nodes: Vec<Node>,
    /// The scene to show, when the file marks one.
    pub scene: Option<usize>,
    pub scenes: Vec<Scene>,
    pub skins: Vec<Skin>,
    pub textures: Vec<Texture>,
}

impl Root {
    /// Reads and checks a glTF JSON document (the bytes of a `.gltf` file or a GLB's JSON chunk,
    /// with or without a UTF-8 byte order mark).
    ///
    /// Animation channels that target no node (`KHR_animation_pointer` animates materials,
    /// lights and cameras through a JSON pointer instead) are dropped with a warning.
    ///
    /// # Errors
    /// [`ImportError::Json`] for bytes that are not JSON, [`ImportError::Invalid`] naming the
    /// field (`meshes[0].primitives[1].indices: …`) for a missing required field, a value of the
    /// wrong kind, an unknown enum value or an index out of range.
    pub(crate) fn read(json: &[u8], warnings: &mut Vec<String>) -> Result<Root, ImportError> {
        // A UTF-8 byte order mark is not JSON, but some tools write one.
        let json = json.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(json);
        let value: Value = serde_json::from_slice(json).map_err(|e| ImportError::Json(e.to_string()))?;
        read::root(value, warnings).map_err(ImportError::Invalid)
    }
}

/// An accessor (§3.6.2): typed elements in a buffer view, or zeros without one.
#[derive(Clone, Debug)]
pub(crate) struct Accessor {
    pub buffer_view: Option<usize>,
    pub byte_offset: u64,
    pub component_type: ComponentType,
    pub normalized: bool,
    pub count: u64,
    pub type_: Type,
    pub sparse: Option<Sparse>,
}

/// The elements a sparse accessor substitutes (§3.6.2.3).
#[derive(Clone, Debug)]
pub(crate) struct Sparse {
    pub count: u64,
    pub indices: SparseIndices,
    pub values: SparseValues,
}

/// Where a sparse accessor's indices are, and their type (`U8`, `U16` or `U32`).
#[derive(Clone, Debug)]
pub(crate) struct SparseIndices {
    pub buffer_view: usize,
    pub byte_offset: u64,
    pub component_type: ComponentType,
}

/// Where a sparse accessor's substituted values are.
#[derive(Clone, Debug)]
pub(crate) struct SparseValues {
    pub buffer_view: usize,
    pub byte_offset: u64,
}

/// An animation (§3.11): channels and the samplers they name.
#[derive(Clone, Debug)]
pub(crate) struct Animation {
    pub name: Option<String>,
    pub channels: Vec<Channel>,
    pub samplers: Vec<AnimationSampler>,
}

/// One animated property of one node; `sampler` indexes its animation's samplers.
#[derive(Clone, Debug)]
pub(crate) struct Channel {
    pub sampler: usize,
    pub node: usize,
    pub path: Property,
}

/// Key times (`input`) and values (`output`), both accessors.
#[derive(Clone, Debug)]
pub(crate) struct AnimationSampler {
    pub input: usize,
    pub output: usize,
    pub interpolation: Interpolation,
}

/// A buffer (§3.6.1): the GLB binary chunk when it has no `uri` and is the first.
#[derive(Clone, Debug)]
pub(crate) struct Buffer {
    pub byte_length: u64,
    pub uri: Option<String>,
    pub extensions: Extensions,
}

/// A range of a buffer (§3.6.1); `extensions` may say it is stored compressed.
#[derive(Clone, Debug)]
pub(crate) struct BufferView {
    pub buffer: usize,
    pub byte_offset: u64,
    pub byte_length: u64,
    pub byte_stride: Option<usize>,
    pub extensions: Extensions,
}

/// An image (§3.8.3), in a buffer view or at a URI.
#[derive(Clone, Debug)]
pub(crate) struct Image {
    pub buffer_view: Option<usize>,
    pub uri: Option<String>,
    pub mime_type: Option<String>,
}

/// A material (§3.9): what the viewer draws of it.
#[derive(Clone, Debug)]
pub(crate) struct Material {
    pub name: Option<String>,
    /// Linear RGBA; `[1, 1, 1, 1]` when absent.
    pub base_color_factor: [f32; 4],
    pub base_color_texture: Option<TextureInfo>,
    pub alpha_mode: AlphaMode,
    /// Absent unless written; the importer applies the spec's 0.5 for `MASK`.
    pub alpha_cutoff: Option<f32>,
    pub double_sided: bool,
}

/// A material's reference to a texture, with its uv set and `KHR_texture_transform`.
#[derive(Clone, Debug)]
pub(crate) struct TextureInfo {
    pub index: usize,
    pub tex_coord: u32,
    pub transform: Option<TextureTransform>,
}

/// `KHR_texture_transform`: uv' = offset + rotate(rotation) · scale · uv, and an optional uv set
/// that overrides the texture info's.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TextureTransform {
    pub offset: [f32; 2],
    /// Radians, counter-clockwise in uv space.
    pub rotation: f32,
    pub scale: [f32; 2],
    pub tex_coord: Option<u32>,
}

/// A texture (§3.8.2); `source` is absent when its image is only in an extension
/// (`EXT_texture_webp`, `KHR_texture_basisu`, …).
#[derive(Clone, Debug)]
pub(crate) struct Texture {
    pub source: Option<usize>,
}

/// A mesh (§3.7.2).
#[derive(Clone, Debug)]
pub(crate) struct Mesh {
    pub name: Option<String>,
    pub primitives: Vec<Primitive>,
    /// Default morph weights.
    pub weights: Option<Vec<f32>>,
}

/// A primitive (§3.7.2.1): its attributes in the file's order, each an accessor.
#[derive(Clone, Debug)]
pub(crate) struct Primitive {
    pub attributes: Vec<(Semantic, usize)>,
    pub indices: Option<usize>,
    pub material: Option<usize>,
    pub mode: Mode,
    pub targets: Option<Vec<MorphTarget>>,
    pub extensions: Extensions,
}

impl Primitive {
    /// The accessor of attribute `semantic`, if the primitive has it.
    pub(crate) fn attribute(&self, semantic: &Semantic) -> Option<usize> {
        self.attributes.iter().find(|(s, _)| s == semantic).map(|&(_, a)| a)
    }
}

/// The attributes of a morph target the importer reads (§3.7.2.2).
#[derive(Clone, Debug, Default)]
pub(crate) struct MorphTarget {
    pub positions: Option<usize>,
    pub normals: Option<usize>,
    pub tangents: Option<usize>,
}

/// A node (§3.5): its place in the hierarchy, its mesh and skin, and its local transform.
#[derive(Clone, Debug, Default)]
pub(crate) struct Node {
    pub name: Option<String>,
    pub children: Vec<usize>,
    pub mesh: Option<usize>,
    pub skin: Option<usize>,
    /// Column-major.
    pub matrix: Option<[f32; 16]>,
    pub translation: Option<[f32; 3]>,
    /// `[x, y, z, w]`, as written (the importer normalizes it).
    pub rotation: Option<[f32; 4]>,
    pub scale: Option<[f32; 3]>,
    /// Morph weights overriding the mesh's.
    pub weights: Option<Vec<f32>>,
}

/// A scene (§3.5.2): its root nodes.
#[derive(Clone, Debug)]
pub(crate) struct Scene {
    pub nodes: Vec<usize>,
}

/// A skin (§3.7.3): joints (nodes) and their inverse bind matrices (a `MAT4` accessor).
#[derive(Clone, Debug)]
pub(crate) struct Skin {
    pub joints: Vec<usize>,
    pub inverse_bind_matrices: Option<usize>,
}

/// An accessor's element type (§3.6.2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Type {
    Scalar,
    Vec2,
    Vec3,
    Vec4,
    Mat2,
    Mat3,
    Mat4,
}

impl Type {
    const NAMES: [(&'static str, Type); 7] = [
        ("SCALAR", Type::Scalar),
        ("VEC2", Type::Vec2),
        ("VEC3", Type::Vec3),
        ("VEC4", Type::Vec4),
        ("MAT2", Type::Mat2),
        ("MAT3", Type::Mat3),
        ("MAT4", Type::Mat4),
    ];

    /// Components per element.
    pub(crate) fn multiplicity(self) -> usize {
        match self {
            Type::Scalar => 1,
            Type::Vec2 => 2,
            Type::Vec3 => 3,
            Type::Vec4 | Type::Mat2 => 4,
            Type::Mat3 => 9,
            Type::Mat4 => 16,
        }
    }
}

/// An accessor's component type (§3.6.2.2), by its GL code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ComponentType {
    I8,
    U8,
    I16,
    U16,
    U32,
    F32,
}

impl ComponentType {
    /// The GL code a file writes (5120 `BYTE` … 5126 `FLOAT`; 5124, `INT`, is not glTF's).
    fn from_code(code: u64) -> Option<ComponentType> {
        Some(match code {
            5120 => ComponentType::I8,
            5121 => ComponentType::U8,
            5122 => ComponentType::I16,
            5123 => ComponentType::U16,
            5125 => ComponentType::U32,
            5126 => ComponentType::F32,
            _ => return None,
        })
    }

    /// Bytes per component.
    pub(crate) fn size(self) -> usize {
        match self {
            ComponentType::I8 | ComponentType::U8 => 1,
            ComponentType::I16 | ComponentType::U16 => 2,
            ComponentType::U32 | ComponentType::F32 => 4,
        }
    }
}

/// A primitive's topology (§3.7.2.1), by its GL code 0–6.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    Points,
    Lines,
    LineLoop,
    LineStrip,
    Triangles,
    TriangleStrip,
    TriangleFan,
}

/// A vertex attribute's name (§3.7.2.1): the ones the importer reads, and any other as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Semantic {
    Positions,
    Normals,
    Tangents,
    Colors(u32),
    TexCoords(u32),
    Joints(u32),
    Weights(u32),
    /// Any other name (`_BATCHID`, a set number too large, …): never read.
    Other(String),
}

impl Semantic {
    /// The semantic a primitive's `attributes` key names.
    fn parse(name: &str) -> Semantic {
        let set = |prefix: &str, make: fn(u32) -> Semantic| {
            let digits = name.strip_prefix(prefix)?;
            // `TEXCOORD_01` is not a set number the spec writes.
            let canonical = !digits.is_empty() && (digits == "0" || !digits.starts_with('0'));
            digits.parse().ok().filter(|_| canonical).map(make)
        };
        match name {
            "POSITION" => Semantic::Positions,
            "NORMAL" => Semantic::Normals,
            "TANGENT" => Semantic::Tangents,
            _ => set("COLOR_", Semantic::Colors)
                .or_else(|| set("TEXCOORD_", Semantic::TexCoords))
                .or_else(|| set("JOINTS_", Semantic::Joints))
                .or_else(|| set("WEIGHTS_", Semantic::Weights))
                .unwrap_or_else(|| Semantic::Other(name.to_string())),
        }
    }
}

impl fmt::Display for Semantic {
    /// The name as a file writes it (`TEXCOORD_0`).
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Semantic::Positions => f.write_str("POSITION"),
            Semantic::Normals => f.write_str("NORMAL"),
            Semantic::Tangents => f.write_str("TANGENT"),
            Semantic::Colors(n) => write!(f, "COLOR_{n}"),
            Semantic::TexCoords(n) => write!(f, "TEXCOORD_{n}"),
            Semantic::Joints(n) => write!(f, "JOINTS_{n}"),
            Semantic::Weights(n) => write!(f, "WEIGHTS_{n}"),
            Semantic::Other(name) => f.write_str(name),
        }
    }
}

/// What an animation channel drives (§3.11).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Property {
    Translation,
    Rotation,
    Scale,
    MorphTargetWeights,
}

/// How an animation sampler interpolates between keys (§3.11).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interpolation {
    Linear,
    Step,
    CubicSpline,
}

/// A material's alpha mode (§3.9.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AlphaMode {
    Opaque,
    Mask,
    Blend,
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn semantics_read_as_the_spec_writes_them() {
        assert_eq!(Semantic::parse("POSITION"), Semantic::Positions);
        assert_eq!(Semantic::parse("TEXCOORD_1"), Semantic::TexCoords(1));
        assert_eq!(Semantic::parse("JOINTS_0"), Semantic::Joints(0));
        assert_eq!(Semantic::parse("WEIGHTS_12"), Semantic::Weights(12));
        assert_eq!(Semantic::parse("TEXCOORD_01"), Semantic::Other("TEXCOORD_01".into()));
        assert_eq!(Semantic::parse("COLOR_"), Semantic::Other("COLOR_".into()));
        assert_eq!(Semantic::parse("_BATCHID"), Semantic::Other("_BATCHID".into()));
        for name in ["POSITION", "NORMAL", "TANGENT", "COLOR_0", "TEXCOORD_3", "JOINTS_1", "WEIGHTS_1", "_X"]
        {
            assert_eq!(Semantic::parse(name).to_string(), name);
        }
    }

    #[test]
    fn component_types_are_gltf_codes() {
        assert_eq!(ComponentType::from_code(5126), Some(ComponentType::F32));
        assert_eq!(ComponentType::from_code(5124), None, "INT is not a glTF component type");
        assert_eq!(ComponentType::from_code(5123).map(ComponentType::size), Some(2));
        assert_eq!(Type::Mat4.multiplicity(), 16);
    }
}
