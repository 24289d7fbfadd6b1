//! Clearance: how far a point is from the input's *other* parts (connected components over
//! position classes). The collapse engine prices a part that vanishes with it: every surface of
//! the part goes, and each of its points ends up as far away as the nearest surface left, which
//! for a finger is the hand beside it and for a plate lying on a body the body under it.
//!
//! The other parts are taken as they are in the input, not as simplified so far (the parts left
//! are simplified versions of the input's, close to them at the levels where a part vanishes),
//! but without the parts that have vanished already ([`Clearance::vanish`]): on robot.glb the
//! antenna's tip ball went first, onto the antenna's rod, and then the rod onto the head, each
//! priced against the other's input surface, which left the tip's points 4.8 % of the diagonal
//! from anything at a 4.5 % floor; the right hand's palm and fingers likewise went onto each
//! other, 7.3 % at the 82-triangle level under the default 5 %. So a price can rise when a part
//! nearby vanishes first, and the engine re-queues an entry whose price changed.
//!
//! The price is a mean over a sheet's corners; the distance floor asks more of a part that
//! vanishes ([`Clearance::leaves_within`]): every one of its input points within the floor of a
//! part left. A vanished part hands its extreme points to the parts nearest them,
//! which answer for them when they vanish in turn ([`Clearance::vanish`]).
//!
//! An open part (its last triangle) is measured against the live triangles of the parts left
//! as well (`collapse/floors.rs`, `Floors::squared_to_level`): [`Clearance::visit_near`] finds the
//! input triangles near a point, and the triangles now standing for them are tested.
//!
//! The index is built on the first query, so a mesh none of whose parts vanishes pays nothing:
//! a uniform grid (`clearance/grid.rs`; about one triangle a cell) holding each triangle in every
//! cell its bounding box overlaps, searched shell by shell around the query until the shells
//! cover the nearest distance found; a triangle whose box spans more than
//! [`MAX_CELLS_PER_TRIANGLE`](grid::MAX_CELLS_PER_TRIANGLE) cells is kept apart and always
//! tested, so the grid's memory stays linear in the triangles. Positions are in the input's
//! units; distances come back squared.

mod grid;

use super::topology::{PositionClasses, NONE};
use crate::metrics::closest_point_on_triangle;
use glam::Vec3;
use grid::{Grid, Tested};
use std::collections::{HashMap, HashSet};

/// Points whose distance [`Clearance::leaves_within`] keeps to vouch for their neighbours: the
/// test of a point against them is linear in their number.
const MAX_VOUCHERS: usize = 32;
/// A search for the nearest triangle, however far.
const UNBOUNDED: (f32, f32) = (f32::INFINITY, 0.0);

/// The input triangles, with their parts and the grid found on the first query. Queries take
/// `&mut self`: the first builds the index, and answers are remembered.
pub(super) struct Clearance<'a> {
    positions: &'a [Vec3],
    indices: &'a [u32],
    /// The parts and their grid, built on the first query.
    index: Option<Index>,
    /// The last answer per class, with the part it found: a sheet's three edges are priced with
    /// the same corners. Stale once that part has vanished.
    answers: HashMap<u32, (Vec3, Option<Found>)>,
    /// Parts found not to vanish within a limit (part, the limit's bits).
    stranded: HashSet<(u32, u32)>,
    /// The triangles a search has tested already.
    tested: Tested,
}

/// A search's answer: the squared distance to the nearest triangle found, and its part.
type Found = (f32, u32);

struct Index {
    /// Per position class, the lowest class of its part. A collapse joins two classes of one
    /// part, so a live class is in its input class's part.
    class_part: Vec<u32>,
    /// Per input vertex, its part ([`NONE`] for a vertex no triangle uses).
    vertex_part: Vec<u32>,
    grid: Grid,
    /// `points[point_start[p]..point_start[p + 1]]`: part `p`'s input points, one vertex per
    /// position class.
    point_start: Vec<u32>,
    points: Vec<u32>,
    /// Per part (by its lowest class), whether it has vanished: searches skip its triangles.
    vanished: Vec<bool>,
    /// Per part, the input vertices that vanished parts left to it.
    left_to: HashMap<u32, Vec<u32>>,
    /// Parts not vanished.
    parts_left: usize,
    /// Per part, its triangles.
    part_triangles: Vec<u32>,
    /// The triangles of parts not vanished, and of those the grids were built over.
    live_triangles: usize,
    gridded_triangles: usize,
}

