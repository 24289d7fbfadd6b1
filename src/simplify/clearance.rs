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

use crate::metrics::closest_point_on_triangle;
use glam::{IVec3, UVec3, Vec3};
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;

/// Cells along the grid's longest side at most: bounds its memory whatever the input's shape.
const MAX_CELLS_PER_AXIS: u32 = 128;
/// A triangle whose bounding box overlaps more cells than this is tested by every query instead:
/// with about one triangle a cell, only a mesh's few largest triangles are, and the grid holds at
/// most this many entries per triangle.
const MAX_CELLS_PER_TRIANGLE: u32 = 64;

/// The input triangles and their parts, with the grid built on demand.
pub(super) struct Clearance<'a> {
    positions: &'a [Vec3],
    indices: &'a [u32],
    /// Per input vertex, the lowest class of its part.
    vertex_part: Vec<u32>,
    grid: OnceCell<Grid>,
    /// The last answer per class: a sheet's three edges are priced with the same corners.
    answers: RefCell<HashMap<u32, (Vec3, Option<f32>)>>,
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
    /// Per triangle, its part (that of its first corner).
    part: Vec<u32>,
    /// Per triangle, a bounding sphere (centre, radius): a cheap lower bound of its distance,
    /// which skips the exact test for most triangles once a near one is found.
    sphere: Vec<(Vec3, f32)>,
}

impl<'a> Clearance<'a> {
    /// `class_of` maps each input vertex to its position class (`class_count` of them; NONE for
    /// a vertex no triangle uses).
    pub(super) fn new(
        positions: &'a [Vec3],
        indices: &'a [u32],
        class_of: &[u32],
        class_count: usize,
    ) -> Self {
        let class_part = parts(class_of, indices, class_count);
        let vertex_part =
            class_of.iter().map(|&c| class_part.get(c as usize).copied().unwrap_or(c)).collect();
        Clearance { positions, indices, vertex_part, grid: OnceCell::new(), answers: RefCell::default() }
    }

    /// The part of input vertex `vertex`.
    pub(super) fn part_of_vertex(&self, vertex: u32) -> u32 {
        self.vertex_part[vertex as usize]
    }

    /// The squared distance from class `class`, at `q`, to the nearest input triangle of a part
    /// other than `part` (the class's), or `None` when the input has no other part.
    pub(super) fn squared_to_other_parts(&self, class: u32, q: Vec3, part: u32) -> Option<f32> {
        if let Some(&(at, answer)) = self.answers.borrow().get(&class) {
            if at == q {
                return answer;
            }
        }
        let answer = self.search(q, part);
        self.answers.borrow_mut().insert(class, (q, answer));
        answer
    }

