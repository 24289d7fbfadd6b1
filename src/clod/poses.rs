//! Simplification poses: where the articulated progressive mesh is simplified, and the quadrics that
//! let several animation frames vote on every collapse.
//!
//! Houle & Poulin (2001) simplify the skinned mesh in one static pose. We call that pose `P0`; its
//! per-vertex blended skin matrix `M0(v)` maps bind space to it, and the simplifier runs on the
//! posed positions `p0(v) = M0(v) · b(v)`. With several poses (multi-pose, after Mohr & Gleicher
//! 2003), every frame `f` contributes plane quadrics measured where the triangle really is in that
//! frame, pulled back into `P0` space through `A_f(v) = Mf(v) · M0(v)⁻¹`: at a `P0` position the
//! pulled-back quadric measures the squared distance its skinned image would have from the frame's
//! plane. All quadrics are area-weighted and averaged over frames, so one pose or many give errors
//! on the same scale (squared model units).
//!
//! The pull-back is done in each vertex's local frame, by [`FrameQuadrics`] (`frame_quadrics.rs`).
//!
//! Morph targets take part: a frame poses the bind positions with the clip's morph weights at
//! that time applied first, as the viewer draws them. A morphed vertex moves by its own offset,
//! which `x_f(v)` includes, so the pull-back is unchanged; what the morph changes is the frame's
//! planes (a mouth that opens tilts the triangles around it), and those are what the frames vote
//! with. A level's created vertex carries its children's deltas, blended (`clod::morph`), so it
//! follows the morph as the pull-back assumes.

use glam::{Mat3, Mat4, Vec3};

#[cfg(test)]
use super::frame_quadrics::add_frame_quadrics;
use super::frame_quadrics::FrameQuadrics;

use crate::animation::{Clip, Wrap};
use crate::character::Character;
use crate::morph::MorphDeltas;
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
    /// pose, where one clip frame sometimes does (bench/README.md, lod-vs-meshoptimizer.mjs).
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

/// Relative distance from 1 within which a skin's scale counts as none: f32 skin matrices composed
/// along a joint chain carry about 1e-6 of round-off, and a change of units is a factor of 2.54
/// (inches) or more (centimetres, gltfpack's integer grid).
const UNIT_SCALE_TOLERANCE: f32 = 1e-3;

/// The scale from bind space to model space, when they are not in the same units: `None` for
/// ordinary skins, whose skin matrices in the rest pose are rotations and translations.
///
/// Some files keep the mesh in other units and fold the conversion into the inverse bind
/// matrices: gltfpack stores positions on an integer grid (`KHR_mesh_quantization`) and scales
/// them back in the skin; rigs exported in centimetres carry a 0.01 there. Simplifying "in the
/// bind pose" would then measure areas and attribute weights in grid units while the multi-pose
/// quadrics measure model units, and level errors would be in grid units. The scale is the
/// median over vertices of the rest-pose skin matrix of each vertex's strongest joint, measured as
/// `∛|det L|` (`L`: the linear part), so a few scaled bones (a joint scaled to zero to hide a
/// prop) do not set it.
pub fn bind_to_model_scale(character: &Character) -> Option<f32> {
    let mesh = &character.mesh;
    let skin = character.skin_matrices(&character.skeleton.rest_pose());
    let mut scales: Vec<f32> = (0..mesh.vertex_count())
        .filter_map(|v| {
            let w = mesh.weights[v];
            let strongest = (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b]))?;
            let m = skin.get(usize::from(mesh.joints[v][strongest]))?;
            let scale = Mat3::from_mat4(*m).determinant().abs().cbrt();
            (scale.is_finite() && scale > 0.0).then_some(scale)
        })
        .collect();
    if scales.is_empty() {
        return None;
    }
    let middle = scales.len() / 2;
    let (_, &mut median, _) = scales.select_nth_unstable_by(middle, f32::total_cmp);
    ((median - 1.0).abs() > UNIT_SCALE_TOLERANCE).then_some(median)
}