impl Index {
    /// A grid over the triangles of the parts not vanished, at `positions`.
    fn grid_over(&self, positions: &[Vec3], indices: &[u32]) -> Grid {
        let part_of = |v: u32| self.vertex_part[v as usize];
        Grid::new(positions, indices, part_of, |t| !self.vanished[part_of(indices[3 * t]) as usize])
    }

    /// Part `part`'s own input points and those vanished parts left to it.
    fn points_of(&self, part: u32) -> impl Iterator<Item = u32> + '_ {
        let own = &self.points
            [self.point_start[part as usize] as usize..self.point_start[part as usize + 1] as usize];
        own.iter().chain(self.left_to.get(&part).into_iter().flatten()).copied()
    }
}

impl<'a> Clearance<'a> {
    /// Holds the input; nothing is computed before the first query.
    pub(super) fn new(positions: &'a [Vec3], indices: &'a [u32]) -> Self {
        Clearance {
            positions,
            indices,
            index: None,
            answers: HashMap::new(),
            stranded: HashSet::new(),
            tested: Tested::default(),
        }
    }

    /// The squared distance from class `class`, at `q`, to the nearest input triangle of a part
    /// other than the class's (where parts overlap densely, the nearest within the search's
    /// budget, [`MAX_VISITS`](grid::MAX_VISITS)), or `None` when the input has no other part.
    /// `classes` are the input's position classes (the same on every call).
    pub(super) fn squared_to_other_parts(
        &mut self,
        classes: &PositionClasses,
        class: u32,
        q: Vec3,
    ) -> Option<f32> {
        let index = built(&mut self.index, classes, self.positions, self.indices);
        if let Some(&(at, answer)) = self.answers.get(&class) {
            // Stale once the part it found has vanished.
            if at == q && answer.is_none_or(|(_, found)| !index.vanished[found as usize]) {
                return answer.map(|(squared, _)| squared);
            }
        }
        let part = index.class_part[class as usize];
        let pose = (self.positions, &index.grid);
        let answer = index.search(self.indices, pose, &mut self.tested, q, part, UNBOUNDED);
        self.answers.insert(class, (q, answer));
        answer.map(|(squared, _)| squared)
    }

    /// The input points of class `class`'s part: its own (one per position class) and those
    /// vanished parts left to it.
    pub(super) fn points_of_part(&mut self, classes: &PositionClasses, class: u32) -> Vec<u32> {
        let index = built(&mut self.index, classes, self.positions, self.indices);
        index.points_of(index.class_part[class as usize]).collect()
    }

    /// Calls `visit` with the input triangles of parts other than `class`'s and not vanished
    /// that may lie within `radius` of `q` (in the simplification pose), nearest cells first.
    /// `visit` answers the squared distance the caller has found so far (infinite for none): the
    /// search skips the triangles and stops at the shells beyond it, and once one is found, after
    /// [`MAX_VISITS`](grid::MAX_VISITS) entries, as [`Clearance::squared_to_other_parts`] does.
    pub(super) fn visit_near(
        &mut self,
        classes: &PositionClasses,
        class: u32,
        q: Vec3,
        radius: f32,
        visit: &mut dyn FnMut(u32) -> f32,
    ) {
        let index = built(&mut self.index, classes, self.positions, self.indices);
        let grid = &index.grid;
        let part = index.class_part[class as usize];
        let within = radius * radius;
        let mut found = f32::INFINITY;
        let mut test = |t: u32| {
            let other = grid.part[t as usize];
            if other == part || index.vanished[other as usize] {
                return found;
            }
            let (centre, sphere) = grid.sphere[t as usize];
            let beyond = (centre.distance(q) - sphere).max(0.0);
            if beyond * beyond <= found.min(within) {
                found = visit(t);
            }
            found
        };
        let start = grid.large.iter().fold(f32::INFINITY, |_, &t| test(t));
        grid.search(&mut self.tested, q, start, within, &mut test);
    }

