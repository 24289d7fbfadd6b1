//! Mesh topology for the simplifier: position classes, per-class corner lists, vertex kinds and
//! constraint edges.
//!
//! Vertices are *wedges* (Hoppe 1999): vertices whose positions are bit-identical (after mapping
//! −0.0 to +0.0) form one *position class*; the simplifier collapses classes and carries their
//! wedges along. Vertices that no triangle references take part in nothing and get no class.
//!
//! A position edge is a *constraint edge* when it is a mesh border (one triangle), a material
//! border (two triangles with different materials) or an attribute seam (two triangles that use
//! different wedges at one of its ends); a seam whose wedges' normals differ is a *crease*. Open
//! borders, material borders and creases are *outlines*: lines that show where they run. Like
//! meshoptimizer's vertex kinds, a class is
//! - [`Kind::Interior`]: no constraint edge, its triangle fan is one closed disk;
//! - [`Kind::Line`]: exactly two constraint edges, on one disk or half-disk: it lies on a border,
//!   seam or material line and collapses only along it (two vertices of a border or seam line
//!   merge at their quadric's minimiser, which the line's penalty planes hold near the line; on
//!   a material line, at the best point of their edge);
//! - [`Kind::Corner`]: a line vertex where the line turns by more than 45°: it collapses only
//!   along its line too; on a border or seam line it merges with its neighbour at their
//!   quadric's minimiser, which the two lines' penalty planes hold near the corner, and on a
//!   material line onto its neighbour, never to a point between two vertices (that would round
//!   a colour outline's corner off);
//! - [`Kind::Junction`]: a single disk or half-disk with one constraint edge (a line end) or
//!   three or more (lines meeting): it may be removed only by a collapse that carries every wedge
//!   it uses onto its own wedge of the survivor (a seam end moving to a neighbour, a junction
//!   sliding along one of its lines), and the survivor keeps its position (but see below);
//! - [`Kind::Locked`]: anything else (non-manifold or inconsistently oriented edges, fans that
//!   are not a single disk, triangles with two corners at one position): it is never removed,
//!   though other vertices may collapse onto it.
//!
//! An interior vertex may collapse onto any of them. Onto an outline the survivor stays where it
//! is; onto a line, corner or junction whose lines are all seams the two merge at their quadric's
//! minimiser, as interior vertices do, and the seam moves with its surface (`collapse/plan.rs`).

use glam::Vec3;

use crate::twins::{lowest_of_equal_keys, position_bits, triangle_layers, vertex_layers};

pub(crate) use crate::progressive::NONE;

/// The role of a position class; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Interior,
    Line,
    Corner,
    Junction,
    Locked,
}

impl Kind {
    /// On a border, seam or material line (collapses only along it).
    pub fn on_line(self) -> bool {
        matches!(self, Kind::Line | Kind::Corner)
    }

    /// Never moves when something collapses onto it (a line end, junction or complex vertex).
    pub fn pinned(self) -> bool {
        matches!(self, Kind::Junction | Kind::Locked)
    }
}

/// A line turning by more than 45° at a vertex makes it a corner: cos 45°. Smaller turns are
/// the polyline of a smooth outline, whose vertices may move along it.
const CORNER_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Which kind of constraint an edge is; it selects the penalty-plane weight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Constraint {
    /// One triangle: an open border of the surface.
    Border,
    /// Two triangles with different materials.
    Material,
    /// Two triangles of one material that use different wedges at an end, with the same normal
    /// at both ends: a uv or colour seam inside one smooth (or faceted) surface.
    Seam,
    /// A seam whose sides' normals differ at an end ([`creases`]): a hard edge of a
    /// smooth-shaded mesh, or where a faceted region meets a smooth one.
    Crease,
}

/// Two normals within 2° are one: exporters quantise normals (8-bit components are off by up to
/// about 0.5°), while a hard edge turns the normal by far more. As `clod::shading`'s flat test.
const CREASE_COS: f32 = 0.999_39;

