//! Reads a parsed glTF JSON value into [`Root`], checking as it goes (see the parent module).
//!
//! Every error names the field by its JSON path, as the spec's validator does
//! (`accessors[3].componentType: 5124 is not one of 5120, 5121, 5122, 5123, 5125, 5126`). An
//! index is checked against the length of the array it names, which the reader takes from the
//! document before reading anything, so the order of the top-level arrays does not matter.

use serde_json::{Map, Value};

use super::{
    Accessor, AlphaMode, Animation, AnimationSampler, Buffer, BufferView, Channel, ComponentType, Extensions,
    Image, Interpolation, Material, Mesh, Mode, MorphTarget, Node, Primitive, Property, Root, Scene,
    Semantic, Skin, Sparse, SparseIndices, SparseValues, Texture, TextureInfo, TextureTransform, Type,
};

type Object = Map<String, Value>;

/// The lengths of the top-level arrays an index may name.
struct Lengths {
    accessors: usize,
    buffers: usize,
    buffer_views: usize,
    images: usize,
    materials: usize,
    meshes: usize,
    nodes: usize,
    scenes: usize,
    skins: usize,
    textures: usize,
}

/// An object being read and its path, for messages.
struct At<'v> {
    object: &'v Object,
    path: String,
}

/// Reads the document `value`, whose buffer and image URIs it moves out rather than copies (an
/// embedded buffer's base64 `data:` URI is most of a `.gltf` file).
pub(super) fn root(mut value: Value, warnings: &mut Vec<String>) -> Result<Root, String> {
    let mut buffer_uris = take_uris(&mut value, "buffers");
    let mut image_uris = take_uris(&mut value, "images");
    let Value::Object(object) = &value else {
        return Err(format!("the document must be a JSON object, got {}", kind(&value)));
    };
    let at = At { object, path: String::new() };
    if let Some(version) = asset_version(object) {
        if !version.starts_with("2.") {
            return Err(format!("asset.version: this is glTF {version}; the viewer reads glTF 2.0"));
        }
    }
    let len = |key: &str| object.get(key).and_then(Value::as_array).map_or(0, Vec::len);
    let n = Lengths {
        accessors: len("accessors"),
        buffers: len("buffers"),
        buffer_views: len("bufferViews"),
        images: len("images"),
        materials: len("materials"),
        meshes: len("meshes"),
        nodes: len("nodes"),
        scenes: len("scenes"),
        skins: len("skins"),
        textures: len("textures"),
    };
    let mut dropped_channels = Vec::new();
    let root = Root {
        accessors: at.objects("accessors", |a| accessor(&a, &n))?,
        animations: at.objects_indexed("animations", |i, a| animation(&a, i, &n, &mut dropped_channels))?,
        buffers: at.objects_indexed("buffers", |i, b| {
            Ok(Buffer {
                byte_length: b.required("byteLength", b.uint("byteLength")?)?,
                uri: buffer_uris
                    .get_mut(i)
                    .and_then(Option::take)
                    .map_or_else(|| b.text("uri"), |uri| Ok(Some(uri)))?,
                extensions: b.extensions()?,
            })
        })?,
        buffer_views: at.objects("bufferViews", |v| buffer_view(&v, &n))?,
        extensions_used: at.texts("extensionsUsed")?,
        extensions_required: at.texts("extensionsRequired")?,
        images: at.objects_indexed("images", |k, i| {
            Ok(Image {
                buffer_view: i.index("bufferView", n.buffer_views)?,
                uri: image_uris
                    .get_mut(k)
                    .and_then(Option::take)
                    .map_or_else(|| i.text("uri"), |uri| Ok(Some(uri)))?,
                mime_type: i.text("mimeType")?,
            })
        })?,
        materials: at.objects("materials", |m| material(&m, &n))?,
        meshes: at.objects("meshes", |m| mesh(&m, &n))?,
        nodes: at.objects("nodes", |node| self::node(&node, &n))?,
        scene: at.index("scene", n.scenes)?,
        scenes: at.objects("scenes", |s| Ok(Scene { nodes: s.indices("nodes", n.nodes)? }))?,
        skins: at.objects("skins", |s| {
            Ok(Skin {
                joints: s.required("joints", s.indices_if_present("joints", n.nodes)?)?,
                inverse_bind_matrices: s.index("inverseBindMatrices", n.accessors)?,
            })
        })?,
        textures: at.objects("textures", |t| Ok(Texture { source: t.index("source", n.images)? }))?,
    };
    if !dropped_channels.is_empty() {
        warnings.push(format!(
            "animation channels that target no node (KHR_animation_pointer: materials, lights, cameras) are \
             dropped: {}",
            dropped_channels.join(", ")
        ));
    }
    Ok(root)
}

