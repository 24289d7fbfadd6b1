//! The node tree of the default scene (glTF 2.0 §3.5): parent links with cycle and
//! shared-child checks, rest transforms, and the [`Skeleton`] nodes — every skin joint used by the
//! scene's meshes, every mesh node, and all their ancestors — in parent-first order.
//!
//! glTF validation checks that child indices exist but not that the children lists form a forest,
//! so every walk here is bounded: traversals mark visited nodes and ancestor walks stop after as
//! many steps as there are nodes.

use std::collections::HashMap;

use super::document::{Root, Type};
use glam::{Mat4, Quat, Vec3};

use super::accessor::{read_floats, Source};
use super::{ImportError, MAX_JOINTS};
use crate::skeleton::{Node, Skeleton, SkinJoint, Transform};

/// `node {index}` or the node's name.
pub(crate) fn node_name(root: &Root, node: usize) -> String {
    match root.nodes.get(node).and_then(|n| n.name.as_deref()) {
        Some(name) => name.to_string(),
        None => format!("node {node}"),
    }
}

fn node_error(root: &Root, node: usize, problem: impl Into<String>) -> ImportError {
    ImportError::Node { node, name: node_name(root, node), problem: problem.into() }
}

/// A node of the scene that carries a mesh.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MeshInstance {
    /// glTF node index.
    pub node: usize,
    pub mesh: usize,
    pub skin: Option<usize>,
}

/// Parent links of all glTF nodes and the mesh nodes of the default scene.
pub(crate) struct SceneGraph {
    /// `parent[n]`: the glTF node whose children list holds `n`.
    parent: Vec<Option<usize>>,
    /// Mesh nodes of the default scene, in depth-first order from its root nodes.
    pub instances: Vec<MeshInstance>,
    /// The scene shown instead of scene 0 when no scene is marked as the default and scene 0
    /// has no mesh.
    pub chosen_scene: Option<usize>,
}

/// The mesh nodes under `roots`, depth first; checks the hierarchy below them (see
/// [`SceneGraph::new`]).
fn mesh_instances(
    root: &Root,
    parent: &[Option<usize>],
    roots: &[usize],
) -> Result<Vec<MeshInstance>, ImportError> {
    let n = root.nodes.len();
    let mut visited = vec![false; n];
    let mut instances = Vec::new();
    let mut stack = Vec::new();
    for &r in roots.iter().rev() {
        if r >= n {
            return Err(ImportError::Invalid(format!("the scene lists node {r} but there are {n} nodes")));
        }
        stack.push(r);
    }
    while let Some(i) = stack.pop() {
        if visited[i] {
            // A scene root listed twice, or a root that is also another root's descendant.
            if roots.contains(&i) && parent[i].is_none() {
                continue;
            }
            return Err(node_error(root, i, "is reached twice (cycle in the node hierarchy)"));
        }
        visited[i] = true;
        let node = &root.nodes[i];
        if let Some(mesh) = node.mesh {
            instances.push(MeshInstance { node: i, mesh, skin: node.skin });
        }
        for &child in node.children.iter().rev() {
            stack.push(child);
        }
    }
    Ok(instances)
}

impl SceneGraph {
    /// Builds parent links and finds the mesh nodes of the default scene.
    ///
    /// # Errors
    /// A node listed as child of two nodes or of itself, or a cycle reachable from the scene.
    pub fn new(root: &Root) -> Result<Self, ImportError> {
        let n = root.nodes.len();
        let mut parent = vec![None; n];
        for (p, node) in root.nodes.iter().enumerate() {
            for &c in &node.children {
                if c >= n {
                    return Err(node_error(root, p, format!("has child {c} but there are {n} nodes")));
                }
                if c == p {
                    return Err(node_error(root, p, "is its own child (cycle in the node hierarchy)"));
                }
                if let Some(other) = parent[c] {
                    return Err(node_error(root, c, format!("is a child of both node {other} and node {p}")));
                }
                parent[c] = Some(p);
            }
        }
        // The scene's root nodes: the marked scene, else scene 0, else every parentless node.
        let roots: Vec<usize> = match root.scene.unwrap_or(0) {
            s if s < root.scenes.len() => root.scenes[s].nodes.clone(),
            _ if root.scenes.is_empty() => (0..n).filter(|&i| parent[i].is_none()).collect(),
            s => return Err(ImportError::Invalid(format!("default scene {s} does not exist"))),
        };
        let mut instances = mesh_instances(root, &parent, &roots)?;
        // No scene is marked and scene 0 shows nothing: the spec leaves the choice to the viewer,
        // and a later scene with meshes is what the file has to show.
        let mut chosen_scene = None;
        if root.scene.is_none() && instances.is_empty() {
            for (s, scene) in root.scenes.iter().enumerate().skip(1) {
                let roots: Vec<usize> = scene.nodes.clone();
                instances = mesh_instances(root, &parent, &roots)?;
                if !instances.is_empty() {
                    chosen_scene = Some(s);
                    break;
                }
            }
        }
        Ok(Self { parent, instances, chosen_scene })
    }

