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
//! `clearance.rs`), since nothing of it is left where it was. An open part goes the same way
//! from its last triangle, whose collapse would otherwise merge two border lines: priced and
//! held to the floor by its distance to the live triangles of the parts left, as well as to
//! their input.

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::topology::{other_corners, Kind, NONE};
use super::floors::Floors;
use super::mesh::Mesh;
use super::scratch::Scratch;
use super::Plan;
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
/// The fraction of the distance limit under which an input point's distance from the merged
/// vertex stands for its distance from the surface (see [`Probes`]). Most collapses of a fine
/// mesh move their ends less than that; at 0.5 CesiumMan's toes went again.
const SEARCH_FROM: f64 = 0.1;

/// The topological and geometric checks of a planned collapse: link condition, no duplicate
/// triangles, no merged constraint lines, no folds. A valid collapse gives the input vertex
/// the merged vertex is to track and its distance from the surface the collapse leaves (see
/// [`Probes`]); `None` for an invalid one. `steps`: the collapses logged so far (see
/// [`Floors::open_part_within`]); `scratch` lends its marks and probe buffers.
pub(super) fn check(
    mesh: &Mesh,
    floors: &mut Floors,
    scratch: &mut Scratch,
    steps: usize,
    plan: &Plan,
) -> Option<(u32, f64)> {
    let (u, v) = (plan.u, plan.v);
    let stamp = scratch.marks.next_stamp();
    for corner in mesh.lists.iter(v) {
        let (n, p) = other_corners(corner);
        let (a, b) = (mesh.class_at(n), mesh.class_at(p));
        scratch.marks.set(a, stamp);
        scratch.marks.set(b, stamp);
    }
    let mut opposite = [NONE; 2];
    let mut count = 0;
    for corner in mesh.lists.iter(u) {
        let (n, p) = other_corners(corner);
        let (a, b) = (mesh.class_at(n), mesh.class_at(p));
        let x = if a == v {
            b
        } else if b == v {
            a
        } else {
            continue;
        };
        if count == 2 {
            return None;
        }
        opposite[count] = x;
        count += 1;
    }
    if count == 0 {
        return None; // no longer an edge
    }
    if count == 2 && opposite[0] == opposite[1] {
        // A pinched edge: its two triangles have the same corners. Only a two-sided sheet
        // standing alone may collapse; both triangles die and nothing of it is left to fold.
        // One that would leave a point beyond the floor counts as infinitely far.
        let sheet = [u, v, opposite[0]];
        return mesh.is_lone(&sheet, 2).then(|| {
            let within = !floors.distance_floor || floors.vanishes_within_floor(mesh, sheet);
            let distance = if within { 0.0 } else { f64::INFINITY };
            (floors.farthest_input[v as usize], distance)
        });
    }
    let is_opposite = |x: u32| x == opposite[0] || x == opposite[1];
    for corner in mesh.lists.iter(u) {
        let (n, p) = other_corners(corner);
        let (a, b) = (mesh.class_at(n), mesh.class_at(p));
        if a == v || b == v {
            continue;
        }
        // Link condition: u and v may only share the neighbours across the edge.
        for x in [a, b] {
            if scratch.marks.is_set(x, stamp) && !is_opposite(x) {
                return None;
            }
        }
        // Triangle (u, a, b) with both a and b across the edge would duplicate (v, a, b),
        // which is allowed only when the four are a lone tetrahedron (it becomes a sheet).
        if is_opposite(a) && is_opposite(b) && mesh.has_triangle(v, a, b) && !mesh.is_lone(&[u, v, a, b], 3) {
            return None;
        }
    }
    if count == 1 && floors.open_parts_within_reach && mesh.lone_triangle_corner(u, v).is_some() {
        // A lone open triangle: its part vanishes no farther from the level than the level
        // has reached (its price, `plan.rs`).
        let reached = floors.reached_distance;
        let within = floors.open_part_within(mesh, steps, u, reached).is_ok();
        return Some((floors.farthest_input[v as usize], if within { reached } else { f64::INFINITY }));
    }
    if mesh.kind[u as usize] != Kind::Interior {
        for &x in &opposite[..count] {
            // Two constraint edges of one triangle would merge into one, changing the
            // number of lines at v and x (a line vertex would become a line end). Harmless
            // when both are locked anyway: that only closes a chart corner or a border ear.
            let both_locked = mesh.kind[v as usize].pinned() && mesh.kind[x as usize].pinned();
            if !both_locked && mesh.edge_is_constraint(u, x) && mesh.edge_is_constraint(v, x) {
                return None;
            }
        }
    }
    let buffer = std::mem::take(&mut scratch.probe_triangles);
    let ends = [u, v].map(|end| floors.farthest_input[end as usize]);
    let points = ends.map(|vertex| floors.input_positions[vertex as usize].as_dvec3());
    let mut probes = Probes::new(points, plan.p, floors.max_distance, buffer);
    let unfolded = mesh.fan_unfolded(u, v, plan.p, &mut probes)
        && if plan.p == mesh.position[v as usize] {
            // v's triangles keep their corners: nothing to check, still surface to measure.
            mesh.measure_fan(v, u, &mut probes);
            true
        } else {
            mesh.fan_unfolded(v, u, plan.p, &mut probes)
        };
    let farthest = unfolded.then(|| {
        let (k, distance) = probes.farthest();
        (ends[k], distance)
    });
    scratch.probe_triangles = probes.triangles;
    farthest
}