/// Skin matrices of every frame a multi-pose build samples: `frames_per_clip` evenly spaced
/// frames of each clip (the clip's end is left out since loops repeat their start), capped at
/// [`MAX_FRAMES`] in total by sampling fewer frames per clip, down to one; a file with more
/// clips than that (a motion library) gives one frame to each of [`MAX_FRAMES`] clips spread
/// evenly over its list.
pub fn multi_pose_frames(character: &Character, frames_per_clip: usize) -> Vec<Vec<Mat4>> {
    frame_times(character, frames_per_clip)
        .map(|(clip, time)| {
            let mut pose = character.skeleton.rest_pose();
            clip.sample_into(time, Wrap::Clamp, &mut pose);
            character.skeleton.pose_skin_matrices(&pose)
        })
        .collect()
}

/// The morph weights of the frames [`multi_pose_frames`] samples, in the same order: the clip's
/// weights at that time over the default weights (one per morph target, empty without targets).
pub fn multi_pose_morph_weights(character: &Character, frames_per_clip: usize) -> Vec<Vec<f32>> {
    frame_times(character, frames_per_clip)
        .map(|(clip, time)| {
            let mut weights = character.default_morph_weights();
            clip.sample_morph_weights(time, Wrap::Clamp, &mut weights);
            weights
        })
        .collect()
}

/// The clips and times of the multi-pose frames (see [`multi_pose_frames`]).
fn frame_times(character: &Character, frames_per_clip: usize) -> impl Iterator<Item = (&Clip, f32)> {
    let clips = character.clips.len().max(1);
    let per_clip = frames_per_clip.clamp(1, (MAX_FRAMES / clips).max(1));
    let sampled_clips = clips.min(MAX_FRAMES);
    // `k · clips / sampled_clips` is every clip when there are at most MAX_FRAMES of them.
    (0..sampled_clips).filter_map(move |k| character.clips.get(k * clips / sampled_clips)).flat_map(
        move |clip| (0..per_clip).map(move |f| (clip, clip.duration() * f as f32 / per_clip as f32)),
    )
}

