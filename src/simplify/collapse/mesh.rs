//! The mesh as the collapses leave it: its position classes and their kinds, the corner lists
//! and every corner's wedge and class, which triangles are alive, each class's position, which
//! class a dead one merged into, and each class's version. The queries on it are topological
//! (neighbours, the parts that vanish with a collapse, constraint edges); the costs, the order
//! and the floors are kept apart (`costs.rs`, `order.rs`, `floors.rs`). Part of the collapse
//! engine in `mod.rs`.
//!
//! Invariants: the corner lists hold exactly the live triangles' corners, each under its
//! corner's class (`corner_class[k] == classes.class_of[corner_wedge[k]]` for a live corner `k`);
//! a class is alive until it merges into another, then `merged_into` names that one; a class's
//! version moves on whenever a collapse changes what its queued candidates were priced on, so a
//! candidate is current while both ends are alive and its stamp matches their versions.

use super::super::queue::Candidate;
use super::super::topology::{
    classify, creases, other_corners, position_classes, Classification, ConstraintSide, CornerLists, Kind,
    PositionClasses, NONE,
};
use super::super::SimplifyInput;
use super::scratch::Marks;
use glam::{DVec3, Vec3};

/// Low bits of both versions: 16 of `u`'s, 15 of `v`'s (the top bit marks a bound, see
/// [`Candidate::bound`]).
fn stamp(version_u: u32, version_v: u32) -> u32 {
    (version_u & 0xFFFF) | ((version_v & 0x7FFF) << 16)
}

/// The mesh's topology and state (see the module docs).
pub(super) struct Mesh<'a> {
    pub(super) classes: PositionClasses,
    /// One material id per input triangle (or empty for one material).
    pub(super) materials: &'a [u32],
    /// Per input triangle, its unit normal (zero for a degenerate one).
    pub(super) input_normal: Vec<DVec3>,
    pub(super) kind: Vec<Kind>,
    /// Per class: on an open border or material line (see [`Classification::on_outline`]); a
    /// survivor inherits it.
    pub(super) on_outline: Vec<bool>,
    pub(super) lists: CornerLists,
    pub(super) corner_wedge: Vec<u32>,
    /// `classes.class_of[corner_wedge[corner]]`, kept beside it: the checks and plans ask for a
    /// corner's class far more often than for its wedge, and one load is cheaper than two.
    pub(super) corner_class: Vec<u32>,
    pub(super) triangle_alive: Vec<bool>,
    pub(super) live_triangles: usize,
    /// Per class, its position (the input's, until a collapse moves it).
    pub(super) position: Vec<DVec3>,
    pub(super) alive: Vec<bool>,
    /// Per class, the class it merged into ([`NONE`] while alive).
    pub(super) merged_into: Vec<u32>,
    /// Per class, a counter that moves on with every change that makes its candidates stale.
    pub(super) version: Vec<u32>,
}

impl<'a> Mesh<'a> {
    /// The input as a mesh of position classes, none collapsed; also the sides of every
    /// constraint edge, where the costs put their penalty planes. `normal_channel`: see
    /// [`super::super::SimplifyOptions::normal_channel`].
    pub(super) fn new(
        input: &SimplifyInput<'a>,
        normal_channel: Option<usize>,
    ) -> (Mesh<'a>, Vec<ConstraintSide>) {
        let positions = input.positions;
        let indices = input.indices;
        let m = input.attribute_weights.len();
        let triangle_count = indices.len() / 3;
        let classes = position_classes(positions, indices);
        let class_count = classes.count();
        let lists = CornerLists::new(|k| classes.class_of[indices[k] as usize], indices.len(), class_count);
        // A seam creases where its wedges' normals differ; without a normal channel none does.
        let normal = |vertex: u32, channel: usize| {
            let at = vertex as usize * m + channel;
            Vec3::from_slice(&input.attributes[at..at + 3])
        };
        let creased = |a: u32, b: u32| normal_channel.is_some_and(|c| creases(normal(a, c), normal(b, c)));
        let Classification { kinds: kind, on_outline, sides } =
            classify(&classes, positions, &lists, indices, input.triangle_materials, creased);
        let position: Vec<DVec3> =
            classes.representative.iter().map(|&v| positions[v as usize].as_dvec3()).collect();
        let corner_point = |corner: usize| positions[indices[corner] as usize].as_dvec3();
        let input_normal: Vec<DVec3> = (0..triangle_count)
            .map(|t| {
                let (p0, p1, p2) = (corner_point(3 * t), corner_point(3 * t + 1), corner_point(3 * t + 2));
                (p1 - p0).cross(p2 - p0).normalize_or_zero()
            })
            .collect();
        let mesh = Mesh {
            materials: input.triangle_materials,
            input_normal,
            kind,
            on_outline,
            lists,
            corner_wedge: indices.to_vec(),
            corner_class: indices.iter().map(|&w| classes.class_of[w as usize]).collect(),
            triangle_alive: vec![true; triangle_count],
            live_triangles: triangle_count,
            position,
            alive: vec![true; class_count],
            merged_into: vec![NONE; class_count],
            version: vec![0; class_count],
            classes,
        };
        (mesh, sides)
    }
}

