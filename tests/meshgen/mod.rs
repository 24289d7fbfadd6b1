//! Seeded test meshes and the progressive-mesh invariant checker shared by the simplifier tests.
#![allow(dead_code)]

use clod_viewer::progressive::ProgressiveMesh;
use clod_viewer::simplify::{SimplifyInput, SimplifyOptions};
use glam::{DVec3, Vec3};
use std::collections::HashMap;

/// The seeded generator of the test data (SplitMix64, shared with the metrics).
pub use clod_viewer::metrics::SplitMix64 as Rng;

/// A test mesh with its simplifier inputs.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub attributes: Vec<f32>,
    pub weights: Vec<f32>,
    pub indices: Vec<u32>,
    pub materials: Vec<u32>,
}

impl Mesh {
    pub fn input(&self) -> SimplifyInput<'_> {
        SimplifyInput {
            positions: &self.positions,
            attributes: &self.attributes,
            attribute_weights: &self.weights,
            indices: &self.indices,
            triangle_materials: &self.materials,
            vertex_quadrics: None,
        }
    }

    pub fn simplify(&self, options: &SimplifyOptions) -> ProgressiveMesh {
        clod_viewer::simplify::simplify(&self.input(), options).expect("valid input")
    }
}

/// An `nx × ny`-quad grid in the xy plane with unit spacing, heights from `z`, two triangles
/// per quad; vertex `(i, j)` is `j * (nx + 1) + i`.
pub fn grid(nx: u32, ny: u32, z: impl Fn(u32, u32) -> f32) -> Mesh {
    let mut mesh = Mesh::default();
    for j in 0..=ny {
        for i in 0..=nx {
            mesh.positions.push(Vec3::new(i as f32, j as f32, z(i, j)));
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (b, c, d) = (a + 1, a + nx + 1, a + nx + 2);
            mesh.indices.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    mesh
}

/// A closed torus of `nu × nv` quads with radial noise, analytic normals and uv (channels: normal
/// xyz, uv): the rows at `u = 1` and `v = 1` duplicate the first ones with other uv, so there are
/// two seam loops crossing at one vertex.
pub fn torus(nu: u32, nv: u32, noise: f32, seed: u64) -> Mesh {
    let mut rng = Rng(seed);
    let bumps: Vec<f32> = (0..nu * nv).map(|_| noise * rng.signed()).collect();
    let (big, small) = (1.0f32, 0.35f32);
    let mut mesh = Mesh { weights: vec![0.05, 0.05, 0.05, 1.0, 1.0], ..Mesh::default() };
    for j in 0..=nv {
        for i in 0..=nu {
            let (iu, jv) = (i % nu, j % nv);
            let theta = std::f32::consts::TAU * iu as f32 / nu as f32;
            let phi = std::f32::consts::TAU * jv as f32 / nv as f32;
            let r = small + bumps[(jv * nu + iu) as usize];
            let ring = big + r * phi.cos();
            mesh.positions.push(Vec3::new(ring * theta.cos(), ring * theta.sin(), r * phi.sin()));
            let n = Vec3::new(phi.cos() * theta.cos(), phi.cos() * theta.sin(), phi.sin());
            mesh.attributes.extend_from_slice(&[n.x, n.y, n.z, i as f32 / nu as f32, j as f32 / nv as f32]);
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let a = j * (nu + 1) + i;
            let (b, c, d) = (a + 1, a + nu + 1, a + nu + 2);
            mesh.indices.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    mesh
}

fn key(p: Vec3) -> [u32; 3] {
    let bits = |x: f32| if x == 0.0 { 0 } else { x.to_bits() };
    [bits(p.x), bits(p.y), bits(p.z)]
}

fn normal(a: Vec3, b: Vec3, c: Vec3) -> DVec3 {
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    (b - a).cross(c - a)
}

/// `t` rotated to start at its smallest element (the winding kept).
fn rotated_to_min<T: Ord + Copy>(mut t: [T; 3]) -> [T; 3] {
    let min = (0..3).min_by_key(|&r| t[r]).unwrap();
    t.rotate_left(min);
    t
}

fn sorted<T: Ord>(mut v: Vec<T>) -> Vec<T> {
    v.sort();
    v
}

/// Levels to check: a spread over all collapses including both ends.
pub fn spread_levels(pm: &ProgressiveMesh, count: usize) -> Vec<usize> {
    let n = pm.collapse_count();
    let mut levels: Vec<usize> = (0..=count).map(|i| i * n / count.max(1)).collect();
    levels.dedup();
    levels
}

/// Checks every progressive-mesh invariant at the given levels (ascending). `closed`: the input
/// is a closed manifold, so every level must be watertight at the position level.
pub fn check_invariants(mesh: &Mesh, pm: &ProgressiveMesh, levels: &[usize], closed: bool) {
    let t0 = mesh.indices.len() / 3;
    if let Err(broken) = pm.validate() {
        panic!("the progressive mesh breaks an invariant: {broken}");
    }
    // Lossless: the base triangles are the input triangles, reordered.
    assert_eq!(pm.triangle_count_after(0), t0);
    assert_eq!(pm.triangle_source.len(), t0);
    for (i, &s) in pm.triangle_source.iter().enumerate() {
        let s = s as usize;
        assert_eq!(&pm.indices[3 * i..3 * i + 3], &mesh.indices[3 * s..3 * s + 3]);
    }
    let input_tris: Vec<[u32; 3]> = mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let level0: Vec<[u32; 3]> = pm.indices_at(0).chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    assert_eq!(sorted(level0), sorted(input_tris), "refining fully is lossless");
    // Monotone errors and counts.
    for k in 1..=pm.collapse_count() {
        assert!(pm.error_after(k) >= pm.error_after(k - 1), "error not monotone at {k}");
        assert!(pm.distance_after(k) >= pm.distance_after(k - 1));
        assert!(pm.triangle_count_after(k) <= pm.triangle_count_after(k - 1));
        let record = &pm.collapses[k - 1];
        assert!(record.cost.is_finite() && record.cost >= 0.0);
        for x in record.first_new_vertex..record.first_new_vertex + record.new_vertex_count {
            assert_eq!(pm.born_at[x as usize] as usize, k);
        }
    }
    // An input that repeats triangles (a surface drawn twice, a doubled sheet) keeps copies on
    // the same corners as its layers simplify side by side (`clod_viewer::twins`).
    let mut input_keys: Vec<_> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let mut k = [0, 1, 2].map(|j| key(mesh.positions[t[j] as usize]));
            k.sort();
            k
        })
        .collect();
    input_keys.sort();
    let input_has_twins = input_keys.windows(2).any(|w| w[0] == w[1]);
    let mut previous: Option<(usize, Vec<u32>)> = None;
    for &k in levels {
        let tris = pm.indices_at(k);
        assert_eq!(tris.len(), 3 * pm.triangle_count_after(k));
        let mut seen = HashMap::new();
        for (i, t) in tris.chunks_exact(3).enumerate() {
            for &v in t {
                assert!((v as usize) < pm.vertex_total(), "index out of range");
                // Alive at k: born by k, not yet merged.
                assert!(pm.born_at[v as usize] as usize <= k);
                let p = pm.parent[v as usize];
                assert!(p == u32::MAX || pm.born_at[p as usize] as usize > k, "vertex {v} dead at {k}");
            }
            let [a, b, c] = [t[0], t[1], t[2]];
            assert!(a != b && b != c && a != c, "degenerate triangle at level {k}");
            let [pa, pb, pc] = [a, b, c].map(|v| pm.positions[v as usize]);
            let winding = [key(pa), key(pb), key(pc)];
            let mut pkey = winding;
            assert!(pkey[0] != pkey[1] && pkey[1] != pkey[2] && pkey[0] != pkey[2], "collapsed positions");
            pkey.sort();
            // Two triangles on the same corners must face opposite ways: a two-sided sheet, what
            // a closed tetrahedron becomes on its way out.
            let windings: &mut Vec<[[u32; 3]; 3]> = seen.entry(pkey).or_default();
            windings.push(rotated_to_min(winding));
            let reversed = rotated_to_min([winding[0], winding[2], winding[1]]);
            assert!(
                input_has_twins || windings.len() == 1 || (windings.len() == 2 && windings[0] == reversed),
                "duplicate triangle at level {k}"
            );
            // No fold: within 90° of the input triangle it descends from.
            let s = pm.triangle_source[i] as usize;
            let [ia, ib, ic] = [0, 1, 2].map(|j| mesh.positions[mesh.indices[3 * s + j] as usize]);
            let input_normal = normal(ia, ib, ic);
            if input_normal != DVec3::ZERO {
                assert!(normal(pa, pb, pc).dot(input_normal) > 0.0, "triangle {i} folded at level {k}");
            }
        }
        if closed {
            let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
            for t in tris.chunks_exact(3) {
                for e in 0..3 {
                    let (a, b) =
                        (key(pm.positions[t[e] as usize]), key(pm.positions[t[(e + 1) % 3] as usize]));
                    // +1 one way, −1 the other: a closed, consistently oriented surface sums to 0.
                    if a < b {
                        *edges.entry((a, b)).or_default() += 1;
                    } else {
                        *edges.entry((b, a)).or_default() -= 1;
                    }
                }
            }
            assert!(edges.values().all(|&c| c == 0), "crack or flap at level {k}");
        }
        // Coarser levels are the finer ones with corners replaced by their ancestors.
        if let Some((k_fine, fine)) = &previous {
            let mapped: Vec<[u32; 3]> = fine
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]].map(|v| pm.ancestor_at(v, k)))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            let coarse: Vec<[u32; 3]> = tris.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
            assert_eq!(sorted(mapped), sorted(coarse), "level {k} is not level {k_fine} mapped to ancestors");
        }
        previous = Some((k, tris));
    }
}

/// Moves a cursor through `levels` (in the given order) and compares it with rebuilding.
pub fn check_cursor(pm: &ProgressiveMesh, levels: &[usize]) {
    let mut cursor = pm.cursor();
    for &k in levels {
        cursor.set_collapses(k);
        assert_eq!(cursor.level(), k.min(pm.collapse_count()));
        let vertices = cursor.vertices();
        assert_eq!(vertices.len(), pm.vertex_count_after(k));
        let expanded: Vec<u32> = cursor
            .indices()
            .iter()
            .map(|&slot| {
                assert!((slot as usize) < vertices.len(), "slot out of range at level {k}");
                vertices[slot as usize]
            })
            .collect();
        assert_eq!(expanded, pm.indices_at(k), "cursor differs from rebuild at level {k}");
    }
}
