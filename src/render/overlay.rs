//! Overlays drawn on all three views alike: the triangle edges of the drawn level (wireframe), a
//! colour per level (so a change of level is seen even where shading hides it), or the skeleton
//! (a line from each skin joint to its parent joint, in the animated pose). Pure data: the edge
//! list each level's line-list index buffer holds, the tint each draw gets, and the bone segments
//! of a pose in model space.
//!
//! A geomorphing draw shows neither level exactly, so its tint is the two levels' tints mixed by
//! the morph parameter `t`, as its shape is.

use glam::Mat4;

use super::plan::Morph;
use crate::skeleton::Skeleton;

/// What is drawn over the shaded views.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Overlay {
    #[default]
    None,
    /// The edges of the drawn triangles, dark lines over the shading.
    Wireframe,
    /// Each level tinted with its own colour.
    Levels,
    /// The skin's bones, bright lines drawn through the body.
    Skeleton,
    /// A heat map of where each view differs from the full-detail reference (the live meter's
    /// pictures, `difference.wgsl`): magenta for coverage, amber for colour.
    Difference,
}

/// Distinct colours for levels 0, 1, 2, … (linear RGB), repeating after the last: blue, orange,
/// green, red, purple, yellow, cyan, pink — hues far apart, so neighbouring levels never look alike.
const LEVEL_COLORS: [[f32; 3]; 8] = [
    [0.10, 0.30, 0.90],
    [0.95, 0.40, 0.05],
    [0.10, 0.70, 0.15],
    [0.85, 0.08, 0.10],
    [0.50, 0.20, 0.80],
    [0.95, 0.85, 0.10],
    [0.05, 0.75, 0.80],
    [0.95, 0.45, 0.70],
];

/// How much of a surface's own colour the level tint replaces: enough to tell the levels apart,
/// little enough that lighting still shows the shape.
pub const TINT_STRENGTH: f32 = 0.7;

/// The tint of a draw of level `level` morphing towards its ancestors in `morph.coarse` by
/// `morph.t` (`None`: no morph): linear RGB and strength, all zero when the overlay is not [`Overlay::Levels`].
pub fn draw_tint(overlay: Overlay, level: usize, morph: Option<Morph>) -> [f32; 4] {
    if overlay != Overlay::Levels {
        return [0.0; 4];
    }
    let (coarse_level, t) = morph.map_or((level, 0.0), |m| (m.coarse, m.t.clamp(0.0, 1.0)));
    let fine = LEVEL_COLORS[level % LEVEL_COLORS.len()];
    let coarse = LEVEL_COLORS[coarse_level % LEVEL_COLORS.len()];
    let mix = |c: usize| fine[c] * (1.0 - t) + coarse[c] * t;
    [mix(0), mix(1), mix(2), TINT_STRENGTH]
}

/// The edges of a triangle list as a line list: each undirected edge once, as `(low, high)` vertex
/// pairs in increasing order. A trailing partial triangle is ignored.
pub fn edge_indices(triangles: &[u32]) -> Vec<u32> {
    let mut edges: Vec<(u32, u32)> = triangles
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .filter(|(a, b)| a != b)
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges.into_iter().flat_map(|(a, b)| [a, b]).collect()
}

