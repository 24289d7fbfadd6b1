//! Morph deltas of the vertices collapses create (Houle & Poulin 2001 carry positions back to
//! bind space; this carries the morph targets the same way).
//!
//! A vertex merged from `a` and `b` at `x` gets the deltas of `a` and `b` blended by where `x`
//! projects onto the edge `ab` in the simplification pose `P0` (clamped to the edge): exactly the
//! survivor's deltas when `x` sits on it (half-edge collapses), the linear interpolation of the
//! two when `x` lies between. The blend happens in `P0`: each child's deltas go through the
//! linear part of its blended skin matrix at `P0`, and the sum comes back through the inverse of
//! the new vertex's — the same round trip its position takes — so children skinned differently
//! mix as they move. A vertex with one child (a wedge that moved) keeps that child's deltas.
//! Units: bind-space deltas in the character's units.

use glam::{Mat3, Mat4, Vec3};

use crate::morph::{blend_rows, MorphDeltas};
use crate::skinning;

use crate::progressive::NONE;

/// The row of created vertex `x`: see the module docs. `children` are `x`'s merged vertices
/// (`NONE` where absent), `survivor` the vertex it inherits identity from, `skin` the joints and
/// weights `x` was given, `p0_skin` the skin matrices of `P0` (`None`: bind space).
#[allow(clippy::too_many_arguments)]
pub(crate) fn created_row(
    deltas: &MorphDeltas,
    positions: &[Vec3],
    influences: (&[[u16; 4]], &[[f32; 4]]),
    x: usize,
    children: [u32; 2],
    survivor: usize,
    skin: ([u16; 4], [f32; 4]),
    p0_skin: Option<&[Mat4]>,
) -> Vec<(u16, Vec3, Vec3)> {
    let [a, b] = children;
    if a == NONE || b == NONE {
        return deltas.of(survivor).collect();
    }
    let (a, b) = (a as usize, b as usize);
    let (pa, pb, px) = (positions[a], positions[b], positions[x]);
    let edge = pb - pa;
    let s = if edge.length_squared() > 0.0 {
        ((px - pa).dot(edge) / edge.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    // Exactly one child's deltas: no rounding through the blend.
    let only = match s {
        0.0 => Some(a),
        1.0 => Some(b),
        _ => None,
    };
    let Some(p0_skin) = p0_skin else {
        return match only {
            Some(v) => deltas.of(v).collect(),
            None => blend_rows(deltas.of(a), deltas.of(b), s),
        };
    };
    let linear = |joints, weights| Mat3::from_mat4(skinning::blend_matrix(p0_skin, joints, weights));
    let (ja, wa) = (influences.0[a], influences.1[a]);
    let (jb, wb) = (influences.0[b], influences.1[b]);
    let mx = linear(skin.0, skin.1);
    if let Some(v) = only {
        if (influences.0[v], influences.1[v]) == skin {
            return deltas.of(v).collect();
        }
    }
    // Where a blended 3×3 part is numerically singular for f32 inverses (as in
    // `clod::back_propagate`): keep the survivor's deltas.
    let (ma, mb) = (linear(ja, wa), linear(jb, wb));
    if !(skinning::is_invertible(mx) && skinning::is_invertible(ma) && skinning::is_invertible(mb)) {
        return deltas.of(survivor).collect();
    }
    // Into P0: positions by M, normals by M⁻ᵀ; back: M_x⁻¹ and M_xᵀ.
    let to_p0 = |m: Mat3, v: usize| {
        let n = m.inverse().transpose();
        deltas.of(v).map(move |(t, dp, dn)| (t, m * dp, n * dn))
    };
    let (mx_inv, mx_t) = (mx.inverse(), mx.transpose());
    let blended = match only {
        Some(v) => to_p0(if v == a { ma } else { mb }, v).collect(),
        None => blend_rows(to_p0(ma, a), to_p0(mb, b), s),
    };
    blended.into_iter().map(|(t, dp, dn)| (t, mx_inv * dp, mx_t * dn)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// Two input vertices on the x axis, `a` with a lift of 1 for target 0, `b` with none, and
    /// the merged vertex `x` at a quarter of the way from `a` to `b`.
    fn edge() -> (MorphDeltas, Vec<Vec3>) {
        let mut deltas = MorphDeltas::default();
        deltas.push_row([(0, Vec3::Z, Vec3::X)]);
        deltas.push_row([(1, Vec3::Y, Vec3::ZERO)]);
        (deltas, vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.5, 0.0, 0.0)])
    }

    const ONE: ([u16; 4], [f32; 4]) = ([0; 4], [1.0, 0.0, 0.0, 0.0]);

    #[test]
    fn a_moved_vertex_blends_its_childrens_deltas_by_where_it_lies() {
        let (deltas, positions) = edge();
        let influences = (&[ONE.0; 2][..], &[ONE.1; 2][..]);
        let row = created_row(&deltas, &positions, influences, 2, [0, 1], 0, ONE, None);
        assert_eq!(
            row,
            vec![
                (0, Vec3::new(0.0, 0.0, 0.75), Vec3::new(0.75, 0.0, 0.0)),
                (1, Vec3::new(0.0, 0.25, 0.0), Vec3::ZERO)
            ]
        );
        // On the survivor (a half-edge collapse): exactly its deltas.
        let positions = [positions[0], positions[1], positions[0]];
        let row = created_row(&deltas, &positions, influences, 2, [0, 1], 0, ONE, None);
        assert_eq!(row, vec![(0, Vec3::Z, Vec3::X)]);
        // One child (a wedge that moved): the survivor's deltas.
        let row = created_row(&deltas, &positions, influences, 2, [1, NONE], 1, ONE, None);
        assert_eq!(row, vec![(1, Vec3::Y, Vec3::ZERO)]);
    }

    #[test]
    fn in_a_posed_p0_deltas_go_through_the_skin_and_back() {
        // P0 turns the whole mesh a quarter around z: blending there and coming back through the
        // same rotation gives the bind-space blend.
        let (deltas, bind) = edge();
        let turn = Mat4::from_quat(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2));
        let positions: Vec<Vec3> = bind.iter().map(|&p| turn.transform_point3(p)).collect();
        let influences = (&[ONE.0; 2][..], &[ONE.1; 2][..]);
        let row = created_row(&deltas, &positions, influences, 2, [0, 1], 0, ONE, Some(&[turn]));
        assert_eq!(row.len(), 2);
        assert!(row[0].1.abs_diff_eq(Vec3::new(0.0, 0.0, 0.75), 1e-6), "{row:?}");
        assert!(row[0].2.abs_diff_eq(Vec3::new(0.75, 0.0, 0.0), 1e-6), "{row:?}");
        assert!(row[1].1.abs_diff_eq(Vec3::new(0.0, 0.25, 0.0), 1e-6), "{row:?}");
    }
}