/// The string `uri` of every object in array `key` of `document`, moved out (`None` where there
/// is none), index for index; a `uri` that is not a string stays, for its reader to refuse.
fn take_uris(document: &mut Value, key: &str) -> Vec<Option<String>> {
    let Some(items) = document.get_mut(key).and_then(Value::as_array_mut) else { return Vec::new() };
    let take = |item: &mut Value| match item.get_mut("uri") {
        Some(Value::String(uri)) => Some(std::mem::take(uri)),
        _ => None,
    };
    items.iter_mut().map(take).collect()
}

/// `asset.version`, when `asset` is an object that has one.
fn asset_version(root: &Object) -> Option<&str> {
    root.get("asset")?.get("version")?.as_str()
}

fn accessor(a: &At, n: &Lengths) -> Result<Accessor, String> {
    let sparse = match a.object("sparse")? {
        None => None,
        Some(s) => {
            let indices = s.required("indices", s.object("indices")?)?;
            let values = s.required("values", s.object("values")?)?;
            let index_type = indices.required("componentType", indices.component_type()?)?;
            if !matches!(index_type, ComponentType::U8 | ComponentType::U16 | ComponentType::U32) {
                return Err(format!("{}.componentType: sparse indices must be unsigned", indices.path));
            }
            Some(Sparse {
                count: s.required("count", s.uint("count")?)?,
                indices: SparseIndices {
                    buffer_view: indices
                        .required("bufferView", indices.index("bufferView", n.buffer_views)?)?,
                    byte_offset: indices.uint("byteOffset")?.unwrap_or(0),
                    component_type: index_type,
                },
                values: SparseValues {
                    buffer_view: values
                        .required("bufferView", values.index("bufferView", n.buffer_views)?)?,
                    byte_offset: values.uint("byteOffset")?.unwrap_or(0),
                },
            })
        }
    };
    Ok(Accessor {
        buffer_view: a.index("bufferView", n.buffer_views)?,
        byte_offset: a.uint("byteOffset")?.unwrap_or(0),
        component_type: a.required("componentType", a.component_type()?)?,
        normalized: a.flag("normalized")?.unwrap_or(false),
        count: a.required("count", a.uint("count")?)?,
        type_: a.required("type", a.choice("type", &Type::NAMES)?)?,
        sparse,
    })
}

fn buffer_view(v: &At, n: &Lengths) -> Result<BufferView, String> {
    let byte_stride = match v.uint("byteStride")? {
        // 0 is glTF 1.0's "tightly packed", which some writers still put there.
        None | Some(0) => None,
        // §3.6.1.1 allows 4 to 252; the importer checks a stride against its elements' size.
        Some(s) if s <= 252 => Some(s as usize),
        Some(s) => return Err(format!("{}.byteStride: {s} is more than 252", v.path)),
    };
    Ok(BufferView {
        buffer: v.required("buffer", v.index("buffer", n.buffers)?)?,
        byte_offset: v.uint("byteOffset")?.unwrap_or(0),
        byte_length: v.required("byteLength", v.uint("byteLength")?)?,
        byte_stride,
        extensions: v.extensions()?,
    })
}