/// Whether two wedges' normals make their seam a crease: they differ by more than 2°, or one is
/// zero (not priced: a faceted vertex, see `clod::shading`) and the other is not. Two zero
/// normals (both faceted) are no crease: a faceted surface's shading follows its positions.
pub(crate) fn creases(a: Vec3, b: Vec3) -> bool {
    match (a.normalize_or_zero(), b.normalize_or_zero()) {
        (Vec3::ZERO, Vec3::ZERO) => false,
        (Vec3::ZERO, _) | (_, Vec3::ZERO) => true,
        (a, b) => a.dot(b) < CREASE_COS,
    }
}

/// One side of a constraint edge: the edge from corner `corner` to the next corner of its
/// triangle, for one penalty plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConstraintSide {
    pub corner: u32,
    pub constraint: Constraint,
}

/// Position classes of the referenced vertices.
pub(crate) struct PositionClasses {
    /// Class of each vertex, [`NONE`] for vertices no triangle references.
    pub class_of: Vec<u32>,
    /// `wedges[wedge_start[c]..wedge_start[c + 1]]` are the vertices of class `c`, ascending.
    pub wedge_start: Vec<u32>,
    pub wedges: Vec<u32>,
    /// Lowest vertex index of each class (its position is the class's position).
    pub representative: Vec<u32>,
    /// When triangles repeat each other and classes are layered ([`crate::twins`]): per class,
    /// the lowest class at its position.
    pub same_position: Option<Vec<u32>>,
}

impl PositionClasses {
    pub fn count(&self) -> usize {
        self.representative.len()
    }

    pub fn wedges_of(&self, class: u32) -> &[u32] {
        let c = class as usize;
        &self.wedges[self.wedge_start[c] as usize..self.wedge_start[c + 1] as usize]
    }
}

/// Groups the referenced vertices by bit-identical position, and by *layer* where triangles
/// repeat each other ([`crate::twins`]: each copy of a repeated surface simplifies on its own).
/// Class ids follow the order of each class's lowest vertex index, so the result does not depend
/// on sorting details.
pub(crate) fn position_classes(positions: &[Vec3], indices: &[u32]) -> PositionClasses {
    let plain = weld(positions, indices, None);
    match triangle_layers(|v| plain.class_of[v as usize], indices, plain.count()) {
        None => plain,
        Some(triangle_layer) => {
            let layer = vertex_layers(&triangle_layer, indices, positions.len());
            let mut layered = weld(positions, indices, Some(&layer));
            // Per layered class, the plain class of its position, as the lowest layered class
            // there: class ids follow lowest vertices in both weldings.
            let mut first_at = vec![NONE; plain.count()];
            let same_position = (0..layered.count())
                .map(|c| {
                    let at = &mut first_at[plain.class_of[layered.representative[c] as usize] as usize];
                    if *at == NONE {
                        *at = c as u32;
                    }
                    *at
                })
                .collect();
            layered.same_position = Some(same_position);
            layered
        }
    }
}

