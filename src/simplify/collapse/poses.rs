//! The distance floor in the other poses ([`super::super::SimplifyInput::other_poses`]): a
//! collapse is skipped when, in some pose, a point of the triangles it leaves stands farther than
//! [`super::super::SimplifyOptions::max_distance`] from the triangles it replaces. The input pose
//! cannot see what a joint does to a collapse across it: CesiumMan's knee, merged into its hip
//! while the leg was straight, left a triangle from the hip to the heel that in a stride spans the
//! air behind the bent knee, 5.6 % of the diagonal from the mesh (its 82-triangle level; every
//! input vertex stayed within 4.6 %, so the points the input pose tracks, `Probes` in
//! `checks.rs`, could not see it).
//!
//! Positions in a pose: a live class moves with its own input vertex, by that vertex's shift
//! from the input pose; the merged vertex by its ends' shifts blended by where it lies along the
//! edge, as back-propagation blends their skins (`clod::back_propagate`). The pose's rotation of
//! a class's own move is not known to the simplifier and is left out: those moves are short where
//! limbs bend, a fraction of an edge.
//!
//! A point of a new triangle at weight λ of the merged corner stands at most λ times its end's
//! move from where it stood on the old triangle. So only where an end moves more than twice the
//! floor in a pose are points measured: the midpoints of the new triangles' edges to the merged
//! vertex (where a chord across a bent joint leaves the surface), and their centroids where the
//! end moves more than three times the floor, against the triangles around both ends as they
//! were, and for a point beyond the floor from those, around their neighbours too: a chord may
//! pass near surface beyond the ends' own (one Fox.glb collapse was refused for lack of it, and
//! its coarsest level came out 5 % worse). That is a sample, not a bound, and a step, not the
//! distance from the input: steps add up, as the quadric's errors do. Measured with 8 frames, the
//! checks that measure any point: Fox.glb 19 of 261, CesiumMan 36 of 2,378, RiggedSimple 2 of
//! 391, the built-in character none of 25,471 (the clod build gives 4 frames, which measure no
//! more).

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::checks::ProbeTriangle;
use super::floors::Floors;
use super::mesh::Mesh;
use super::{OtherPoses, Plan};
use crate::metrics::closest_point_on_triangle_f64;
use glam::DVec3;