impl Mesh<'_> {
    /// Whether triangle `t` is acceptable after the corners at class `moving` go to `p`: not
    /// degenerate, within ~90° of its input normal, and not turned by 90° or more in this step.
    fn triangle_ok(&self, t: usize, moving: u32, p: DVec3, probes: &mut Probes) -> bool {
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
        if !(old_cross == DVec3::ZERO || cross.dot(old_cross) > 0.0) {
            return false;
        }
        probes.measure(ProbeTriangle { corners: new, cross, length_squared });
        true
    }

    /// Whether every triangle around `moving` that survives the collapse with `other` (does not
    /// contain it) stays acceptable when `moving` goes to `p` (see [`Mesh::triangle_ok`]).
    fn fan_unfolded(&self, moving: u32, other: u32, p: DVec3, probes: &mut Probes) -> bool {
        self.lists.iter(moving).all(|corner| {
            let (n, q) = other_corners(corner);
            self.class_at(n) == other
                || self.class_at(q) == other
                || self.triangle_ok(corner as usize / 3, moving, p, probes)
        })
    }

    /// Measures `probes` on the triangles around `c` that do not contain `other`, as they are.
    fn measure_fan(&self, c: u32, other: u32, probes: &mut Probes) {
        if !probes.keeps_triangles() {
            return;
        }
        for corner in self.lists.iter(c) {
            let t = corner as usize / 3;
            let classes = [0, 1, 2].map(|k| self.class_at((3 * t + k) as u32));
            if classes.contains(&other) {
                continue;
            }
            let corners = classes.map(|x| self.position[x as usize]);
            let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
            let length_squared = cross.length_squared();
            if length_squared > 0.0 {
                probes.measure(ProbeTriangle { corners, cross, length_squared });
            }
        }
    }
}