/// The welding of [`position_classes`]: by position, and within a position by `layer` if given.
fn weld(positions: &[Vec3], indices: &[u32], layer: Option<&[u32]>) -> PositionClasses {
    let mut referenced = vec![false; positions.len()];
    for &i in indices {
        referenced[i as usize] = true;
    }
    // The lowest referenced vertex at each position, or of each layer at a position.
    let lowest = lowest_of_equal_keys(positions.len(), |v| {
        let [x, y, z] = position_bits(positions[v]);
        referenced[v].then(|| [x, y, z, layer.map_or(0, |layer| layer[v])])
    });
    let mut class_of = vec![NONE; positions.len()];
    let mut representative = Vec::new();
    for v in 0..positions.len() {
        let low = lowest[v];
        if low == NONE {
            continue;
        }
        if low as usize == v {
            class_of[v] = representative.len() as u32;
            representative.push(v as u32);
        } else {
            class_of[v] = class_of[low as usize];
        }
    }
    let mut wedge_start = vec![0u32; representative.len() + 1];
    for &c in &class_of {
        if c != NONE {
            wedge_start[c as usize + 1] += 1;
        }
    }
    for c in 0..representative.len() {
        wedge_start[c + 1] += wedge_start[c];
    }
    let mut fill = wedge_start.clone();
    let mut wedges = vec![0u32; wedge_start[representative.len()] as usize];
    for (v, &c) in class_of.iter().enumerate() {
        if c != NONE {
            wedges[fill[c as usize] as usize] = v as u32;
            fill[c as usize] += 1;
        }
    }
    PositionClasses { class_of, wedge_start, wedges, representative, same_position: None }
}

/// For every class, a linked list of the corners (`3 × triangle + k`) at that class. Flat
/// arrays: collapses splice lists together and unlink dead triangles in constant time, without
/// allocating or walking a list (each step of a walk is a cache miss).
pub(crate) struct CornerLists {
    head: Vec<u32>,
    /// The next corner of the list, NONE after the last.
    next: Vec<u32>,
    /// The previous corner of the list; for the first, the last (so a list's tail is one read
    /// away).
    prev: Vec<u32>,
}

impl CornerLists {
    pub fn new(corner_class: impl Fn(usize) -> u32, corner_count: usize, class_count: usize) -> Self {
        let mut head = vec![NONE; class_count];
        let mut next = vec![NONE; corner_count];
        let mut prev = vec![NONE; corner_count];
        // Pushing in reverse makes every list ascend by corner.
        for corner in (0..corner_count).rev() {
            let c = corner_class(corner) as usize;
            let first = head[c];
            next[corner] = first;
            // The new first corner's `prev` is the tail: the old first's tail, or itself.
            prev[corner] = if first == NONE { corner as u32 } else { prev[first as usize] };
            if first != NONE {
                prev[first as usize] = corner as u32;
            }
            head[c] = corner as u32;
        }
        CornerLists { head, next, prev }
    }

    /// The corners of `class`.
    pub fn iter(&self, class: u32) -> CornerIter<'_> {
        CornerIter { next: &self.next, at: self.head[class as usize] }
    }

    /// Whether `class` has exactly two corners, in constant time: the first's successor is the
    /// tail.
    pub fn has_two(&self, class: u32) -> bool {
        let first = self.head[class as usize];
        first != NONE
            && self.next[first as usize] != NONE
            && self.prev[first as usize] == self.next[first as usize]
    }

    /// Whether `class` has exactly one corner.
    pub fn has_one(&self, class: u32) -> bool {
        let first = self.head[class as usize];
        first != NONE && self.next[first as usize] == NONE
    }

    /// Moves every corner of `from` into `into`'s list, ahead of `into`'s own.
    pub fn splice(&mut self, from: u32, into: u32) {
        let first = self.head[from as usize];
        if first == NONE {
            return;
        }
        let last = self.prev[first as usize];
        let old_first = self.head[into as usize];
        if old_first != NONE {
            let tail = self.prev[old_first as usize];
            self.next[last as usize] = old_first;
            self.prev[old_first as usize] = last;
            self.prev[first as usize] = tail;
        }
        self.head[into as usize] = first;
        self.head[from as usize] = NONE;
    }

    /// Removes `corner` from `class`'s list, which must hold it.
    pub fn unlink(&mut self, class: u32, corner: u32) {
        let (before, after) = (self.prev[corner as usize], self.next[corner as usize]);
        let first = self.head[class as usize];
        if corner == first {
            self.head[class as usize] = after;
            if after != NONE {
                self.prev[after as usize] = before; // the tail
            }
            return;
        }
        self.next[before as usize] = after;
        if after != NONE {
            self.prev[after as usize] = before;
        } else {
            self.prev[first as usize] = before; // the new tail
        }
    }
}