impl Floors<'_> {
    /// Whether an end of `plan` moves farther than twice the floor in some pose: only then are
    /// points of its new triangles measured there (see the module docs).
    pub(super) fn measures_in_poses(&self, mesh: &Mesh, plan: &Plan) -> bool {
        let Some(poses) = self.other_poses else {
            return false;
        };
        let edge = self.posed_edge(mesh, plan);
        (0..poses.count).any(|f| edge.moves_beyond(&poses, f, 2.0 * self.max_distance))
    }

    /// The distance from the replaced triangles of a point of the surviving `triangles` in the
    /// first pose where one stands beyond the floor, or 0 when none does (see the module docs).
    /// `old` is scratch.
    pub(super) fn step_beyond_floor_in_poses(
        &self,
        mesh: &Mesh,
        plan: &Plan,
        triangles: &[ProbeTriangle],
        old: &mut Vec<[DVec3; 3]>,
    ) -> f64 {
        let Some(poses) = self.other_poses else {
            return 0.0;
        };
        let limit_squared = self.max_distance * self.max_distance;
        let within = |q: DVec3, old: &[[DVec3; 3]]| {
            // A corner is on its triangle: most points are settled by one.
            old.iter().flatten().any(|corner| !(q.distance_squared(*corner) > limit_squared))
                || old.iter().any(|&[a, b, c]| {
                    !(q.distance_squared(closest_point_on_triangle_f64(q, a, b, c)) > limit_squared)
                })
        };
        let edge = self.posed_edge(mesh, plan);
        for f in 0..poses.count {
            let moves = edge.end_moves_squared(&poses, f);
            if !(moves[0].max(moves[1]) > 4.0 * limit_squared) {
                continue;
            }
            let merged = edge.merged(&poses, f);
            old.clear();
            // The second ring, built only for a point beyond the floor from the first (rare).
            let mut wide = Vec::new();
            for triangle in triangles {
                let Some(k) = triangle.classes.iter().position(|&c| c == plan.u || c == plan.v) else {
                    continue;
                };
                // A point at weight λ of the merged corner stands at most λ times its end's move
                // from where it stood on the old triangle: a midpoint can be beyond the floor
                // only where the end moves more than twice the floor, a centroid three times.
                let end_move_squared = moves[usize::from(triangle.classes[k] == plan.v)];
                if !(end_move_squared > 4.0 * limit_squared) {
                    continue;
                }
                if old.is_empty() {
                    self.posed_fans(mesh, &poses, plan, f, old);
                }
                let [a, b] = [(k + 1) % 3, (k + 2) % 3]
                    .map(|j| self.posed_class(mesh, &poses, triangle.classes[j], triangle.corners[j], f));
                let centroid = (end_move_squared > 9.0 * limit_squared).then_some((merged + a + b) / 3.0);
                for q in [Some((merged + a) / 2.0), Some((merged + b) / 2.0), centroid].into_iter().flatten()
                {
                    if within(q, old) {
                        continue;
                    }
                    if wide.is_empty() {
                        self.posed_second_ring(mesh, &poses, plan, f, &mut wide);
                    }
                    if !within(q, &wide) {
                        let nearest = wide
                            .iter()
                            .map(|&[a, b, c]| q.distance_squared(closest_point_on_triangle_f64(q, a, b, c)))
                            .fold(f64::INFINITY, f64::min);
                        return nearest.sqrt();
                    }
                }
            }
        }
        0.0
    }

    /// The triangles around `plan`'s ends as they are, in pose `f`, into `old`.
    fn posed_fans(&self, mesh: &Mesh, poses: &OtherPoses, plan: &Plan, f: usize, old: &mut Vec<[DVec3; 3]>) {
        for end in [plan.u, plan.v] {
            self.push_posed_fan(mesh, poses, end, f, old);
        }
    }

    /// The triangles around every corner of the triangles around `plan`'s ends, as they are, in
    /// pose `f`, into `wide`.
    fn posed_second_ring(
        &self,
        mesh: &Mesh,
        poses: &OtherPoses,
        plan: &Plan,
        f: usize,
        wide: &mut Vec<[DVec3; 3]>,
    ) {
        let mut ring: Vec<u32> = [plan.u, plan.v]
            .iter()
            .flat_map(|&end| mesh.lists.iter(end))
            .flat_map(|corner| {
                let t = 3 * (corner / 3);
                [t, t + 1, t + 2].map(|k| mesh.class_at(k))
            })
            .collect();
        ring.sort_unstable();
        ring.dedup();
        for &c in &ring {
            self.push_posed_fan(mesh, poses, c, f, wide);
        }
    }

    /// The live triangles around class `c` as they are, in pose `f`, onto `out`.
    fn push_posed_fan(&self, mesh: &Mesh, poses: &OtherPoses, c: u32, f: usize, out: &mut Vec<[DVec3; 3]>) {
        for corner in mesh.lists.iter(c) {
            let t = 3 * (corner / 3);
            out.push([t, t + 1, t + 2].map(|k| {
                let corner_class = mesh.class_at(k);
                self.posed_class(mesh, poses, corner_class, mesh.position[corner_class as usize], f)
            }));
        }
    }

    fn posed_edge(&self, mesh: &Mesh, plan: &Plan) -> PosedEdge {
        let (u, v) = (plan.u as usize, plan.v as usize);
        let (x_u, x_v) = (mesh.position[u], mesh.position[v]);
        let edge = x_v - x_u;
        let length_squared = edge.length_squared();
        let along = if length_squared > 0.0 {
            ((plan.p - x_u).dot(edge) / length_squared).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let vertices = [u, v].map(|c| mesh.classes.representative[c] as usize);
        PosedEdge {
            p: plan.p,
            moves: [x_u - plan.p, x_v - plan.p],
            along,
            vertices,
            inputs: vertices.map(|vertex| self.input_positions[vertex].as_dvec3()),
        }
    }

    /// Live class `c`, standing at `at` in the input pose, in pose `f`.
    fn posed_class(&self, mesh: &Mesh, poses: &OtherPoses, c: u32, at: DVec3, f: usize) -> DVec3 {
        let vertex = mesh.classes.representative[c as usize] as usize;
        at + shift(poses, vertex, self.input_positions[vertex].as_dvec3(), f)
    }
}

/// A collapse's edge as the poses see it. In pose `f` a class moves with its input vertex, by
/// that vertex's shift `d(f)`; the merged vertex by the ends' shifts blended, `p + d_u + s (d_v −
/// d_u)` with `s` how far along the edge it lies (0 at `u`, 1 at `v`, ½ on an edge of no length),
/// as back-propagation blends the ends' skins. So an end moves to it by its move in the input
/// pose and a share of the ends' relative shift.
struct PosedEdge {
    p: DVec3,
    /// Each end's position less the merged vertex's, in the input pose.
    moves: [DVec3; 2],
    along: f64,
    /// The ends' input vertices and their input positions.
    vertices: [usize; 2],
    inputs: [DVec3; 2],
}

impl PosedEdge {
    fn shifts(&self, poses: &OtherPoses, f: usize) -> [DVec3; 2] {
        [0, 1].map(|k| shift(poses, self.vertices[k], self.inputs[k], f))
    }

    /// Whether an end moves farther than `limit` to the merged vertex in pose `f`.
    fn moves_beyond(&self, poses: &OtherPoses, f: usize, limit: f64) -> bool {
        let [u, v] = self.end_moves_squared(poses, f);
        u.max(v) > limit * limit
    }

    /// The squared distances the ends move to the merged vertex in pose `f`.
    fn end_moves_squared(&self, poses: &OtherPoses, f: usize) -> [f64; 2] {
        let [d_u, d_v] = self.shifts(poses, f);
        let relative = d_v - d_u;
        [
            (self.moves[0] - self.along * relative).length_squared(),
            (self.moves[1] + (1.0 - self.along) * relative).length_squared(),
        ]
    }

    /// The merged vertex in pose `f`.
    fn merged(&self, poses: &OtherPoses, f: usize) -> DVec3 {
        let [d_u, d_v] = self.shifts(poses, f);
        self.p + d_u.lerp(d_v, self.along)
    }
}

/// How far input vertex `vertex` (at `input` in the input pose) stands from there in pose `f`.
fn shift(poses: &OtherPoses, vertex: usize, input: DVec3, f: usize) -> DVec3 {
    poses.positions[vertex * poses.count + f].as_dvec3() - input
}
