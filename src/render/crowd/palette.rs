//! The crowd's pose palette (Larkin 2011, §2 "animation"): one clip pre-sampled at a fixed rate
//! into rows of `model_from_bind` joint matrices, so that every instance reads its pose from the
//! row nearest its own clip time instead of evaluating the skeleton. One row costs
//! `joints × 64` bytes; the GPU holds the palette as an `rgba32float` texture, each pose row laid
//! out as the single view's joint texture ([`crate::render::joint_texture`]: four texels per
//! column-major matrix, at most 512 joints to a texture row, so a pose of more joints spans
//! several texture rows), which WebGPU and WebGL2 both read with `textureLoad`. Each row also
//! holds the clip's morph-target weights at that time (glTF §3.7.2.2, over the character's default
//! weights), a second texture of `⌈targets / 4⌉` texels by `rows`, so an instance's face moves
//! with its own clip time as its skeleton does.

use glam::Mat4;

use crate::character::Character;
use crate::render::joint_texture::{joint_texels, joint_texture_size};

/// Samples per second of clip time: at 30 a pose is at most 1/60 s from the clip's own, less than
/// a walk moves a foot by a pixel at crowd distances.
pub const PALETTE_RATE: f32 = 30.0;
/// Most rows: WebGL2's smallest guaranteed texture height. Longer clips are sampled more sparsely,
/// and so are characters of more than 512 joints, whose poses take several texture rows each.
pub const MAX_ROWS: usize = 2048;

/// A clip sampled into rows of joint matrices (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct PosePalette {
    /// Joints per row (the character's skin joints, at least 1).
    pub joints: usize,
    /// Rows; row `r` is the pose at `r / rows × duration`.
    pub rows: usize,
    /// Seconds the rows span (0: one row, the rest pose).
    pub duration: f32,
    /// `rows × joints` matrices, row after row.
    pub matrices: Vec<Mat4>,
    /// Morph targets per row (the character's, 0 when it has none).
    pub targets: usize,
    /// `rows × targets` morph weights, row after row.
    pub weights: Vec<f32>,
    /// The clip asked for (`None`: the rest pose; a clip that does not exist or lasts no time
    /// also gives the rest pose, and is kept here so that it is not sampled again).
    pub clip: Option<usize>,
}

impl PosePalette {
    /// Samples `clip` of `character` (`None`, or a clip index out of range, gives the rest pose).
    pub fn sample(character: &Character, clip: Option<usize>) -> Self {
        let joints = character.skeleton.joints.len().max(1);
        let targets = character.morph_targets.len();
        let clip_ref = clip.and_then(|c| character.clips.get(c)).filter(|c| c.duration() > 0.0);
        let Some(c) = clip_ref else {
            let mut matrices = character.skin_matrices(&character.skeleton.rest_pose());
            matrices.resize(joints, Mat4::IDENTITY);
            let weights = character.default_morph_weights();
            return Self { joints, rows: 1, duration: 0.0, matrices, targets, weights, clip };
        };
        let duration = c.duration();
        let texture_rows_per_pose = joint_texture_size(joints).1 as usize;
        let rows = ((duration * PALETTE_RATE).ceil() as usize).clamp(1, MAX_ROWS / texture_rows_per_pose);
        let mut matrices = Vec::with_capacity(rows * joints);
        let mut weights = Vec::with_capacity(rows * targets);
        for r in 0..rows {
            let time = r as f32 / rows as f32 * duration;
            let mut row = character.skin_matrices(&character.pose_at(c, time));
            row.resize(joints, Mat4::IDENTITY);
            matrices.extend(row);
            weights.extend(character.morph_weights_at(c, time));
        }
        Self { joints, rows, duration, matrices, targets, weights, clip }
    }

    /// The row nearest clip time `time` (seconds, looping; any finite or infinite value).
    pub fn row_at(&self, time: f64) -> u32 {
        if self.rows <= 1 || !time.is_finite() || self.duration <= 0.0 {
            return 0;
        }
        let phase = (time / f64::from(self.duration)).rem_euclid(1.0);
        ((phase * self.rows as f64).round() as usize % self.rows) as u32
    }

    /// Width and height of the palette texture: each pose row is a joint texture
    /// ([`joint_texture_size`]) and they stack, so `crowd.wgsl` finds a pose's texture rows as the
    /// height over the weights texture's (one row per pose).
    pub fn texture_size(&self) -> (u32, u32) {
        let (width, rows_per_pose) = joint_texture_size(self.joints);
        (width, rows_per_pose * self.rows as u32)
    }

    /// The palette as texels ([`Self::texture_size`]): row after row, each pose's matrices laid
    /// out as [`joint_texels`] lays out a frame's.
    pub fn texels(&self) -> Vec<[f32; 4]> {
        self.matrices.chunks(self.joints.max(1)).flat_map(|pose| joint_texels(pose, self.joints)).collect()
    }

    /// Texels per row of the weights texture: four weights each, at least one (a texture cannot
    /// be empty).
    pub fn weight_texels_per_row(&self) -> usize {
        self.targets.div_ceil(4).max(1)
    }

    /// The morph weights as texels: `rows` rows of [`Self::weight_texels_per_row`] RGBA32F texels,
    /// target `t` at texel `t / 4`, channel `t % 4`; zero past the last target, and everywhere when
    /// `apply` is false (morphs switched off, or more targets than the renderer binds).
    pub fn weight_texels(&self, apply: bool) -> Vec<[f32; 4]> {
        let width = self.weight_texels_per_row();
        let mut texels = vec![[0.0; 4]; width * self.rows];
        if apply && self.targets > 0 {
            for (r, row) in self.weights.chunks_exact(self.targets).enumerate() {
                for (t, &w) in row.iter().enumerate() {
                    texels[r * width + t / 4][t % 4] = w;
                }
            }
        }
        texels
    }
}