pub(crate) struct CornerIter<'a> {
    next: &'a [u32],
    at: u32,
}

impl Iterator for CornerIter<'_> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        if self.at == NONE {
            return None;
        }
        let corner = self.at;
        self.at = self.next[corner as usize];
        Some(corner)
    }
}

/// The two other corners of `corner`'s triangle, in winding order.
#[inline]
pub(crate) fn other_corners(corner: u32) -> (u32, u32) {
    let base = corner - corner % 3;
    let k = corner % 3;
    (base + (k + 1) % 3, base + (k + 2) % 3)
}

/// What [`classify`] finds: per class its kind and whether it lies on an outline, and the sides
/// of every constraint edge.
pub(crate) struct Classification {
    pub kinds: Vec<Kind>,
    /// Per class: it has an open border, a material border or a crease among its edges, a line
    /// that shows where it runs. A class whose only lines are seams lies inside one smooth (or
    /// faceted) surface: its seams split uv or colour, not the shape, and may move with it.
    pub on_outline: Vec<bool>,
    /// The sides of every constraint edge (each undirected edge once).
    pub sides: Vec<ConstraintSide>,
}

/// Kinds of all classes, which lie on outlines, and the sides of all constraint edges;
/// `creased(a, b)`: whether a seam between vertices `a` and `b` is a crease ([`creases`] of their
/// normals).
pub(crate) fn classify(
    classes: &PositionClasses,
    positions: &[Vec3],
    lists: &CornerLists,
    indices: &[u32],
    materials: &[u32],
    creased: impl Fn(u32, u32) -> bool,
) -> Classification {
    let class_at = |corner: u32| classes.class_of[indices[corner as usize] as usize];
    let material = |corner: u32| materials.get(corner as usize / 3).copied().unwrap_or(0);
    let mut kinds = vec![Kind::Locked; classes.count()];
    let mut on_outline = vec![false; classes.count()];
    let mut sides = Vec::new();
    // Per class scratch: (neighbour, 0 = edge leaves this class / 1 = edge enters it, corner of
    // this class), and the link edges (a → b) of the fan.
    let mut incident: Vec<(u32, u8, u32)> = Vec::new();
    let mut link: Vec<(u32, u32)> = Vec::new();
    for c in 0..classes.count() as u32 {
        incident.clear();
        link.clear();
        let mut locked = false;
        for corner in lists.iter(c) {
            let (next, prev) = other_corners(corner);
            let (a, b) = (class_at(next), class_at(prev));
            if a == c || b == c || a == b {
                // Two corners at one position: no fan structure to reason about.
                locked = true;
                continue;
            }
            incident.push((a, 0, corner));
            incident.push((b, 1, corner));
            link.push((a, b));
        }
        incident.sort_unstable();
        let mut constraint_count = 0;
        let mut line_neighbours = [NONE; 2];
        let mut start = 0;
        while start < incident.len() {
            let neighbour = incident[start].0;
            let mut end = start;
            while end < incident.len() && incident[end].0 == neighbour {
                end += 1;
            }
            let run = &incident[start..end];
            let outs = run.iter().filter(|e| e.1 == 0).count();
            let constraint = match (outs, run.len()) {
                (_, 1) => Some(Constraint::Border),
                (1, 2) => {
                    // run[0] leaves c (corner → neighbour is `next`), run[1] enters c.
                    let (c0, c1) = (run[0].2, run[1].2);
                    let n0 = other_corners(c0).0;
                    let n1 = other_corners(c1).1;
                    let ends = [(c0, c1), (n0, n1)].map(|(a, b)| (indices[a as usize], indices[b as usize]));
                    if material(c0) != material(c1) {
                        Some(Constraint::Material)
                    } else if ends.iter().any(|&(a, b)| a != b && creased(a, b)) {
                        Some(Constraint::Crease)
                    } else if ends.iter().any(|&(a, b)| a != b) {
                        Some(Constraint::Seam)
                    } else {
                        None
                    }
                }
                _ => {
                    // Three or more triangles, or two with the same orientation.
                    locked = true;
                    None
                }
            };
            if let Some(constraint) = constraint {
                on_outline[c as usize] |= constraint != Constraint::Seam;
                if constraint_count < 2 {
                    line_neighbours[constraint_count] = neighbour;
                }
                constraint_count += 1;
                if c < neighbour {
                    for &(_, dir, corner) in run {
                        // The side's edge must run from `corner` to its successor: for an
                        // entering edge (neighbour → c) start at the predecessor corner.
                        let side_corner = if dir == 0 { corner } else { other_corners(corner).1 };
                        sides.push(ConstraintSide { corner: side_corner, constraint });
                    }
                }
            }
            start = end;
        }
        let disk = !locked && single_fan(&mut link);
        kinds[c as usize] = match (disk, constraint_count) {
            (true, 0) => Kind::Interior,
            (true, 2) => {
                let at = |class: u32| positions[classes.representative[class as usize] as usize].as_dvec3();
                let (d1, d2) = (at(line_neighbours[0]) - at(c), at(line_neighbours[1]) - at(c));
                // Straight on: d1 and d2 point in opposite directions.
                let cos_turn = -d1.dot(d2) / (d1.length() * d2.length());
                if cos_turn >= CORNER_COS {
                    Kind::Line
                } else {
                    Kind::Corner
                }
            }
            (true, _) => Kind::Junction,
            _ => Kind::Locked,
        };
    }
    Classification { kinds, on_outline, sides }
}

