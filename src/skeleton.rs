//! The node hierarchy that drives a character, its skin joints, and poses of it.
//!
//! A [`Skeleton`] keeps every node the character needs — skin joints, nodes that carry rigid parts,
//! and their non-joint ancestors up to the scene root — in parent-first order, so one forward pass
//! computes `model_from_node` for all of them. Model space is the glTF scene's root space.
//! A [`SkinJoint`] pairs a node with its inverse bind matrix `joint_from_bind`; the skin matrix of
//! joint `j` in a pose is `model_from_node[joint.node] * joint.joint_from_bind`, which maps a
//! bind-space vertex to its posed model-space position.

use glam::{Mat4, Quat, Vec3};

/// A translation, rotation and scale, applied as `T * R * S` (glTF's TRS order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Transform {
    pub const IDENTITY: Self = Self { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };

    /// The matrix `parent_from_node` of this transform.
    pub fn to_matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// One node of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The glTF node's name, or `node <index>` when it has none.
    pub name: String,
    /// Index of the parent in [`Skeleton::nodes`]; always smaller than this node's own index.
    pub parent: Option<usize>,
    /// Local transform at rest (the file's node transform).
    pub rest: Transform,
}

/// A skin joint: the node it follows and the inverse bind matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinJoint {
    /// Index into [`Skeleton::nodes`].
    pub node: usize,
    /// Maps bind-space points into the joint's node space (glTF's inverse bind matrix).
    pub joint_from_bind: Mat4,
}

/// Node hierarchy plus skin joints; see the module docs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    /// Parent-first: `nodes[i].parent < Some(i)`.
    pub nodes: Vec<Node>,
    /// The joints vertices refer to through [`crate::SkinnedMesh::joints`].
    pub joints: Vec<SkinJoint>,
}

/// Local transforms of every node of a [`Skeleton`], as produced by animation sampling.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    pub local: Vec<Transform>,
}

impl Skeleton {
    /// The rest pose: every node at its file transform.
    pub fn rest_pose(&self) -> Pose {
        Pose { local: self.nodes.iter().map(|n| n.rest).collect() }
    }

    /// `model_from_node` for every node of `pose`, in one parent-first pass.
    ///
    /// # Panics
    /// If `pose` has a different node count than the skeleton.
    pub fn model_from_node(&self, pose: &Pose) -> Vec<Mat4> {
        assert_eq!(pose.local.len(), self.nodes.len(), "pose does not match the skeleton");
        let mut out: Vec<Mat4> = Vec::with_capacity(self.nodes.len());
        for (node, local) in self.nodes.iter().zip(&pose.local) {
            let parent_from_node = local.to_matrix();
            let m = match node.parent {
                Some(p) => out[p] * parent_from_node,
                None => parent_from_node,
            };
            out.push(m);
        }
        out
    }

    /// Skin matrices (`model_from_bind`) of every joint, given `model_from_node` of a pose.
    pub fn skin_matrices(&self, model_from_node: &[Mat4]) -> Vec<Mat4> {
        self.joints.iter().map(|j| model_from_node[j.node] * j.joint_from_bind).collect()
    }

    /// Skin matrices of `pose`: [`Self::model_from_node`] followed by [`Self::skin_matrices`].
    pub fn pose_skin_matrices(&self, pose: &Pose) -> Vec<Mat4> {
        self.skin_matrices(&self.model_from_node(pose))
    }
}
