//! Multi-pose quadrics pulled back into the simplification pose `P0`, in each vertex's local frame
//! (the poses and their notation are in `poses.rs`: `M0(v)`, `Mf(v)`, `A_f(v) = Mf(v) · M0(v)⁻¹`).
//!
//! Every plane added at `v` in frame `f` goes through `v`'s posed position `x_f(v) = A_f(v) p0(v)`,
//! so around it the plane has no offset and the frame's planes at `v` sum to a 3×3
//! `N_f(v) = Σ area · n nᵀ`. Skin matrices are affine, `x − x_f(v) = L_f(v) (p − p0(v))` with
//! `L_f(v)` the linear part of `A_f(v)`, so the pulled-back quadric is
//! `(p − p0)ᵀ L_fᵀ N_f L_f (p − p0)`. [`FrameQuadrics`] sums `M(v) = Σ_f L_fᵀ N_f L_f` over frames
//! and turns it into a [`Quadric`] once: `A = M`, `b = −M p0`, `c = p0ᵀ M p0`. That is the 4×4
//! pull-back `A_fᵀ K A_f` of the frame's plane sum `K` with less work per frame: no plane offsets,
//! no `b` and `c`, and posed positions only for the corners that need them. Posed positions are
//! f32, as the skinning; planes and their sums are f64 (see [`FrameQuadrics`] for why).

use glam::{DMat3, DVec3, Mat4, Vec3};

use crate::simplify::Quadric;

/// Adds the area-weighted plane quadrics of one frame to every vertex, pulled back into `P0`
/// space (see the module docs), each scaled by `frame_weight` (1 / number of frames).
///
/// `frame_matrices[v]` is `Mf(v)`; `p0_matrices[v]` is `M0(v)`, or `None` when `P0` is the bind
/// pose (every `M0` is the identity). Triangles with no area in the frame add nothing, and so do
/// the triangles marked in `skip` (shorter or empty: none), which [`super::poses::add_rigid_quadrics`] covers.
/// For several frames, [`FrameQuadrics`] keeps its buffers and converts to quadrics once.
pub fn add_frame_quadrics(
    quadrics: &mut [Quadric],
    bind_positions: &[Vec3],
    indices: &[u32],
    p0_matrices: Option<&[Mat4]>,
    frame_matrices: &[Mat4],
    frame_weight: f64,
    skip: &[bool],
) {
    let mut frames = FrameQuadrics::new(bind_positions, indices, p0_matrices, skip);
    frames.add(frame_matrices, frame_weight);
    frames.finish(quadrics);
}

/// The upper triangle `[xx, xy, xz, yy, yz, zz]` of a symmetric 3×3 matrix (as [`Quadric::a`]).
type Sym3 = [f64; 6];

/// The multi-pose quadrics of one mesh, summed frame after frame in each vertex's local frame
/// (see the module docs) and turned into [`Quadric`]s once, by [`FrameQuadrics::finish`].
///
/// Posed positions are f32, as the skinning; planes and their sums are f64. In f32 (13 % faster
/// on the built-in character) a flat vertex's `M` gets rounding of about 1e-7 of its trace in
/// the directions it does not constrain, above the 1e-10 at which [`Quadric::minimize`] calls
/// them flat, and that changed CesiumMan's multi-pose chain: its animated error at 234
/// triangles rose by 9 %. In f64 every level's error is the 4×4 pull-back's.
pub struct FrameQuadrics<'a> {
    bind_positions: &'a [Vec3],
    /// The triangles not skipped, by their corners' places in `vertices`.
    triangles: Vec<[u32; 3]>,
    /// Their corners, each once, in increasing order: the vertices whose matrices are read. The
    /// buffers below are indexed by place in this list, which keeps them dense.
    vertices: Vec<u32>,
    /// `M0(v)`'s linear part inverted, per vertex; `None` for the bind pose.
    p0_linear_inverse: Option<Vec<DMat3>>,
    /// `P0` positions, as the simplifier sees them; `None` for the bind pose.
    p0_positions: Option<Vec<Vec3>>,
    /// The frame's posed positions.
    posed: Vec<DVec3>,
    /// The frame's `N = Σ area · n nᵀ` and `Σ area` per vertex; all zero between frames.
    in_frame: Vec<(Sym3, f64)>,
    /// `Σ_f weight_f · L_fᵀ N_f L_f` and `Σ_f weight_f · area` per vertex.
    summed: Vec<(Sym3, f64)>,
}

