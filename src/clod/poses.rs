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

use glam::{DMat3, DMat4, DVec3, DVec4, Mat4, Vec3};

use crate::animation::Wrap;
use crate::character::Character;
use crate::simplify::Quadric;
use crate::skinning::blend_matrix;

/// Which static pose the progressive mesh is simplified in.
#[derive(Clone, Debug, PartialEq)]
pub enum SimplificationPose {
    /// The bind pose: the mesh exactly as stored (every skin matrix is the identity).
    Bind,
    /// One frame of one clip, e.g. a half-bent pose as in Houle & Poulin.
    ClipFrame { clip: String, time: f32 },
    /// Simplified in the bind pose, with quadrics summed over frames sampled from every clip.
    /// The default: of bind, mid-clip and multi-pose it gave the lowest animated error averaged
    /// over the shared models and the built-in character, and it never did worse than the bind
    /// pose, where one clip frame sometimes does (README, "Articulated progressive mesh").
    MultiPose { frames_per_clip: usize },
    /// The middle frame of the first clip (the bind pose when there is no clip): Houle &
    /// Poulin's half-bent pose without having to name one.
    MidClip,
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

/// Largest deviation of `Lᵀ L` from the identity (`L`: the linear part of a skin matrix) for
/// which a joint still counts as moving rigidly. f32 skin matrices composed along a joint chain
/// carry rounding of about 1e-6; any real scale or shear is orders of magnitude above 1e-5.
const RIGID_TOLERANCE: f32 = 1e-5;

/// Per triangle: whether it moves rigidly with the bind pose in every frame, because its three
/// corners follow one joint alone (a single weight of exactly 1) and that joint's skin matrix is
/// a rotation plus translation in every frame.
///
/// A rigidly moved triangle has, pulled back into the bind pose, the same plane and area in every
/// frame: its bind-pose plane. [`add_rigid_quadrics`] adds that once instead of once per frame
/// (on the built-in character 41 % of the triangles, skipping that share of the multi-pose
/// work). Joints missing from a frame's matrices make their triangles non-rigid.
pub fn rigid_triangles(
    joints: &[[u16; 4]],
    weights: &[[f32; 4]],
    indices: &[u32],
    frames: &[Vec<Mat4>],
) -> Vec<bool> {
    let joint_count = frames.iter().map(Vec::len).min().unwrap_or(0);
    let rigid_joint: Vec<bool> = (0..joint_count)
        .map(|j| {
            frames.iter().all(|skin| {
                let l = glam::Mat3::from_mat4(skin[j]);
                let gram = l.transpose() * l - glam::Mat3::IDENTITY;
                gram.to_cols_array().iter().all(|x| x.abs() <= RIGID_TOLERANCE)
            })
        })
        .collect();
    // The one joint a vertex follows alone, if any.
    let sole_joint = |v: usize| -> Option<u16> {
        let mut sole = None;
        for (&j, &w) in joints.get(v)?.iter().zip(weights.get(v)?) {
            match (w, sole) {
                (0.0, _) => {}
                (1.0, None) => sole = Some(j),
                _ => return None,
            }
        }
        sole.filter(|&j| rigid_joint.get(j as usize) == Some(&true))
    };
    indices
        .chunks_exact(3)
        .map(|t| {
            let j = sole_joint(t[0] as usize);
            j.is_some() && j == sole_joint(t[1] as usize) && j == sole_joint(t[2] as usize)
        })
        .collect()
}

/// Adds, for every triangle marked in `rigid`, its area-weighted bind-pose plane quadric to its
/// three corners with weight 1: what the frames together add for it (each `1 / frames` of the
/// same plane, see [`rigid_triangles`]).
pub fn add_rigid_quadrics(
    quadrics: &mut [Quadric],
    bind_positions: &[Vec3],
    indices: &[u32],
    rigid: &[bool],
) {
    for (tri, _) in indices.chunks_exact(3).zip(rigid).filter(|(_, &r)| r) {
        let [a, b, c] = [0, 1, 2].map(|k| bind_positions[tri[k] as usize].as_dvec3());
        let plane = Quadric::from_triangle(a, b, c);
        for &i in tri {
            quadrics[i as usize].add(&plane);
        }
    }
}

/// Adds the area-weighted plane quadrics of one frame to every vertex, pulled back into `P0`
/// space (see the module docs), each scaled by `frame_weight` (1 / number of frames).
///
/// `frame_matrices[v]` is `Mf(v)`; `p0_inverse[v]` is `M0(v)⁻¹`, or `None` when `P0` is the bind
/// pose (every `M0` is the identity). Triangles with no area in the frame add nothing, and so do
/// the triangles marked in `skip` (shorter or empty: none), which [`add_rigid_quadrics`] covers.
///
/// Pulling back is linear: `Σ (Aᵀπ)(Aᵀπ)ᵀ = Aᵀ (Σ ππᵀ) A` for the vertex's `A(v)`, so the planes
/// are summed per vertex in the frame first and each vertex's sum is transformed once, instead of
/// transforming every plane at every corner (three times fewer matrix products, and a plane
/// quadric per triangle instead of per corner).
pub fn add_frame_quadrics(
    quadrics: &mut [Quadric],
    bind_positions: &[Vec3],
    indices: &[u32],
    p0_inverse: Option<&[Mat4]>,
    frame_matrices: &[Mat4],
    frame_weight: f64,
    skip: &[bool],
) {
    FrameQuadrics::new(bind_positions, indices, p0_inverse, skip).add(quadrics, frame_matrices, frame_weight);
}

/// [`add_frame_quadrics`] for frame after frame of one mesh, keeping its per-frame buffers (a
/// posed position and a quadric per vertex) instead of allocating and clearing them every frame.
pub struct FrameQuadrics<'a> {
    bind_positions: &'a [Vec3],
    indices: &'a [u32],
    p0_inverse: Option<&'a [Mat4]>,
    skip: &'a [bool],
    posed: Vec<DVec3>,
    /// The frame's planes per vertex; all zero between frames.
    in_frame: Vec<Quadric>,
}

