//! Faceted low-poly shapes for `lowpoly-robot.glb` and `critter.glb`, written the way an exporter
//! writes a flat-shaded model: every triangle has its own three vertices and its face normal, and
//! no two neighbouring triangles lie in one plane, so every edge is a normal seam. Tubes are
//! swept along a polyline with each ring turned half a step from the last (antiprism bands);
//! their ends are low pyramids; boxes have a low pyramid on each face. Positions in metres, bind
//! (model) space; triangles counter-clockwise seen from outside.

use glam::Vec3;

use crate::math::sin_cos;
use crate::shapes::Shape;

/// Appends the triangle `a b c` with its own vertices and its face normal, turned to face away
/// from `inside`.
pub fn triangle(shape: &mut Shape, [a, b, c]: [Vec3; 3], inside: Vec3) {
    let n = (b - a).cross(c - a);
    let (b, c, n) = if n.dot((a + b + c) / 3.0 - inside) < 0.0 { (c, b, -n) } else { (b, c, n) };
    let base = shape.positions.len() as u32;
    shape.positions.extend_from_slice(&[a, b, c]);
    shape.normals.extend(std::iter::repeat_n(n.normalize(), 3));
    shape.indices.extend_from_slice(&[base, base + 1, base + 2]);
}

/// A closed faceted tube through `centers`, with elliptic radii `radii[k]` (across, up) at each,
/// `sides` sides, every ring turned half a side from the previous, and pointed ends standing
/// `tips.0` beyond the first center and `tips.1` beyond the last (along the tube). The ring's
/// "up" is `up` made perpendicular to the tube. Returns the shape and, per vertex, the ring it
/// belongs to (`usize::MAX` for a tip), so callers can skin by ring.
pub fn sweep(
    centers: &[Vec3],
    radii: &[(f32, f32)],
    sides: u32,
    up: Vec3,
    tips: (f32, f32),
) -> (Shape, Vec<usize>) {
    assert!(centers.len() >= 2 && centers.len() == radii.len());
    let last = centers.len() - 1;
    let tangent = |k: usize| (centers[(k + 1).min(last)] - centers[k.saturating_sub(1)]).normalize();
    let rings: Vec<Vec<Vec3>> = (0..centers.len())
        .map(|k| {
            let t = tangent(k);
            let across = up.cross(t).normalize();
            let upward = t.cross(across);
            (0..sides)
                .map(|i| {
                    let (s, c) = sin_cos(std::f32::consts::TAU * (i as f32 + 0.5 * k as f32) / sides as f32);
                    centers[k] + across * (radii[k].0 * c) + upward * (radii[k].1 * s)
                })
                .collect()
        })
        .collect();
    let mut shape = Shape::default();
    let mut ring_of = Vec::new();
    let mut add = |shape: &mut Shape, corners: [Vec3; 3], inside: Vec3, rings: [usize; 3]| {
        triangle(shape, corners, inside);
        // `triangle` may swap b and c; the ring labels follow the positions they were given with.
        let n = shape.positions.len();
        let placed = [shape.positions[n - 3], shape.positions[n - 2], shape.positions[n - 1]];
        for p in placed {
            let k = corners.iter().position(|&q| q == p).expect("a corner");
            ring_of.push(rings[k]);
        }
    };
    let n = sides as usize;
    for k in 0..last {
        let (a, b) = (&rings[k], &rings[k + 1]);
        let inside = 0.5 * (centers[k] + centers[k + 1]);
        // Ring k + 1 is turned half a side ahead: b[i] lies between a[i] and a[i + 1].
        for i in 0..n {
            add(&mut shape, [a[i], a[(i + 1) % n], b[i]], inside, [k, k, k + 1]);
            add(&mut shape, [b[i], a[(i + 1) % n], b[(i + 1) % n]], inside, [k + 1, k, k + 1]);
        }
    }
    for (k, apex, towards) in [(0, tips.0, -tangent(0)), (last, tips.1, tangent(last))] {
        let tip = centers[k] + towards * apex;
        let inside = centers[k] - towards * (0.1 * apex.abs() + 1e-3);
        for i in 0..n {
            add(&mut shape, [rings[k][i], rings[k][(i + 1) % n], tip], inside, [k, k, usize::MAX]);
        }
    }
    (shape, ring_of)
}

/// A closed faceted box centred at `center` with half-extents `half` along `x`, `y`, `z` (a
/// right-handed frame), each face a low pyramid of four triangles rising `rise` times the smaller
/// half-extent of the face.
pub fn tented_box(center: Vec3, (x, y, z): (Vec3, Vec3, Vec3), half: Vec3, rise: f32) -> Shape {
    // The eight corners once each (so that the faces meet exactly), by their signs along x, y, z.
    let corner = |s: [f32; 3]| center + x * (s[0] * half.x) + y * (s[1] * half.y) + z * (s[2] * half.z);
    let mut shape = Shape::default();
    let axes = [(x, half.x), (y, half.y), (z, half.z)];
    for (k, &(normal, h)) in axes.iter().enumerate() {
        let (hu, hv) = (axes[(k + 1) % 3].1, axes[(k + 2) % 3].1);
        for sign in [1.0, -1.0] {
            let apex = center + normal * (sign * (h + rise * hu.min(hv)));
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(a, b)| {
                let mut s = [0.0; 3];
                (s[k], s[(k + 1) % 3], s[(k + 2) % 3]) = (sign, a, b);
                corner(s)
            });
            for i in 0..4 {
                triangle(&mut shape, [corners[i], corners[(i + 1) % 4], apex], center);
            }
        }
    }
    shape
}

/// Points `count + 1` along `a → b` (both ends included).
pub fn along(a: Vec3, b: Vec3, count: usize) -> Vec<Vec3> {
    (0..=count).map(|k| a.lerp(b, k as f32 / count as f32)).collect()
}

/// A faceted ball: a sweep along `axis` through `center` whose rings follow a circle of `radius`
/// (`rings` rings, pointed poles on the sphere).
pub fn ball(center: Vec3, axis: Vec3, radius: Vec3, sides: u32, rings: usize) -> Shape {
    let axis = axis.normalize();
    let up = if axis.y.abs() < 0.9 { Vec3::Y } else { Vec3::Z };
    let (mut centers, mut radii) = (Vec::new(), Vec::new());
    for k in 0..rings {
        let (s, c) = sin_cos(std::f32::consts::PI * (k as f32 + 0.5) / rings as f32);
        centers.push(center - axis * (radius.y * c));
        radii.push((radius.x * s, radius.z * s));
    }
    let tip = radius.y * (1.0 - sin_cos(std::f32::consts::PI * 0.5 / rings as f32).1);
    sweep(&centers, &radii, sides, up, (tip, tip)).0
}