    fn search(&self, q: Vec3, part: u32) -> Option<f32> {
        let grid = self.grid.get_or_init(|| Grid::new(self.positions, self.indices, &self.vertex_part));
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
fn parts(class_of: &[u32], indices: &[u32], class_count: usize) -> Vec<u32> {
    fn root(parent: &mut [u32], mut c: u32) -> u32 {
        while parent[c as usize] != c {
            let up = parent[parent[c as usize] as usize];
            parent[c as usize] = up;
            c = up;
        }
        c
    }
    let mut parent: Vec<u32> = (0..class_count as u32).collect();
    for t in indices.chunks_exact(3) {
        for &k in &t[1..] {
            let (a, b) =
                (root(&mut parent, class_of[t[0] as usize]), root(&mut parent, class_of[k as usize]));
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    (0..class_count as u32).map(|c| root(&mut parent, c)).collect()
}

impl Grid {
    fn new(positions: &[Vec3], indices: &[u32], vertex_part: &[u32]) -> Grid {
        let count = indices.len() / 3;
        let corners = |t: usize| [0, 1, 2].map(|k| positions[indices[3 * t + k] as usize]);
        let (min, max) = indices.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(positions[v as usize]), hi.max(positions[v as usize]))
        });
        let size = (max - min).max(Vec3::ZERO);
        // About one triangle a cell over the box's volume, at most MAX_CELLS_PER_AXIS a side.
        let volume = size.x.max(1e-30) * size.y.max(1e-30) * size.z.max(1e-30);
        let cell = (volume / count.max(1) as f32).cbrt().max(size.max_element() / MAX_CELLS_PER_AXIS as f32);
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
                let part = (0..count).map(|t| vertex_part[indices[3 * t] as usize]).collect();
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
    /// starts at `best` and is what `test` returns); returns that distance.
    fn search(&self, q: Vec3, mut best: f32, test: &mut dyn FnMut(u32) -> f32) -> f32 {
        let dims = self.dims.as_ivec3();
        // A query outside the grid starts from the nearest cell. After shells 0..s, a triangle
        // not yet seen lies outside the cube of cells within s − 1 of the start, which holds
        // every point within (s − 1) cells of `q` (clamping moved the start towards `q`).
        let at = ((q - self.origin) / self.cell).floor().as_ivec3().clamp(IVec3::ZERO, dims - 1);
        for shell in 0..=dims.max_element() {
            let covered = (shell - 1).max(0) as f32 * self.cell;
            if covered * covered >= best {
                return best;
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
    use super::*;
    use crate::metrics::SplitMix64;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// The exact answer, by testing every triangle.
    fn brute_force(
        positions: &[Vec3],
        indices: &[u32],
        vertex_part: &[u32],
        q: Vec3,
        part: u32,
    ) -> Option<f32> {
        let best = indices
            .chunks_exact(3)
            .filter(|t| vertex_part[t[0] as usize] != part)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
                closest_point_on_triangle(q, a, b, c).distance_squared(q)
            })
            .fold(f32::INFINITY, f32::min);
        best.is_finite().then_some(best)
    }

    #[test]
    fn the_grid_finds_the_nearest_triangle_of_another_part() {
        // Seeded random parts: small triangles in clusters, a few long slivers (which span many
        // cells or go to the large list), queries inside, between and far outside the parts.
        let mut rng = SplitMix64(7);
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        let mut class_of = Vec::new();
        for part in 0..12u32 {
            let centre = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 10.0;
            for t in 0..(10 + part * 7) {
                let size = if t % 17 == 0 { 8.0 } else { 0.5 };
                let base = positions.len() as u32;
                for _ in 0..3 {
                    let jitter = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
                    positions.push(centre + jitter * size);
                    // One class per part: enough for the parts, which is all the grid reads.
                    class_of.push(part);
                }
                indices.extend([base, base + 1, base + 2]);
            }
        }
        let clearance = Clearance::new(&positions, &indices, &class_of, 12);
        for k in 0..300 {
            let q = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.25)
                * if k % 10 == 0 { 40.0 } else { 12.0 };
            let part = k % 12;
            let expected = brute_force(&positions, &indices, &clearance.vertex_part, q, part);
            assert_eq!(clearance.squared_to_other_parts(k, q, part), expected, "query {k} at {q}");
        }
        // A mesh of one part has no other part.
        let one = Clearance::new(&positions[..3], &indices[..3], &[0, 0, 0], 1);
        assert_eq!(one.squared_to_other_parts(0, Vec3::ZERO, 0), None);
    }

    #[test]
    fn parts_are_the_components_over_classes() {
        // Triangles 0 and 1 share class 1; triangle 2 (classes 5–7) stands alone; vertex 9 is
        // used by no triangle (no class, no part).
        let none = super::super::topology::NONE;
        let class_of = [0, 1, 2, 1, 3, 4, 5, 6, 7, none];
        let indices = [0, 1, 2, 3, 4, 5, 6, 7, 8];
        assert_eq!(parts(&class_of, &indices, 8), [0, 0, 0, 0, 0, 5, 5, 5]);
        let positions = vec![Vec3::ZERO; 10];
        let clearance = Clearance::new(&positions, &indices, &class_of, 8);
        assert_eq!(clearance.part_of_vertex(6), 5);
        assert_eq!(clearance.part_of_vertex(9), none);
    }
}