fn animation(a: &At, index: usize, n: &Lengths, dropped: &mut Vec<String>) -> Result<Animation, String> {
    let name = a.text("name")?;
    let samplers = a.objects("samplers", |s| {
        const INTERPOLATIONS: [(&str, Interpolation); 3] = [
            ("LINEAR", Interpolation::Linear),
            ("STEP", Interpolation::Step),
            ("CUBICSPLINE", Interpolation::CubicSpline),
        ];
        Ok(AnimationSampler {
            input: s.required("input", s.index("input", n.accessors)?)?,
            output: s.required("output", s.index("output", n.accessors)?)?,
            interpolation: s.choice("interpolation", &INTERPOLATIONS)?.unwrap_or(Interpolation::Linear),
        })
    })?;
    let mut nodeless = 0;
    let mut channels = Vec::new();
    for c in a.required("channels", a.list("channels")?)? {
        let c = c?;
        let target = c.required("target", c.object("target")?)?;
        let Some(node) = target.index("node", n.nodes)? else {
            nodeless += 1;
            continue;
        };
        const PATHS: [(&str, Property); 4] = [
            ("translation", Property::Translation),
            ("rotation", Property::Rotation),
            ("scale", Property::Scale),
            ("weights", Property::MorphTargetWeights),
        ];
        channels.push(Channel {
            sampler: c.required("sampler", c.index("sampler", samplers.len())?)?,
            node,
            path: target.required("path", target.choice("path", &PATHS)?)?,
        });
    }
    if nodeless > 0 {
        let name = name.as_ref().map(|n| format!(" ('{n}')")).unwrap_or_default();
        dropped.push(format!("animation {index}{name}: {nodeless}"));
    }
    Ok(Animation { name, channels, samplers })
}

fn material(m: &At, n: &Lengths) -> Result<Material, String> {
    const ALPHA_MODES: [(&str, AlphaMode); 3] =
        [("OPAQUE", AlphaMode::Opaque), ("MASK", AlphaMode::Mask), ("BLEND", AlphaMode::Blend)];
    let pbr = m.object("pbrMetallicRoughness")?;
    let (base_color_factor, base_color_texture) = match &pbr {
        None => ([1.0; 4], None),
        Some(pbr) => (
            pbr.floats("baseColorFactor")?.unwrap_or([1.0; 4]),
            match pbr.object("baseColorTexture")? {
                None => None,
                Some(info) => Some(texture_info(&info, n)?),
            },
        ),
    };
    Ok(Material {
        name: m.text("name")?,
        base_color_factor,
        base_color_texture,
        alpha_mode: m.choice("alphaMode", &ALPHA_MODES)?.unwrap_or(AlphaMode::Opaque),
        alpha_cutoff: m.number("alphaCutoff")?.map(|c| c as f32),
        double_sided: m.flag("doubleSided")?.unwrap_or(false),
    })
}

fn texture_info(info: &At, n: &Lengths) -> Result<TextureInfo, String> {
    let transform = match info.object("extensions")? {
        None => None,
        Some(e) => match e.object("KHR_texture_transform")? {
            None => None,
            Some(t) => Some(TextureTransform {
                offset: t.floats("offset")?.unwrap_or([0.0; 2]),
                rotation: t.number("rotation")?.unwrap_or(0.0) as f32,
                scale: t.floats("scale")?.unwrap_or([1.0; 2]),
                tex_coord: t.small_uint("texCoord")?,
            }),
        },
    };
    Ok(TextureInfo {
        index: info.required("index", info.index("index", n.textures)?)?,
        tex_coord: info.small_uint("texCoord")?.unwrap_or(0),
        transform,
    })
}

fn mesh(m: &At, n: &Lengths) -> Result<Mesh, String> {
    let primitives = m
        .required("primitives", m.list("primitives")?)?
        .map(|p| primitive(&p?, n))
        .collect::<Result<_, _>>()?;
    Ok(Mesh { name: m.text("name")?, primitives, weights: m.float_list("weights")? })
}

