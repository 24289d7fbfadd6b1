//! Quadric error metrics (Garland & Heckbert 1997) and Hoppe's (1999) memory-efficient
//! attribute quadrics.
//!
//! A [`Quadric`] is the weighted sum of squared distances from a point `p` to a set of planes,
//! `Q(p) = pᵀ A p + 2 b·p + c`. Face quadrics are weighted by triangle area, so
//! `Q(p) / Q.weight` is a mean squared distance in position units².
//!
//! Attribute quadrics (Hoppe 1999, "New quadric metric for simplifying meshes with appearance
//! attributes"): every face carries, per attribute channel, the linear field `s(p) = g·p + d` that
//! interpolates the channel's three corner values over the face's plane (`TriangleFrame`). The
//! error of a vertex at `p` with channel value `s` is `Σ area · w · (g·p + d − s)²`. Expanding it,
//! the `A`, `b`, `c` parts are plain quadric terms and are summed into a 3×3 [`Quadric`]; only the
//! cross terms `Σ area·w·g`, `Σ area·w·d` and `Σ area` are kept per wedge (4 numbers per channel
//! instead of a (3+m)² matrix). Minimising over `s` in closed form leaves a 3×3 system in `p`
//! (the Schur complement), see [`Quadric::add_optimal_attribute`].
//!
//! Everything is f64: quadric coefficients cancel catastrophically in f32 when a mesh lies far
//! from the origin (c ≈ |b|² / |A|), and the solve needs the headroom.

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use glam::DVec3;

/// A symmetric quadric `Q(p) = pᵀ A p + 2 b·p + c` with the total weight (area) of its planes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadric {
    /// Upper triangle of the symmetric 3×3 matrix `A`: `[xx, xy, xz, yy, yz, zz]`.
    pub a: [f64; 6],
    /// Linear term `b` (the error has `2 b·p`).
    pub b: [f64; 3],
    /// Constant term.
    pub c: f64,
    /// Sum of plane weights (triangle areas for face quadrics); errors are divided by it to get a
    /// mean squared distance. Penalty planes add error but no weight.
    pub weight: f64,
}

impl Quadric {
    /// The quadric of no plane at all.
    pub const ZERO: Quadric = Quadric { a: [0.0; 6], b: [0.0; 3], c: 0.0, weight: 0.0 };

    /// The squared distance to the plane `normal·p + offset = 0`, times `weight`.
    ///
    /// `normal` should be unit length; a longer one scales the error by its squared length.
    pub fn from_plane(normal: DVec3, offset: f64, weight: f64) -> Quadric {
        let n = normal;
        let w = weight;
        Quadric {
            a: [w * n.x * n.x, w * n.x * n.y, w * n.x * n.z, w * n.y * n.y, w * n.y * n.z, w * n.z * n.z],
            b: [w * offset * n.x, w * offset * n.y, w * offset * n.z],
            c: w * offset * offset,
            weight: w,
        }
    }

    /// The area-weighted plane quadric of a triangle (Garland & Heckbert's face quadric).
    ///
    /// A degenerate (zero-area) triangle has no plane and gives [`Quadric::ZERO`].
    pub fn from_triangle(p0: DVec3, p1: DVec3, p2: DVec3) -> Quadric {
        let cross = (p1 - p0).cross(p2 - p0);
        let length = cross.length();
        if !(length > 0.0) || !length.is_finite() {
            return Quadric::ZERO;
        }
        let normal = cross / length;
        Quadric::from_plane(normal, -normal.dot(p0), 0.5 * length)
    }

    /// Adds `other` to `self` (planes and weights).
    pub fn add(&mut self, other: &Quadric) {
        for k in 0..6 {
            self.a[k] += other.a[k];
        }
        for k in 0..3 {
            self.b[k] += other.b[k];
        }
        self.c += other.c;
        self.weight += other.weight;
    }