    /// Whether class `class`'s part, if it vanished, would leave its input points, and those other
    /// parts left to it, within `limit` of a part left (each point is looked at only to `limit`,
    /// and only until one part is that near). Also when no other part is left: there is nothing
    /// to measure against.
    pub(super) fn leaves_within(&mut self, classes: &PositionClasses, class: u32, limit: f32) -> bool {
        let index = built(&mut self.index, classes, self.positions, self.indices);
        let part = index.class_part[class as usize];
        if index.parts_left <= 1 {
            return true;
        }
        // Parts only vanish and points are only left to a part, so one that is not within the
        // limit never will be (the limit is the run's floor): its sheet's other edges ask again.
        let key = (part, limit.to_bits());
        if self.stranded.contains(&key) {
            return false;
        }
        let (positions, indices) = (self.positions, self.indices);
        // A point within `d` of a part left puts every point within `limit − d` of it within
        // `limit` too: those need no search. Searches stop at a part within half the limit, so
        // most found points vouch for their neighbours.
        let mut found: Vec<(Vec3, f32)> = Vec::new();
        let within = index.points_of(part).all(|vertex| {
            let q = positions[vertex as usize];
            if found.iter().any(|&(p, d)| d + p.distance(q) <= limit) {
                return true;
            }
            let pose = (positions, &index.grid);
            let Some((squared, _)) =
                index.search(indices, pose, &mut self.tested, q, part, (limit, 0.5 * limit))
            else {
                return false;
            };
            if found.len() < MAX_VOUCHERS {
                found.push((q, squared.sqrt()));
            }
            true
        });
        if !within {
            self.stranded.insert(key);
        }
        within
    }

    /// Records that class `class`'s part has vanished: later searches skip it, and its extreme
    /// points (of its own and those left to it: the farthest along each of 26 directions, the
    /// cube's faces, edges and corners) go to the part left nearest each, which answers for them
    /// when it vanishes in turn. A point far from everything left is one a part reaches out to, on
    /// its hull: a tip, a corner. Only parts within `limit` (the floor:
    /// [`Clearance::leaves_within`] let it vanish) are looked for, and a point within a quarter
    /// of it of a part left may go to that part rather than the nearest.
    pub(super) fn vanish(&mut self, classes: &PositionClasses, class: u32, limit: f32) {
        let index = built(&mut self.index, classes, self.positions, self.indices);
        let part = index.class_part[class as usize];
        let mut extremes: Vec<(f32, u32)> = vec![(f32::NEG_INFINITY, NONE); 26];
        for vertex in index.points_of(part) {
            let q = self.positions[vertex as usize];
            for (extreme, direction) in extremes.iter_mut().zip(directions()) {
                let along = q.dot(direction);
                if along > extreme.0 {
                    *extreme = (along, vertex);
                }
            }
        }
        let mut points: Vec<u32> = extremes.iter().map(|&(_, v)| v).filter(|&v| v != NONE).collect();
        points.sort_unstable();
        points.dedup();
        let heirs: Vec<(u32, u32)> = points
            .iter()
            .filter_map(|&vertex| {
                let q = self.positions[vertex as usize];
                let near_enough = (limit, 0.25 * limit);
                let pose = (self.positions, &index.grid);
                let (_, heir) = index.search(self.indices, pose, &mut self.tested, q, part, near_enough)?;
                Some((heir, vertex))
            })
            .collect();
        if !std::mem::replace(&mut index.vanished[part as usize], true) {
            index.parts_left -= 1;
            index.live_triangles -= index.part_triangles[part as usize] as usize;
        }
        index.left_to.remove(&part);
        for (heir, vertex) in heirs {
            index.left_to.entry(heir).or_default().push(vertex);
        }
        // Once most triangles in the grid have vanished, searches would sweep cells of them:
        // the grid is built again over the live ones, with cells for their number (each
        // rebuild at most halves the triangles, so all of them cost a few builds of the first).
        if index.live_triangles > 0 && 2 * index.live_triangles < index.gridded_triangles {
            index.grid = index.grid_over(self.positions, self.indices);
            index.gridded_triangles = index.live_triangles;
        }
    }
}

