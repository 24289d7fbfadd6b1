//! Writes the character as a binary glTF 2.0 file (glTF 2.0 §4.4 GLB container) with `gltf-json`.
//!
//! Layout: one buffer holding, in order, each primitive's POSITION, NORMAL, TEXCOORD_0, COLOR_0,
//! JOINTS_0 (u16), WEIGHTS_0 and indices (u32), then the inverse bind matrices, then every
//! animation sampler's input and output. Every accessor has its own tightly packed buffer view
//! starting on a 4-byte boundary. Nodes: the joints in [`crate::body::joint`] order, then the
//! skinned mesh node; the scene's roots are the hips and the mesh node. Output is deterministic:
//! the JSON is serialized from ordered structures (attribute maps are `BTreeMap`s) and numbers
//! are printed by serde_json's shortest round-trip formatting.

use std::collections::BTreeMap;

use glam::{Mat4, Vec3};
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};

use crate::body::Joint;
use crate::clips::{rest_locals, Clip, Interpolation, Track};
use crate::regions::{Primitive, Region};

/// Accumulates the binary chunk and the accessors that point into it.
pub struct Builder {
    pub root: json::Root,
    pub bin: Vec<u8>,
}

impl Builder {
    /// An empty document and binary chunk.
    pub fn new() -> Builder {
        Builder { root: json::Root::default(), bin: Vec::new() }
    }

    /// The `.glb`: the binary chunk padded to 4 bytes as buffer 0, the generator's asset record,
    /// the JSON and the chunk.
    pub fn into_glb(mut self) -> Vec<u8> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        self.root.asset = json::Asset {
            generator: Some("clod-viewer tools/make-character".to_string()),
            version: "2.0".to_string(),
            ..Default::default()
        };
        let json_text = json::serialize::to_vec(&self.root).expect("glTF JSON always serializes");
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
            json: std::borrow::Cow::Owned(json_text),
            bin: Some(std::borrow::Cow::Owned(self.bin)),
        };
        glb.to_vec().expect("GLB of in-memory data always writes")
    }

    /// Appends `bytes` as a new buffer view (4-byte aligned) and returns an accessor over it.
    #[allow(clippy::too_many_arguments)]
    pub fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: Option<json::buffer::Target>,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let view = self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(self.bin.len())),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: Default::default(),
        });
        self.bin.extend_from_slice(bytes);
        let (min, max) = match min_max {
            Some((lo, hi)) => (Some(json::Value::from(lo)), Some(json::Value::from(hi))),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    pub fn floats(
        &mut self,
        values: &[f32],
        per_item: usize,
        type_: json::accessor::Type,
    ) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let target = Some(json::buffer::Target::ArrayBuffer);
        let component = json::accessor::ComponentType::F32;
        self.accessor(&bytes, values.len() / per_item, component, type_, target, None)
    }
}