impl<'a> FrameQuadrics<'a> {
    /// The mesh, `P0` and the triangles to skip, as [`add_frame_quadrics`] takes them.
    pub fn new(
        bind_positions: &'a [Vec3],
        indices: &'a [u32],
        p0_matrices: Option<&[Mat4]>,
        skip: &[bool],
    ) -> FrameQuadrics<'a> {
        let kept = || indices.chunks_exact(3).enumerate().filter(|(t, _)| skip.get(*t) != Some(&true));
        let mut used = vec![false; bind_positions.len()];
        for (_, tri) in kept() {
            for &i in tri {
                used[i as usize] = true;
            }
        }
        let vertices: Vec<u32> = (0..used.len() as u32).filter(|&v| used[v as usize]).collect();
        // Each used vertex's place in `vertices`.
        let mut place = vec![0; used.len()];
        for (i, &v) in vertices.iter().enumerate() {
            place[v as usize] = i as u32;
        }
        let triangles = kept().map(|(_, tri)| [0, 1, 2].map(|k| place[tri[k] as usize])).collect();
        let n = vertices.len();
        let p0_linear_inverse =
            p0_matrices.map(|m| m.iter().map(|m| DMat3::from_mat4(m.as_dmat4()).inverse()).collect());
        let p0_positions =
            p0_matrices.map(|m| bind_positions.iter().zip(m).map(|(&b, m)| m.transform_point3(b)).collect());
        FrameQuadrics {
            bind_positions,
            triangles,
            vertices,
            p0_linear_inverse,
            p0_positions,
            posed: vec![DVec3::ZERO; n],
            in_frame: vec![([0.0; 6], 0.0); n],
            summed: vec![([0.0; 6], 0.0); n],
        }
    }

    /// The vertices whose `frame_matrices` entries [`FrameQuadrics::add`] reads (the others may
    /// hold anything): the corners of the triangles not skipped, in increasing order.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// Adds one frame, `frame_matrices[v]` being `Mf(v)`, with weight `frame_weight`.
    pub fn add(&mut self, frame_matrices: &[Mat4], frame_weight: f64) {
        self.add_morphed(frame_matrices, self.bind_positions, frame_weight);
    }

    /// Adds one frame whose bind positions are `morphed` (the bind positions with the frame's
    /// morph weights applied, as many), posed by `frame_matrices`, with weight `frame_weight`.
    pub fn add_morphed(&mut self, frame_matrices: &[Mat4], morphed: &[Vec3], frame_weight: f64) {
        for (posed, &v) in self.posed.iter_mut().zip(&self.vertices) {
            let v = v as usize;
            *posed = frame_matrices[v].transform_point3(morphed[v]).as_dvec3();
        }
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|i| self.posed[i as usize]);
            let Some((plane, area)) = local_plane(a, b, c) else { continue };
            for &i in tri {
                let (n, sum) = &mut self.in_frame[i as usize];
                for (n, p) in n.iter_mut().zip(plane) {
                    *n += p;
                }
                *sum += area;
            }
        }
        for (i, &v) in self.vertices.iter().enumerate() {
            let v = v as usize;
            let (n, area) = std::mem::take(&mut self.in_frame[i]);
            if area == 0.0 {
                continue; // no plane at this vertex in this frame
            }
            // The linear part of A(v) = Mf(v) · M0(v)⁻¹.
            let l = match &self.p0_linear_inverse {
                Some(inverse) => DMat3::from_mat4(frame_matrices[v].as_dmat4()) * inverse[v],
                None => DMat3::from_mat4(frame_matrices[v].as_dmat4()),
            };
            let (m, sum) = &mut self.summed[i];
            for (m, x) in m.iter_mut().zip(congruence(&n, &l)) {
                *m += frame_weight * x;
            }
            *sum += frame_weight * area;
        }
    }

    /// Adds the frames' quadrics, centred on the `P0` positions, to `quadrics`.
    pub fn finish(self, quadrics: &mut [Quadric]) {
        for (&v, &(m, weight)) in self.vertices.iter().zip(&self.summed) {
            let v = v as usize;
            if weight == 0.0 {
                continue;
            }
            let p0 = self.p0_positions.as_ref().map_or(self.bind_positions[v], |p| p[v]);
            quadrics[v].add(&centred_quadric(m, weight, p0.as_dvec3()));
        }
    }
}

