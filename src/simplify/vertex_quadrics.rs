//! Initial vertex quadrics, the second stage of the pipeline (after `topology`).
//!
//! - Geometric quadrics per position class: the caller's per-vertex quadrics summed over the
//!   class's wedges, or area-weighted face planes (Garland & Heckbert 1997); plus penalty planes
//!   through every constraint edge, perpendicular to its triangle, so that moving a vertex off a
//!   border, material border or seam costs error.
//! - Attribute quadrics (Hoppe 1999, see [`super::quadric`]): the `A, b, c` parts summed per
//!   class, the cross terms `Σ area·w·g`, `Σ area·w·d` and `Σ area` kept per wedge, flat, with
//!   stride `1 + 4 k` for `k` priced channels: `[Σ area, (gx, gy, gz, d) per priced channel]`.

use super::channels::Channels;
use super::quadric::{Quadric, TriangleFrame};
use super::topology::{other_corners, Constraint, ConstraintSide, PositionClasses, NONE};
use super::SimplifyInput;
use glam::DVec3;

/// Penalty-plane weight (× edge length², so it scales like the area-weighted face quadrics) for
/// open mesh borders. Moving a border by δ along a length L uncovers or covers about L·δ of
/// surface, the area a face plane of that size weighs: the same weight as the surface, so
/// collapses are ordered by the area they change. Measured against 10 (the material borders'
/// weight) on `parts.glb`, 57 open plates: animated error against meshoptimizer 1.25 → 1.14 ×
/// averaged over levels, lower at every level; the other models have no open borders.
const OPEN_BORDER_WEIGHT: f64 = 1.0;
/// Penalty-plane weight for material borders. Moving a material outline by δ costs about
/// 10 × δ² per unit of area, an order of magnitude more than bending the surface by δ: a colour
/// boundary shows before the shape does, so material outlines go last (Garland & Heckbert 1997
/// use a similar weight for borders).
const MATERIAL_BORDER_WEIGHT: f64 = 10.0;
/// Penalty weight for attribute seams: they are not geometric boundaries, so they only weigh as
/// much as the surface; their attribute quadrics carry the rest.
const SEAM_WEIGHT: f64 = 1.0;
/// The weights above are per constraint edge. An open border has one triangle, so one penalty
/// plane; a material border or a seam has two, one plane in each, so each plane takes half the
/// edge's weight (on a flat stretch the two planes coincide and add up to it). Before this
/// division a seam weighed twice the surface and a material border 20 × (meshoptimizer likewise
/// halves its seam weight, "applied twice due to opposite edges"). Measured with
/// `bench/animated-vs-meshoptimizer.mjs` (ours ÷ the better meshoptimizer, mean over levels /
/// worst level): Fox (uv seams) 0.89 / 1.03 → 0.84 / 0.95, the built-in character (five
/// materials, a uv seam) 0.65 / 0.87 → 0.63 / 0.83; CesiumMan, RiggedSimple, robot.glb and
/// parts.glb unchanged. Each half alone helped its model: seams alone Fox, material borders
/// alone the character.
const PLANES_PER_TWO_SIDED_EDGE: f64 = 2.0;

fn corner_point(input: &SimplifyInput, corner: usize) -> DVec3 {
    input.positions[input.indices[corner] as usize].as_dvec3()
}

/// Geometric quadric of every class, penalty planes included (they add error but no weight).
pub(super) fn geometric_quadrics(
    classes: &PositionClasses,
    input: &SimplifyInput,
    sides: &[ConstraintSide],
    input_normal: &[DVec3],
) -> Vec<Quadric> {
    let indices = input.indices;
    let class_at = |corner: usize| classes.class_of[indices[corner] as usize] as usize;
    let mut geometric = vec![Quadric::ZERO; classes.count()];
    match input.vertex_quadrics {
        Some(quadrics) => {
            for (v, q) in quadrics.iter().enumerate() {
                let c = classes.class_of[v];
                if c != NONE {
                    geometric[c as usize] += q;
                }
            }
        }
        None => {
            for t in 0..indices.len() / 3 {
                let [p0, p1, p2] = [0, 1, 2].map(|k| corner_point(input, 3 * t + k));
                let q = Quadric::from_triangle(p0, p1, p2);
                for k in 0..3 {
                    geometric[class_at(3 * t + k)] += &q;
                }
            }
        }
    }
    for side in sides {
        let (a, b) = (side.corner as usize, other_corners(side.corner).0 as usize);
        let (pa, pb) = (corner_point(input, a), corner_point(input, b));
        let edge = pb - pa;
        let plane = edge.cross(input_normal[a / 3]).normalize_or_zero();
        if plane == DVec3::ZERO {
            continue; // degenerate triangle or edge: no direction to keep
        }
        let weight = match side.constraint {
            Constraint::Border => OPEN_BORDER_WEIGHT,
            Constraint::Material => MATERIAL_BORDER_WEIGHT / PLANES_PER_TWO_SIDED_EDGE,
            Constraint::Seam | Constraint::Crease => SEAM_WEIGHT / PLANES_PER_TWO_SIDED_EDGE,
        } * edge.length_squared();
        let mut q = Quadric::from_plane(plane, -plane.dot(pa), weight);
        q.weight = 0.0;
        geometric[class_at(a)] += &q;
        geometric[class_at(b)] += &q;
    }
    geometric
}

/// Attribute quadric parts per class and the per-wedge sums (see the module docs) of the priced
/// channels (see [`Channels`]). Degenerate triangles contribute nothing.
pub(super) fn attribute_quadrics(
    classes: &PositionClasses,
    input: &SimplifyInput,
    channels: &Channels,
) -> (Vec<Quadric>, Vec<f64>) {
    let indices = input.indices;
    let m = input.attribute_weights.len();
    let stride = channels.stride();
    let mut appearance = vec![Quadric::ZERO; classes.count()];
    let mut wedge_sums = vec![0.0f64; input.positions.len() * stride];
    if channels.priced.is_empty() {
        return (appearance, wedge_sums);
    }
    for t in 0..indices.len() / 3 {
        let corners = [3 * t, 3 * t + 1, 3 * t + 2];
        let [p0, p1, p2] = corners.map(|k| corner_point(input, k));
        let Some(frame) = TriangleFrame::new(p0, p1, p2) else {
            continue;
        };
        for corner in corners {
            wedge_sums[indices[corner] as usize * stride] += frame.area;
        }
        // Σ over channels of aw · (g·p + d)², the attribute errors' pure-position part: summed
        // per face first, then added to each corner's class once.
        let mut face = Quadric::ZERO;
        for (k, &(j, w)) in channels.priced.iter().enumerate() {
            let s = corners.map(|c| input.attributes[indices[c] as usize * m + j] as f64);
            let (g, d) = frame.gradient(s[0], s[1], s[2]);
            let aw = frame.area * w as f64;
            face += &Quadric::from_plane(g, d, aw);
            for corner in corners {
                let base = indices[corner] as usize * stride + 1 + 4 * k;
                wedge_sums[base] += aw * g.x;
                wedge_sums[base + 1] += aw * g.y;
                wedge_sums[base + 2] += aw * g.z;
                wedge_sums[base + 3] += aw * d;
            }
        }
        face.weight = 0.0;
        for corner in corners {
            appearance[classes.class_of[indices[corner] as usize] as usize] += &face;
        }
    }
    (appearance, wedge_sums)
}