fn primitive(p: &At, n: &Lengths) -> Result<Primitive, String> {
    const MODES: [Mode; 7] = [
        Mode::Points,
        Mode::Lines,
        Mode::LineLoop,
        Mode::LineStrip,
        Mode::Triangles,
        Mode::TriangleStrip,
        Mode::TriangleFan,
    ];
    let attributes = p.required("attributes", p.object("attributes")?)?;
    let attributes = attributes
        .object
        .keys()
        .map(|name| {
            Ok((Semantic::parse(name), attributes.required(name, attributes.index(name, n.accessors)?)?))
        })
        .collect::<Result<_, String>>()?;
    let mode = match p.uint("mode")? {
        None => Mode::Triangles,
        Some(code) => *MODES
            .get(code as usize)
            .ok_or_else(|| format!("{}.mode: {code} is not a primitive mode (0 to 6)", p.path))?,
    };
    let targets = match p.list("targets")? {
        None => None,
        Some(list) => Some(
            list.map(|t| {
                let t = t?;
                Ok(MorphTarget {
                    positions: t.index("POSITION", n.accessors)?,
                    normals: t.index("NORMAL", n.accessors)?,
                    tangents: t.index("TANGENT", n.accessors)?,
                })
            })
            .collect::<Result<_, String>>()?,
        ),
    };
    Ok(Primitive {
        attributes,
        indices: p.index("indices", n.accessors)?,
        material: p.index("material", n.materials)?,
        mode,
        targets,
        extensions: p.extensions()?,
    })
}

fn node(node: &At, n: &Lengths) -> Result<Node, String> {
    Ok(Node {
        name: node.text("name")?,
        children: node.indices("children", n.nodes)?,
        mesh: node.index("mesh", n.meshes)?,
        skin: node.index("skin", n.skins)?,
        matrix: node.floats("matrix")?,
        translation: node.floats("translation")?,
        rotation: node.floats("rotation")?,
        scale: node.floats("scale")?,
        weights: node.float_list("weights")?,
    })
}

/// A whole number ≥ 0: an integer as JSON writes it, or a number with no fraction (`3.0`, as
/// some writers print every number), up to 2^53 where doubles still count in ones.
fn whole(value: &Value) -> Option<u64> {
    const EXACT: f64 = (1u64 << 53) as f64;
    let float = || value.as_f64().filter(|x| x.fract() == 0.0 && (0.0..=EXACT).contains(x)).map(|x| x as u64);
    value.as_u64().or_else(float)
}

/// A value as a message quotes it: a number or string as written, anything else by its kind.
fn shown(value: &Value) -> String {
    match value {
        Value::Number(_) | Value::String(_) => value.to_string(),
        other => kind(other).to_string(),
    }
}

/// The kind of a JSON value, for messages.
fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "true or false",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

impl<'v> At<'v> {
    fn field_path(&self, key: &str) -> String {
        match self.path.is_empty() {
            true => key.to_string(),
            false => format!("{}.{key}", self.path),
        }
    }

    fn wrong(&self, key: &str, wants: &str, got: &Value) -> String {
        format!("{}: must be {wants}, got {}", self.field_path(key), shown(got))
    }