/// A triangle's plane in local coordinates around any of its corners: `area · n nᵀ` for its unit
/// normal `n`, and its area; `None` for a triangle with no area (or non-finite corners).
fn local_plane(a: DVec3, b: DVec3, c: DVec3) -> Option<(Sym3, f64)> {
    let n = (b - a).cross(c - a);
    let double_area = n.length();
    // NaN is not finite.
    if !double_area.is_finite() || double_area <= 0.0 {
        return None;
    }
    // area · (n / |n|)(n / |n|)ᵀ with area = |n| / 2.
    let s = 0.5 / double_area;
    let plane = [s * n.x * n.x, s * n.x * n.y, s * n.x * n.z, s * n.y * n.y, s * n.y * n.z, s * n.z * n.z];
    Some((plane, 0.5 * double_area))
}

/// `Lᵀ N L` of a symmetric `N`: what `N` measures at `L d`, measured at `d`.
fn congruence(n: &Sym3, l: &DMat3) -> Sym3 {
    let [xx, xy, xz, yy, yz, zz] = *n;
    let n = DMat3::from_cols(DVec3::new(xx, xy, xz), DVec3::new(xy, yy, yz), DVec3::new(xz, yz, zz));
    // (Lᵀ N L)[i][j] = column i of L · column j of N L.
    let nl = n * *l;
    let (l0, l1, l2) = (l.x_axis, l.y_axis, l.z_axis);
    [
        l0.dot(nl.x_axis),
        l0.dot(nl.y_axis),
        l0.dot(nl.z_axis),
        l1.dot(nl.y_axis),
        l1.dot(nl.z_axis),
        l2.dot(nl.z_axis),
    ]
}

