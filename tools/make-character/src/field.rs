//! The body as an implicit surface: signed distance bounds of capsules and ellipsoids, combined
//! with a polynomial smooth minimum (Quilez, "smooth minimum", 2013) and cut flat at the floor.
//!
//! Negative values are inside. The tapered capsule uses the radius interpolated at the closest
//! point of its segment, and the ellipsoid uses Quilez's first-order distance estimate; both are
//! close to true distances for the mild tapers and aspect ratios used here, which is all the
//! mesher and the skin weights need. Units are metres.

use glam::{Quat, Vec3};

/// An implicit primitive in model space.
#[derive(Clone, Debug)]
pub enum Shape {
    /// Segment `a`–`b` swept by a sphere whose radius goes linearly from `ra` to `rb`.
    Capsule { a: Vec3, b: Vec3, ra: f32, rb: f32 },
    /// Ellipsoid with semi-axes `radii` along the axes of `rotation` (`model_from_local`).
    Ellipsoid { center: Vec3, rotation: Quat, radii: Vec3 },
    /// Box with half-extents `half` along the axes of `rotation`, grown by `radius` (rounded
    /// edges of that radius; exact distance outside).
    RoundedBox { center: Vec3, rotation: Quat, half: Vec3, radius: f32 },
}

impl Shape {
    /// Approximate signed distance from `p` to the surface.
    pub fn distance(&self, p: Vec3) -> f32 {
        match *self {
            Shape::Capsule { a, b, ra, rb } => {
                let ab = b - a;
                // A degenerate segment is a sphere around `a`.
                let len2 = ab.length_squared();
                let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
                (p - (a + t * ab)).length() - (ra + t * (rb - ra))
            }
            Shape::Ellipsoid { center, rotation, radii } => {
                let q = rotation.inverse() * (p - center);
                let k0 = (q / radii).length();
                let k1 = (q / (radii * radii)).length();
                // At the exact centre the estimate is 0/0; the centre is inside by the smallest radius.
                if k1 == 0.0 {
                    return -radii.min_element();
                }
                k0 * (k0 - 1.0) / k1
            }
            Shape::RoundedBox { center, rotation, half, radius } => {
                let q = (rotation.inverse() * (p - center)).abs() - half;
                q.max(Vec3::ZERO).length() + q.max_element().min(0.0) - radius
            }
        }
    }
}

/// One implicit primitive of the body, owned by a bone (a joint index).
#[derive(Clone, Debug)]
pub struct Part {
    pub shape: Shape,
    pub bone: usize,
    /// Smooth-union radius with everything before it, in metres (larger = softer crease).
    pub blend: f32,
}

/// Polynomial smooth minimum: equals `min(a, b)` when they differ by more than `k`, and rounds
/// the crease within `k` (the result is at most `k / 4` below the minimum).
pub fn smooth_min(a: f32, b: f32, k: f32) -> f32 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k * 0.25
}

/// The whole body: smooth union of the parts in order, intersected with the half-space y >= 0
/// so the soles are flat and the character stands exactly on the floor.
pub fn body_distance(parts: &[Part], p: Vec3) -> f32 {
    let mut d = f32::MAX;
    for part in parts {
        let di = part.shape.distance(p);
        d = if d == f32::MAX { di } else { smooth_min(d, di, part.blend) };
    }
    d.max(-p.y)
}

/// Unit outward normal of the body at `p`: the normalized central-difference gradient with step
/// `eps` (a fraction of the mesher's cell size, small enough to see the blend creases).
pub fn body_normal(parts: &[Part], p: Vec3, eps: f32) -> Vec3 {
    let dx = Vec3::new(eps, 0.0, 0.0);
    let dy = Vec3::new(0.0, eps, 0.0);
    let dz = Vec3::new(0.0, 0.0, eps);
    let g = Vec3::new(
        body_distance(parts, p + dx) - body_distance(parts, p - dx),
        body_distance(parts, p + dy) - body_distance(parts, p - dy),
        body_distance(parts, p + dz) - body_distance(parts, p - dz),
    );
    g.try_normalize().unwrap_or(Vec3::Y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capsule_distance_is_exact_for_constant_radius() {
        let s = Shape::Capsule { a: Vec3::ZERO, b: Vec3::Y, ra: 0.5, rb: 0.5 };
        assert_eq!(s.distance(Vec3::new(2.0, 0.5, 0.0)), 1.5);
        assert_eq!(s.distance(Vec3::new(0.0, 3.0, 0.0)), 1.5);
    }

    #[test]
    fn ellipsoid_distance_is_exact_on_its_axes() {
        let s = Shape::Ellipsoid {
            center: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            radii: Vec3::new(1.0, 2.0, 3.0),
        };
        assert!((s.distance(Vec3::new(2.0, 0.0, 0.0)) - 1.0).abs() < 1e-6);
        assert!(s.distance(Vec3::new(0.0, 2.0, 0.0)).abs() < 1e-6);
        assert_eq!(s.distance(Vec3::ZERO), -1.0);
    }

    #[test]
    fn rounded_box_distance_is_exact_on_faces_and_corners() {
        let s =
            Shape::RoundedBox { center: Vec3::ZERO, rotation: Quat::IDENTITY, half: Vec3::ONE, radius: 0.5 };
        assert_eq!(s.distance(Vec3::new(3.0, 0.0, 0.0)), 1.5);
        assert_eq!(s.distance(Vec3::new(4.0, 5.0, 1.0)), 4.5);
        assert_eq!(s.distance(Vec3::ZERO), -1.5);
    }

    #[test]
    fn smooth_min_is_min_far_apart_and_rounds_close() {
        assert_eq!(smooth_min(1.0, 3.0, 0.5), 1.0);
        assert_eq!(smooth_min(1.0, 1.0, 0.4), 0.9);
    }
}