    /// The field's value; `null` counts as absent, as JSON writers use it.
    fn get(&self, key: &str) -> Option<&'v Value> {
        self.object.get(key).filter(|v| !v.is_null())
    }

    /// The value read from field `key`, which the spec requires: an error naming it when absent.
    fn required<T>(&self, key: &str, found: Option<T>) -> Result<T, String> {
        found.ok_or_else(|| format!("{}: missing (the spec requires it)", self.field_path(key)))
    }

    fn object(&self, key: &str) -> Result<Option<At<'v>>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Object(object)) => Ok(Some(At { object, path: self.field_path(key) })),
            Some(other) => Err(self.wrong(key, "an object", other)),
        }
    }

    fn array(&self, key: &str) -> Result<Option<&'v [Value]>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Array(items)) => Ok(Some(items)),
            Some(other) => Err(self.wrong(key, "an array", other)),
        }
    }

    /// The objects of array `key`, each with its path (`meshes[2]`).
    fn list(&self, key: &str) -> Result<Option<impl Iterator<Item = Result<At<'v>, String>> + 'v>, String> {
        let path = self.field_path(key);
        Ok(self.array(key)?.map(move |items| {
            items.iter().enumerate().map(move |(i, item)| match item {
                Value::Object(object) => Ok(At { object, path: format!("{path}[{i}]") }),
                other => Err(format!("{path}[{i}]: must be an object, got {}", shown(other))),
            })
        }))
    }

    /// Every object of array `key` read with `read` (an empty list when absent).
    fn objects<T>(&self, key: &str, read: impl FnMut(At<'v>) -> Result<T, String>) -> Result<Vec<T>, String> {
        let mut read = read;
        self.objects_indexed(key, |_, at| read(at))
    }

    fn objects_indexed<T>(
        &self,
        key: &str,
        mut read: impl FnMut(usize, At<'v>) -> Result<T, String>,
    ) -> Result<Vec<T>, String> {
        let Some(list) = self.list(key)? else { return Ok(Vec::new()) };
        list.enumerate().map(|(i, at)| read(i, at?)).collect()
    }

    fn uint(&self, key: &str) -> Result<Option<u64>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(value) => match whole(value) {
                Some(n) => Ok(Some(n)),
                None => Err(self.wrong(key, "a whole number ≥ 0", value)),
            },
        }
    }

    /// A uv set or similar small count.
    fn small_uint(&self, key: &str) -> Result<Option<u32>, String> {
        match self.uint(key)? {
            None => Ok(None),
            Some(n) => {
                u32::try_from(n).map(Some).map_err(|_| format!("{}: {n} is too large", self.field_path(key)))
            }
        }
    }

    fn index(&self, key: &str, len: usize) -> Result<Option<usize>, String> {
        match self.uint(key)? {
            Some(i) if i < len as u64 => Ok(Some(i as usize)),
            Some(i) => Err(format!("{}: index {i} is out of range (there are {len})", self.field_path(key))),
            None => Ok(None),
        }
    }

    fn indices_if_present(&self, key: &str, len: usize) -> Result<Option<Vec<usize>>, String> {
        let Some(items) = self.array(key)? else { return Ok(None) };
        let path = self.field_path(key);
        let index = |(k, item): (usize, &Value)| match whole(item) {
            Some(i) if i < len as u64 => Ok(i as usize),
            Some(i) => Err(format!("{path}[{k}]: index {i} is out of range (there are {len})")),
            None => Err(format!("{path}[{k}]: must be a whole number ≥ 0, got {}", shown(item))),
        };
        items.iter().enumerate().map(index).collect::<Result<_, _>>().map(Some)
    }

    /// An array of indices into an array of `len` (empty when absent).
    fn indices(&self, key: &str, len: usize) -> Result<Vec<usize>, String> {
        Ok(self.indices_if_present(key, len)?.unwrap_or_default())
    }

    fn number(&self, key: &str) -> Result<Option<f64>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(value) => value.as_f64().map(Some).ok_or_else(|| self.wrong(key, "a number", value)),
        }
    }

    fn float_list(&self, key: &str) -> Result<Option<Vec<f32>>, String> {
        let Some(items) = self.array(key)? else { return Ok(None) };
        let wrong = || format!("{}: must be an array of numbers", self.field_path(key));
        items
            .iter()
            .map(|v| v.as_f64().map(|x| x as f32).ok_or_else(wrong))
            .collect::<Result<_, _>>()
            .map(Some)
    }

    /// An array of exactly `N` numbers.
    fn floats<const N: usize>(&self, key: &str) -> Result<Option<[f32; N]>, String> {
        let Some(list) = self.float_list(key)? else { return Ok(None) };
        let found = list.len();
        list.try_into()
            .map(Some)
            .map_err(|_| format!("{}: must be {N} numbers, got {found}", self.field_path(key)))
    }

    fn flag(&self, key: &str) -> Result<Option<bool>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Bool(b)) => Ok(Some(*b)),
            Some(other) => Err(self.wrong(key, "true or false", other)),
        }
    }

    fn text(&self, key: &str) -> Result<Option<String>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.clone())),
            Some(other) => Err(self.wrong(key, "a string", other)),
        }
    }

    /// An array of strings (empty when absent).
    fn texts(&self, key: &str) -> Result<Vec<String>, String> {
        let Some(items) = self.array(key)? else { return Ok(Vec::new()) };
        let wrong = || format!("{}: must be an array of strings", self.field_path(key));
        items.iter().map(|v| v.as_str().map(String::from).ok_or_else(wrong)).collect()
    }

    /// One of the names in `choices`.
    fn choice<T: Copy>(&self, key: &str, choices: &[(&str, T)]) -> Result<Option<T>, String> {
        let Some(value) = self.get(key) else { return Ok(None) };
        let found = value.as_str().and_then(|s| choices.iter().find(|(name, _)| *name == s));
        found.map(|&(_, v)| Some(v)).ok_or_else(|| {
            let names: Vec<&str> = choices.iter().map(|(name, _)| *name).collect();
            format!("{}: {value} is not one of {}", self.field_path(key), names.join(", "))
        })
    }

    fn component_type(&self) -> Result<Option<ComponentType>, String> {
        match self.uint("componentType")? {
            None => Ok(None),
            Some(code) => ComponentType::from_code(code).map(Some).ok_or_else(|| {
                format!(
                    "{}: {code} is not one of 5120, 5121, 5122, 5123, 5125, 5126",
                    self.field_path("componentType")
                )
            }),
        }
    }

    fn extensions(&self) -> Result<Extensions, String> {
        Ok(self.object("extensions")?.map(|e| e.object.clone()).unwrap_or_default())
    }
}

