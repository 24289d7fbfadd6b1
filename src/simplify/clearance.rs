//! Clearance: how far a point is from the input's *other* parts (connected components over
//! position classes). The collapse engine prices a part that vanishes with it: every surface of
//! the part goes, and each of its points ends up as far away as the nearest surface left, which
//! for a finger is the hand beside it and for a plate lying on a body the body under it.
//!
//! The other parts are taken as they are in the input, not as simplified so far, so a price is a
//! function of the vanishing part's own classes alone and stays exact in the queue until one of
//! them changes (the parts left are simplified versions of the input's, close to them at the
//! levels where a part vanishes).
//!
//! The index is built on the first query, so a mesh none of whose parts vanishes pays nothing:
//! a uniform grid (about one triangle a cell) holding each triangle in every cell its bounding
//! box overlaps, searched shell by shell around the query until the shells cover the nearest
//! distance found; a triangle whose box spans more than [`MAX_CELLS_PER_TRIANGLE`] cells is kept
//! apart and always tested, so the grid's memory stays linear in the triangles. Positions are in
//! the input's units; distances come back squared.

use super::topology::PositionClasses;
use crate::metrics::closest_point_on_triangle;
use glam::{IVec3, UVec3, Vec3};
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;

/// A search stops once it has tested this many grid entries and found a triangle of another
/// part, and answers the nearest found: where parts overlap densely a cell holds hundreds of
/// triangles, and without a bound the run's time would grow with the number of parts times their
/// density. The answer is then at least the true clearance, so such a part is priced high rather
/// than low, and it is the same on every run (the search's order is fixed). robot.glb's queries
/// test about 400 entries; its levels are the same as with no bound. 20,000 small tetrahedra
/// overlapping in a 5 m box (80,000 triangles) simplify to nothing in about 2 s (0.16 s without
/// the clearance; spread over 100 m, 0.46 s): there most tests are exact ones, since the query
/// lies in many triangles' bounding spheres.
const MAX_VISITS: usize = 1024;
/// Cells per input triangle at most, over the grid's whole box.
const CELLS_PER_TRIANGLE: f32 = 8.0;
/// Cells along the grid's longest side at most: bounds its memory whatever the input's shape.
const MAX_CELLS_PER_AXIS: u32 = 128;
/// A triangle whose bounding box overlaps more cells than this is tested by every query instead:
/// with about one triangle a cell, only a mesh's few largest triangles are, and the grid holds at
/// most this many entries per triangle.
const MAX_CELLS_PER_TRIANGLE: u32 = 64;

/// The input triangles, with their parts and the grid found on the first query.
pub(super) struct Clearance<'a> {
    positions: &'a [Vec3],
    indices: &'a [u32],
    index: OnceCell<Index>,
    /// The last answer per class: a sheet's three edges are priced with the same corners.
    answers: RefCell<HashMap<u32, (Vec3, Option<f32>)>>,
}

struct Index {
    /// Per position class, the lowest class of its part. A collapse joins two classes of one
    /// part, so a live class is in its input class's part.
    class_part: Vec<u32>,
    grid: Grid,
}

struct Grid {
    origin: Vec3,
    /// Cell edge length (> 0).
    cell: f32,
    dims: UVec3,
    /// Per cell, where its triangles start in `entries` (one more than there are cells).
    start: Vec<u32>,
    /// Triangle indices, cell after cell.
    entries: Vec<u32>,
    /// The triangles too large for the cells.
    large: Vec<u32>,
    /// Per triangle, its part.
    part: Vec<u32>,
    /// Per triangle, a bounding sphere (centre, radius): a cheap lower bound of its distance,
    /// which skips the exact test for most triangles once a near one is found.
    sphere: Vec<(Vec3, f32)>,
}

impl<'a> Clearance<'a> {
    /// Holds the input; nothing is computed before the first query.
    pub(super) fn new(positions: &'a [Vec3], indices: &'a [u32]) -> Self {
        Clearance { positions, indices, index: OnceCell::new(), answers: RefCell::default() }
    }

    /// The squared distance from class `class`, at `q`, to the nearest input triangle of a part
    /// other than the class's (where parts overlap densely, the nearest within the search's
    /// budget, [`MAX_VISITS`]), or `None` when the input has no other part. `classes` are the
    /// input's position classes (the same on every call).
    pub(super) fn squared_to_other_parts(
        &self,
        classes: &PositionClasses,
        class: u32,
        q: Vec3,
    ) -> Option<f32> {
        if let Some(&(at, answer)) = self.answers.borrow().get(&class) {
            if at == q {
                return answer;
            }
        }
        let index = self.index.get_or_init(|| {
            let class_part = parts(classes, self.indices);
            let grid = Grid::new(self.positions, self.indices, |v| {
                class_part[classes.class_of[v as usize] as usize]
            });
            Index { class_part, grid }
        });
        let answer = self.search(&index.grid, q, index.class_part[class as usize]);
        self.answers.borrow_mut().insert(class, (q, answer));
        answer
    }