    /// `A p`.
    fn a_times(&self, p: DVec3) -> DVec3 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        DVec3::new(
            xx * p.x + xy * p.y + xz * p.z,
            xy * p.x + yy * p.y + yz * p.z,
            xz * p.x + yz * p.y + zz * p.z,
        )
    }

    /// The raw (weighted, not normalised) error `Q(p)`. Rounding can make it slightly negative.
    pub fn error(&self, p: DVec3) -> f64 {
        let ap = self.a_times(p);
        p.dot(ap) + 2.0 * (self.b[0] * p.x + self.b[1] * p.y + self.b[2] * p.z) + self.c
    }

    /// The point minimising `Q`, or `None` when `A` is (nearly) singular.
    ///
    /// Solves `A p = −b` by an LDLᵀ factorisation (A is positive semi-definite). A pivot below
    /// 1e-10 of the trace means `Q` is flat along some direction (coplanar or collinear planes):
    /// the "minimiser" would be arbitrary along it, so the caller must place the point another
    /// way (see [`Quadric::minimize_on_segment`]).
    pub fn minimize(&self) -> Option<DVec3> {
        self.solve(1e-10)
    }

    /// A lower bound of `min_p Q(p)`, for deferring work that only matters if `Q` can get that
    /// low (the collapse queue's bounds): `Q` at its minimiser less a rounding margin, or 0
    /// when `A` is not well conditioned (a positive semi-definite `Q` is never below 0).
    ///
    /// The minimiser is only accepted when every pivot exceeds 1e-6 of the trace, so that its
    /// f64 rounding error (condition number × 1e-16) raises `Q` above the true minimum by far
    /// less than the margin; the margin, 1e-12 of the magnitude of the terms summed (thousands of
    /// f64 ulps), covers the rounding of this evaluation and of a caller that sums the same
    /// quadric in another order.
    pub fn minimum_lower_bound(&self) -> f64 {
        let Some(p) = self.solve(1e-6) else {
            return 0.0;
        };
        let quadratic = p.dot(self.a_times(p));
        let linear = 2.0 * (self.b[0] * p.x + self.b[1] * p.y + self.b[2] * p.z);
        let magnitude = quadratic.abs() + linear.abs() + self.c.abs();
        let bound = quadratic + linear + self.c - 1e-12 * magnitude;
        if bound > 0.0 {
            bound
        } else {
            0.0
        }
    }

    /// A lower bound of `Q(p)` for every `p` within `radius` of `center`: the bound
    /// [`Quadric::minimum_lower_bound`] cannot give when `A` is singular, as it is for the
    /// planes of a flat or cylindrical patch (every normal at a right angle to one direction).
    ///
    /// In coordinates `t = p − center`, `Q` is `tᵀ A t + 2 β·t + Q(center)`. Coordinates are
    /// minimised out one at a time, the one of largest curvature first (symmetric pivoting), while
    /// the curvature left exceeds 1e-6 of the trace; that minimum over all of space is below the
    /// one over the ball. A coordinate left (a flat direction) keeps its box `|tₖ| ≤ radius`, a
    /// superset of the ball, on which its linear term is at least `−2 |βₖ| radius` (its
    /// quadratic part, positive semi-definite, is dropped). Margins cover rounding: 1e-9 of the
    /// terms eliminated (pivots down to 1e-6 of the trace), and, as in
    /// [`Quadric::minimum_lower_bound`], 1e-12 of the terms of `Q(center)`, for an evaluation of
    /// `Q` near `center` whose terms cancel far from the origin. Returns 0 where that is all it can say
    /// (a positive semi-definite `Q` is never below 0), and for a non-finite argument.
    pub fn lower_bound_within(&self, center: DVec3, radius: f64) -> f64 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let mut m = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
        let ac = self.a_times(center);
        let mut beta = [ac.x + self.b[0], ac.y + self.b[1], ac.z + self.b[2]];
        let mut constant = self.error(center);
        // The caller's own evaluation of `Q` near `center` rounds in proportion to its terms,
        // which cancel when the points are far from the origin: the margin covers those too.
        let quadratic = center.dot(ac);
        let linear = 2.0 * (self.b[0] * center.x + self.b[1] * center.y + self.b[2] * center.z);
        let evaluation = quadratic.abs() + linear.abs() + self.c.abs();
        let mut magnitude = constant.abs();
        let eps = (xx + yy + zz) * 1e-6;
        let mut left = [true; 3];
        for _ in 0..3 {
            let Some(k) = (0..3).filter(|&k| left[k]).max_by(|&i, &j| m[i][i].total_cmp(&m[j][j])) else {
                break;
            };
            let pivot = m[k][k];
            if !(pivot > eps) {
                break;
            }
            left[k] = false;
            // Minimising over tₖ: Q loses βₖ² / mₖₖ, and the others see the Schur complement.
            let drop = beta[k] * beta[k] / pivot;
            constant -= drop;
            magnitude += drop;
            for i in (0..3).filter(|&i| left[i]) {
                let factor = m[i][k] / pivot;
                beta[i] -= factor * beta[k];
                for j in (0..3).filter(|&j| left[j]) {
                    m[i][j] -= factor * m[k][j];
                }
            }
        }
        for k in (0..3).filter(|&k| left[k]) {
            let slope = 2.0 * beta[k].abs() * radius;
            constant -= slope;
            magnitude += slope;
        }
        let bound = constant - 1e-9 * magnitude - 1e-12 * evaluation;
        if bound > 0.0 {
            bound
        } else {
            0.0
        }
    }

    /// Solves `A p = −b` (see [`Quadric::minimize`]), refusing pivots at or below
    /// `relative_pivot` of the trace.
    fn solve(&self, relative_pivot: f64) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let trace = xx + yy + zz;
        if !(trace > 0.0) || !trace.is_finite() {
            return None;
        }
        let eps = trace * relative_pivot;
        let d0 = xx;
        if !(d0 > eps) {
            return None;
        }
        let l10 = xy / d0;
        let l20 = xz / d0;
        let d1 = yy - l10 * xy;
        if !(d1 > eps) {
            return None;
        }
        let l21 = (yz - l20 * xy) / d1;
        let d2 = zz - l20 * xz - l21 * l21 * d1;
        if !(d2 > eps) {
            return None;
        }
        let r = [-self.b[0], -self.b[1], -self.b[2]];
        let y0 = r[0];
        let y1 = r[1] - l10 * y0;
        let y2 = r[2] - l20 * y0 - l21 * y1;
        let x2 = y2 / d2;
        let x1 = y1 / d1 - l21 * x2;
        let x0 = y0 / d0 - l10 * x1 - l20 * x2;
        let p = DVec3::new(x0, x1, x2);
        p.is_finite().then_some(p)
    }

    /// The point of the segment `from..=to` minimising `Q`.
    ///
    /// `Q(from + t (to − from))` is a parabola in `t`; its minimum is clamped to `[0, 1]`. When
    /// the parabola is flat (the segment lies in every plane, or is a point) the midpoint is
    /// returned unless one end is better by more than a negligible margin; the midpoint keeps
    /// triangles evenly sized when nothing else decides.
    pub fn minimize_on_segment(&self, from: DVec3, to: DVec3) -> DVec3 {
        let d = to - from;
        let len2 = d.length_squared();
        let trace = self.a[0] + self.a[3] + self.a[5];
        let curvature = d.dot(self.a_times(d));
        let slope = d.dot(self.a_times(from) + DVec3::from_array(self.b));
        // Relative to the largest possible curvature along `d`, 1e-12 is rounding noise.
        let flat = !(curvature > 1e-12 * trace * len2);
        let t = if !flat {
            (-slope / curvature).clamp(0.0, 1.0)
        } else {
            // Error changes by 2·slope over the segment; below 1e-9 of weight·|d|² (a mean squared
            // distance of 1e-9 of the segment length²) that is noise, not a preference.
            let tolerance = 1e-9 * self.weight.max(0.0) * len2;
            if slope > tolerance {
                0.0
            } else if slope < -tolerance {
                1.0
            } else {
                0.5
            }
        };
        if t == 0.0 {
            from
        } else if t == 1.0 {
            to
        } else {
            from + d * t
        }
    }

    /// Adds one attribute channel's best achievable error reduction, to be subtracted (see
    /// [`Quadric::subtract`]) from a quadric that holds the channel's error: that turns
    /// `Q(p) + error(p, s)` into `min_s [Q(p) + error(p, s)]` for the channel sums
    /// `gradient = Σ area·w·g`, `offset = Σ area·w·d` and `inverse_alpha_w = 1 / Σ area·w`
    /// (Hoppe 1999, eq. for the optimal `s`). Summing the reductions of all channels first keeps
    /// the sums in registers; callers pass the inverse because many channels share one area sum.
    ///
    /// The attribute error itself, `Σ area·w·(g·p+d)²`, must already be in the quadric it is
    /// subtracted from (it is summed into the per-vertex quadric). Does nothing when
    /// `inverse_alpha_w` is not positive.
    pub fn add_optimal_attribute(&mut self, gradient: DVec3, offset: f64, inverse_alpha_w: f64) {
        if !(inverse_alpha_w > 0.0) {
            return;
        }
        let k = inverse_alpha_w;
        let g = gradient;
        let (kgx, kgy, kgz) = (k * g.x, k * g.y, k * g.z);
        self.a[0] += kgx * g.x;
        self.a[1] += kgx * g.y;
        self.a[2] += kgx * g.z;
        self.a[3] += kgy * g.y;
        self.a[4] += kgy * g.z;
        self.a[5] += kgz * g.z;
        self.b[0] += kgx * offset;
        self.b[1] += kgy * offset;
        self.b[2] += kgz * offset;
        self.c += k * offset * offset;
    }

    /// Subtracts the planes of `other` (not its weight: a reduction has none).
    pub fn subtract(&mut self, other: &Quadric) {
        for k in 0..6 {
            self.a[k] -= other.a[k];
        }
        for k in 0..3 {
            self.b[k] -= other.b[k];
        }
        self.c -= other.c;
    }

    /// Adds the cross terms of one attribute channel held at the fixed value `s`:
    /// `−2 s (gradient·p + offset) + alpha_w s²` (the `(g·p+d)²` part is already in `self`).
    pub fn add_fixed_attribute(&mut self, gradient: DVec3, offset: f64, alpha_w: f64, s: f64) {
        self.b[0] -= s * gradient.x;
        self.b[1] -= s * gradient.y;
        self.b[2] -= s * gradient.z;
        self.c += alpha_w * s * s - 2.0 * s * offset;
    }
}

