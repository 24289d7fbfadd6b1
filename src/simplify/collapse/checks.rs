//! The validity checks of a planned collapse (the link condition, duplicate triangles, merged
//! constraint lines, folds) and the parking of an edge that failed them; part of the collapse
//! engine in `mod.rs`, whose state they read.
//!
//! One exception to "no duplicate triangles" lets a closed part go away whole, as
//! meshoptimizer's parts do: a lone tetrahedron collapses to a two-sided sheet (two triangles on
//! the same corners, facing opposite ways, so a culled material still shows it from both
//! sides), and a lone sheet collapses to nothing. The first step is priced like any other
//! collapse (the merged quadric holds every plane of the part); the second at least as the part's
//! area times its squared clearance, its distance to the input's other parts (`plan.rs`,
//! `clearance.rs`), since nothing of it is left where it was.

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::topology::{other_corners, Kind, NONE};
use super::{Engine, Plan};
use crate::metrics::closest_point_on_triangle_f64;
use glam::DVec3;

/// A triangle may not face away from the input triangle it descends from: the cosine between its
/// normal and that input normal must exceed this (≈ 89.9°). Turning past 90° is what makes a
/// back face out of a front face (a fold); the small margin keeps the decision stable under
/// rounding.
const MIN_COS_TO_INPUT: f64 = 1e-3;
/// A new triangle whose smallest angle is below about 1e-6 rad (|cross| < 1e-6 · longest edge²)
/// counts as degenerate: its normal is rounding noise.
const MIN_SIN_ANGLE: f64 = 1e-6;
/// An input point closer than this fraction of the limit to the merged vertex is taken to be as
/// far from the surface as from that vertex (an upper bound, since the vertex is on the surface)
/// without a search: far under the limit either way, and most collapses of a fine mesh move
/// their ends less than that, so the search runs for the few that move far (on the built-in
/// character the build took 1–3 % longer, within the machine's noise).
const SEARCH_FROM: f64 = 0.1;