impl<'a> FrameQuadrics<'a> {
    /// The mesh, `P0` and the triangles to skip, as [`add_frame_quadrics`] takes them.
    pub fn new(
        bind_positions: &'a [Vec3],
        indices: &'a [u32],
        p0_inverse: Option<&'a [Mat4]>,
        skip: &'a [bool],
    ) -> FrameQuadrics<'a> {
        let n = bind_positions.len();
        FrameQuadrics {
            bind_positions,
            indices,
            p0_inverse,
            skip,
            posed: Vec::with_capacity(n),
            in_frame: vec![Quadric::ZERO; n],
        }
    }

    /// Adds one frame's pulled-back plane quadrics to `quadrics` (see [`add_frame_quadrics`]).
    pub fn add(&mut self, quadrics: &mut [Quadric], frame_matrices: &[Mat4], frame_weight: f64) {
        self.posed.clear();
        self.posed.extend(
            self.bind_positions.iter().zip(frame_matrices).map(|(&b, m)| m.transform_point3(b).as_dvec3()),
        );
        for (t, tri) in self.indices.chunks_exact(3).enumerate() {
            if self.skip.get(t) == Some(&true) {
                continue;
            }
            let v = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
            let [a, b, c] = v.map(|i| self.posed[i]);
            let n = (b - a).cross(c - a);
            let double_area = n.length();
            // Zero-area or non-finite (NaN compares false) triangles have no plane.
            if double_area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !double_area.is_finite()
            {
                continue;
            }
            let normal = n / double_area;
            let plane = Quadric::from_plane(normal, -normal.dot(a), 0.5 * double_area * frame_weight);
            for &i in &v {
                self.in_frame[i].add(&plane);
            }
        }
        for (i, q) in self.in_frame.iter_mut().enumerate() {
            if q.weight == 0.0 {
                continue; // no plane at this vertex in this frame
            }
            // The frame's planes seen from P0 space: A(v)ᵀ K A(v) with A(v) = Mf(v) · M0(v)⁻¹.
            let frame_from_p0 = match self.p0_inverse {
                Some(inverse) => (frame_matrices[i] * inverse[i]).as_dmat4(),
                None => frame_matrices[i].as_dmat4(),
            };
            quadrics[i].add(&pull_back(q, &frame_from_p0));
            *q = Quadric::ZERO;
        }
    }
}