    fn search(&self, grid: &Grid, q: Vec3, part: u32) -> Option<f32> {
        let mut best = f32::INFINITY;
        let mut test = |t: u32| {
            let t = t as usize;
            let (centre, radius) = grid.sphere[t];
            let beyond = (centre.distance(q) - radius).max(0.0);
            if grid.part[t] != part && beyond * beyond < best {
                let [a, b, c] = [0, 1, 2].map(|k| self.positions[self.indices[3 * t + k] as usize]);
                best = best.min(closest_point_on_triangle(q, a, b, c).distance_squared(q));
            }
            best
        };
        let large = grid.large.iter().fold(f32::INFINITY, |_, &t| test(t));
        let best = grid.search(q, large, &mut test);
        best.is_finite().then_some(best)
    }
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

impl Grid {
    /// `part_of` gives an input vertex's part (every vertex a triangle uses has one).
    fn new(positions: &[Vec3], indices: &[u32], part_of: impl Fn(u32) -> u32) -> Grid {
        let count = indices.len() / 3;
        let corners = |t: usize| [0, 1, 2].map(|k| positions[indices[3 * t + k] as usize]);
        let (min, max) = indices.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(positions[v as usize]), hi.max(positions[v as usize]))
        });
        let size = (max - min).max(Vec3::ZERO);
        // Cells the size of a typical triangle (the median of their boxes' longest sides), so a
        // triangle overlaps a few cells and a cell holds a few triangles where the surface is;
        // no more than CELLS_PER_TRIANGLE cells per triangle over the box (a surface fills
        // little of its box), nor MAX_CELLS_PER_AXIS a side.
        let mut sides: Vec<f32> = (0..count)
            .map(|t| {
                let [a, b, c] = corners(t);
                (a.max(b).max(c) - a.min(b).min(c)).max_element()
            })
            .collect();
        let median =
            if sides.is_empty() { 0.0 } else { *sides.select_nth_unstable_by(count / 2, f32::total_cmp).1 };
        let volume = size.x.max(1e-30) * size.y.max(1e-30) * size.z.max(1e-30);
        let cell = median
            .max((volume / (CELLS_PER_TRIANGLE * count.max(1) as f32)).cbrt())
            .max(size.max_element() / MAX_CELLS_PER_AXIS as f32);
        let cell = if cell.is_finite() && cell > 0.0 { cell } else { 1.0 };
        let dims = ((size / cell).as_uvec3() + 1).min(UVec3::splat(MAX_CELLS_PER_AXIS));
        let cell_of = |p: Vec3| ((p - min) / cell).max(Vec3::ZERO).as_uvec3().min(dims - 1);
        let range = |t: usize| {
            let [a, b, c] = corners(t);
            (cell_of(a.min(b).min(c)), cell_of(a.max(b).max(c)))
        };
        let spans = |(lo, hi): (UVec3, UVec3)| {
            let n = hi - lo + 1;
            n.x * n.y * n.z
        };
        let index = |k: UVec3| (k.x + dims.x * (k.y + dims.y * k.z)) as usize;
        let cells = (dims.x * dims.y * dims.z) as usize;
        let mut start = vec![0u32; cells + 1];
        let mut large = Vec::new();
        // Two passes over the boxes: count per cell, then fill.
        for pass in 0..2 {
            let mut fill = if pass == 1 { start.clone() } else { Vec::new() };
            let mut entries = if pass == 1 { vec![0u32; start[cells] as usize] } else { Vec::new() };
            for t in 0..count {
                let (lo, hi) = range(t);
                if spans((lo, hi)) > MAX_CELLS_PER_TRIANGLE {
                    if pass == 0 {
                        large.push(t as u32);
                    }
                    continue;
                }
                for z in lo.z..=hi.z {
                    for y in lo.y..=hi.y {
                        for x in lo.x..=hi.x {
                            let k = index(UVec3::new(x, y, z));
                            if pass == 0 {
                                start[k + 1] += 1;
                            } else {
                                entries[fill[k] as usize] = t as u32;
                                fill[k] += 1;
                            }
                        }
                    }
                }
            }
            if pass == 0 {
                for k in 0..cells {
                    start[k + 1] += start[k];
                }
            } else {
                let part = (0..count).map(|t| part_of(indices[3 * t])).collect();
                let sphere = (0..count)
                    .map(|t| {
                        let corners = corners(t);
                        let centre = corners.iter().sum::<Vec3>() / 3.0;
                        (centre, corners.iter().map(|p| p.distance(centre)).fold(0.0, f32::max))
                    })
                    .collect();
                return Grid { origin: min, cell, dims, start, entries, large, part, sphere };
            }
        }
        unreachable!("the second pass returns")
    }

    /// Calls `test` with the triangles of the cells around `q`, shell after shell, until the
    /// shells searched hold every triangle nearer than the best squared distance so far (which
    /// starts at `best` and is what `test` returns), or [`MAX_VISITS`] entries have been tested
    /// and one was found; returns that distance.
    fn search(&self, q: Vec3, mut best: f32, test: &mut dyn FnMut(u32) -> f32) -> f32 {
        let dims = self.dims.as_ivec3();
        // A query outside the grid starts from the nearest cell. After shells 0..s, a triangle
        // not yet seen overlaps no cell of the cube within s − 1 of the start: it lies beyond
        // one of the cube's faces that are not on the grid's boundary, at least as far from `q`
        // as that face (`q` is inside the cube, or outside the grid beyond a boundary face).
        let at = ((q - self.origin) / self.cell).floor().as_ivec3().clamp(IVec3::ZERO, dims - 1);
        let mut visited = 0;
        for shell in 0..=dims.max_element() {
            if shell > 0 {
                let reach = shell - 1;
                let mut covered = f32::INFINITY;
                for axis in 0..3 {
                    if at[axis] - reach > 0 {
                        let face = self.origin[axis] + (at[axis] - reach) as f32 * self.cell;
                        covered = covered.min(q[axis] - face);
                    }
                    if at[axis] + reach < dims[axis] - 1 {
                        let face = self.origin[axis] + (at[axis] + reach + 1) as f32 * self.cell;
                        covered = covered.min(face - q[axis]);
                    }
                }
                let covered = covered.max(0.0);
                if covered * covered >= best {
                    return best;
                }
            }
            let (lo, hi) = ((at - shell).max(IVec3::ZERO), (at + shell).min(dims - 1));
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    // Off the shell's faces in z and y, only its two x ends lie on it.
                    let on_face = (z - at.z).abs() == shell || (y - at.y).abs() == shell;
                    let step = if on_face { 1 } else { (2 * shell).max(1) as usize };
                    let first = if on_face { lo.x } else { at.x - shell };
                    for x in (first..=hi.x).step_by(step).filter(|&x| x >= 0) {
                        let k = (x + dims.x * (y + dims.y * z)) as usize;
                        for &t in &self.entries[self.start[k] as usize..self.start[k + 1] as usize] {
                            best = test(t);
                            visited += 1;
                            if visited >= MAX_VISITS && best.is_finite() {
                                return best;
                            }
                        }
                    }
                }
            }
        }
        best
    }
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
        let clearance = Clearance::new(&positions, &indices);
        for k in 0..300 {
            let q = (random() - 0.25) * if k % 10 == 0 { 40.0 } else { 12.0 };
            let class = classes.class_of[indices[(k * 7) % indices.len()] as usize];
            let expected = brute_force(&positions, &indices, &classes, class, q);
            assert_eq!(clearance.squared_to_other_parts(&classes, class, q), expected, "query {k} at {q}");
            // Asked again at the same point: the stored answer.
            assert_eq!(clearance.squared_to_other_parts(&classes, class, q), expected);
        }
        // A mesh of one part has no other part.
        let one = Clearance::new(&positions[..3], &indices[..3]);
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
        let clearance = Clearance::new(&positions, &indices);
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
    fn a_copy_lying_on_a_part_is_no_other_part() {
        // Triangle 0 1 2 and its reversed copy on vertices 3 4 5: two layers of classes, one part.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ZERO, Vec3::X, Vec3::Y];
        let indices = [0, 1, 2, 3, 5, 4];
        let classes = position_classes(&positions, &indices);
        assert_eq!(classes.count(), 6, "the copy is layered apart");
        assert_eq!(parts(&classes, &indices), [0; 6]);
        let clearance = Clearance::new(&positions, &indices);
        assert_eq!(clearance.squared_to_other_parts(&classes, classes.class_of[3], Vec3::ZERO), None);
    }
}