impl std::ops::AddAssign<&Quadric> for Quadric {
    fn add_assign(&mut self, other: &Quadric) {
        self.add(other);
    }
}

/// The frame of one triangle for Hoppe's attribute gradients: the linear field over the triangle's
/// plane that takes given values at its three corners.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TriangleFrame {
    p0: DVec3,
    e1: DVec3,
    e2: DVec3,
    /// Inverse Gram matrix of (e1, e2): `[g11, g12, g22]` of `inv([[e1·e1, e1·e2], [e1·e2, e2·e2]])`.
    inverse_gram: [f64; 3],
    /// Triangle area.
    pub area: f64,
}

impl TriangleFrame {
    /// `None` for a degenerate triangle: |e1 × e2|² below 1e-12 of |e1|²|e2|² (angles under
    /// ~1e-6 rad) would make the gradient blow up with rounding noise.
    pub fn new(p0: DVec3, p1: DVec3, p2: DVec3) -> Option<TriangleFrame> {
        let e1 = p1 - p0;
        let e2 = p2 - p0;
        let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let det = a * c - b * b;
        if !(det > 1e-12 * a * c) || !det.is_finite() {
            return None;
        }
        let inverse_gram = [c / det, -b / det, a / det];
        Some(TriangleFrame { p0, e1, e2, inverse_gram, area: 0.5 * det.sqrt() })
    }