    /// The skeleton nodes (see the module docs) with their rest transforms, and for every glTF
    /// node its index in [`Skeleton::nodes`] if kept. [`Skeleton::joints`] is left empty.
    ///
    /// # Errors
    /// A joint index out of range, a cycle above a needed node, or a bad rest transform.
    pub fn skeleton(&self, root: &Root) -> Result<(Skeleton, Vec<Option<usize>>), ImportError> {
        let n = root.nodes.len();
        let mut needed = vec![false; n];
        let mut seeds: Vec<usize> = Vec::new();
        for inst in &self.instances {
            seeds.push(inst.node);
            if let Some(skin) = inst.skin {
                let skin_json = root.skins.get(skin).ok_or_else(|| {
                    node_error(
                        root,
                        inst.node,
                        format!("uses skin {skin} but there are {}", root.skins.len()),
                    )
                })?;
                seeds.extend(&skin_json.joints);
            }
        }
        for seed in seeds {
            if seed >= n {
                return Err(ImportError::Invalid(format!(
                    "a skin names joint node {seed} but there are {n} nodes"
                )));
            }
            // Mark the seed and its ancestors; a path longer than the node count is a cycle.
            let mut at = Some(seed);
            let mut steps = 0;
            while let Some(i) = at {
                if needed[i] {
                    break;
                }
                needed[i] = true;
                steps += 1;
                if steps > n {
                    return Err(node_error(root, seed, "has a cycle among its ancestors"));
                }
                at = self.parent[i];
            }
        }
        // Depth-first from the top of each needed tree: parents come before children.
        let mut slots = vec![None; n];
        let mut nodes = Vec::new();
        let mut stack: Vec<usize> = (0..n).rev().filter(|&i| needed[i] && self.parent[i].is_none()).collect();
        while let Some(i) = stack.pop() {
            if slots[i].is_some() {
                return Err(node_error(root, i, "is reached twice (cycle in the node hierarchy)"));
            }
            slots[i] = Some(nodes.len());
            nodes.push(Node {
                name: node_name(root, i),
                parent: self.parent[i].and_then(|p| slots[p]),
                rest: rest_transform(root, i)?,
            });
            for &child in root.nodes[i].children.iter().rev() {
                if needed[child] {
                    stack.push(child);
                }
            }
        }
        // A needed node on a cycle has no parentless ancestor and was never reached.
        if let Some(i) = (0..n).find(|&i| needed[i] && slots[i].is_none()) {
            return Err(node_error(root, i, "has a cycle among its ancestors"));
        }
        Ok((Skeleton { nodes, joints: Vec::new() }, slots))
    }
}

/// Smallest quaternion length accepted as a rotation before normalizing it; anything shorter is
/// noise, not a direction.
const MIN_QUAT_LENGTH: f32 = 1e-6;