/// The quadric `(p − p0)ᵀ M (p − p0)` with weight `weight`: `A = M`, `b = −M p0`,
/// `c = p0ᵀ M p0`.
fn centred_quadric(m: Sym3, weight: f64, p0: DVec3) -> Quadric {
    let [xx, xy, xz, yy, yz, zz] = m;
    let mp = DVec3::new(
        xx * p0.x + xy * p0.y + xz * p0.z,
        xy * p0.x + yy * p0.y + yz * p0.z,
        xz * p0.x + yz * p0.y + zz * p0.z,
    );
    Quadric { a: m, b: (-mp).to_array(), c: p0.dot(mp), weight }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skinning::blend_matrix;
    use glam::{DMat4, DVec4};
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    const TRIANGLE: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    fn one_frame(frame: Mat4) -> Vec<Quadric> {
        let mut q = vec![Quadric::ZERO; 3];
        add_frame_quadrics(&mut q, &TRIANGLE, &[0, 1, 2], None, &[frame; 3], 1.0, &[]);
        q
    }

    #[test]
    fn a_pulled_back_plane_measures_distance_in_its_frame() {
        // The frame lifts everything by 2 along z; P0 is the bind pose.
        let q = one_frame(Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)));
        // Area 0.5 on each corner; on the plane the error is 0, one unit off it is 0.5 · 1².
        assert!(q[0].error(DVec3::ZERO).abs() < 1e-12);
        assert!((q[0].error(DVec3::new(0.3, 0.3, 1.0)) - 0.5).abs() < 1e-9);
        assert_eq!(q[0].weight, 0.5);
    }

    /// The 4×4 pull-back the local frame replaced, all in f64: each frame's plane quadrics summed
    /// per vertex and transformed as `A(v)ᵀ K A(v)` with `A(v) = Mf(v) · M0(v)⁻¹`.
    fn pull_back_reference(
        positions: &[Vec3],
        indices: &[u32],
        p0_matrices: Option<&[Mat4]>,
        frames: &[Vec<Mat4>],
    ) -> Vec<Quadric> {
        let weight = 1.0 / frames.len() as f64;
        let mut summed = vec![Quadric::ZERO; positions.len()];
        for frame in frames {
            let posed: Vec<DVec3> = positions
                .iter()
                .zip(frame)
                .map(|(b, m)| m.as_dmat4().transform_point3(b.as_dvec3()))
                .collect();
            let mut in_frame = vec![Quadric::ZERO; positions.len()];
            for tri in indices.chunks_exact(3) {
                let [a, b, c] = [0, 1, 2].map(|k| posed[tri[k] as usize]);
                let n = (b - a).cross(c - a);
                let normal = n.normalize();
                let plane = Quadric::from_plane(normal, -normal.dot(a), 0.5 * n.length() * weight);
                for &i in tri {
                    in_frame[i as usize].add(&plane);
                }
            }
            for (v, q) in in_frame.iter().enumerate() {
                let p0_inverse = p0_matrices.map_or(DMat4::IDENTITY, |m| m[v].as_dmat4().inverse());
                let a = frame[v].as_dmat4() * p0_inverse;
                let [xx, xy, xz, yy, yz, zz] = q.a;
                let [bx, by, bz] = q.b;
                let k = DMat4::from_cols(
                    DVec4::new(xx, xy, xz, bx),
                    DVec4::new(xy, yy, yz, by),
                    DVec4::new(xz, yz, zz, bz),
                    DVec4::new(bx, by, bz, q.c),
                );
                let r = a.transpose() * k * a;
                summed[v].add(&Quadric {
                    a: [r.x_axis.x, r.y_axis.x, r.z_axis.x, r.y_axis.y, r.z_axis.y, r.z_axis.z],
                    b: [r.w_axis.x, r.w_axis.y, r.w_axis.z],
                    c: r.w_axis.w,
                    weight: q.weight,
                });
            }
        }
        summed
    }

    #[test]
    fn the_local_frame_equals_the_4x4_pull_back() {
        // A bent strip of 8 vertices over two joints, blended along x; frames bend, twist,
        // stretch (non-uniform scale) and move it, and P0 is the bind pose or a turned pose.
        let positions: Vec<Vec3> =
            (0..8).map(|i| Vec3::new((i / 2) as f32, (i % 2) as f32, 0.1 * (i / 2) as f32)).collect();
        let indices: Vec<u32> =
            (0..3).flat_map(|s| [2 * s, 2 * s + 2, 2 * s + 1, 2 * s + 1, 2 * s + 2, 2 * s + 3]).collect();
        let joints = [[0, 1, 0, 0]; 8];
        let weights: Vec<[f32; 4]> =
            (0..8).map(|i| (i / 2) as f32 / 3.0).map(|w| [1.0 - w, w, 0.0, 0.0]).collect();
        let skin = |angle: f32, stretch: f32| {
            let first = Mat4::from_rotation_translation(
                glam::Quat::from_rotation_y(angle),
                Vec3::new(0.5, angle, 2.0),
            );
            let second = Mat4::from_rotation_z(1.5 * angle) * Mat4::from_scale(Vec3::new(stretch, 1.0, 0.5));
            let skin = [first, second];
            (0..8).map(|v| blend_matrix(&skin, joints[v], weights[v])).collect::<Vec<_>>()
        };
        let frames: Vec<Vec<Mat4>> = [(0.3, 1.2), (-0.9, 0.8), (1.4, 1.0)].map(|(a, s)| skin(a, s)).to_vec();
        let p0 = skin(0.6, 1.1);
        for p0_matrices in [None, Some(p0.as_slice())] {
            let reference = pull_back_reference(&positions, &indices, p0_matrices, &frames);
            let mut local = vec![Quadric::ZERO; positions.len()];
            let mut passes = FrameQuadrics::new(&positions, &indices, p0_matrices, &[]);
            for frame in &frames {
                passes.add(frame, 1.0 / frames.len() as f64);
            }
            passes.finish(&mut local);
            for (v, (r, l)) in reference.iter().zip(&local).enumerate() {
                let p0 = p0_matrices.map_or(positions[v], |m| m[v].transform_point3(positions[v])).as_dvec3();
                // Both read the same f32 matrices; the reference poses in f64, this in f32. The
                // errors agree to about 1e-7 of the quadric's scale (its trace times the squared
                // offset, the largest error at that offset); 1e-5 leaves a hundredfold margin.
                let [xx, _, _, yy, _, zz] = r.a;
                for d in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.3, -0.7, 0.6)] {
                    let tolerance = 1e-5 * (xx + yy + zz) * d.length_squared();
                    let (re, le) = (r.error(p0 + d), l.error(p0 + d));
                    assert!((re - le).abs() <= tolerance, "vertex {v}, offset {d}: {re} vs {le}");
                }
                assert!((r.weight - l.weight).abs() <= 1e-6 * r.weight, "{} vs {}", r.weight, l.weight);
            }
        }
    }

    #[test]
    fn frames_average_rather_than_add() {
        let mut two = vec![Quadric::ZERO; 3];
        for _ in 0..2 {
            add_frame_quadrics(&mut two, &TRIANGLE, &[0, 1, 2], None, &[Mat4::IDENTITY; 3], 0.5, &[]);
        }
        let one = one_frame(Mat4::IDENTITY);
        let p = DVec3::new(0.1, 0.2, 0.7);
        assert!((one[1].error(p) - two[1].error(p)).abs() < 1e-12);
    }

    #[test]
    fn a_scaled_frame_scales_the_measured_distance() {
        // The frame doubles z: a point 1 above the plane in P0 is 2 above it in the frame.
        let q = one_frame(Mat4::from_scale(Vec3::new(1.0, 1.0, 2.0)));
        assert!((q[2].error(DVec3::Z) - 0.5 * 4.0).abs() < 1e-9);
    }

    #[test]
    fn p0_space_is_undone_before_the_frame_applies() {
        // P0 moved the vertices up by 1; the frame puts them back at z = 0. A P0 point at z = 1
        // is on the frame's plane.
        let p0 = Mat4::from_translation(Vec3::Z);
        let mut q = vec![Quadric::ZERO; 3];
        add_frame_quadrics(&mut q, &TRIANGLE, &[0, 1, 2], Some(&[p0; 3]), &[Mat4::IDENTITY; 3], 1.0, &[]);
        assert!(q[0].error(DVec3::new(0.2, 0.2, 1.0)).abs() < 1e-12);
        assert!((q[0].error(DVec3::new(0.2, 0.2, 0.0)) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn a_morphed_frame_votes_with_its_morphed_planes() {
        // The frame's morph lifts corner 2 by 1 along z: the triangle (0,0,0), (1,0,0), (0,1,1)
        // has normal (0, -1, 1)/√2 and area √2/2. Its skin is the identity.
        let morphed = [TRIANGLE[0], TRIANGLE[1], Vec3::new(0.0, 1.0, 1.0)];
        let mut frames = FrameQuadrics::new(&TRIANGLE, &[0, 1, 2], None, &[]);
        frames.add_morphed(&[Mat4::IDENTITY; 3], &morphed, 1.0);
        let mut q = vec![Quadric::ZERO; 3];
        frames.finish(&mut q);
        let area = 0.5 * 2f64.sqrt();
        assert!((q[0].weight - area).abs() < 1e-7);
        // Centred on the bind position: along the hinge (x) nothing, one unit up z half a unit².
        assert!(q[0].error(DVec3::X).abs() < 1e-7);
        assert!((q[0].error(DVec3::Z) - 0.5 * area).abs() < 1e-7);
        // Unmorphed, the same point is a whole unit off the plane z = 0.
        assert!((one_frame(Mat4::IDENTITY)[0].error(DVec3::Z) - 0.5).abs() < 1e-9);
    }
}
