//! Writes a [`crate::robot::Design`] as GLB: several skinned meshes, each with its own skin and
//! morph targets, and clips that animate joint rotations and morph weights (glTF 2.0 §3.7.2.2
//! morph targets, §3.11 animations). Layout as in [`crate::glb`]: one buffer, one tightly packed
//! view per accessor. Nodes: the joints in design order (parents first, translation only), then
//! one node per mesh at the scene root.

use std::collections::BTreeMap;

use glam::{Mat4, Vec3};
use gltf_json as json;
use json::validation::Checked::Valid;

use crate::glb::{flatten3, Builder};
use crate::robot::Design;

fn vec3_accessor(b: &mut Builder, values: &[Vec3], bounds: bool) -> json::Index<json::Accessor> {
    use json::accessor::{ComponentType as C, Type as T};
    let bytes: Vec<u8> = flatten3(values).iter().flat_map(|v| v.to_le_bytes()).collect();
    // POSITION accessors (base and targets) must carry min and max (glTF 2.0 §3.7.2.1).
    let min_max = bounds.then(|| {
        let (lo, hi) = values.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        (lo.to_array().to_vec(), hi.to_array().to_vec())
    });
    b.accessor(&bytes, values.len(), C::F32, T::Vec3, Some(json::buffer::Target::ArrayBuffer), min_max)
}

/// Serializes the design into GLB bytes.
pub fn write(design: &Design) -> Vec<u8> {
    use json::accessor::{ComponentType as C, Type as T};
    let mut b = Builder::new();
    for (name, color) in &design.materials {
        b.root.push(json::Material {
            name: Some(name.clone()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(*color),
                metallic_factor: json::material::StrengthFactor(0.3),
                roughness_factor: json::material::StrengthFactor(0.6),
                ..Default::default()
            },
            ..Default::default()
        });
    }

    // Joint nodes.
    for (i, joint) in design.joints.iter().enumerate() {
        let children: Vec<json::Index<json::Node>> = (0..design.joints.len())
            .filter(|&c| design.joints[c].parent == Some(i))
            .map(|c| json::Index::new(c as u32))
            .collect();
        let parent_head = joint.parent.map_or(Vec3::ZERO, |p| design.joints[p].head);
        b.root.push(json::Node {
            children: if children.is_empty() { None } else { Some(children) },
            name: Some(joint.name.clone()),
            translation: Some((joint.head - parent_head).to_array()),
            ..Default::default()
        });
    }

    let mut roots: Vec<json::Index<json::Node>> = (0..design.joints.len())
        .filter(|&i| design.joints[i].parent.is_none())
        .map(|i| json::Index::new(i as u32))
        .collect();
    for mesh in &design.meshes {
        let mut primitives = Vec::new();
        for prim in &mesh.primitives {
            let s = &prim.shape;
            let position = vec3_accessor(&mut b, &s.positions, true);
            let normal = vec3_accessor(&mut b, &s.normals, false);
            let joint_bytes: Vec<u8> = prim.joints.iter().flatten().flat_map(|j| j.to_le_bytes()).collect();
            let target = Some(json::buffer::Target::ArrayBuffer);
            let joints = b.accessor(&joint_bytes, prim.joints.len(), C::U16, T::Vec4, target, None);
            let weight_values: Vec<f32> = prim.weights.iter().flatten().copied().collect();
            let weights = b.floats(&weight_values, 4, T::Vec4);
            let index_bytes: Vec<u8> = s.indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect();
            let element = Some(json::buffer::Target::ElementArrayBuffer);
            let indices = b.accessor(&index_bytes, s.indices.len(), C::U16, T::Scalar, element, None);
            let mut attributes = BTreeMap::new();
            attributes.insert(Valid(json::mesh::Semantic::Positions), position);
            attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
            attributes.insert(Valid(json::mesh::Semantic::Joints(0)), joints);
            attributes.insert(Valid(json::mesh::Semantic::Weights(0)), weights);
            let targets = if prim.targets.is_empty() {
                None
            } else {
                let mut out = Vec::new();
                for (positions, normals) in &prim.targets {
                    out.push(json::mesh::MorphTarget {
                        positions: Some(vec3_accessor(&mut b, positions, true)),
                        normals: Some(vec3_accessor(&mut b, normals, false)),
                        tangents: None,
                    });
                }
                Some(out)
            };
            primitives.push(json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(indices),
                material: Some(json::Index::new(prim.material as u32)),
                mode: Valid(json::mesh::Mode::Triangles),
                targets,
            });
        }
        let mesh_index = b.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(mesh.name.to_string()),
            primitives,
            weights: if mesh.default_weights.is_empty() { None } else { Some(mesh.default_weights.clone()) },
        });
        let ibm_values: Vec<f32> = mesh
            .skin
            .iter()
            .flat_map(|&j| Mat4::from_translation(-design.joints[j].head).to_cols_array())
            .collect();
        let ibm_bytes: Vec<u8> = ibm_values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let ibm = b.accessor(&ibm_bytes, mesh.skin.len(), C::F32, T::Mat4, None, None);
        let skin = b.root.push(json::Skin {
            extensions: None,
            extras: Default::default(),
            inverse_bind_matrices: Some(ibm),
            joints: mesh.skin.iter().map(|&j| json::Index::new(j as u32)).collect(),
            name: Some(mesh.name.to_string()),
            skeleton: None,
        });
        roots.push(b.root.push(json::Node {
            mesh: Some(mesh_index),
            skin: Some(skin),
            name: Some(mesh.name.to_string()),
            ..Default::default()
        }));
    }
    let scene = b.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(design.scene.to_string()),
        nodes: roots,
    });
    b.root.scene = Some(scene);

    let mesh_nodes = design.joints.len();
    for clip in &design.clips {
        let lo = clip.times.iter().copied().fold(f32::MAX, f32::min);
        let hi = clip.times.iter().copied().fold(f32::MIN, f32::max);
        let time_bytes: Vec<u8> = clip.times.iter().flat_map(|v| v.to_le_bytes()).collect();
        let input =
            b.accessor(&time_bytes, clip.times.len(), C::F32, T::Scalar, None, Some((vec![lo], vec![hi])));
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        let mut add = |node: usize, path, output| {
            let sampler = json::Index::new(samplers.len() as u32);
            samplers.push(json::animation::Sampler {
                extensions: None,
                extras: Default::default(),
                input,
                interpolation: Valid(json::animation::Interpolation::Linear),
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
        };
        for (joint, values) in &clip.rotations {
            let bytes: Vec<u8> =
                values.iter().flat_map(|q| q.to_array()).flat_map(|v: f32| v.to_le_bytes()).collect();
            let output = b.accessor(&bytes, values.len(), C::F32, T::Vec4, None, None);
            add(*joint, json::animation::Property::Rotation, output);
        }
        for (mesh, values) in &clip.weights {
            let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
            let output = b.accessor(&bytes, values.len(), C::F32, T::Scalar, None, None);
            add(mesh_nodes + mesh, json::animation::Property::MorphTargetWeights, output);
        }
        b.root.push(json::Animation {
            extensions: None,
            extras: Default::default(),
            channels,
            name: Some(clip.name.to_string()),
            samplers,
        });
    }

    b.into_glb()
}