impl Index {
    /// The squared distance from `q` to the nearest triangle of a part that is neither `part` nor
    /// vanished, among the triangles of `grid` over `positions` (the input in one pose), and that
    /// triangle's part; only triangles nearer than `limit` (a distance) are looked for, and the
    /// search may stop at the first one nearer than `enough`. `None` when none is found.
    fn search(
        &self,
        indices: &[u32],
        (positions, grid): (&[Vec3], &Grid),
        tested: &mut Tested,
        q: Vec3,
        part: u32,
        (limit, enough): (f32, f32),
    ) -> Option<Found> {
        // A triangle at exactly `limit` is within it: look for those nearer than the next float
        // (the bits of a non-negative float count up with it).
        let squared = limit * limit;
        let limit_squared = if squared.is_finite() { f32::from_bits(squared.to_bits() + 1) } else { squared };
        let enough_squared = enough * enough;
        let mut best = (limit_squared, part);
        let mut test = |t: u32| {
            let t = t as usize;
            // The part first: most triangles near a point are of its own part.
            let other = grid.part[t];
            if other != part && !self.vanished[other as usize] {
                let (centre, radius) = grid.sphere[t];
                let beyond = (centre.distance(q) - radius).max(0.0);
                if beyond * beyond < best.0 {
                    let [a, b, c] = [0, 1, 2].map(|k| positions[indices[3 * t + k] as usize]);
                    let squared = closest_point_on_triangle(q, a, b, c).distance_squared(q);
                    if squared < best.0 {
                        best = (squared, other);
                    }
                }
            }
            if best.1 == part {
                f32::INFINITY // none found yet: the search's budget does not run
            } else if best.0 <= enough_squared {
                0.0 // nothing nearer is wanted: the shells searched so far cover 0
            } else {
                best.0
            }
        };
        let start = grid.large.iter().fold(f32::INFINITY, |_, &t| test(t));
        grid.search(tested, q, start, limit_squared, &mut test);
        (best.1 != part).then_some(best)
    }
}

/// The parts and their grid in `index`, built on the first call.
fn built<'i>(
    index: &'i mut Option<Index>,
    classes: &PositionClasses,
    positions: &[Vec3],
    indices: &[u32],
) -> &'i mut Index {
    index.get_or_insert_with(|| {
        let class_part = parts(classes, indices);
        let vertex_part: Vec<u32> =
            classes.class_of.iter().map(|&c| if c == NONE { NONE } else { class_part[c as usize] }).collect();
        let grid = Grid::new(positions, indices, |v| vertex_part[v as usize], |_| true);
        let live_triangles = indices.len() / 3;
        let mut part_triangles = vec![0u32; class_part.len()];
        for t in indices.chunks_exact(3) {
            part_triangles[vertex_part[t[0] as usize] as usize] += 1;
        }
        // Per part, its classes' representatives (one input vertex per position).
        let mut point_start = vec![0u32; class_part.len() + 1];
        for &part in &class_part {
            point_start[part as usize + 1] += 1;
        }
        for k in 0..class_part.len() {
            point_start[k + 1] += point_start[k];
        }
        let mut fill = point_start.clone();
        let mut points = vec![0u32; class_part.len()];
        for (class, &part) in class_part.iter().enumerate() {
            points[fill[part as usize] as usize] = classes.representative[class];
            fill[part as usize] += 1;
        }
        let vanished = vec![false; class_part.len()];
        let parts_left = class_part.iter().enumerate().filter(|&(c, &part)| part == c as u32).count();
        Index {
            class_part,
            vertex_part,
            grid,
            point_start,
            points,
            vanished,
            left_to: HashMap::new(),
            parts_left,
            part_triangles,
            live_triangles,
            gridded_triangles: live_triangles,
        }
    })
}

/// The 26 directions from a cube's centre to its faces, edges and corners (not normalised: only
/// the order along each matters).
fn directions() -> impl Iterator<Item = Vec3> {
    (0..27)
        .filter(|&k| k != 13)
        .map(|k| Vec3::new((k % 3) as f32 - 1.0, ((k / 3) % 3) as f32 - 1.0, (k / 9) as f32 - 1.0))
}

