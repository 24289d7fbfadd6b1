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

/// Whether the 3×3 matrix `m` is far enough from singular to invert in f32: its determinant is
/// at least 1e-12 of the cube of its longest column, so the test does not depend on units (for a
/// matrix of unit scale it is the old absolute 1e-12; relative to the largest column, not to the
/// product of all three, so that two columns that nearly cancel still count as singular).
/// Measured against the determinant alone, a skin that holds a change of units counted as
/// singular: gltfpack keeps positions on a 14-bit grid and scales them back in the inverse bind
/// matrices, by about 1e-4 per axis for a character 1.5 m tall, a determinant of 1e-12; every
/// vertex the LOD build moved then fell back to its survivor's bind position, and packed
/// CesiumMan's levels were 1.2–1.5× as far from its surface as the original's.
pub fn is_invertible(m: Mat3) -> bool {
    let det = m.determinant();
    let longest = m.x_axis.length().max(m.y_axis.length()).max(m.z_axis.length());
    det.is_finite() && det != 0.0 && det.abs() >= 1e-12 * longest * longest * longest
}

/// The inverse transpose of `m`, or `None` when `m` is singular ([`is_invertible`]).
///
/// Uses the cofactor matrix (`det(m) · m⁻ᵀ`) whose direction is what normals need; the sign of
/// the determinant keeps normals pointing outwards under mirroring.
fn normal_matrix(m: Mat3) -> Option<Mat3> {
    if !is_invertible(m) {
        return None;
    }
    let det = m.determinant();
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

    #[test]
    fn invertibility_does_not_depend_on_units() {
        // gltfpack's grid for a 1.5 m character: 1.5 / 16,383 per axis, a determinant of 7.7e-13.
        let rotation = Mat3::from_quat(Quat::from_rotation_y(0.7));
        for scale in [1.0, 1e-2, 1.5 / 16_383.0, 1e4] {
            assert!(is_invertible(rotation * scale), "scale {scale}");
        }
        // Opposite half-turns blended half and half: the x and z columns cancel.
        let half_turn = Mat3::from_quat(Quat::from_rotation_y(std::f32::consts::PI));
        assert!(!is_invertible((Mat3::IDENTITY + half_turn) * 0.5));
        assert!(!is_invertible(Mat3::ZERO));
        let flat = Mat3::from_cols(Vec3::X, Vec3::Y, Vec3::X + Vec3::Y);
        assert!(!is_invertible(flat * 1e-4));
    }
}
