//! The uniform grid [`super::Clearance`] searches: each input triangle in every cell its bounding
//! box overlaps (about one triangle a cell), the few too large for the cells apart, and the
//! search shell by shell around a query until the shells cover the nearest distance found.
//! Positions are in the input's units; distances are squared.

use glam::{IVec3, UVec3, Vec3};

/// A search stops once it has tested this many grid entries and found a triangle of another
/// part, and answers the nearest found: where parts overlap densely a cell holds hundreds of
/// triangles, and without a bound the run's time would grow with the number of parts times their
/// density. The answer is then at least the true clearance, so such a part is priced high rather
/// than low, and it is the same on every run (the search's order is fixed). robot.glb's queries
/// test about 400 entries; its levels are the same as with no bound. 20,000 small tetrahedra
/// overlapping in a 5 m box (80,000 triangles) simplify to nothing in about 2 s (0.16 s without
/// the clearance; spread over 100 m, 0.46 s): there most tests are exact ones, since the query
/// lies in many triangles' bounding spheres.
pub(super) const MAX_VISITS: usize = 1024;

/// Cells per input triangle at most, over the grid's whole box.
const CELLS_PER_TRIANGLE: f32 = 8.0;
/// Cells along the grid's longest side at most: bounds its memory whatever the input's shape.
const MAX_CELLS_PER_AXIS: u32 = 128;
/// A triangle whose bounding box overlaps more cells than this is tested by every query instead:
/// with about one triangle a cell, only a mesh's few largest triangles are, and the grid holds at
/// most this many entries per triangle.
pub(super) const MAX_CELLS_PER_TRIANGLE: u32 = 64;

/// Per input triangle, the search that last tested it: a triangle overlaps several cells of a
/// grid (about four where cells are the size of a typical triangle), and a search tests it once.
/// Testing it again could not change the search's answer (its distance is already counted), so
/// skipping it leaves every answer as it was.
#[derive(Default)]
pub(super) struct Tested {
    by: Vec<u32>,
    search: u32,
}

impl Tested {
    /// Starts a search over `triangles` triangles: none tested yet.
    pub(super) fn start(&mut self, triangles: usize) {
        if self.by.len() < triangles {
            self.by.resize(triangles, 0);
        }
        self.search = self.search.wrapping_add(1);
        if self.search == 0 {
            // Wrapped: stamps of 2³² searches ago would read as this one's.
            self.by.fill(0);
            self.search = 1;
        }
    }

    /// Whether triangle `t` is not tested yet in this search; it counts as tested from now on.
    pub(super) fn first_time(&mut self, t: u32) -> bool {
        let by = &mut self.by[t as usize];
        let first = *by != self.search;
        *by = self.search;
        first
    }
}

pub(super) struct Grid {
    origin: Vec3,
    /// Cell edge length (> 0).
    cell: f32,
    dims: UVec3,
    /// Per cell, where its triangles start in `entries` (one more than there are cells).
    start: Vec<u32>,
    /// Triangle indices, cell after cell.
    entries: Vec<u32>,
    /// The triangles too large for the cells.
    pub(super) large: Vec<u32>,
    /// Per triangle, its part.
    pub(super) part: Vec<u32>,
    /// Per triangle, a bounding sphere (centre, radius): a cheap lower bound of its distance,
    /// which skips the exact test for most triangles once a near one is found.
    pub(super) sphere: Vec<(Vec3, f32)>,
}