/// Per class, the lowest class of its connected component (union–find over the triangles).
/// Classes at one position are one part even when they are layered (`topology::twin_layers`): a
/// copy of a part lying on it is not something else for it to vanish onto.
fn parts(classes: &PositionClasses, indices: &[u32]) -> Vec<u32> {
    fn root(parent: &mut [u32], mut c: u32) -> u32 {
        while parent[c as usize] != c {
            let up = parent[parent[c as usize] as usize];
            parent[c as usize] = up;
            c = up;
        }
        c
    }
    let (class_of, class_count) = (&classes.class_of, classes.count());
    let mut parent: Vec<u32> = (0..class_count as u32).collect();
    let mut join = |a: u32, b: u32| {
        let (a, b) = (root(&mut parent, a), root(&mut parent, b));
        parent[a.max(b) as usize] = a.min(b);
    };
    for t in indices.chunks_exact(3) {
        for &k in &t[1..] {
            join(class_of[t[0] as usize], class_of[k as usize]);
        }
    }
    for (c, &at) in classes.same_position.iter().flatten().enumerate() {
        join(c as u32, at);
    }
    (0..class_count as u32).map(|c| root(&mut parent, c)).collect()
}

#[cfg(test)]
mod tests {
    use super::super::topology::{position_classes, NONE};
    use super::*;
    use crate::metrics::SplitMix64;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The exact answer, by testing every triangle whose part differs from `class`'s.
    fn brute_force(
        positions: &[Vec3],
        indices: &[u32],
        classes: &PositionClasses,
        class: u32,
        q: Vec3,
    ) -> Option<f32> {
        let part = parts(classes, indices);
        let part_of = |v: u32| part[classes.class_of[v as usize] as usize];
        let best = indices
            .chunks_exact(3)
            .filter(|t| part_of(t[0]) != part[class as usize])
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
                closest_point_on_triangle(q, a, b, c).distance_squared(q)
            })
            .fold(f32::INFINITY, f32::min);
        best.is_finite().then_some(best)
    }

    #[test]
    fn the_grid_finds_the_nearest_triangle_of_another_part() {
        // Seeded random parts (fans around a centre): small triangles, a few long slivers (which
        // span many cells or go to the large list), queries inside, between and far outside.
        let mut rng = SplitMix64(7);
        let mut random = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for part in 0..12u32 {
            let centre = random() * 10.0;
            let hub = positions.len() as u32;
            positions.push(centre);
            for t in 0..(10 + part * 7) {
                let size = if t % 17 == 0 { 8.0 } else { 0.5 };
                let base = positions.len() as u32;
                positions.push(centre + (random() - 0.5) * size);
                positions.push(centre + (random() - 0.5) * size);
                indices.extend([hub, base, base + 1]);
            }
        }
        let classes = position_classes(&positions, &indices);
        let mut clearance = Clearance::new(&positions, &indices);
        for k in 0..300 {
            let q = (random() - 0.25) * if k % 10 == 0 { 40.0 } else { 12.0 };
            let class = classes.class_of[indices[(k * 7) % indices.len()] as usize];
            let expected = brute_force(&positions, &indices, &classes, class, q);
            assert_eq!(clearance.squared_to_other_parts(&classes, class, q), expected, "query {k} at {q}");
            // Asked again at the same point: the stored answer.
            assert_eq!(clearance.squared_to_other_parts(&classes, class, q), expected);
        }
        // A mesh of one part has no other part.
        let mut one = Clearance::new(&positions[..3], &indices[..3]);
        assert_eq!(
            one.squared_to_other_parts(&position_classes(&positions[..3], &indices[..3]), 0, Vec3::ZERO),
            None
        );
    }

    #[test]
    fn a_search_over_its_budget_answers_no_nearer_than_the_truth() {
        // 2,000 small parts crowded in a unit box: the cells around a query hold more than
        // MAX_VISITS entries.
        let mut rng = SplitMix64(11);
        let mut random = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let (mut positions, mut indices) = (Vec::new(), Vec::new());
        for _ in 0..2000 {
            let (c, base) = (random(), positions.len() as u32);
            for _ in 0..4 {
                positions.push(c + (random() - 0.5) * 0.3);
            }
            indices.extend([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3].map(|k| k + base));
        }
        let classes = position_classes(&positions, &indices);
        let mut clearance = Clearance::new(&positions, &indices);
        for k in 0..50u32 {
            let class = classes.class_of[indices[k as usize * 12] as usize];
            let q = random();
            let exact = brute_force(&positions, &indices, &classes, class, q).unwrap();
            let answer = clearance.squared_to_other_parts(&classes, class, q).unwrap();
            assert!(answer >= exact, "query {k}: {answer} below the truth {exact}");
        }
    }

    #[test]
    fn parts_are_the_components_over_position_classes() {
        // Two triangles that share a position (vertices 2 and 3 are copies), one apart, and
        // vertex 9, which no triangle uses.
        let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        let positions = [
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(0.0, 1.0),
            p(0.0, 1.0),
            p(1.0, 1.0),
            p(2.0, 2.0),
            p(5.0, 0.0),
            p(6.0, 0.0),
            p(5.0, 1.0),
            p(9.0, 9.0),
        ];
        let indices = [0, 3, 1, 2, 1, 4, 6, 7, 8];
        let classes = position_classes(&positions, &indices);
        assert_eq!(classes.class_of[9], NONE);
        let part = parts(&classes, &indices);
        let of = |v: usize| part[classes.class_of[v] as usize];
        assert_eq!([0, 1, 2, 3, 4].map(of), [of(0); 5]);
        assert_eq!([6, 7, 8].map(of), [of(6); 3]);
        assert_ne!(of(0), of(6));
    }

    #[test]
    fn a_vanished_part_is_no_clearance_and_hands_its_points_on() {
        // Three one-triangle parts in the planes x = 0, 1 and 3, each over the same square in
        // y and z: a point of one is |dx| from another.
        let at = |x: f32| [Vec3::new(x, 0.0, 0.0), Vec3::new(x, 1.0, 0.0), Vec3::new(x, 0.0, 1.0)];
        let positions: Vec<Vec3> = [0.0, 1.0, 3.0].into_iter().flat_map(at).collect();
        let indices: Vec<u32> = (0..9).collect();
        let classes = position_classes(&positions, &indices);
        let class = |part: u32| classes.class_of[3 * part as usize];
        let mut clearance = Clearance::new(&positions, &indices);
        let squared_at = |clearance: &mut Clearance, part: u32| {
            clearance.squared_to_other_parts(&classes, class(part), positions[3 * part as usize])
        };
        // The farthest a part leaves a point: just within a limit, not within one a bit less.
        let leaves = |clearance: &mut Clearance, part: u32, distance: f32| {
            clearance.leaves_within(&classes, class(part), distance)
                && !clearance.leaves_within(&classes, class(part), distance * 0.999)
        };
        assert_eq!(squared_at(&mut clearance, 0), Some(1.0));
        assert!(leaves(&mut clearance, 0, 1.0));
        assert!(leaves(&mut clearance, 2, 2.0));

        // The middle part goes, leaving its points at x = 1 to the nearest part left, the first.
        clearance.vanish(&classes, class(1), 10.0);
        assert_eq!(squared_at(&mut clearance, 0), Some(9.0));
        assert!(leaves(&mut clearance, 2, 3.0));
        // The first part answers for them too: its own points stand 3 from the last part, those
        // left to it 2.
        assert!(leaves(&mut clearance, 0, 3.0));

        // Then the first goes: the last part is alone, with nothing left to measure against.
        clearance.vanish(&classes, class(0), 10.0);
        assert_eq!(squared_at(&mut clearance, 2), None);
        assert!(clearance.leaves_within(&classes, class(2), 0.0));
    }

    #[test]
    fn a_copy_lying_on_a_part_is_no_other_part() {
        // Triangle 0 1 2 and its reversed copy on vertices 3 4 5: two layers of classes, one part.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ZERO, Vec3::X, Vec3::Y];
        let indices = [0, 1, 2, 3, 5, 4];
        let classes = position_classes(&positions, &indices);
        assert_eq!(classes.count(), 6, "the copy is layered apart");
        assert_eq!(parts(&classes, &indices), [0; 6]);
        let mut clearance = Clearance::new(&positions, &indices);
        assert_eq!(clearance.squared_to_other_parts(&classes, classes.class_of[3], Vec3::ZERO), None);
    }
}