impl Engine<'_> {
    /// Whether `u` and `v` share a constraint edge (one triangle, or two that differ in material
    /// or wedges); non-manifold edges count as constraints.
    fn edge_is_constraint(&self, a: u32, b: u32) -> bool {
        let mut count = 0;
        let mut first = (NONE, NONE, NONE);
        for corner in self.lists.iter(a) {
            let (n, p) = other_corners(corner);
            let b_corner = if self.class_at(n) == b {
                n
            } else if self.class_at(p) == b {
                p
            } else {
                continue;
            };
            let side = (
                self.corner_wedge[corner as usize],
                self.corner_wedge[b_corner as usize],
                self.materials.get(corner as usize / 3).copied().unwrap_or(0),
            );
            count += 1;
            if count == 1 {
                first = side;
            } else if side != first {
                return true;
            }
        }
        count != 2
    }

    /// Whether triangle `t` is acceptable after the corners at class `moving` go to `p`: not
    /// degenerate, within ~90° of its input normal, and not turned by 90° or more in this step.
    fn triangle_ok(&self, t: usize, moving: u32, p: DVec3) -> bool {
        let classes = [0, 1, 2].map(|k| self.class_at((3 * t + k) as u32));
        let old = classes.map(|c| self.position[c as usize]);
        let new = [0, 1, 2].map(|k| if classes[k] == moving { p } else { old[k] });
        let cross = (new[1] - new[0]).cross(new[2] - new[0]);
        let longest = (new[1] - new[0])
            .length_squared()
            .max((new[2] - new[0]).length_squared())
            .max((new[2] - new[1]).length_squared());
        // Squared on both sides, so no square root: |cross| > MIN_SIN_ANGLE · longest.
        let length_squared = cross.length_squared();
        let min_length = MIN_SIN_ANGLE * longest;
        if !(length_squared > min_length * min_length) {
            return false;
        }
        // cross · input > MIN_COS_TO_INPUT · |cross|, squared once it is known positive.
        let input = self.input_normal[t];
        if input != DVec3::ZERO {
            let along = cross.dot(input);
            if !(along > 0.0) || along * along <= MIN_COS_TO_INPUT * MIN_COS_TO_INPUT * length_squared {
                return false;
            }
        }
        let old_cross = (old[1] - old[0]).cross(old[2] - old[0]);
        old_cross == DVec3::ZERO || cross.dot(old_cross) > 0.0
    }

    /// The topological and geometric checks of a planned collapse: link condition, no duplicate
    /// triangles, no merged constraint lines, no folds.
    pub(super) fn check(&mut self, plan: &Plan) -> bool {
        let (u, v) = (plan.u, plan.v);
        let stamp = self.next_stamp();
        for corner in self.lists.iter(v) {
            let (n, p) = other_corners(corner);
            let (a, b) = (self.class_at(n), self.class_at(p));
            self.mark[a as usize] = stamp;
            self.mark[b as usize] = stamp;
        }
        let mut opposite = [NONE; 2];
        let mut count = 0;
        for corner in self.lists.iter(u) {
            let (n, p) = other_corners(corner);
            let (a, b) = (self.class_at(n), self.class_at(p));
            let x = if a == v {
                b
            } else if b == v {
                a
            } else {
                continue;
            };
            if count == 2 {
                return false;
            }
            opposite[count] = x;
            count += 1;
        }
        if count == 0 {
            return false; // no longer an edge
        }
        if count == 2 && opposite[0] == opposite[1] {
            // A pinched edge: its two triangles have the same corners. Only a two-sided sheet
            // standing alone may collapse; both triangles die and nothing of it is left to fold.
            return self.is_lone(&[u, v, opposite[0]], 2);
        }
        let is_opposite = |x: u32| x == opposite[0] || x == opposite[1];
        for corner in self.lists.iter(u) {
            let (n, p) = other_corners(corner);
            let (a, b) = (self.class_at(n), self.class_at(p));
            if a == v || b == v {
                continue;
            }
            // Link condition: u and v may only share the neighbours across the edge.
            for x in [a, b] {
                if self.mark[x as usize] == stamp && !is_opposite(x) {
                    return false;
                }
            }
            // Triangle (u, a, b) with both a and b across the edge would duplicate (v, a, b),
            // which is allowed only when the four are a lone tetrahedron (it becomes a sheet).
            if is_opposite(a)
                && is_opposite(b)
                && self.has_triangle(v, a, b)
                && !self.is_lone(&[u, v, a, b], 3)
            {
                return false;
            }
        }
        if self.kind[u as usize] != Kind::Interior {
            for &x in &opposite[..count] {
                // Two constraint edges of one triangle would merge into one, changing the
                // number of lines at v and x (a line vertex would become a line end). Harmless
                // when both are locked anyway: that only closes a chart corner or a border ear.
                let both_locked = self.kind[v as usize].pinned() && self.kind[x as usize].pinned();
                if !both_locked && self.edge_is_constraint(u, x) && self.edge_is_constraint(v, x) {
                    return false;
                }
            }
        }
        self.fan_unfolded(u, v, plan.p)
            && (plan.p == self.position[v as usize] || self.fan_unfolded(v, u, plan.p))
    }

    /// The input point the merged vertex would carry if the collapse is made: of the two ends'
    /// `farthest_input` points, the one farther from the surface the collapse leaves (the
    /// nearest surviving triangle around the merged vertex). `None` when that exceeds `limit`
    /// (position units): the collapse would cut away input surface that far, whatever its mean
    /// squared error (the toe of a sliver foot merged with its heel).
    pub(super) fn farthest_input_within(&self, plan: &Plan, limit: f64) -> Option<DVec3> {
        let (u, v, p) = (plan.u, plan.v, plan.p);
        let mut farthest = (p, 0.0f64);
        for end in [u, v] {
            let input = self.farthest_input[end as usize];
            let mut distance = input.distance(p);
            if distance > SEARCH_FROM * limit {
                // Nothing left around it: the part's own pricing (`clearance.rs`) weighs that.
                distance = self.distance_to_merged_fan(u, v, p, input).unwrap_or(0.0);
            }
            if distance >= farthest.1 {
                farthest = (input, distance);
            }
        }
        (!(farthest.1 > limit)).then_some(farthest.0)
    }

    /// The distance from `point` to the nearest triangle around `u` and `v` that survives their
    /// collapse at `p` (with `p` for their corners); `None` when none survives.
    fn distance_to_merged_fan(&self, u: u32, v: u32, p: DVec3, point: DVec3) -> Option<f64> {
        let mut nearest = f64::INFINITY;
        for corner in self.lists.iter(u).chain(self.lists.iter(v)) {
            let t = corner as usize / 3;
            let classes = [0, 1, 2].map(|k| self.class_at((3 * t + k) as u32));
            if classes.contains(&u) && classes.contains(&v) {
                continue;
            }
            let [a, b, c] = classes.map(|x| if x == u || x == v { p } else { self.position[x as usize] });
            nearest = nearest.min(point.distance_squared(closest_point_on_triangle_f64(point, a, b, c)));
        }
        (nearest < f64::INFINITY).then(|| nearest.sqrt())
    }

    /// Whether every triangle around `moving` that survives the collapse with `other` (does not
    /// contain it) stays acceptable when `moving` goes to `p` (see [`Engine::triangle_ok`]).
    fn fan_unfolded(&self, moving: u32, other: u32, p: DVec3) -> bool {
        self.lists.iter(moving).all(|corner| {
            let (n, q) = other_corners(corner);
            self.class_at(n) == other
                || self.class_at(q) == other
                || self.triangle_ok(corner as usize / 3, moving, p)
        })
    }

    /// Marks `c` parked, remembering that its collapse with `partner` failed a check.
    pub(super) fn park(&mut self, c: u32, partner: u32) {
        let record = self.failed.len() as u32;
        self.failed.push((partner, self.failed_head[c as usize]));
        self.failed_head[c as usize] = record;
    }

    /// Whether each of `classes` lies on exactly `corners` live triangles.
    fn is_lone(&self, classes: &[u32], corners: usize) -> bool {
        classes.iter().all(|&c| self.lists.iter(c).count() == corners)
    }

    /// Whether a live triangle has classes `c`, `a` and `b` (corner lists hold only live
    /// triangles).
    fn has_triangle(&self, c: u32, a: u32, b: u32) -> bool {
        self.lists.iter(c).any(|corner| {
            let (n, p) = other_corners(corner);
            let (x, y) = (self.class_at(n), self.class_at(p));
            (x == a && y == b) || (x == b && y == a)
        })
    }
}
