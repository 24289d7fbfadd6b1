//! Polygonization of the implicit body with naive surface nets (Gibson 1998, "Constrained
//! elastic surface nets"; the naive variant as popularised by Mikola Lysenko).
//!
//! The field is sampled on a regular grid whose outer layer lies outside the body, so the
//! result is a closed surface. Every grid cell with a sign change gets one vertex (the mean of
//! its edge crossings), and every grid edge with a sign change gets the quad of the four cells
//! around it, wound so its normal points from inside (negative) to outside. Quads are split along
//! their shorter diagonal. Vertices are then pulled onto the surface with Newton steps along the
//! field gradient, which removes the grid's terracing.
//!
//! Output order is fixed by the grid scan (x fastest, then y, then z), so it is deterministic.

use glam::Vec3;

use crate::field::{body_distance, body_normal, Part};

/// A regular sampling grid: `dims` samples per axis, `cell` metres apart, starting at `origin`.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    pub origin: Vec3,
    pub cell: f32,
    pub dims: [usize; 3],
}

impl Grid {
    /// The smallest grid with spacing `cell` covering `lo..hi` plus two empty layers each side
    /// (one so the boundary samples are outside, one for the normal's finite differences).
    pub fn covering(lo: Vec3, hi: Vec3, cell: f32) -> Self {
        let origin = lo - Vec3::splat(2.0 * cell);
        let n = ((hi - lo) / cell).ceil() + Vec3::splat(5.0);
        Self { origin, cell, dims: [n.x as usize, n.y as usize, n.z as usize] }
    }

    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    fn point(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.origin + self.cell * Vec3::new(i as f32, j as f32, k as f32)
    }
}

/// An indexed triangle mesh straight out of the mesher.
#[derive(Clone, Debug, Default)]
pub struct RawMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
}

/// Samples the body distance at every grid point.
pub fn sample(parts: &[Part], grid: &Grid) -> Vec<f32> {
    let [nx, ny, nz] = grid.dims;
    let mut values = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                values.push(body_distance(parts, grid.point(i, j, k)));
            }
        }
    }
    values
}

/// Corner offsets of a cell, bit 0 = x, bit 1 = y, bit 2 = z.
const CORNERS: [[usize; 3]; 8] =
    [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]];

/// The twelve cell edges as corner pairs (corners that differ in exactly one bit).
const EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [2, 3],
    [4, 5],
    [6, 7], // along x
    [0, 2],
    [1, 3],
    [4, 6],
    [5, 7], // along y
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7], // along z
];

/// Newton steps that pull each vertex onto the surface; two are enough for the field's smooth
/// parts, and more would only chase the floor cut's kink.
const PROJECTION_STEPS: usize = 2;

/// Builds the surface net of `values` (sampled on `grid` from `parts`); see the module docs.
pub fn surface_nets(parts: &[Part], grid: &Grid, values: &[f32]) -> RawMesh {
    let [nx, ny, nz] = grid.dims;
    let inside = |i: usize, j: usize, k: usize| values[grid.index(i, j, k)] < 0.0;

    // One vertex per cell with a sign change, at the mean of its edge crossings.
    let cell_index = |i: usize, j: usize, k: usize| i + (nx - 1) * (j + (ny - 1) * k);
    let mut cell_vertex = vec![u32::MAX; (nx - 1) * (ny - 1) * (nz - 1)];
    let mut positions = Vec::new();
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let f = CORNERS.map(|[a, b, c]| values[grid.index(i + a, j + b, k + c)]);
                if f.iter().all(|&v| v < 0.0) || f.iter().all(|&v| v >= 0.0) {
                    continue;
                }
                let mut sum = Vec3::ZERO;
                let mut count = 0.0;
                for [e0, e1] in EDGES {
                    if (f[e0] < 0.0) != (f[e1] < 0.0) {
                        let t = f[e0] / (f[e0] - f[e1]);
                        let p0 = Vec3::from(CORNERS[e0].map(|c| c as f32));
                        let p1 = Vec3::from(CORNERS[e1].map(|c| c as f32));
                        sum += p0 + t * (p1 - p0);
                        count += 1.0;
                    }
                }
                cell_vertex[cell_index(i, j, k)] = positions.len() as u32;
                positions.push(grid.point(i, j, k) + grid.cell * (sum / count));
            }
        }
    }

    // One quad per grid edge with a sign change, from the four cells sharing that edge.
    let mut indices = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let here = inside(i, j, k);
                for axis in 0..3 {
                    let mut n = [i, j, k];
                    n[axis] += 1;
                    if n[axis] >= grid.dims[axis] || inside(n[0], n[1], n[2]) == here {
                        continue;
                    }
                    // The other two axes in cyclic order, so (axis, u, v) is right-handed.
                    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                    let base = [i, j, k];
                    if base[u] == 0
                        || base[v] == 0
                        || base[u] + 1 >= grid.dims[u]
                        || base[v] + 1 >= grid.dims[v]
                    {
                        continue; // on the grid boundary, which the body never reaches
                    }
                    let cell = |du: usize, dv: usize| {
                        let mut c = base;
                        c[u] = c[u] + du - 1;
                        c[v] = c[v] + dv - 1;
                        cell_vertex[cell_index(c[0], c[1], c[2])]
                    };
                    // Counter-clockwise around +axis: (0,0) (1,0) (1,1) (0,1) in (u, v).
                    let mut quad = [cell(0, 0), cell(1, 0), cell(1, 1), cell(0, 1)];
                    if !here {
                        quad.reverse(); // inside lies at +axis: the surface faces -axis
                    }
                    push_quad(&positions, quad, &mut indices);
                }
            }
        }
    }

    // Newton projection onto the zero set, each step capped at half a cell so a vertex cannot
    // jump across a thin feature.
    let eps = 0.25 * grid.cell;
    for p in &mut positions {
        for _ in 0..PROJECTION_STEPS {
            let d = body_distance(parts, *p);
            let n = body_normal(parts, *p, eps);
            *p -= n * d.clamp(-0.5 * grid.cell, 0.5 * grid.cell);
        }
    }
    let normals = positions.iter().map(|&p| body_normal(parts, p, eps)).collect();
    RawMesh { positions, normals, indices }
}

/// Splits a quad along its shorter diagonal (better-shaped triangles; ties take `a`–`c`).
fn push_quad(positions: &[Vec3], [a, b, c, d]: [u32; 4], indices: &mut Vec<u32>) {
    let p = |v: u32| positions[v as usize];
    if p(a).distance_squared(p(c)) <= p(b).distance_squared(p(d)) {
        indices.extend_from_slice(&[a, b, c, a, c, d]);
    } else {
        indices.extend_from_slice(&[a, b, d, b, c, d]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::Shape;
    use crate::validate::bad_edges;

    #[test]
    fn a_sphere_becomes_a_closed_manifold_of_the_right_size() {
        let parts = [Part {
            shape: Shape::Capsule { a: Vec3::Y, b: Vec3::Y, ra: 0.5, rb: 0.5 },
            bone: 0,
            blend: 0.1,
        }];
        let grid = Grid::covering(Vec3::new(-0.5, 0.5, -0.5), Vec3::new(0.5, 1.5, 0.5), 0.05);
        let values = sample(&parts, &grid);
        let mesh = surface_nets(&parts, &grid, &values);
        assert!(mesh.indices.len() > 1000);
        assert_eq!(bad_edges(&mesh.indices), vec![]);
        for p in &mesh.positions {
            assert!((p.distance(Vec3::Y) - 0.5).abs() < 1e-3, "{p}");
        }
    }
}