/// The node's local transform at rest: its TRS, or its `matrix` decomposed into TRS (a matrix with
/// shear has no exact TRS form; the decomposition keeps its scale and the nearest rotation).
fn rest_transform(root: &Root, index: usize) -> Result<Transform, ImportError> {
    let node = &root.nodes[index];
    let t = match node.matrix {
        Some(m) => {
            if !m.iter().all(|v| v.is_finite()) {
                return Err(node_error(root, index, "has a non-finite matrix"));
            }
            let (scale, rotation, translation) = Mat4::from_cols_array(&m).to_scale_rotation_translation();
            Transform { translation, rotation, scale }
        }
        None => Transform {
            translation: node.translation.map_or(Vec3::ZERO, Vec3::from_array),
            rotation: node.rotation.map_or(Quat::IDENTITY, Quat::from_array),
            scale: node.scale.map_or(Vec3::ONE, Vec3::from_array),
        },
    };
    if !(t.translation.is_finite() && t.rotation.is_finite() && t.scale.is_finite()) {
        return Err(node_error(root, index, "has a non-finite transform"));
    }
    if t.rotation.length() < MIN_QUAT_LENGTH {
        return Err(node_error(root, index, "has a zero-length rotation"));
    }
    Ok(Transform { rotation: t.rotation.normalize(), ..t })
}

/// [`Skeleton::joints`] under construction: identical (node, inverse bind matrix) pairs of
/// different skins share one joint.
#[derive(Default)]
pub(crate) struct JointTable {
    pub joints: Vec<SkinJoint>,
    lookup: HashMap<(usize, [u32; 16]), u16>,
    /// Per glTF skin, the joint index of each of its joints.
    skins: HashMap<usize, Vec<u16>>,
}

impl JointTable {
    /// The joint index of (`node`, `joint_from_bind`), adding it if new.
    ///
    /// # Errors
    /// More than [`MAX_JOINTS`] distinct joints.
    pub fn add(&mut self, node: usize, joint_from_bind: Mat4) -> Result<u16, ImportError> {
        let key = (node, joint_from_bind.to_cols_array().map(f32::to_bits));
        if let Some(&j) = self.lookup.get(&key) {
            return Ok(j);
        }
        if self.joints.len() >= MAX_JOINTS {
            return Err(ImportError::TooLarge {
                what: "skin joints".into(),
                count: self.joints.len() as u64 + 1,
                limit: MAX_JOINTS as u64,
            });
        }
        let j = self.joints.len() as u16;
        self.joints.push(SkinJoint { node, joint_from_bind });
        self.lookup.insert(key, j);
        Ok(j)
    }

    /// For each joint of glTF skin `skin`, its index in the table (adding the skin if new).
    ///
    /// Missing inverse bind matrices are identity (§3.7.3.1).
    ///
    /// # Errors
    /// Bad inverse bind matrix accessor, non-finite matrices, too many joints.
    pub fn skin(&mut self, src: Source, slots: &[Option<usize>], skin: usize) -> Result<&[u16], ImportError> {
        if !self.skins.contains_key(&skin) {
            let skin_json = &src.root.skins[skin];
            let count = skin_json.joints.len();
            if count > MAX_JOINTS {
                return Err(ImportError::TooLarge {
                    what: format!("skin {skin} joints"),
                    count: count as u64,
                    limit: MAX_JOINTS as u64,
                });
            }
            let matrices = match skin_json.inverse_bind_matrices {
                Some(a) => {
                    let usage = format!("inverse bind matrices of skin {skin}");
                    let m = read_floats(src, a, &usage, &[Type::Mat4], MAX_JOINTS)?;
                    if m.count() < count {
                        return Err(ImportError::Accessor {
                            index: a,
                            usage,
                            problem: format!("has {} matrices for {count} joints", m.count()),
                        });
                    }
                    if !m.values.iter().all(|v| v.is_finite()) {
                        return Err(ImportError::Accessor {
                            index: a,
                            usage,
                            problem: "has non-finite values".into(),
                        });
                    }
                    m.values
                }
                None => Mat4::IDENTITY.to_cols_array().repeat(count),
            };
            let mut remap = Vec::with_capacity(count);
            for (k, &joint) in skin_json.joints.iter().enumerate() {
                // Every joint was marked needed by `SceneGraph::skeleton`.
                let node = slots.get(joint).copied().flatten().ok_or_else(|| {
                    ImportError::Invalid(format!(
                        "skin {skin} joint {k} names node {joint} outside the scene"
                    ))
                })?;
                let cols: [f32; 16] = matrices[16 * k..16 * k + 16].try_into().unwrap_or([0.0; 16]);
                remap.push(self.add(node, Mat4::from_cols_array(&cols))?);
            }
            self.skins.insert(skin, remap);
        }
        Ok(&self.skins[&skin])
    }
}