/// `Aᵀ K A` of the 4×4 symmetric matrix `K = [[a, b], [bᵀ, c]]` of a quadric: the quadric that
/// measures at `p` what `q` measures at `A p`. Weight is kept.
///
/// Skin matrices are affine (`A p = L p + t`), which expands to `a' = Lᵀ a L`,
/// `b' = Lᵀ (a t + b)`, `c' = tᵀ a t + 2 b·t + c`: a third of the general product's work.
/// A matrix with a projective row takes the general product.
fn pull_back(q: &Quadric, frame_from_p0: &DMat4) -> Quadric {
    let [xx, xy, xz, yy, yz, zz] = q.a;
    let a = DMat3::from_cols(DVec3::new(xx, xy, xz), DVec3::new(xy, yy, yz), DVec3::new(xz, yz, zz));
    let b = DVec3::from_array(q.b);
    if frame_from_p0.row(3) == DVec4::W {
        let l = DMat3::from_mat4(*frame_from_p0);
        let t = frame_from_p0.w_axis.truncate();
        let at = a * t;
        let al = a * l;
        // (Lᵀ a L)[i][j] = column i of L · column j of a L.
        let (l0, l1, l2) = (l.x_axis, l.y_axis, l.z_axis);
        let (m0, m1, m2) = (al.x_axis, al.y_axis, al.z_axis);
        let bb = at + b;
        return Quadric {
            a: [l0.dot(m0), l0.dot(m1), l0.dot(m2), l1.dot(m1), l1.dot(m2), l2.dot(m2)],
            b: [l0.dot(bb), l1.dot(bb), l2.dot(bb)],
            c: t.dot(at) + 2.0 * b.dot(t) + q.c,
            weight: q.weight,
        };
    }
    let k = DMat4::from_cols(a.x_axis.extend(b.x), a.y_axis.extend(b.y), a.z_axis.extend(b.z), b.extend(q.c));
    let r = frame_from_p0.transpose() * k * *frame_from_p0;
    // Symmetric up to rounding: read the upper triangle (column j, row i ≤ j).
    Quadric {
        a: [r.x_axis.x, r.y_axis.x, r.z_axis.x, r.y_axis.y, r.z_axis.y, r.z_axis.z],
        b: [r.w_axis.x, r.w_axis.y, r.w_axis.z],
        c: r.w_axis.w,
        weight: q.weight,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    const TRIANGLE: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    fn one_frame(frame: Mat4) -> Vec<Quadric> {
        let mut q = vec![Quadric::ZERO; 3];
        add_frame_quadrics(&mut q, &TRIANGLE, &[0, 1, 2], None, &[frame; 3], 1.0, &[]);
        q
    }

    #[test]
    fn a_pulled_back_plane_measures_distance_in_its_frame() {
        // The frame lifts everything by 2 along z; P0 is the bind pose.
        let q = one_frame(Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)));
        // Area 0.5 on each corner; on the plane the error is 0, one unit off it is 0.5 · 1².
        assert!(q[0].error(DVec3::ZERO).abs() < 1e-12);
        assert!((q[0].error(DVec3::new(0.3, 0.3, 1.0)) - 0.5).abs() < 1e-9);
        assert_eq!(q[0].weight, 0.5);
    }

    #[test]
    fn affine_and_projective_pull_backs_agree() {
        // The same affine matrix through both paths: the general product is taken when the
        // last row is scaled by 2 (a projective-looking row that scales K by 4).
        let q = Quadric::from_plane(DVec3::new(0.6, 0.0, 0.8), -1.5, 2.0);
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 2.0, 0.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(3.0, -1.0, 2.0),
        )
        .as_dmat4();
        let affine = pull_back(&q, &m);
        let general = pull_back(&q, &(m * 2.0));
        let p = DVec3::new(0.3, -0.2, 1.1);
        assert!((4.0 * affine.error(p) - general.error(p)).abs() < 1e-9 * general.error(p).abs().max(1.0));
        // And the pulled-back quadric measures q at the mapped point.
        assert!((affine.error(p) - q.error(m.transform_point3(p))).abs() < 1e-9);
    }

    #[test]
    fn frames_average_rather_than_add() {
        let mut two = vec![Quadric::ZERO; 3];
        for _ in 0..2 {
            add_frame_quadrics(&mut two, &TRIANGLE, &[0, 1, 2], None, &[Mat4::IDENTITY; 3], 0.5, &[]);
        }
        let one = one_frame(Mat4::IDENTITY);
        let p = DVec3::new(0.1, 0.2, 0.7);
        assert!((one[1].error(p) - two[1].error(p)).abs() < 1e-12);
    }

    #[test]
    fn a_scaled_frame_scales_the_measured_distance() {
        // The frame doubles z: a point 1 above the plane in P0 is 2 above it in the frame.
        let q = one_frame(Mat4::from_scale(Vec3::new(1.0, 1.0, 2.0)));
        assert!((q[2].error(DVec3::Z) - 0.5 * 4.0).abs() < 1e-9);
    }

    #[test]
    fn p0_space_is_undone_before_the_frame_applies() {
        // P0 moved the vertices up by 1; the frame puts them back at z = 0. A P0 point at z = 1
        // is on the frame's plane.
        let p0 = Mat4::from_translation(Vec3::Z);
        let mut q = vec![Quadric::ZERO; 3];
        add_frame_quadrics(
            &mut q,
            &TRIANGLE,
            &[0, 1, 2],
            Some(&[p0.inverse(); 3]),
            &[Mat4::IDENTITY; 3],
            1.0,
            &[],
        );
        assert!(q[0].error(DVec3::new(0.2, 0.2, 1.0)).abs() < 1e-12);
        assert!((q[0].error(DVec3::new(0.2, 0.2, 0.0)) - 0.5).abs() < 1e-9);
    }

    /// Positions, indices, joints and weights of a skinned mesh.
    type SkinnedTriangles = (Vec<Vec3>, Vec<u32>, Vec<[u16; 4]>, Vec<[f32; 4]>);

    /// Two triangles sharing an edge: the first follows joint 0 alone, the second mixes joints 0
    /// and 1 at one corner.
    fn two_triangles() -> SkinnedTriangles {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.5)];
        let joints = vec![[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 1, 0, 0]];
        let weights =
            vec![[1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0]];
        (positions, vec![0, 1, 2, 1, 3, 2], joints, weights)
    }

    #[test]
    fn rigid_triangles_follow_one_rigid_joint() {
        let (_, indices, joints, weights) = two_triangles();
        let turn =
            Mat4::from_rotation_translation(glam::Quat::from_rotation_z(0.5), Vec3::new(0.2, 0.0, 1.0));
        let stretch = Mat4::from_scale(Vec3::new(1.0, 1.5, 1.0));
        let rigid = |frames: &[Vec<Mat4>]| rigid_triangles(&joints, &weights, &indices, frames);
        assert_eq!(rigid(&[vec![turn, stretch], vec![Mat4::IDENTITY, turn]]), [true, false]);
        // One frame stretching joint 0 makes it non-rigid everywhere.
        assert_eq!(rigid(&[vec![turn, turn], vec![stretch, turn]]), [false, false]);
        // A frame without joint 1 still decides joint 0; a weight below 1 is not "alone".
        assert_eq!(rigid(&[vec![turn]]), [true, false]);
        let halved: Vec<[f32; 4]> = weights.iter().map(|w| w.map(|x| x * 0.5)).collect();
        assert_eq!(rigid_triangles(&joints, &halved, &indices, &[vec![turn]]), [false, false]);
    }

    #[test]
    fn rigid_shortcut_equals_summing_every_frame() {
        let (positions, indices, joints, weights) = two_triangles();
        let frames: Vec<Vec<Mat4>> = [0.3f32, -0.8, 1.4]
            .iter()
            .map(|&angle| {
                let turn = Mat4::from_rotation_translation(
                    glam::Quat::from_rotation_x(angle),
                    Vec3::new(angle, 1.0, 0.0),
                );
                vec![turn, Mat4::from_rotation_y(angle) * Mat4::from_scale(Vec3::splat(1.0 + angle * 0.1))]
            })
            .collect();
        let vertex_matrices = |skin: &[Mat4]| -> Vec<Mat4> {
            (0..positions.len()).map(|v| blend_matrix(skin, joints[v], weights[v])).collect()
        };
        let weight = 1.0 / frames.len() as f64;
        let mut every_frame = vec![Quadric::ZERO; positions.len()];
        for skin in &frames {
            add_frame_quadrics(
                &mut every_frame,
                &positions,
                &indices,
                None,
                &vertex_matrices(skin),
                weight,
                &[],
            );
        }
        let rigid = rigid_triangles(&joints, &weights, &indices, &frames);
        assert_eq!(rigid, [true, false]);
        let mut shortcut = vec![Quadric::ZERO; positions.len()];
        add_rigid_quadrics(&mut shortcut, &positions, &indices, &rigid);
        for skin in &frames {
            add_frame_quadrics(
                &mut shortcut,
                &positions,
                &indices,
                None,
                &vertex_matrices(skin),
                weight,
                &rigid,
            );
        }
        let p = DVec3::new(0.3, -0.4, 0.9);
        for (a, b) in every_frame.iter().zip(&shortcut) {
            assert!((a.error(p) - b.error(p)).abs() < 1e-6 * a.error(p).abs().max(1.0), "{a:?} vs {b:?}");
            // The frames move the rigid triangle in f32: its area agrees to f32 rounding.
            assert!((a.weight - b.weight).abs() < 1e-6 * a.weight);
        }
    }
}