#[cfg(test)]
mod tests {
    use super::super::Root;
    use crate::import::ImportError;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A document with one triangle primitive, one node and one animation, as the reader checks
    /// it; `edit` changes the JSON text first.
    fn read(edit: impl FnOnce(&mut serde_json::Value)) -> Result<(Root, Vec<String>), ImportError> {
        let mut value: serde_json::Value = serde_json::from_str(
            r#"{"asset": {"version": "2.0"},
                "buffers": [{"byteLength": 48}],
                "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
                "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                              {"bufferView": 1, "componentType": 5126, "count": 3, "type": "SCALAR"}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "_BATCHID": 1}}]}],
                "nodes": [{"mesh": 0, "children": []}],
                "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "scale"}}],
                                "samplers": [{"input": 1, "output": 0}]}]}"#,
        )
        .unwrap();
        edit(&mut value);
        let mut warnings = Vec::new();
        Root::read(&serde_json::to_vec(&value).unwrap(), &mut warnings).map(|root| (root, warnings))
    }

    fn invalid(edit: impl FnOnce(&mut serde_json::Value)) -> String {
        match read(edit) {
            Err(ImportError::Invalid(message)) => message,
            other => panic!("expected Invalid, got {other:?}"),
        }
    }

    #[test]
    fn absent_fields_take_the_spec_defaults() {
        let (root, warnings) = read(|_| {}).unwrap();
        assert!(warnings.is_empty());
        let p = &root.meshes[0].primitives[0];
        assert_eq!(p.mode, super::Mode::Triangles);
        assert_eq!(p.attribute(&super::Semantic::Positions), Some(0));
        assert_eq!(p.attribute(&super::Semantic::Other("_BATCHID".into())), Some(1));
        assert_eq!((root.buffer_views[0].byte_offset, root.buffer_views[1].byte_offset), (0, 36));
        assert_eq!(root.buffer_views[0].byte_stride, None);
        assert_eq!(root.accessors[0].byte_offset, 0);
        assert!(!root.accessors[0].normalized);
        assert_eq!(root.animations[0].samplers[0].interpolation, super::Interpolation::Linear);
        assert_eq!(root.scene, None);
    }

    #[test]
    fn every_error_names_the_field_by_its_path() {
        assert_eq!(
            invalid(|v| v["meshes"][0]["primitives"][0]["indices"] = 7.into()),
            "meshes[0].primitives[0].indices: index 7 is out of range (there are 2)"
        );
        assert_eq!(
            invalid(|v| v["accessors"][1]["componentType"] = 5124.into()),
            "accessors[1].componentType: 5124 is not one of 5120, 5121, 5122, 5123, 5125, 5126"
        );
        assert_eq!(
            invalid(|v| v["accessors"][0]["type"] = "VEC5".into()),
            r#"accessors[0].type: "VEC5" is not one of SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4"#
        );
        assert_eq!(
            invalid(|v| v["bufferViews"][1].as_object_mut().unwrap().clear()),
            "bufferViews[1].buffer: missing (the spec requires it)"
        );
        assert_eq!(
            invalid(|v| v["nodes"][0]["children"] = serde_json::json!([0, -1])),
            "nodes[0].children[1]: must be a whole number ≥ 0, got -1"
        );
        assert_eq!(
            invalid(|v| v["nodes"][0]["rotation"] = serde_json::json!([0, 0, 1])),
            "nodes[0].rotation: must be 4 numbers, got 3"
        );
        assert_eq!(
            invalid(|v| v["animations"][0]["channels"][0]["sampler"] = 1.into()),
            "animations[0].channels[0].sampler: index 1 is out of range (there are 1)"
        );
        assert_eq!(invalid(|v| v["meshes"][0] = 3.into()), "meshes[0]: must be an object, got 3");
        assert_eq!(invalid(|v| v["buffers"][0]["uri"] = 5.into()), "buffers[0].uri: must be a string, got 5");
        assert_eq!(
            invalid(|v| v["accessors"][0]["count"] = 2.5.into()),
            "accessors[0].count: must be a whole number ≥ 0, got 2.5"
        );
        assert_eq!(
            invalid(|v| v["asset"]["version"] = "1.0".into()),
            "asset.version: this is glTF 1.0; the viewer reads glTF 2.0"
        );
        assert!(matches!(Root::read(b"{\"nodes\": [", &mut Vec::new()), Err(ImportError::Json(_))));
        assert!(matches!(Root::read(b"[]", &mut Vec::new()), Err(ImportError::Invalid(_))));
    }

    #[test]
    fn uris_are_read_as_written() {
        let (root, _) = read(|v| {
            v["buffers"][0]["uri"] = "data:application/octet-stream;base64,AAAA".into();
            v["images"] =
                serde_json::json!([{"uri": "skin.png"}, {"bufferView": 1, "mimeType": "image/png"}]);
        })
        .unwrap();
        assert_eq!(root.buffers[0].uri.as_deref(), Some("data:application/octet-stream;base64,AAAA"));
        assert_eq!(root.images[0].uri.as_deref(), Some("skin.png"));
        assert_eq!((root.images[1].uri.as_deref(), root.images[1].buffer_view), (None, Some(1)));
    }

    #[test]
    fn what_older_writers_put_still_reads() {
        let (root, _) = read(|v| {
            v["accessors"][0]["count"] = 3.0.into();
            v["nodes"][0]["mesh"] = 0.0.into();
            v["bufferViews"][1]["byteStride"] = 0.into();
        })
        .unwrap();
        assert_eq!((root.accessors[0].count, root.nodes[0].mesh), (3, Some(0)));
        assert_eq!(root.buffer_views[1].byte_stride, None, "0 is glTF 1.0's tightly packed");
    }

    #[test]
    fn a_channel_without_a_node_is_dropped_with_a_warning() {
        let (root, warnings) = read(|v| {
            v["animations"][0]["name"] = "wave".into();
            let pointer = serde_json::json!({"sampler": 0, "target": {"path": "pointer"}});
            v["animations"][0]["channels"].as_array_mut().unwrap().insert(0, pointer);
        })
        .unwrap();
        assert_eq!(root.animations[0].channels.len(), 1);
        assert_eq!(root.animations[0].channels[0].path, super::Property::Scale);
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].ends_with("dropped: animation 0 ('wave'): 1"), "{}", warnings[0]);
    }
}