/// Per vertex: whether some frame's `weights` move it, i.e. it has a non-zero delta for a target
/// some frame weighs. Its triangles change shape between frames, so they are not rigid (see
/// [`rigid_triangles`]) even when their joint is.
pub fn morphing_vertices(morph: &MorphDeltas, vertex_count: usize, weights: &[Vec<f32>]) -> Vec<bool> {
    let targets = weights.iter().map(Vec::len).max().unwrap_or(0);
    let weighed: Vec<bool> =
        (0..targets).map(|t| weights.iter().any(|w| w.get(t).is_some_and(|&x| x != 0.0))).collect();
    (0..vertex_count)
        .map(|v| morph.of(v).any(|(t, dp, _)| dp != Vec3::ZERO && weighed.get(t as usize) == Some(&true)))
        .collect()
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
///
/// `bind_scale` is the scale from bind space to the simplification pose (1, or
/// [`bind_to_model_scale`] for a skin that holds a change of units): a joint is rigid when its
/// skin matrix divided by it is a rotation plus translation. Without it no joint of a gltfpack
/// file counted as rigid and its rigid robot built in 1.37× the time.
pub fn rigid_triangles(
    joints: &[[u16; 4]],
    weights: &[[f32; 4]],
    indices: &[u32],
    frames: &[Vec<Mat4>],
    bind_scale: f32,
) -> Vec<bool> {
    let joint_count = frames.iter().map(Vec::len).min().unwrap_or(0);
    let rigid_joint: Vec<bool> = (0..joint_count)
        .map(|j| {
            frames.iter().all(|skin| {
                let l = Mat3::from_mat4(skin[j]) * bind_scale.recip();
                let gram = l.transpose() * l - Mat3::IDENTITY;
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

/// Adds, for every triangle marked in `rigid`, its area-weighted plane quadric in the
/// simplification pose (`p0_positions`: the bind pose, scaled by `bind_scale` of
/// [`rigid_triangles`]) to its three corners with weight 1: what the frames together add for it
/// (each `1 / frames` of the same plane, see [`rigid_triangles`]).
pub fn add_rigid_quadrics(quadrics: &mut [Quadric], p0_positions: &[Vec3], indices: &[u32], rigid: &[bool]) {
    for (tri, _) in indices.chunks_exact(3).zip(rigid).filter(|(_, &r)| r) {
        let [a, b, c] = [0, 1, 2].map(|k| p0_positions[tri[k] as usize].as_dvec3());
        let plane = Quadric::from_triangle(a, b, c);
        for &i in tri {
            quadrics[i as usize].add(&plane);
        }
    }
}

/// Plane quadrics averaged over frames of every clip, each frame with its morph weights, in bind
/// space (`P0` of multi-pose); `None` when the character has no clip, so the simplifier uses the
/// bind pose's own planes.
///
/// They are measured on `indices`, the triangles the simplifier sees, flat-shaded copies welded: a
/// welded-away copy has its representative's position and skin (within
/// [`super::shading::SKIN_WELD_TOLERANCE`]), so posing it again would only repeat the work, four
/// times over on a fully faceted mesh such as Fox.glb. Welded-away vertices get no planes.
/// `p0_positions`, `p0_matrices` and `bind_scale` describe `P0` as the simplifier sees it: the
/// bind pose, or the bind pose scaled by `bind_scale` where the skin holds a change of units (then
/// `p0_matrices` holds that scale for every vertex; see [`bind_to_model_scale`]); without
/// `bind_scale` no triangle counts as rigid.
pub(crate) fn multi_pose_quadrics(
    character: &Character,
    indices: &[u32],
    p0_positions: &[Vec3],
    p0_matrices: Option<&[Mat4]>,
    bind_scale: Option<f32>,
    frames_per_clip: usize,
) -> Option<Vec<Quadric>> {
    let frames = multi_pose_frames(character, frames_per_clip);
    if frames.is_empty() {
        return None;
    }
    let mesh = &character.mesh;
    let mut quadrics = vec![Quadric::ZERO; mesh.vertex_count()];
    let morph_weights = multi_pose_morph_weights(character, frames_per_clip);
    let morphing = morphing_vertices(&mesh.morph, mesh.vertex_count(), &morph_weights);
    // Triangles that only move rigidly with the bind pose add their plane in P0 once, not per
    // frame; a triangle with a morphing corner changes shape from frame to frame, so it is not one.
    let mut rigid = match bind_scale {
        Some(scale) => rigid_triangles(&mesh.joints, &mesh.weights, indices, &frames, scale),
        None => Vec::new(),
    };
    for (is_rigid, tri) in rigid.iter_mut().zip(indices.chunks_exact(3)) {
        *is_rigid &= !tri.iter().any(|&v| morphing[v as usize]);
    }
    add_rigid_quadrics(&mut quadrics, p0_positions, indices, &rigid);
    let weight = 1.0 / frames.len() as f64;
    let mut matrices = vec![Mat4::IDENTITY; mesh.vertex_count()];
    let mut frame_quadrics = FrameQuadrics::new(&mesh.positions, indices, p0_matrices, &rigid);
    // The frame's morphed bind positions: only the morphing vertices change from frame to frame.
    let morphing_vertices: Vec<usize> = (0..morphing.len()).filter(|&v| morphing[v]).collect();
    let mut morphed = if morphing_vertices.is_empty() { Vec::new() } else { mesh.positions.clone() };
    for (skin, morph_weights) in frames.iter().zip(&morph_weights) {
        // Only the corners of the other triangles need their skin matrices.
        for &v in frame_quadrics.vertices() {
            let v = v as usize;
            matrices[v] = blend_matrix(skin, mesh.joints[v], mesh.weights[v]);
        }
        if !morphing_vertices.is_empty() {
            for &v in &morphing_vertices {
                morphed[v] = mesh.positions[v] + mesh.morph.position_offset(v, morph_weights);
            }
        }
        if morphing_vertices.is_empty() {
            frame_quadrics.add(&matrices, weight);
        } else {
            frame_quadrics.add_morphed(&matrices, &morphed, weight);
        }
    }
    frame_quadrics.finish(&mut quadrics);
    Some(quadrics)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A one-joint character with `clips` empty clips.
    fn with_clips(clips: usize) -> Character {
        use crate::skeleton::{Node, SkinJoint, Transform};
        let rest = Transform { translation: Vec3::ZERO, rotation: glam::Quat::IDENTITY, scale: Vec3::ONE };
        Character {
            mesh: crate::SkinnedMesh::default(),
            skeleton: crate::Skeleton {
                nodes: vec![Node { name: "root".into(), parent: None, rest }],
                joints: vec![SkinJoint { node: 0, joint_from_bind: Mat4::IDENTITY }],
            },
            clips: (0..clips).map(|k| crate::animation::Clip::new(format!("clip {k}"), Vec::new())).collect(),
            materials: Vec::new(),
            morph_targets: Vec::new(),
            warnings: Vec::new(),
        }
    }

    #[test]
    fn frames_stay_within_the_cap_however_many_clips() {
        let frames = |clips| multi_pose_frames(&with_clips(clips), DEFAULT_FRAMES_PER_CLIP).len();
        // 8 per clip while that fits, then fewer per clip, then one frame of MAX_FRAMES clips.
        assert_eq!([0, 1, 3, 6, 7, 10, 48].map(frames), [0, 8, 24, 48, 42, 40, 48]);
        assert_eq!([49, 100, 1000].map(frames), [MAX_FRAMES; 3]);
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
        let rigid = |frames: &[Vec<Mat4>]| rigid_triangles(&joints, &weights, &indices, frames, 1.0);
        assert_eq!(rigid(&[vec![turn, stretch], vec![Mat4::IDENTITY, turn]]), [true, false]);
        // A skin that holds a change of units (gltfpack's grid) is rigid over that scale.
        let grid = Mat4::from_scale(Vec3::splat(1e-4));
        let on_grid = [vec![turn * grid, stretch * grid], vec![grid, turn * grid]];
        assert_eq!(rigid_triangles(&joints, &weights, &indices, &on_grid, 1e-4), [true, false]);
        assert_eq!(rigid(&on_grid), [false, false]);
        // One frame stretching joint 0 makes it non-rigid everywhere.
        assert_eq!(rigid(&[vec![turn, turn], vec![stretch, turn]]), [false, false]);
        // A frame without joint 1 still decides joint 0; a weight below 1 is not "alone".
        assert_eq!(rigid(&[vec![turn]]), [true, false]);
        let halved: Vec<[f32; 4]> = weights.iter().map(|w| w.map(|x| x * 0.5)).collect();
        assert_eq!(rigid_triangles(&joints, &halved, &indices, &[vec![turn]], 1.0), [false, false]);
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
        let rigid = rigid_triangles(&joints, &weights, &indices, &frames, 1.0);
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

    #[test]
    fn only_weighed_non_zero_deltas_morph_a_vertex() {
        let mut morph = MorphDeltas::default();
        morph.push_row([(0, Vec3::Z, Vec3::ZERO)]); // target 0, weighed in frame 1
        morph.push_row([(1, Vec3::Z, Vec3::ZERO)]); // target 1, never weighed
        morph.push_row([(0, Vec3::ZERO, Vec3::X)]); // a normal delta only
        morph.push_row([]);
        let weights = [vec![0.0, 0.0], vec![0.5, 0.0]];
        assert_eq!(morphing_vertices(&morph, 5, &weights), [true, false, false, false, false]);
        assert_eq!(morphing_vertices(&MorphDeltas::default(), 2, &weights), [false, false]);
    }
}