    /// The gradient `g` (in the triangle's plane) and offset `d` of the linear field with values
    /// `s0, s1, s2` at the corners: `s(p) = g·p + d`.
    pub fn gradient(&self, s0: f64, s1: f64, s2: f64) -> (DVec3, f64) {
        let (ds1, ds2) = (s1 - s0, s2 - s0);
        let [i11, i12, i22] = self.inverse_gram;
        let alpha = i11 * ds1 + i12 * ds2;
        let beta = i12 * ds1 + i22 * ds2;
        let g = self.e1 * alpha + self.e2 * beta;
        (g, s0 - g.dot(self.p0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_axis_planes_meet_at_their_corner() {
        let mut q = Quadric::from_plane(DVec3::X, -1.0, 1.0);
        q += &Quadric::from_plane(DVec3::Y, -2.0, 1.0);
        q += &Quadric::from_plane(DVec3::Z, -3.0, 1.0);
        let p = q.minimize().unwrap();
        assert!((p - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12, "{p}");
        assert!(q.error(p).abs() < 1e-12);
        assert_eq!(q.error(DVec3::new(1.0, 2.0, 4.0)), 1.0);
    }

    #[test]
    fn coplanar_planes_are_singular_and_the_segment_decides() {
        let q = Quadric::from_triangle(DVec3::ZERO, DVec3::X, DVec3::Y);
        assert!((q.weight - 0.5).abs() < 1e-15);
        assert!(q.minimize().is_none());
        // In-plane segment: flat, so the midpoint.
        let m = q.minimize_on_segment(DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(m, DVec3::new(1.0, 0.0, 0.0));
        // Crossing the plane: the crossing point.
        let c = q.minimize_on_segment(DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.0, 0.0, 3.0));
        assert!((c - DVec3::ZERO).length() < 1e-12, "{c}");
        // Not crossing: the nearer end.
        let e = q.minimize_on_segment(DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, 3.0));
        assert_eq!(e, DVec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn minimum_lower_bound_is_below_every_value_and_near_the_minimum() {
        // Four planes with no common point, far from the origin (where the terms cancel most).
        for origin in [DVec3::ZERO, DVec3::new(3e3, -2e3, 5e3)] {
            let mut q = Quadric::ZERO;
            for (normal, through) in [
                (DVec3::X, DVec3::ZERO),
                (DVec3::Y, DVec3::ZERO),
                (DVec3::Z, DVec3::ZERO),
                (DVec3::ONE.normalize(), DVec3::ONE * 0.1),
            ] {
                let through = origin + through;
                q += &Quadric::from_plane(normal, -normal.dot(through), 2.0);
            }
            let minimum = q.error(q.minimize().unwrap());
            let bound = q.minimum_lower_bound();
            // Near the origin the bound is the minimum to rounding; 5,000 units away the margin is
            // about 1e-2 of it.
            assert!(bound <= minimum && bound > 0.95 * minimum, "{bound} vs {minimum}");
            for k in 0..125 {
                let step = DVec3::new((k % 5) as f64, (k / 5 % 5) as f64, (k / 25) as f64) * 0.02;
                assert!(bound <= q.error(origin + step));
            }
        }
        // Singular (one plane): no well-conditioned minimiser, so the bound that always holds.
        let flat = Quadric::from_triangle(DVec3::ZERO, DVec3::X, DVec3::Y);
        assert_eq!(flat.minimum_lower_bound(), 0.0);
        assert_eq!(Quadric::ZERO.minimum_lower_bound(), 0.0);
    }

    #[test]
    fn lower_bound_within_a_ball_holds_where_the_planes_leave_a_direction_free() {
        // A cylinder's side planes around an axis along (1, 2, 2) / 3, 5,000 units from the
        // origin: `A` is singular along the axis, so the global bound can only say 0.
        let origin = DVec3::new(3e3, -2e3, 5e3);
        let axis = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        let (u, w) = (DVec3::new(2.0, 1.0, -2.0) / 3.0, DVec3::new(2.0, -2.0, 1.0) / 3.0);
        let mut q = Quadric::ZERO;
        for k in 0..7 {
            let angle = k as f64 * 0.3;
            let normal = u * angle.cos() + w * angle.sin();
            let through = origin + normal * 2.0 + axis * (k as f64 * 0.1);
            q += &Quadric::from_plane(normal, -normal.dot(through), 1.5);
        }
        assert_eq!(q.minimum_lower_bound(), 0.0);
        // Within 0.5 of a centre 3 units out, Q stays above the bound. Q is constant along the
        // axis, so the bound is its least value over all of space (found with a faint plane
        // across the axis that fixes the free direction), less the margin.
        let center = origin + u * 3.0;
        let bound = q.lower_bound_within(center, 0.5);
        for k in 0..343 {
            let step = DVec3::new((k % 7) as f64, (k / 7 % 7) as f64, (k / 49) as f64) / 6.0 - 0.5;
            let step = step.normalize_or_zero() * 0.5 * (k % 5) as f64 / 4.0;
            let value = q.error(center + step);
            assert!(bound <= value, "{bound} above {value} at {step}");
        }
        let mut pinned = q;
        pinned += &Quadric::from_plane(axis, -axis.dot(origin), 1e-6);
        let least = q.error(pinned.minimize().unwrap());
        assert!(bound <= least && bound > 0.999 * least, "{bound} vs {least}");
        // With no singular direction it is no higher than the global minimum.
        let mut full = q;
        full += &Quadric::from_plane(axis, -axis.dot(origin), 1.0);
        let minimum = full.error(full.minimize().unwrap());
        assert!(full.lower_bound_within(center, 0.5) <= minimum);
        assert_eq!(Quadric::ZERO.lower_bound_within(center, 1.0), 0.0);
        assert_eq!(q.lower_bound_within(DVec3::NAN, 1.0), 0.0);
    }

    #[test]
    fn gradient_reproduces_corner_values() {
        let (p0, p1, p2) = (DVec3::new(1.0, 0.0, 2.0), DVec3::new(3.0, 1.0, 2.0), DVec3::new(0.0, 4.0, 5.0));
        let frame = TriangleFrame::new(p0, p1, p2).unwrap();
        let (g, d) = frame.gradient(0.25, -1.0, 3.0);
        for (p, s) in [(p0, 0.25), (p1, -1.0), (p2, 3.0)] {
            assert!((g.dot(p) + d - s).abs() < 1e-12);
        }
        // The gradient lies in the plane.
        assert!(g.dot((p1 - p0).cross(p2 - p0)).abs() < 1e-9);
        assert!(TriangleFrame::new(p0, p1, p1).is_none());
    }

    #[test]
    fn optimal_attribute_matches_brute_force() {
        // Two faces with different fields for one channel; the reduced quadric at p must equal the
        // error at the best s.
        let f1 = TriangleFrame::new(DVec3::ZERO, DVec3::X, DVec3::Y).unwrap();
        let f2 = TriangleFrame::new(DVec3::ZERO, DVec3::Y, DVec3::new(-1.0, 0.0, 0.5)).unwrap();
        let (w, mut q, mut g_sum, mut d_sum, mut alpha) = (2.0, Quadric::ZERO, DVec3::ZERO, 0.0, 0.0);
        for (f, s) in [(f1, [0.0, 1.0, 0.5]), (f2, [0.2, 0.9, -0.3])] {
            let (g, d) = f.gradient(s[0], s[1], s[2]);
            let aw = f.area * w;
            let mut part = Quadric::from_plane(g, d, aw);
            part.weight = 0.0;
            q += &part;
            g_sum += g * aw;
            d_sum += d * aw;
            alpha += aw;
        }
        let p = DVec3::new(0.1, 0.3, 0.05);
        let s_best = (g_sum.dot(p) + d_sum) / alpha;
        let mut fixed = q;
        fixed.add_fixed_attribute(g_sum, d_sum, alpha, s_best);
        let mut reduction = Quadric::ZERO;
        reduction.add_optimal_attribute(g_sum, d_sum, 1.0 / alpha);
        let mut reduced = q;
        reduced.subtract(&reduction);
        assert!((fixed.error(p) - reduced.error(p)).abs() < 1e-12);
        let mut worse = q;
        worse.add_fixed_attribute(g_sum, d_sum, alpha, s_best + 0.1);
        assert!(worse.error(p) > fixed.error(p));
    }
}
