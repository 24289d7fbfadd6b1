//! Smooth skin weights from the bones' own primitives.
//!
//! A bone's influence on a surface point falls off with the point's distance to the nearest
//! primitive that bone owns (distance to its segment minus its radius, so thick and thin limbs get
//! the same falloff). The kernel is Müller's poly6, `(1 - (d/R)²)³` for `d < R`: smooth, compact,
//! and 1 on the bone's own surface. At a joint both adjacent bones' primitives meet, so the
//! weights cross over smoothly there; away from joints a single bone has all the weight, which
//! keeps hands, feet and the head rigid. The four largest influences are kept and renormalized.

use glam::Vec3;

use crate::body::joint;
use crate::field::Part;

/// Falloff radius in metres: the bend at an elbow or knee spreads over about this much skin on
/// either side of the joint, roughly one limb radius, which is what painted rigs do.
const FALLOFF: f32 = 0.05;

fn kernel(d: f32) -> f32 {
    if d >= FALLOFF {
        return 0.0;
    }
    let x = 1.0 - (d / FALLOFF) * (d / FALLOFF);
    x * x * x
}

/// Four joints and four weights (decreasing, summing to 1) for every position.
///
/// Points inside a primitive count as on it (distance 0). The nearest primitive of a surface
/// point is always within the smooth-union depth (a few millimetres), so every point gets at
/// least one non-zero weight; if not (a point far from the body), it goes rigidly to the bone of
/// the nearest primitive.
pub fn skin_weights(parts: &[Part], positions: &[Vec3]) -> (Vec<[u16; 4]>, Vec<[f32; 4]>) {
    let mut joints = Vec::with_capacity(positions.len());
    let mut weights = Vec::with_capacity(positions.len());
    for &p in positions {
        let mut nearest = [f32::MAX; joint::COUNT];
        for part in parts {
            let d = part.shape.distance(p).max(0.0);
            nearest[part.bone] = nearest[part.bone].min(d);
        }
        // Largest four by weight; ties keep the lower joint index (stable sort).
        let mut ranked: Vec<(usize, f32)> = nearest.iter().map(|&d| kernel(d)).enumerate().collect();
        ranked.sort_by(|a, b| b.1.total_cmp(&a.1));
        let mut j = [0u16; 4];
        let mut w = [0.0f32; 4];
        let total: f32 = ranked[..4].iter().map(|r| r.1).sum();
        if total > 0.0 {
            for k in 0..4 {
                if ranked[k].1 > 0.0 {
                    j[k] = ranked[k].0 as u16;
                    w[k] = ranked[k].1 / total;
                }
            }
        } else {
            let bone = nearest.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).map_or(0, |(i, _)| i);
            j[0] = bone as u16;
            w[0] = 1.0;
        }
        joints.push(j);
        weights.push(w);
    }
    (joints, weights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::Shape;

    #[test]
    fn weights_cross_over_at_a_joint_and_are_rigid_away_from_it() {
        let bone = |a: Vec3, b: Vec3, bone: usize| Part {
            shape: Shape::Capsule { a, b, ra: 0.04, rb: 0.04 },
            bone,
            blend: 0.03,
        };
        let parts = [bone(Vec3::ZERO, Vec3::Y * 0.3, 1), bone(Vec3::Y * 0.3, Vec3::Y * 0.6, 2)];
        let at_joint = Vec3::new(0.04, 0.3, 0.0);
        let far = Vec3::new(0.04, 0.05, 0.0);
        let (j, w) = skin_weights(&parts, &[at_joint, far]);
        assert_eq!((j[0][0], j[0][1]), (1, 2));
        assert_eq!(w[0][0], 0.5);
        assert_eq!(w[0][1], 0.5);
        assert_eq!(j[1], [1, 0, 0, 0]);
        assert_eq!(w[1], [1.0, 0.0, 0.0, 0.0]);
    }
}