impl Mesh<'_> {
    #[inline]
    pub(super) fn class_at(&self, corner: u32) -> u32 {
        self.corner_class[corner as usize]
    }

    /// The distinct neighbour classes of `c`, into `out` (cleared first); `marks` is scratch.
    pub(super) fn neighbours_into(&self, c: u32, marks: &mut Marks, out: &mut Vec<u32>) {
        out.clear();
        let stamp = marks.next_stamp();
        marks.set(c, stamp);
        for corner in self.lists.iter(c) {
            let (n, p) = other_corners(corner);
            for x in [self.class_at(n), self.class_at(p)] {
                if !marks.is_set(x, stamp) {
                    marks.set(x, stamp);
                    out.push(x);
                }
            }
        }
    }

    /// The version stamp of a candidate `u → v`.
    pub(super) fn stamp_of(&self, u: u32, v: u32) -> u32 {
        stamp(self.version[u as usize], self.version[v as usize])
    }

    /// Whether `candidate` is current: both its classes alive, neither changed since it was
    /// queued (see [`stamp`]).
    #[inline]
    pub(super) fn is_current(&self, candidate: &Candidate) -> bool {
        let (u, v) = (candidate.u() as usize, candidate.v as usize);
        self.alive[u] && self.alive[v] && candidate.stamp() == stamp(self.version[u], self.version[v])
    }

    /// The range of class `c`'s wedges in `classes.wedges`.
    pub(super) fn class_wedges(&self, c: usize) -> std::ops::Range<usize> {
        self.classes.wedge_start[c] as usize..self.classes.wedge_start[c + 1] as usize
    }

    /// The class that class `c` has merged into, or `c` while it is alive.
    pub(super) fn live_class(&self, mut c: u32) -> u32 {
        while self.merged_into[c as usize] != NONE {
            c = self.merged_into[c as usize];
        }
        c
    }

    /// The third corner `x` when `u`, `v` and `x` are a lone two-sided sheet (two live triangles
    /// on the same three classes and nothing else around them), which the collapse of `u` into
    /// `v` makes vanish; `None` otherwise.
    fn lone_sheet_corner(&self, u: u32, v: u32) -> Option<u32> {
        // Most pricings end here, without walking a list.
        if !self.lists.has_two(u) || !self.lists.has_two(v) {
            return None;
        }
        let mut third = NONE;
        let mut count = 0;
        for corner in self.lists.iter(u) {
            let x = self.third_class(corner, v)?;
            if count == 2 || (count == 1 && x != third) {
                return None;
            }
            third = x;
            count += 1;
        }
        (count == 2 && self.lists.has_two(third)).then_some(third)
    }

    /// The third corner `x` when the collapse of `u` into `v` makes a part vanish: `u`, `v` and
    /// `x` are a lone two-sided sheet ([`Mesh::lone_sheet_corner`]) or a lone open triangle
    /// ([`Mesh::lone_triangle_corner`]); `None` otherwise.
    pub(super) fn vanishing_corner(&self, u: u32, v: u32) -> Option<u32> {
        self.lone_sheet_corner(u, v).or_else(|| self.lone_triangle_corner(u, v))
    }

    /// The third corner `x` when `u`, `v` and `x` are a lone open triangle: the last triangle of
    /// an open part, each corner on it alone; `None` otherwise.
    pub(super) fn lone_triangle_corner(&self, u: u32, v: u32) -> Option<u32> {
        if !self.lists.has_one(u) || !self.lists.has_one(v) {
            return None;
        }
        let x = self.third_class(self.lists.iter(u).next()?, v)?;
        self.lists.has_one(x).then_some(x)
    }

    /// The class of the third corner of `corner`'s triangle when one of its two other corners is
    /// on class `v`; `None` when neither is.
    fn third_class(&self, corner: u32, v: u32) -> Option<u32> {
        let (n, q) = other_corners(corner);
        let (a, b) = (self.class_at(n), self.class_at(q));
        if a == v {
            Some(b)
        } else if b == v {
            Some(a)
        } else {
            None
        }
    }

    /// Whether `u` and `v` share a constraint edge (one triangle, or two that differ in material
    /// or wedges); non-manifold edges count as constraints.
    pub(super) fn edge_is_constraint(&self, a: u32, b: u32) -> bool {
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

    /// Whether each of `classes` lies on exactly `corners` live triangles.
    pub(super) fn is_lone(&self, classes: &[u32], corners: usize) -> bool {
        classes.iter().all(|&c| self.lists.iter(c).count() == corners)
    }

    /// Whether a live triangle has classes `c`, `a` and `b` (corner lists hold only live
    /// triangles).
    pub(super) fn has_triangle(&self, c: u32, a: u32, b: u32) -> bool {
        self.lists.iter(c).any(|corner| {
            let (n, p) = other_corners(corner);
            let (x, y) = (self.class_at(n), self.class_at(p));
            (x == a && y == b) || (x == b && y == a)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A 3 × 3 grid of vertices 0..9 (vertex `3y + x` at (x, y), each cell split along its
    /// diagonal from `i` to `i + 4`), a lone triangle 9 10 11 far off, and a two-sided sheet on
    /// vertices 12 13 14 (the same triangle both ways round).
    fn mesh() -> (Vec<Vec3>, Vec<u32>) {
        let mut positions: Vec<Vec3> =
            (0..9).map(|i| Vec3::new((i % 3) as f32, (i / 3) as f32, 0.0)).collect();
        positions.extend([Vec3::new(10.0, 0.0, 0.0), Vec3::new(11.0, 0.0, 0.0), Vec3::new(10.0, 1.0, 0.0)]);
        positions.extend([Vec3::new(20.0, 0.0, 0.0), Vec3::new(21.0, 0.0, 0.0), Vec3::new(20.0, 1.0, 0.0)]);
        let mut indices = Vec::new();
        for i in [0, 1, 3, 4] {
            indices.extend([i, i + 1, i + 4, i, i + 4, i + 3]);
        }
        indices.extend([9, 10, 11, 12, 13, 14, 12, 14, 13]);
        (positions, indices)
    }

    fn input<'a>(positions: &'a [Vec3], indices: &'a [u32]) -> SimplifyInput<'a> {
        SimplifyInput {
            positions,
            attributes: &[],
            attribute_weights: &[],
            indices,
            triangle_materials: &[],
            vertex_quadrics: None,
        }
    }

    #[test]
    fn neighbours_are_the_distinct_classes_around_a_class() {
        let (positions, indices) = mesh();
        let (mesh, _) = Mesh::new(&input(&positions, &indices), None);
        let class = |vertex: usize| mesh.classes.class_of[vertex];
        let mut marks = Marks::new(mesh.classes.count());
        let mut out = vec![99];
        let mut sorted = |c: u32, out: &mut Vec<u32>| {
            mesh.neighbours_into(c, &mut marks, out);
            let mut found = out.clone();
            found.sort_unstable();
            found
        };
        let mut expected = [0, 1, 3, 5, 7, 8].map(class);
        expected.sort_unstable();
        assert_eq!(sorted(class(4), &mut out), expected, "the centre's ring, each once");
        let mut expected = [1, 3, 4].map(class);
        expected.sort_unstable();
        assert_eq!(sorted(class(0), &mut out), expected, "cleared before filling");
        assert_eq!(out.len(), 3);
    }

    #[test]
    fn a_lone_triangle_or_sheet_vanishes_with_its_collapse() {
        let (positions, indices) = mesh();
        let (mesh, _) = Mesh::new(&input(&positions, &indices), None);
        let class = |vertex: usize| mesh.classes.class_of[vertex];
        assert_eq!(mesh.lone_triangle_corner(class(9), class(10)), Some(class(11)));
        assert_eq!(mesh.vanishing_corner(class(9), class(10)), Some(class(11)));
        assert_eq!(mesh.lone_sheet_corner(class(12), class(13)), Some(class(14)));
        assert_eq!(mesh.vanishing_corner(class(13), class(12)), Some(class(14)));
        // The grid's collapses leave triangles behind, on its border too.
        assert_eq!(mesh.vanishing_corner(class(4), class(5)), None);
        assert_eq!(mesh.vanishing_corner(class(0), class(1)), None);
        assert!(mesh.is_lone(&[12, 13, 14].map(class), 2));
        assert!(mesh.has_triangle(class(4), class(5), class(8)));
        assert!(!mesh.has_triangle(class(4), class(2), class(6)));
    }

    #[test]
    fn border_edges_are_constraints_and_interior_ones_are_not() {
        let (positions, indices) = mesh();
        let (mesh, _) = Mesh::new(&input(&positions, &indices), None);
        let class = |vertex: usize| mesh.classes.class_of[vertex];
        assert!(mesh.edge_is_constraint(class(0), class(1)), "one triangle");
        assert!(!mesh.edge_is_constraint(class(4), class(5)), "two alike");
        assert!(mesh.edge_is_constraint(class(0), class(8)), "no triangle: no manifold edge");
    }

    #[test]
    fn a_candidate_is_current_until_a_class_changes_or_dies() {
        let (positions, indices) = mesh();
        let (mut mesh, _) = Mesh::new(&input(&positions, &indices), None);
        let (u, v) = (mesh.classes.class_of[4], mesh.classes.class_of[5]);
        let candidate = Candidate::new(1.0, u, v, mesh.stamp_of(u, v));
        assert!(mesh.is_current(&candidate));
        mesh.version[v as usize] += 1;
        assert!(!mesh.is_current(&candidate), "v changed");
        let candidate = Candidate::new(1.0, u, v, mesh.stamp_of(u, v));
        assert!(mesh.is_current(&candidate));
        mesh.alive[u as usize] = false;
        assert!(!mesh.is_current(&candidate), "u died");
    }
}
