//! A loaded character: merged skinned mesh, skeleton, clips and materials, plus the convenience
//! calls that tie them together (pose a clip, skin the mesh).

use glam::{Mat4, Vec3, Vec4};

use crate::animation::{Clip, Wrap};
use crate::mesh::SkinnedMesh;
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

    /// Skin matrices (`model_from_bind`) of every joint in `pose`.
    pub fn skin_matrices(&self, pose: &Pose) -> Vec<Mat4> {
        self.skeleton.pose_skin_matrices(pose)
    }

    /// CPU-skinned positions of the whole mesh in `pose`.
    pub fn skinned_positions(&self, pose: &Pose) -> Vec<Vec3> {
        let skin = self.skin_matrices(pose);
        skinning::skin_positions(&self.mesh.positions, &self.mesh.joints, &self.mesh.weights, &skin)
    }
}
