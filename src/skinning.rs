//! CPU reference skinning: linear blend skinning (Magnenat-Thalmann et al. 1988) of positions and
//! normals. The GPU shaders implement the same formula; tests and the LOD builder use this one.
//!
//! A vertex with joints `j` and weights `w` maps to `M = Σ w_k · skin[j_k]` applied to its bind
//! position. Normals use the inverse transpose of the blended 3×3 part, then renormalize, so they
//! stay perpendicular under non-uniform scale.

use glam::{Mat3, Mat4, Vec3};

/// The blended skin matrix `Σ w_k · skin[j_k]` of one vertex.
///
/// Joint indices outside `skin` contribute nothing (the importer guarantees they are in range).
pub fn blend_matrix(skin: &[Mat4], joints: [u16; 4], weights: [f32; 4]) -> Mat4 {
    let mut m = Mat4::ZERO;
    for (&j, &w) in joints.iter().zip(&weights) {
        if w != 0.0 {
            if let Some(s) = skin.get(j as usize) {
                m += *s * w;
            }
        }
    }
    m
}

/// Skinned positions of every vertex.
///
/// # Panics
/// If `joints` or `weights` are shorter than `positions`.
pub fn skin_positions(
    positions: &[Vec3],
    joints: &[[u16; 4]],
    weights: &[[f32; 4]],
    skin: &[Mat4],
) -> Vec<Vec3> {
    positions
        .iter()
        .enumerate()
        .map(|(v, &p)| blend_matrix(skin, joints[v], weights[v]).transform_point3(p))
        .collect()
}

/// Skinned unit normals of every vertex (inverse-transpose of the blended matrix).
///
/// A vertex whose blended matrix is singular keeps its bind normal.
///
/// # Panics
/// If `joints` or `weights` are shorter than `normals`.
pub fn skin_normals(normals: &[Vec3], joints: &[[u16; 4]], weights: &[[f32; 4]], skin: &[Mat4]) -> Vec<Vec3> {
    normals
        .iter()
        .enumerate()
        .map(|(v, &n)| {
            let m = Mat3::from_mat4(blend_matrix(skin, joints[v], weights[v]));
            normal_matrix(m).map(|nm| nm * n).and_then(Vec3::try_normalize).unwrap_or(n)
        })
        .collect()
}

/// The inverse transpose of `m`, or `None` when `m` is singular.
///
/// Uses the cofactor matrix (`det(m) · m⁻ᵀ`) whose direction is what normals need; the sign of
/// the determinant keeps normals pointing outwards under mirroring.
fn normal_matrix(m: Mat3) -> Option<Mat3> {
    let det = m.determinant();
    if !det.is_finite() || det.abs() < 1e-12 {
        return None;
    }
    let cofactor =
        Mat3::from_cols(m.y_axis.cross(m.z_axis), m.z_axis.cross(m.x_axis), m.x_axis.cross(m.y_axis));
    Some(cofactor * det.signum())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn half_weights_average_two_translations() {
        let skin = [Mat4::from_translation(Vec3::X), Mat4::from_translation(Vec3::Y)];
        let out = skin_positions(&[Vec3::ZERO], &[[0, 1, 0, 0]], &[[0.5, 0.5, 0.0, 0.0]], &skin);
        assert_eq!(out, vec![Vec3::new(0.5, 0.5, 0.0)]);
    }

    #[test]
    fn normals_follow_rotation_and_ignore_translation() {
        let skin =
            [Mat4::from_rotation_translation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2), Vec3::X)];
        let out = skin_normals(&[Vec3::X], &[[0; 4]], &[[1.0, 0.0, 0.0, 0.0]], &skin);
        assert!(out[0].abs_diff_eq(Vec3::Y, 1e-6), "{:?}", out[0]);
    }

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale() {
        // A 45° surface stretched along x: the normal must tilt towards y, not x.
        let skin = [Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0))];
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let out = skin_normals(&[n], &[[0; 4]], &[[1.0, 0.0, 0.0, 0.0]], &skin);
        let tangent = Vec3::new(2.0, -1.0, 0.0); // (1,-1,0) scaled by the matrix
        assert!(out[0].dot(tangent).abs() < 1e-6);
    }
}