/// The input points the two ends of a collapse track (`Floors::farthest_input`) and their
/// distance from the surface the collapse leaves, measured on its surviving triangles as `check`
/// goes over them: the merged vertex tracks the farther one, and the collapse is skipped when
/// that is beyond [`super::super::SimplifyOptions::max_distance`]. The mean squared error misses
/// a small part cut short (the toe of a sliver foot merged with its heel: 2.1 % of the diagonal
/// priced, 8 % moved); this does not.
///
/// A point is at most as far from the new surface as from the merged vertex, which is on it.
/// Within [`SEARCH_FROM`] of the limit of it, that bound stands for its distance; beyond, each
/// surviving triangle whose plane is nearer than the nearest triangle so far is measured. Which
/// point a vertex tracks has to be decided by that distance: by the distance from the merged
/// vertex alone, or from the plane across the new triangles' mean normal, CesiumMan's toes went
/// as before (9.1 % of the diagonal at 72 triangles), since the point a tip keeps is the one
/// left outside the surface, not the one farthest away along it.
pub(super) struct Probes {
    points: [DVec3; 2],
    /// Squared distances: to the nearest surviving triangle so far for a measured point, to the
    /// merged vertex for the others.
    nearest_squared: [f64; 2],
    /// Whether the point is measured on the triangles.
    measured: [bool; 2],
    /// Whether a surviving triangle was seen: with none, nothing is left around the merged
    /// vertex, and the part's own pricing (`clearance.rs`) weighs that.
    pub(super) survivors: bool,
    /// The surviving triangles, measured at the end nearest plane first, so that most of the
    /// others are ruled out by their plane (the engine's scratch, lent for the check).
    pub(super) triangles: Vec<ProbeTriangle>,
}

/// A surviving triangle as [`Probes`] measures it.
#[derive(Clone, Copy, Debug)]
pub(super) struct ProbeTriangle {
    corners: [DVec3; 3],
    /// The unnormalised normal, and its squared length (positive).
    cross: DVec3,
    length_squared: f64,
}

impl Probes {
    fn new(points: [DVec3; 2], p: DVec3, limit: f64, mut triangles: Vec<ProbeTriangle>) -> Self {
        let nearest_squared = points.map(|q| q.distance_squared(p));
        let search_from = (SEARCH_FROM * limit).powi(2);
        triangles.clear();
        Probes {
            points,
            nearest_squared,
            measured: nearest_squared.map(|d| d > search_from),
            survivors: false,
            triangles,
        }
    }

    /// Whether surviving triangles are kept for measuring.
    fn keeps_triangles(&self) -> bool {
        self.measured.contains(&true)
    }

    /// Takes a surviving triangle.
    fn measure(&mut self, triangle: ProbeTriangle) {
        self.survivors = true;
        if self.keeps_triangles() {
            self.triangles.push(triangle);
        }
    }

    /// Measures point `k` on one triangle, unless its plane is already too far.
    fn measure_one(&mut self, k: usize, triangle: ProbeTriangle) {
        if !self.measured[k] {
            return;
        }
        let ProbeTriangle { corners, cross, length_squared, .. } = triangle;
        let q = self.points[k];
        let along = (q - corners[0]).dot(cross);
        // The plane is no farther than the triangle.
        if along * along >= self.nearest_squared[k] * length_squared {
            return;
        }
        let [a, b, c] = corners;
        let nearest = q.distance_squared(closest_point_on_triangle_f64(q, a, b, c));
        self.nearest_squared[k] = self.nearest_squared[k].min(nearest);
    }

    /// Measures the points on the buffered triangles, each starting with the triangle whose
    /// plane is nearest it.
    fn measure_buffered(&mut self) {
        for k in 0..2 {
            if !self.measured[k] {
                continue;
            }
            let q = self.points[k];
            let plane_squared = |t: &ProbeTriangle| {
                let along = (q - t.corners[0]).dot(t.cross);
                along * along / t.length_squared
            };
            let buffered = &self.triangles;
            let nearest_plane = (0..buffered.len())
                .min_by(|&a, &b| plane_squared(&buffered[a]).total_cmp(&plane_squared(&buffered[b])));
            if let Some(first) = nearest_plane {
                self.measure_one(k, self.triangles[first]);
            }
            for t in 0..self.triangles.len() {
                if Some(t) != nearest_plane {
                    self.measure_one(k, self.triangles[t]);
                }
            }
        }
    }

    /// Which point (0 or 1) is farther from the surface, and its distance.
    fn farthest(&mut self) -> (usize, f64) {
        self.measure_buffered();
        // On a tie (both on the surface, say) the survivor `v` keeps its own.
        let k = usize::from(self.nearest_squared[1] >= self.nearest_squared[0]);
        (k, if self.survivors { self.nearest_squared[k].sqrt() } else { 0.0 })
    }
}