/// The bones of the skin in a pose, as a line list in model space: for each joint whose node has
/// an ancestor that is also a skin joint, the nearest such ancestor's origin then the joint's own
/// origin (the translation of `model_from_node`). Joints come in skin order; a joint without a
/// joint above it (the root, or a rigid part's joint hung under plain nodes only) draws nothing,
/// so `n` joints give at most `n - 1` segments.
///
/// `model_from_node` is [`Skeleton::model_from_node`] of the pose, the one the skin matrices are
/// computed from. A joint naming a node past its end is skipped (the importer never makes one).
pub fn bone_segments(skeleton: &Skeleton, model_from_node: &[Mat4]) -> Vec<[f32; 3]> {
    let mut joint_of_node = vec![None; skeleton.nodes.len()];
    for (j, joint) in skeleton.joints.iter().enumerate() {
        if let Some(slot) = joint_of_node.get_mut(joint.node) {
            slot.get_or_insert(j);
        }
    }
    let origin = |node: usize| model_from_node.get(node).map(|m| m.w_axis.truncate().to_array());
    let mut lines = Vec::new();
    for joint in &skeleton.joints {
        // Parents come first (`parent < node`), so this walk ends within `nodes.len()` steps.
        let mut up = skeleton.nodes.get(joint.node).and_then(|n| n.parent);
        while let Some(node) = up {
            if let Some(parent_joint) = joint_of_node.get(node).copied().flatten() {
                let parent_node = skeleton.joints[parent_joint].node;
                if let (Some(a), Some(b)) = (origin(parent_node), origin(joint.node)) {
                    lines.extend([a, b]);
                }
                break;
            }
            up = skeleton.nodes.get(node).and_then(|n| n.parent);
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_quad_of_two_triangles_has_five_edges() {
        // 0-1-2 and 0-2-3 share the diagonal 0-2; the degenerate 1-1-3 adds only 1-3.
        let edges = edge_indices(&[0, 1, 2, 0, 2, 3, 1, 1, 3, 7]);
        assert_eq!(edges, [0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3]);
        assert!(edge_indices(&[]).is_empty());
    }

    #[test]
    fn level_tints_differ_and_geomorphs_mix_them() {
        assert_eq!(draw_tint(Overlay::None, 2, None), [0.0; 4]);
        assert_eq!(draw_tint(Overlay::Wireframe, 2, Some(Morph { coarse: 3, t: 0.5 })), [0.0; 4]);
        for level in 0..LEVEL_COLORS.len() {
            assert_ne!(draw_tint(Overlay::Levels, level, None), draw_tint(Overlay::Levels, level + 1, None));
        }
        let fine = draw_tint(Overlay::Levels, 1, None);
        let coarse = draw_tint(Overlay::Levels, 2, None);
        assert_eq!(draw_tint(Overlay::Levels, 1, Some(Morph { coarse: 2, t: 0.0 })), fine);
        assert_eq!(draw_tint(Overlay::Levels, 1, Some(Morph { coarse: 2, t: 1.0 })), coarse);
        let half = draw_tint(Overlay::Levels, 1, Some(Morph { coarse: 2, t: 0.5 }));
        for c in 0..3 {
            assert!((half[c] - 0.5 * (fine[c] + coarse[c])).abs() < 1e-6);
        }
        assert_eq!(half[3], TINT_STRENGTH);
    }

    #[test]
    fn a_three_joint_chain_draws_two_bones_from_parent_to_child() {
        use crate::skeleton::{Node, SkinJoint, Transform};
        use glam::{Quat, Vec3};
        // node 0: plain scene root, moved up 10; node 1: hip (joint 0), at x = 1;
        // node 2: knee (joint 2), 2 below the hip, turned 90° about z; node 3: foot (joint 1),
        // 3 along the knee's x (which the turn points up: +y).
        let node = |name: &str, parent, translation, rotation| Node {
            name: name.into(),
            parent,
            rest: Transform { translation, rotation, scale: Vec3::ONE },
        };
        let skeleton = Skeleton {
            nodes: vec![
                node("root", None, Vec3::new(0.0, 10.0, 0.0), Quat::IDENTITY),
                node("hip", Some(0), Vec3::new(1.0, 0.0, 0.0), Quat::IDENTITY),
                node("knee", Some(1), Vec3::new(0.0, -2.0, 0.0), Quat::from_rotation_z(90f32.to_radians())),
                node("foot", Some(2), Vec3::new(3.0, 0.0, 0.0), Quat::IDENTITY),
            ],
            joints: [1, 3, 2].map(|node| SkinJoint { node, joint_from_bind: Mat4::IDENTITY }).to_vec(),
        };
        let lines = bone_segments(&skeleton, &skeleton.model_from_node(&skeleton.rest_pose()));
        let round = |p: [f32; 3]| p.map(|c| (c * 1e4).round() / 1e4 + 0.0);
        let rounded: Vec<[f32; 3]> = lines.into_iter().map(round).collect();
        // Skin order: the hip (no joint above) draws nothing; foot: knee → foot; knee: hip → knee.
        assert_eq!(rounded, [[1.0, 8.0, 0.0], [1.0, 11.0, 0.0], [1.0, 10.0, 0.0], [1.0, 8.0, 0.0]]);
        // No joints, or one joint, give no bones.
        let lone = Skeleton { nodes: skeleton.nodes.clone(), joints: skeleton.joints[..1].to_vec() };
        assert!(bone_segments(&lone, &lone.model_from_node(&lone.rest_pose())).is_empty());
        let empty = Skeleton::default();
        assert!(bone_segments(&empty, &[]).is_empty());
    }
}
