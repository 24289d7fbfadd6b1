//! A loaded character: merged skinned mesh, skeleton, clips, materials and morph targets, plus
//! the convenience calls that tie them together (pose a clip, weigh its morph targets, skin the
//! mesh with the morph applied first).

use glam::{Mat4, Vec3, Vec4};

use crate::animation::{Clip, Wrap};
use crate::mesh::SkinnedMesh;
use crate::morph::MorphTarget;
use crate::skeleton::{Pose, Skeleton};
use crate::skinning;

/// How a material's alpha is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    Opaque,
    /// Fragments with alpha below the cutoff are discarded.
    Mask {
        cutoff: f32,
    },
    Blend,
}

/// An encoded image for the browser to decode.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureImage {
    pub bytes: Vec<u8>,
    /// `image/png`, `image/jpeg`, … as the file says or as sniffed from the bytes.
    pub mime_type: String,
}

/// The parts of a glTF material the viewer draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Linear RGBA multiplier.
    pub base_color_factor: Vec4,
    pub base_color_texture: Option<TextureImage>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
}

/// Everything the viewer needs of one glTF scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Character {
    pub mesh: SkinnedMesh,
    pub skeleton: Skeleton,
    pub clips: Vec<Clip>,
    pub materials: Vec<Material>,
    /// Morph targets of every primitive, numbered globally (see [`crate::morph`]); their deltas
    /// are [`SkinnedMesh::morph`].
    pub morph_targets: Vec<MorphTarget>,
    /// Things the importer dropped or changed that a user may want to know (morph targets, …).
    pub warnings: Vec<String>,
}

impl Character {
    /// The clip called `name`.
    pub fn clip(&self, name: &str) -> Option<&Clip> {
        self.clips.iter().find(|c| c.name == name)
    }

    /// The pose of `clip` at `time` (looping), starting from the rest pose.
    pub fn pose_at(&self, clip: &Clip, time: f32) -> Pose {
        let mut pose = self.skeleton.rest_pose();
        clip.sample_into(time, Wrap::Loop, &mut pose);
        pose
    }

    /// The default morph weights (node, else mesh `weights`, else 0), one per target.
    pub fn default_morph_weights(&self) -> Vec<f32> {
        self.morph_targets.iter().map(|t| t.default_weight).collect()
    }

    /// The morph weights of `clip` at `time` (looping) over the default weights.
    pub fn morph_weights_at(&self, clip: &Clip, time: f32) -> Vec<f32> {
        let mut weights = self.default_morph_weights();
        clip.sample_morph_weights(time, Wrap::Loop, &mut weights);
        weights
    }

    /// Skin matrices (`model_from_bind`) of every joint in `pose`.
    pub fn skin_matrices(&self, pose: &Pose) -> Vec<Mat4> {
        self.skeleton.pose_skin_matrices(pose)
    }

    /// CPU-skinned positions of the whole mesh in `pose`, morph targets at weight 0.
    pub fn skinned_positions(&self, pose: &Pose) -> Vec<Vec3> {
        let skin = self.skin_matrices(pose);
        skinning::skin_positions(&self.mesh.positions, &self.mesh.joints, &self.mesh.weights, &skin)
    }

    /// CPU-skinned positions of the whole mesh in `pose` with the morph `weights` (one per
    /// target) applied to the bind positions first.
    pub fn morphed_skinned_positions(&self, pose: &Pose, weights: &[f32]) -> Vec<Vec3> {
        let skin = self.skin_matrices(pose);
        let morphed = self.mesh.morph.morph_positions(&self.mesh.positions, weights);
        skinning::skin_positions(&morphed, &self.mesh.joints, &self.mesh.weights, &skin)
    }

    /// Pose and morph weights of `clip` at `time`, skinned: what the viewer draws.
    pub fn clip_skinned_positions(&self, clip: &Clip, time: f32) -> Vec<Vec3> {
        self.morphed_skinned_positions(&self.pose_at(clip, time), &self.morph_weights_at(clip, time))
    }
}
