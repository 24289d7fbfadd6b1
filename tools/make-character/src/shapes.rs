//! Low-poly shapes for the robot and the many-part character: flat-shaded prisms, boxes and balls
//! (every facet has its own vertices, its normal the facet's normal) and open, smooth-shaded
//! shells. Positions in metres, bind (model) space; triangles counter-clockwise seen from outside.

use glam::Vec3;

use crate::math::sin_cos;

/// A triangle list with per-vertex normals.
#[derive(Clone, Debug, Default)]
pub struct Shape {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
}

impl Shape {
    /// Appends a convex planar polygon (counter-clockwise) as a facet with its own vertices.
    pub fn facet(&mut self, corners: &[Vec3]) {
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize();
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(corners);
        self.normals.extend(std::iter::repeat_n(normal, corners.len()));
        for k in 1..corners.len() as u32 - 1 {
            self.indices.extend_from_slice(&[base, base + k, base + k + 1]);
        }
    }

    pub fn append(&mut self, other: &Shape) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }
}

/// An orthonormal frame `(u, w)` perpendicular to the unit `axis`, fixed by the axis alone.
fn frame(axis: Vec3) -> (Vec3, Vec3) {
    let helper = if axis.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
    let u = helper.cross(axis).normalize();
    (u, axis.cross(u))
}

/// Ring point `i` of `sides` around `center`, elliptical radii `(ru, rw)`, starting at `phase`
/// (fractions of a side).
fn ring(center: Vec3, (u, w): (Vec3, Vec3), (ru, rw): (f32, f32), sides: u32, i: u32, phase: f32) -> Vec3 {
    let angle = std::f32::consts::TAU * (i as f32 + phase) / sides as f32;
    let (s, c) = sin_cos(angle);
    center + u * (c * ru) + w * (s * rw)
}

/// A capped flat-shaded prism from `a` to `b` with `sides` sides, radii `(ru, rw)` and `segments`
/// rings of side facets along its length (coplanar: a simplifier may remove the inner rings for
/// free). `phase` 0.5 with 4 sides and radii `r·√2` gives a box.
pub fn prism(a: Vec3, b: Vec3, radii: (f32, f32), sides: u32, segments: u32, phase: f32) -> Shape {
    let axis = (b - a).normalize();
    let f = frame(axis);
    let mut shape = Shape::default();
    let at = |s: u32, i: u32| ring(a.lerp(b, s as f32 / segments as f32), f, radii, sides, i % sides, phase);
    for s in 0..segments {
        for i in 0..sides {
            shape.facet(&[at(s, i), at(s, i + 1), at(s + 1, i + 1), at(s + 1, i)]);
        }
    }
    let bottom: Vec<Vec3> = (0..sides).rev().map(|i| at(0, i)).collect();
    let top: Vec<Vec3> = (0..sides).map(|i| at(segments, i)).collect();
    shape.facet(&bottom);
    shape.facet(&top);
    shape
}

/// An axis-aligned flat-shaded box between `lo` and `hi`, its four sides cut into `segments`
/// rings along y.
pub fn block(lo: Vec3, hi: Vec3, segments: u32) -> Shape {
    let c = 0.5 * (lo + hi);
    let h = 0.5 * (hi - lo);
    // A 4-sided prism with phase 0.5 has its corners at (±r/√2): scale the radii by √2. Its
    // frame about +y has u = −x and w = +z.
    let r = std::f32::consts::SQRT_2;
    prism(Vec3::new(c.x, lo.y, c.z), Vec3::new(c.x, hi.y, c.z), (h.x * r, h.z * r), 4, segments, 0.5)
}

/// A flat-shaded ball: `sides` meridians and `bands` bands of latitude.
pub fn ball(center: Vec3, radius: f32, sides: u32, bands: u32) -> Shape {
    let mut shape = Shape::default();
    let at = |band: u32, i: u32| {
        // sin π is not exactly 0 in f32: the poles are set exactly, so every fan meets there.
        if band == 0 || band == bands {
            return center + Vec3::Y * if band == 0 { radius } else { -radius };
        }
        let (sl, cl) = sin_cos(std::f32::consts::PI * band as f32 / bands as f32);
        let (s, c) = sin_cos(std::f32::consts::TAU * (i % sides) as f32 / sides as f32);
        center + radius * Vec3::new(sl * c, cl, sl * s)
    };
    for band in 0..bands {
        for i in 0..sides {
            let (p00, p01, p10, p11) = (at(band, i), at(band, i + 1), at(band + 1, i), at(band + 1, i + 1));
            if band == 0 {
                shape.facet(&[p00, p11, p10]);
            } else if band + 1 == bands {
                shape.facet(&[p00, p01, p10]);
            } else {
                shape.facet(&[p00, p01, p11, p10]);
            }
        }
    }
    shape
}

/// An open, smooth-shaded shell: the part of an elliptic cylinder around `a → b` between angles
/// `from` and `to` (fractions of a turn), `columns × rows` quads, normals pointing outward from
/// the axis. Its border is open (an armour plate).
pub fn shell(a: Vec3, b: Vec3, radii: (f32, f32), (from, to): (f32, f32), columns: u32, rows: u32) -> Shape {
    let axis = (b - a).normalize();
    let (u, w) = frame(axis);
    let mut shape = Shape::default();
    for r in 0..=rows {
        let center = a.lerp(b, r as f32 / rows as f32);
        for c in 0..=columns {
            let angle = std::f32::consts::TAU * (from + (to - from) * c as f32 / columns as f32);
            let (s, co) = sin_cos(angle);
            shape.positions.push(center + u * (co * radii.0) + w * (s * radii.1));
            // The ellipse's outward normal: the gradient of (x/ru)² + (y/rw)².
            shape.normals.push((u * (co / radii.0) + w * (s / radii.1)).normalize());
        }
    }
    let stride = columns + 1;
    for r in 0..rows {
        for c in 0..columns {
            let (p, q) = (r * stride + c, (r + 1) * stride + c);
            shape.indices.extend_from_slice(&[p, p + 1, q + 1, p, q + 1, q]);
        }
    }
    shape
}