impl Grid {
    /// `part_of` gives an input vertex's part (every vertex a triangle uses has one).
    pub(super) fn new(
        positions: &[Vec3],
        indices: &[u32],
        part_of: impl Fn(u32) -> u32,
        keep: impl Fn(usize) -> bool,
    ) -> Grid {
        let count = indices.len() / 3;
        let kept: Vec<usize> = (0..count).filter(|&t| keep(t)).collect();
        let corners = |t: usize| [0, 1, 2].map(|k| positions[indices[3 * t + k] as usize]);
        // Each kept triangle's bounding box, read once: the grid's box, its cell size and the
        // cells each triangle overlaps all come from them.
        let boxes: Vec<(Vec3, Vec3)> = kept
            .iter()
            .map(|&t| {
                let [a, b, c] = corners(t);
                (a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let (min, max) = boxes
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &(a, b)| (lo.min(a), hi.max(b)));
        let size = (max - min).max(Vec3::ZERO);
        // Cells the size of a typical triangle (the median of their boxes' longest sides), so a
        // triangle overlaps a few cells and a cell holds a few triangles where the surface is;
        // no more than CELLS_PER_TRIANGLE cells per triangle over the box (a surface fills
        // little of its box), nor MAX_CELLS_PER_AXIS a side.
        let mut sides: Vec<f32> = boxes.iter().map(|&(lo, hi)| (hi - lo).max_element()).collect();
        let median = if sides.is_empty() {
            0.0
        } else {
            *sides.select_nth_unstable_by(kept.len() / 2, f32::total_cmp).1
        };
        let volume = size.x.max(1e-30) * size.y.max(1e-30) * size.z.max(1e-30);
        let cell = median
            .max((volume / (CELLS_PER_TRIANGLE * kept.len().max(1) as f32)).cbrt())
            .max(size.max_element() / MAX_CELLS_PER_AXIS as f32);
        let cell = if cell.is_finite() && cell > 0.0 { cell } else { 1.0 };
        let dims = ((size / cell).as_uvec3() + 1).min(UVec3::splat(MAX_CELLS_PER_AXIS));
        let cell_of = |p: Vec3| ((p - min) / cell).max(Vec3::ZERO).as_uvec3().min(dims - 1);
        let ranges: Vec<(UVec3, UVec3)> = boxes.iter().map(|&(lo, hi)| (cell_of(lo), cell_of(hi))).collect();
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
            for (&t, &(lo, hi)) in kept.iter().zip(&ranges) {
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
    /// starts at `best` and is what `test` returns, infinite until one is found) or than
    /// `within` (squared), or [`MAX_VISITS`] entries have been looked at and one was found; returns
    /// that distance. A triangle in several cells is tested in the first (`tested`), and counts
    /// as an entry in each.
    pub(super) fn search(
        &self,
        tested: &mut Tested,
        q: Vec3,
        mut best: f32,
        within: f32,
        test: &mut dyn FnMut(u32) -> f32,
    ) -> f32 {
        tested.start(self.part.len());
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
                if covered * covered >= best.min(within) {
                    return best;
                }
            }
            let (lo, hi) = ((at - shell).max(IVec3::ZERO), (at + shell).min(dims - 1));
            // Exclusive ranges and a plain loop along x: `..=` and `step_by` cost more per cell.
            for z in lo.z..hi.z + 1 {
                for y in lo.y..hi.y + 1 {
                    // Off the shell's faces in z and y, only its two x ends lie on it.
                    let on_face = (z - at.z).abs() == shell || (y - at.y).abs() == shell;
                    let (mut x, step) = if on_face { (lo.x, 1) } else { (at.x - shell, (2 * shell).max(1)) };
                    while x <= hi.x {
                        if x >= 0 {
                            let k = (x + dims.x * (y + dims.y * z)) as usize;
                            for &t in &self.entries[self.start[k] as usize..self.start[k + 1] as usize] {
                                if tested.first_time(t) {
                                    best = test(t);
                                }
                                visited += 1;
                                if visited >= MAX_VISITS && best.is_finite() {
                                    return best;
                                }
                            }
                        }
                        x += step;
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
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_search_tests_each_triangle_once_however_many_cells_it_lies_in() {
        // A row of unit triangles, and one as long as four of them, which lies in several cells.
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for k in 0..8 {
            let x = k as f32;
            let base = positions.len() as u32;
            positions.extend([Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 0.0, 0.0), Vec3::new(x, 1.0, 0.0)]);
            indices.extend([base, base + 1, base + 2]);
        }
        let base = positions.len() as u32;
        positions.extend([Vec3::new(2.0, 2.0, 0.0), Vec3::new(6.0, 2.0, 0.0), Vec3::new(2.0, 3.0, 0.0)]);
        indices.extend([base, base + 1, base + 2]);
        let grid = Grid::new(&positions, &indices, |_| 0, |_| true);
        let long = base / 3;
        let cells_of_long = grid.entries.iter().filter(|&&t| t == long).count();
        assert!(cells_of_long > 1, "the long triangle lies in {cells_of_long} cells");

        let mut tested = Tested::default();
        for _ in 0..2 {
            // Every triangle is within reach of the query: the search goes over every cell.
            let mut count = vec![0; indices.len() / 3];
            grid.search(&mut tested, Vec3::new(4.0, 1.0, 0.0), f32::INFINITY, 100.0, &mut |t| {
                count[t as usize] += 1;
                f32::INFINITY
            });
            assert_eq!(count, vec![1; indices.len() / 3], "each once, in a second search too");
        }
    }
}
