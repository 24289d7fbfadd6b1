//! Simplification poses: where the articulated progressive mesh is simplified, and the quadrics that
//! let several animation frames vote on every collapse.
//!
//! Houle & Poulin (2001) simplify the skinned mesh in one static pose. We call that pose `P0`; its
//! per-vertex blended skin matrix `M0(v)` maps bind space to it, and the simplifier runs on the
//! posed positions `x = M0(v) · b`. With several poses (multi-pose, after Mohr & Gleicher 2003),
//! every frame `p` contributes plane quadrics measured where the triangle really is in that frame,
//! pulled back into `P0` space through `A_p(v) = Mp(v) · M0(v)⁻¹`: a plane `π` of frame `p` becomes
//! `A_p(v)ᵀ π`, so the pulled-back quadric measures, at a `P0` position, the squared distance its
//! skinned image would have from the frame's plane. All quadrics are area-weighted and averaged
//! over frames, so one pose or many give errors on the same scale (squared model units).

use glam::{DMat4, DVec4, Mat4, Vec3};

use crate::animation::Wrap;
use crate::character::Character;
use crate::skinning::blend_matrix;

/// Which static pose the progressive mesh is simplified in.
#[derive(Clone, Debug, PartialEq)]
pub enum SimplificationPose {
    /// The bind pose: the mesh exactly as stored (every skin matrix is the identity).
    Bind,
    /// One frame of one clip, e.g. a half-bent pose as in Houle & Poulin.
    ClipFrame { clip: String, time: f32 },
    /// Simplified in the bind pose, with quadrics summed over frames sampled from every clip.
    MultiPose { frames_per_clip: usize },
}

/// Frames per clip of the default multi-pose: enough to see every joint bend in a walk cycle,
/// few enough that the quadric pass stays a small part of the build.
pub const DEFAULT_FRAMES_PER_CLIP: usize = 8;

/// Upper bound on frames summed over all clips, so files with dozens of clips stay fast.
pub const MAX_FRAMES: usize = 48;

/// The per-vertex blended skin matrices (`posed_from_bind`) of one pose.
pub fn vertex_matrices(character: &Character, skin: &[Mat4]) -> Vec<Mat4> {
    let mesh = &character.mesh;
    (0..mesh.vertex_count()).map(|v| blend_matrix(skin, mesh.joints[v], mesh.weights[v])).collect()
}

/// Skin matrices of every frame a multi-pose build samples: `frames_per_clip` evenly spaced
/// frames of each clip (the clip's end is left out since loops repeat their start), capped at
/// [`MAX_FRAMES`] in total by sampling fewer frames per clip.
pub fn multi_pose_frames(character: &Character, frames_per_clip: usize) -> Vec<Vec<Mat4>> {
    let clips = character.clips.len().max(1);
    let per_clip = frames_per_clip.clamp(1, (MAX_FRAMES / clips).max(1));
    let mut frames = Vec::new();
    for clip in &character.clips {
        for f in 0..per_clip {
            let time = clip.duration() * f as f32 / per_clip as f32;
            let mut pose = character.skeleton.rest_pose();
            clip.sample_into(time, Wrap::Clamp, &mut pose);
            frames.push(character.skeleton.pose_skin_matrices(&pose));
        }
    }
    frames
}

/// A symmetric 4×4 quadric in f64 (products of plane vectors lose too much in f32 for large
/// models far from the origin).
pub type PlaneQuadric = DMat4;

/// Area-weighted plane quadrics of every vertex, averaged over `frames`, pulled back into the
/// space of `p0_matrices` (see the module docs).
///
/// `frame_vertex_matrices[f][v]` is `Mf(v)`; `p0_inverse[v]` is `M0(v)⁻¹`. Triangles with no
/// area in a frame add nothing for that frame.
pub fn pulled_back_quadrics(
    bind_positions: &[Vec3],
    indices: &[u32],
    p0_inverse: &[Mat4],
    frame_vertex_matrices: &[Vec<Mat4>],
) -> Vec<PlaneQuadric> {
    let mut quadrics = vec![DMat4::ZERO; bind_positions.len()];
    let frame_weight = 1.0 / frame_vertex_matrices.len().max(1) as f64;
    for matrices in frame_vertex_matrices {
        for tri in indices.chunks_exact(3) {
            let v = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
            let [a, b, c] = v.map(|i| matrices[i].transform_point3(bind_positions[i]).as_dvec3());
            let n = (b - a).cross(c - a);
            let double_area = n.length();
            if double_area <= 0.0 || !double_area.is_finite() {
                continue;
            }
            let normal = n / double_area;
            let plane = normal.extend(-normal.dot(a));
            let weight = 0.5 * double_area * frame_weight;
            for &i in &v {
                // The frame's plane seen from P0 space: π' = A(v)ᵀ π with A(v) = Mf(v) · M0(v)⁻¹.
                let a_from_p0 = (matrices[i] * p0_inverse[i]).as_dmat4();
                let pulled = a_from_p0.transpose() * plane;
                quadrics[i] += outer(pulled, pulled) * weight;
            }
        }
    }
    quadrics
}

fn outer(a: DVec4, b: DVec4) -> DMat4 {
    DMat4::from_cols(a * b.x, a * b.y, a * b.z, a * b.w)
}

/// Evaluates a quadric at a point: `[p 1] Q [p 1]ᵀ`.
pub fn quadric_error(q: &PlaneQuadric, p: Vec3) -> f64 {
    let h = p.as_dvec3().extend(1.0);
    h.dot(*q * h)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_pulled_back_plane_measures_distance_in_its_frame() {
        // One triangle in the z = 0 plane; the frame lifts everything by 2 along z.
        let bind = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let lift = vec![Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)); 3];
        let q = pulled_back_quadrics(&bind, &[0, 1, 2], &[Mat4::IDENTITY; 3], &[lift]);
        // Area 0.5, three corners: each corner's quadric has weight 0.5.
        assert!((quadric_error(&q[0], Vec3::ZERO)).abs() < 1e-12);
        // 1 unit off the plane in P0 is 1 unit off in the frame too: error = weight · 1².
        assert!((quadric_error(&q[0], Vec3::new(0.3, 0.3, 1.0)) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn frames_average_rather_than_add() {
        let bind = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let id = vec![Mat4::IDENTITY; 3];
        let one = pulled_back_quadrics(&bind, &[0, 1, 2], &id, std::slice::from_ref(&id));
        let two = pulled_back_quadrics(&bind, &[0, 1, 2], &id, &[id.clone(), id.clone()]);
        let p = Vec3::new(0.1, 0.2, 0.7);
        assert!((quadric_error(&one[1], p) - quadric_error(&two[1], p)).abs() < 1e-12);
    }

    #[test]
    fn a_scaled_frame_scales_the_measured_distance() {
        // The frame doubles z: a point 1 above the plane in P0 is 2 above it in the frame.
        let bind = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let stretch = vec![Mat4::from_scale(Vec3::new(1.0, 1.0, 2.0)); 3];
        let q = pulled_back_quadrics(&bind, &[0, 1, 2], &[Mat4::IDENTITY; 3], &[stretch]);
        assert!((quadric_error(&q[2], Vec3::new(0.0, 0.0, 1.0)) - 0.5 * 4.0).abs() < 1e-9);
    }
}