pub fn flatten3(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// The model-space rest matrix of every joint, chained from the node TRS exactly as a reader
/// computes it (so the inverse bind matrices match the nodes bit for bit in intent).
pub fn model_from_joint_rest(joints: &[Joint]) -> Vec<Mat4> {
    let locals = rest_locals(joints);
    let mut out: Vec<Mat4> = Vec::with_capacity(joints.len());
    for (j, &(t, r)) in joints.iter().zip(&locals) {
        let parent_from_joint = Mat4::from_rotation_translation(r, t);
        out.push(match j.parent {
            Some(p) => out[p] * parent_from_joint,
            None => parent_from_joint,
        });
    }
    out
}

/// Serializes the character into GLB bytes.
pub fn write(joints: &[Joint], primitives: &[Primitive], clips: &[Clip]) -> Vec<u8> {
    use json::accessor::{ComponentType as C, Type as T};
    let mut b = Builder::new();

    // Materials, one per region, in region order.
    for region in Region::ALL {
        let material = json::Material {
            name: Some(region.name().to_string()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(region.base_color()),
                metallic_factor: json::material::StrengthFactor(0.0),
                roughness_factor: json::material::StrengthFactor(0.8),
                ..Default::default()
            },
            ..Default::default()
        };
        b.root.push(material);
    }

    let mut gltf_primitives = Vec::new();
    for (prim, region) in primitives.iter().zip(Region::ALL) {
        if prim.indices.is_empty() {
            continue;
        }
        let (lo, hi) =
            prim.positions.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let pos_bytes: Vec<u8> = flatten3(&prim.positions).iter().flat_map(|v| v.to_le_bytes()).collect();
        let position = b.accessor(
            &pos_bytes,
            prim.positions.len(),
            C::F32,
            T::Vec3,
            Some(json::buffer::Target::ArrayBuffer),
            Some((lo.to_array().to_vec(), hi.to_array().to_vec())),
        );
        let normal = b.floats(&flatten3(&prim.normals), 3, T::Vec3);
        let uv_values: Vec<f32> = prim.uvs.iter().flat_map(|v| v.to_array()).collect();
        let uv = b.floats(&uv_values, 2, T::Vec2);
        let color_values: Vec<f32> = prim.colors.iter().flat_map(|v| v.to_array()).collect();
        let color = b.floats(&color_values, 4, T::Vec4);
        let joint_bytes: Vec<u8> = prim.joints.iter().flatten().flat_map(|j| j.to_le_bytes()).collect();
        let joints_acc = b.accessor(
            &joint_bytes,
            prim.joints.len(),
            C::U16,
            T::Vec4,
            Some(json::buffer::Target::ArrayBuffer),
            None,
        );
        let weight_values: Vec<f32> = prim.weights.iter().flatten().copied().collect();
        let weights = b.floats(&weight_values, 4, T::Vec4);
        // 16-bit indices whenever the primitive's vertices fit (they do at this density): smaller,
        // and the most common index type in real files.
        let (index_bytes, index_type): (Vec<u8>, _) = if prim.positions.len() <= usize::from(u16::MAX) {
            (prim.indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(), C::U16)
        } else {
            (prim.indices.iter().flat_map(|i| i.to_le_bytes()).collect(), C::U32)
        };
        let indices = b.accessor(
            &index_bytes,
            prim.indices.len(),
            index_type,
            T::Scalar,
            Some(json::buffer::Target::ElementArrayBuffer),
            None,
        );
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), position);
        attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
        attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), uv);
        attributes.insert(Valid(json::mesh::Semantic::Colors(0)), color);
        attributes.insert(Valid(json::mesh::Semantic::Joints(0)), joints_acc);
        attributes.insert(Valid(json::mesh::Semantic::Weights(0)), weights);
        gltf_primitives.push(json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: Some(json::Index::new(region as u32)),
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        });
    }
    let mesh = b.root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("Body".to_string()),
        primitives: gltf_primitives,
        weights: None,
    });

    // Joint nodes with their rest TRS, then the skin with its inverse bind matrices.
    let locals = rest_locals(joints);
    for (i, (j, &(t, r))) in joints.iter().zip(&locals).enumerate() {
        let children: Vec<json::Index<json::Node>> = joints
            .iter()
            .enumerate()
            .filter(|(_, c)| c.parent == Some(i))
            .map(|(c, _)| json::Index::new(c as u32))
            .collect();
        b.root.push(json::Node {
            children: if children.is_empty() { None } else { Some(children) },
            name: Some(j.name.to_string()),
            rotation: Some(json::scene::UnitQuaternion(r.to_array())),
            translation: Some(t.to_array()),
            ..Default::default()
        });
    }
    let ibm_values: Vec<f32> =
        model_from_joint_rest(joints).iter().flat_map(|m| m.inverse().to_cols_array()).collect();
    let ibm_bytes: Vec<u8> = ibm_values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let ibm = b.accessor(&ibm_bytes, joints.len(), C::F32, T::Mat4, None, None);
    let skin = b.root.push(json::Skin {
        extensions: None,
        extras: Default::default(),
        inverse_bind_matrices: Some(ibm),
        joints: (0..joints.len()).map(|i| json::Index::new(i as u32)).collect(),
        name: Some("Armature".to_string()),
        skeleton: Some(json::Index::new(0)),
    });
    let body = b.root.push(json::Node {
        mesh: Some(mesh),
        skin: Some(skin),
        name: Some("Body".to_string()),
        ..Default::default()
    });
    let scene = b.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some("Character".to_string()),
        nodes: vec![json::Index::new(0), body],
    });
    b.root.scene = Some(scene);

    for clip in clips {
        write_clip(&mut b, clip);
    }

    b.into_glb()
}

fn write_clip(b: &mut Builder, clip: &Clip) {
    use json::accessor::{ComponentType as C, Type as T};
    let time_bytes: Vec<u8> = clip.times.iter().flat_map(|v| v.to_le_bytes()).collect();
    let lo = clip.times.iter().copied().fold(f32::MAX, f32::min);
    let hi = clip.times.iter().copied().fold(f32::MIN, f32::max);
    // Sampler inputs must carry min and max (glTF 2.0 §3.11).
    let input =
        b.accessor(&time_bytes, clip.times.len(), C::F32, T::Scalar, None, Some((vec![lo], vec![hi])));
    let interpolation = match clip.interpolation {
        Interpolation::Linear => json::animation::Interpolation::Linear,
        Interpolation::CubicSpline => json::animation::Interpolation::CubicSpline,
    };
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    for track in &clip.tracks {
        let (node, path, output) = match track {
            Track::Rotation { node, values } => {
                let flat: Vec<f32> = values.iter().flat_map(|v| v.to_array()).collect();
                let bytes: Vec<u8> = flat.iter().flat_map(|v| v.to_le_bytes()).collect();
                (
                    *node,
                    json::animation::Property::Rotation,
                    b.accessor(&bytes, values.len(), C::F32, T::Vec4, None, None),
                )
            }
            Track::Translation { node, values } => {
                let bytes: Vec<u8> = flatten3(values).iter().flat_map(|v| v.to_le_bytes()).collect();
                (
                    *node,
                    json::animation::Property::Translation,
                    b.accessor(&bytes, values.len(), C::F32, T::Vec3, None, None),
                )
            }
        };
        let sampler = json::Index::new(samplers.len() as u32);
        samplers.push(json::animation::Sampler {
            extensions: None,
            extras: Default::default(),
            input,
            interpolation: Valid(interpolation),
            output,
        });
        channels.push(json::animation::Channel {
            sampler,
            target: json::animation::Target {
                extensions: None,
                extras: Default::default(),
                node: json::Index::new(node as u32),
                path: Valid(path),
            },
            extensions: None,
            extras: Default::default(),
        });
    }
    b.root.push(json::Animation {
        extensions: None,
        extras: Default::default(),
        channels,
        name: Some(clip.name.to_string()),
        samplers,
    });
}