/// Whether the link edges (a → b) of a fan form one cycle or one path (a disk or half-disk).
fn single_fan(link: &mut [(u32, u32)]) -> bool {
    if link.is_empty() {
        return false;
    }
    link.sort_unstable();
    if link.windows(2).any(|w| w[0].0 == w[1].0) {
        return false;
    }
    let successor = |a: u32| link.binary_search_by_key(&a, |e| e.0).ok().map(|i| link[i].1);
    // A path starts at a link vertex that no edge enters; a cycle can start anywhere.
    let mut ends: Vec<u32> = link.iter().map(|e| e.1).collect();
    ends.sort_unstable();
    let start = link.iter().map(|e| e.0).find(|a| ends.binary_search(a).is_err()).unwrap_or(link[0].0);
    let mut at = start;
    let mut steps = 0;
    while let Some(b) = successor(at) {
        steps += 1;
        at = b;
        if at == start || steps > link.len() {
            break;
        }
    }
    steps == link.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn other_corners_follow_the_winding() {
        assert_eq!(other_corners(0), (1, 2));
        assert_eq!(other_corners(1), (2, 0));
        assert_eq!(other_corners(2), (0, 1));
        assert_eq!(other_corners(3 * 1_000_000 + 2), (3_000_000, 3_000_001));
    }

    fn kinds_of(positions: &[Vec3], indices: &[u32], materials: &[u32]) -> Vec<Kind> {
        let classes = position_classes(positions, indices);
        let lists =
            CornerLists::new(|k| classes.class_of[indices[k] as usize], indices.len(), classes.count());
        classify(&classes, positions, &lists, indices, materials, |_, _| false).kinds
    }

    /// A 3×3 vertex grid (4 quads, 8 triangles), centre vertex 4.
    fn grid() -> (Vec<Vec3>, Vec<u32>) {
        let positions = (0..9).map(|i| Vec3::new((i % 3) as f32, (i / 3) as f32, 0.0)).collect();
        let mut indices = Vec::new();
        for y in 0..2 {
            for x in 0..2 {
                let v = y * 3 + x;
                indices.extend_from_slice(&[v, v + 1, v + 4, v, v + 4, v + 3]);
            }
        }
        (positions, indices)
    }

    #[test]
    fn grid_centre_is_interior_and_rim_is_line() {
        let (p, i) = grid();
        let kinds = kinds_of(&p, &i, &[]);
        assert_eq!(kinds[4], Kind::Interior);
        for v in [1, 3, 5, 7] {
            assert_eq!(kinds[v], Kind::Line, "vertex {v}");
        }
        for v in [0, 2, 6, 8] {
            assert_eq!(kinds[v], Kind::Corner, "vertex {v}");
        }
    }

    #[test]
    fn material_line_through_the_centre() {
        let (p, i) = grid();
        // Left column of quads is material 0, right column material 1: the line x = 1.
        let materials = [0, 0, 1, 1, 0, 0, 1, 1];
        let kinds = kinds_of(&p, &i, &materials);
        assert_eq!(kinds[4], Kind::Line);
        // Rim vertices where the material line meets the border have three constraint edges.
        assert_eq!(kinds[1], Kind::Junction);
        assert_eq!(kinds[7], Kind::Junction);
        assert_eq!(kinds[3], Kind::Line);
    }

    #[test]
    fn seam_end_inside_the_surface_is_a_junction() {
        let (mut p, mut i) = grid();
        // Vertex 9 duplicates 1 for the quad right of the edge 1-4: a seam from the border
        // vertex 1 that ends at the centre.
        p.push(p[1]);
        for tri in i[6..12].chunks_exact_mut(3) {
            for v in tri.iter_mut() {
                if *v == 1 {
                    *v = 9;
                }
            }
        }
        let kinds = kinds_of(&p, &i, &[]);
        // One constraint edge at the centre (a line end), three at 1 (two border edges, the seam).
        assert_eq!(kinds[4], Kind::Junction);
        assert_eq!(kinds[1], Kind::Junction);
        assert_eq!(kinds[3], Kind::Line);
    }

    #[test]
    fn a_seam_is_no_outline_unless_it_creases() {
        let (mut p, mut i) = grid();
        // Vertex 9 duplicates 1 for the quad right of the edge 1-4, as above.
        p.push(p[1]);
        for v in i[6..12].iter_mut().filter(|v| **v == 1) {
            *v = 9;
        }
        let classes = position_classes(&p, &i);
        let lists = CornerLists::new(|k| classes.class_of[i[k] as usize], i.len(), classes.count());
        let outline = |creased: &dyn Fn(u32, u32) -> bool| {
            let found = classify(&classes, &p, &lists, &i, &[], creased);
            let crease_sides = found.sides.iter().filter(|s| s.constraint == Constraint::Crease).count();
            (found.on_outline, crease_sides)
        };
        // A uv seam: the centre, where it ends, is on no outline; 1 is, by its border edges.
        let (seam, creases) = outline(&|_, _| false);
        assert_eq!(
            (seam[classes.class_of[4] as usize], seam[classes.class_of[1] as usize], creases),
            (false, true, 0)
        );
        // The same split as a crease: both sides of the edge 1-4 become crease sides.
        let (crease, creases) = outline(&|a, b| (a, b) == (1, 9) || (a, b) == (9, 1));
        assert_eq!((crease[classes.class_of[4] as usize], creases), (true, 2));
    }

    #[test]
    fn creases_are_turns_over_two_degrees_or_a_faceted_side() {
        let turned = |degrees: f32| Vec3::new(degrees.to_radians().sin(), 0.0, degrees.to_radians().cos());
        assert!(!creases(Vec3::Z, turned(1.0)));
        assert!(creases(Vec3::Z, turned(3.0)));
        // Unnormalised normals are compared by direction.
        assert!(!creases(2.0 * Vec3::Z, Vec3::Z));
        // Zero stands for a faceted vertex's normal, which the simplifier does not price.
        assert!(!creases(Vec3::ZERO, Vec3::ZERO));
        assert!(creases(Vec3::ZERO, Vec3::Z));
    }

    #[test]
    fn bowtie_and_nonmanifold_edges_lock() {
        // Two triangles touching at vertex 0 only.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y];
        let kinds = kinds_of(&p, &[0, 1, 2, 0, 3, 4], &[]);
        assert_eq!(kinds[0], Kind::Locked);
        // Three triangles on edge 0-1.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Y];
        let kinds = kinds_of(&p, &[0, 1, 2, 1, 0, 3, 0, 1, 4], &[]);
        assert_eq!(kinds[0], Kind::Locked);
        assert_eq!(kinds[1], Kind::Locked);
    }

    #[test]
    fn duplicated_position_makes_one_class_and_a_seam() {
        let (mut p, mut i) = grid();
        // Split the middle row's right half: vertex 9 duplicates 4 for the right column's quads.
        p.push(p[4]);
        for (t, tri) in i.chunks_exact_mut(3).enumerate() {
            if t % 4 >= 2 {
                for v in tri.iter_mut() {
                    if *v == 4 {
                        *v = 9;
                    }
                }
            }
        }
        let classes = position_classes(&p, &i);
        assert_eq!(classes.count(), 9);
        assert_eq!(classes.class_of[9], classes.class_of[4]);
        assert_eq!(classes.wedges_of(classes.class_of[4]), &[4, 9]);
        let kinds = kinds_of(&p, &i, &[]);
        // Seam runs 1 - 4 - 7: the centre slides along it, its ends are junctions.
        assert_eq!(kinds[4], Kind::Line);
        assert_eq!(kinds[1], Kind::Junction);
    }

    /// Splices and unlinks, first, last and middle corners and whole lists, against plain vectors:
    /// the lists keep their order.
    #[test]
    fn corner_lists_splice_and_unlink_in_order() {
        let class_of = [0u32, 1, 0, 2, 1, 0, 2, 2, 1, 0, 3, 3];
        let mut lists = CornerLists::new(|k| class_of[k], class_of.len(), 4);
        let mut reference: Vec<Vec<u32>> =
            (0..4).map(|c| (0..12).filter(|&k| class_of[k as usize] == c).collect()).collect();
        let check = |lists: &CornerLists, reference: &[Vec<u32>]| {
            for (c, expected) in reference.iter().enumerate() {
                assert_eq!(lists.iter(c as u32).collect::<Vec<_>>(), *expected, "class {c}");
                assert_eq!(lists.has_two(c as u32), expected.len() == 2, "class {c}");
            }
        };
        check(&lists, &reference);
        let unlink = |lists: &mut CornerLists, reference: &mut Vec<Vec<u32>>, c: u32, k: u32| {
            lists.unlink(c, k);
            reference[c as usize].retain(|&x| x != k);
        };
        unlink(&mut lists, &mut reference, 0, 0); // first
        unlink(&mut lists, &mut reference, 1, 8); // last
        check(&lists, &reference);
        lists.splice(1, 0);
        let moved = std::mem::take(&mut reference[1]);
        reference[0].splice(0..0, moved);
        check(&lists, &reference);
        unlink(&mut lists, &mut reference, 0, 9); // the spliced list's last, then its new last
        unlink(&mut lists, &mut reference, 0, 5);
        unlink(&mut lists, &mut reference, 0, 4); // middle
        check(&lists, &reference);
        lists.splice(0, 2);
        let moved = std::mem::take(&mut reference[0]);
        reference[2].splice(0..0, moved);
        lists.splice(3, 2);
        let moved = std::mem::take(&mut reference[3]);
        reference[2].splice(0..0, moved);
        check(&lists, &reference);
        for k in reference[2].clone() {
            unlink(&mut lists, &mut reference, 2, k);
            check(&lists, &reference);
        }
        lists.splice(2, 1); // an empty list moves nothing
        check(&lists, &reference);
    }
}
