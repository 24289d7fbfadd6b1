//! What a collapse is priced with: per class its geometric quadric (face and penalty planes) and
//! its total quadric (plus Hoppe's attribute quadrics), per wedge its attribute sums and current
//! attributes, the priced channels and their weights, and the scale of the order key. Pricing
//! (`plan.rs`) only reads them; a collapse adds `u`'s quadrics and sums to `v`'s. Part of the
//! collapse engine in `mod.rs`.
//!
//! Invariants: a class's quadrics and a wedge's sums only ever grow by what merges into them, so
//! the relaxed quadric of a class (strict order only, see `plan.rs`) stays a lower bound of
//! every pricing it enters until the class changes; a quadric's weight is its face planes' area
//! (penalty and attribute planes weigh nothing).

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::channels::Channels;
use super::super::quadric::Quadric;
use super::super::topology::{ConstraintSide, PositionClasses};
use super::super::vertex_quadrics::{attribute_quadrics, geometric_quadrics};
use super::super::{CollapseMode, Rule, Rules, SimplifyInput, SimplifyOptions};
use glam::DVec3;

/// A pair smaller than this fraction of the mean pair area is ordered as if it had this
/// fraction: its key is its mean squared error × `SMALL_PAIR`, as for a pair of that area.
/// Ordering by the integral alone let a small part coarsen while its error was far larger than
/// the rest's (a pair of a tenth of the mean area went at √10 × the distance of an average one):
/// parts.glb's neck plates were 1.19 % of the diagonal off at its
/// 228-triangle level (animated Hausdorff; meshoptimizer 0.81 %). With 0.3 a small pair goes at
/// most √(1/0.3) ≈ 1.8 × an average pair's distance, and that level is 0.54 % off. Measured
/// (`animated_error --detail --pose multi`, `bench/animated-vs-meshoptimizer.mjs`): 0.1 changes
/// nothing; 0.3 improves CesiumMan's 10/5/1 % levels and Fox's 1 % by 1–4 % and changes no
/// level for the worse by more than robot.glb's 656-triangle 0.016 → 0.017 %; 0.5, 1 and 2 make
/// some levels of Fox, RiggedSimple or robot.glb worse by up to 80 %.
pub(super) const SMALL_PAIR: f64 = 0.3;

/// The costs of collapses (see the module docs).
pub(super) struct Costs {
    /// [`SimplifyOptions::mode`].
    pub(super) mode: CollapseMode,
    /// [`SimplifyOptions::rules`]: the pricing asks it how to place and price.
    pub(super) rules: Rules,
    /// Attribute channels per vertex.
    pub(super) channels: usize,
    /// [`SimplifyOptions::normal_channel`].
    pub(super) normal_channel: Option<usize>,
    /// The priced attribute channels (see [`Channels`]).
    pub(super) priced: Channels,
    /// `1 / weight` per priced channel.
    pub(super) inverse_weights: Vec<f64>,
    /// Wedge sums of nothing: the partner of a wedge that merges with none.
    pub(super) zero_sums: Vec<f64>,
    /// `1 / (2 × mean class area)`: scales `Plan::cost` to a mean squared error for a pair of
    /// average area.
    pub(super) inverse_mean_pair_area: f64,
    /// Geometric quadric per class (face and penalty planes).
    pub(super) geometric: Vec<Quadric>,
    /// Geometric plus attribute quadric per class; its weight is the geometric weight.
    pub(super) total: Vec<Quadric>,
    /// Per class, [`Costs::relaxed_quadric`] (strict order only, else empty): the source of the
    /// bounds that defer re-pricing.
    pub(super) relaxed: Vec<Quadric>,
    /// Per wedge: `[Σ area, then per priced channel Σ area·w·g (3), Σ area·w·d]`, stride
    /// `priced.stride()`.
    pub(super) wedge_sums: Vec<f64>,
    /// Per wedge, its attributes now (`channels` floats).
    pub(super) wedge_attributes: Vec<f32>,
}

impl Costs {
    /// The initial costs of `input`, whose position classes are `classes`, with the penalty
    /// planes of the constraint edges `sides` and the input triangles' unit normals
    /// `input_normal`. No relaxed quadrics yet ([`Costs::relax_all`]).
    pub(super) fn new(
        classes: &PositionClasses,
        sides: &[ConstraintSide],
        input_normal: &[DVec3],
        input: &SimplifyInput<'_>,
        options: &SimplifyOptions,
    ) -> Costs {
        let geometric = geometric_quadrics(classes, input, sides, input_normal);
        let priced = Channels::new(input.attributes, input.attribute_weights);
        let (appearance, wedge_sums) = attribute_quadrics(classes, input, &priced);
        let mut total = geometric.clone();
        for (t, a) in total.iter_mut().zip(&appearance) {
            *t += a;
        }
        // Face planes carry the area as weight (penalty planes none): a class's weight is its
        // triangles' area.
        let mean_pair_area =
            2.0 * geometric.iter().map(|q| q.weight).sum::<f64>() / classes.count().max(1) as f64;
        Costs {
            mode: options.mode,
            rules: options.rules,
            channels: input.attribute_weights.len(),
            normal_channel: options.normal_channel,
            inverse_weights: priced.priced.iter().map(|&(_, w)| 1.0 / w as f64).collect(),
            zero_sums: vec![0.0; priced.stride()],
            priced,
            inverse_mean_pair_area: if mean_pair_area > 0.0 { 1.0 / mean_pair_area } else { 1.0 },
            geometric,
            total,
            relaxed: Vec::new(),
            wedge_sums,
            wedge_attributes: input.attributes.to_vec(),
        }
    }

    /// The order key of a collapse whose quadric error is `error` over a pair of area `weight`
    /// (see the module docs of `mod.rs`): the error over the mean pair area, or for a pair
    /// smaller than [`SMALL_PAIR`] of the mean, over its own area divided by `SMALL_PAIR`
    /// ([`Rule::SmallPairs`]).
    pub(super) fn order_key(&self, error: f64, weight: f64) -> f64 {
        if weight > 0.0 && self.rules.has(Rule::SmallPairs) {
            error * self.inverse_mean_pair_area.max(SMALL_PAIR / weight)
        } else {
            error * self.inverse_mean_pair_area
        }
    }

    /// Computes every class's relaxed quadric (for the strict order's bounds).
    pub(super) fn relax_all(&mut self, classes: &PositionClasses) {
        self.relaxed = (0..classes.count()).map(|c| self.relaxed_quadric(classes, c)).collect();
    }

    /// Class `c`'s relaxed quadric: its total quadric with each wedge's attributes reduced out
    /// at that wedge's own optimum (see the module docs of `plan.rs`).
    pub(super) fn relaxed_quadric(&self, classes: &PositionClasses, c: usize) -> Quadric {
        let mut relaxed = self.total[c];
        let stride = self.priced.stride();
        for &w in classes.wedges_of(c as u32) {
            let sums = &self.wedge_sums[w as usize * stride..(w as usize + 1) * stride];
            if !(sums[0] > 0.0) {
                continue;
            }
            let inverse_alpha = 1.0 / sums[0];
            let mut optimum = Quadric::ZERO;
            for (channel, &inverse_weight) in sums[1..].chunks_exact(4).zip(&self.inverse_weights) {
                let g = DVec3::new(channel[0], channel[1], channel[2]);
                optimum.add_optimal_attribute(g, channel[3], inverse_alpha * inverse_weight);
            }
            relaxed.subtract(&optimum);
        }
        relaxed
    }

    /// Class `v` takes class `u`'s quadrics, merged at `p` (its relaxed quadric follows, once
    /// `v`'s wedge sums have taken `u`'s); returns the distance the merged geometric quadric
    /// measures at `p` (the root of its mean squared error), which the log records.
    pub(super) fn merge_classes(&mut self, classes: &PositionClasses, u: usize, v: usize, p: DVec3) -> f64 {
        let mut geometric = self.geometric[u];
        geometric += &self.geometric[v];
        let weight = if geometric.weight > 0.0 { geometric.weight } else { 1.0 };
        let distance = (geometric.error(p).max(0.0) / weight).sqrt();
        self.geometric[v] = geometric;
        let tu = self.total[u];
        self.total[v] += &tu;
        if !self.relaxed.is_empty() {
            self.relaxed[v] = self.relaxed_quadric(classes, v);
        }
        distance
    }
}

#[cfg(test)]
mod tests {
    use super::super::mesh::Mesh;
    use super::*;
    use glam::Vec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A bent 3 × 3 grid (vertex `3y + x`, the middle row raised) with one priced channel that
    /// varies across it: positions, indices, attributes.
    fn grid() -> (Vec<Vec3>, Vec<u32>, Vec<f32>) {
        let z = |i: u32| if i / 3 == 1 { 0.4 } else { 0.0 };
        let positions = (0..9).map(|i| Vec3::new((i % 3) as f32, (i / 3) as f32, z(i))).collect();
        let indices = [0, 1, 3, 4].iter().flat_map(|&i| [i, i + 1, i + 4, i, i + 4, i + 3]).collect();
        let attributes = (0..9).map(|i| (i * i) as f32 * 0.1).collect();
        (positions, indices, attributes)
    }

    /// The mesh and costs of `grid()`.
    fn costs<'a>((positions, indices, attributes): &'a (Vec<Vec3>, Vec<u32>, Vec<f32>)) -> (Mesh<'a>, Costs) {
        let input = SimplifyInput {
            positions,
            attributes,
            attribute_weights: &[1.0],
            indices,
            triangle_materials: &[],
            vertex_quadrics: None,
        };
        let (mesh, sides) = Mesh::new(&input, None);
        let costs =
            Costs::new(&mesh.classes, &sides, &mesh.input_normal, &input, &SimplifyOptions::default());
        (mesh, costs)
    }

    #[test]
    fn a_small_pair_is_ordered_as_if_it_were_a_fraction_of_the_mean() {
        let grid = grid();
        let (_, mut costs) = costs(&grid);
        let mean = 4.0;
        costs.inverse_mean_pair_area = 1.0 / mean;
        // At or above SMALL_PAIR of the mean: the error over the mean area.
        assert_eq!(costs.order_key(2.0, mean), 0.5);
        assert_eq!(costs.order_key(2.0, SMALL_PAIR * mean), 0.5);
        // Below: its mean squared error × SMALL_PAIR, as for a pair of that fraction.
        let weight = 0.1 * mean;
        assert!((costs.order_key(2.0, weight) - 2.0 / weight * SMALL_PAIR).abs() < 1e-12);
        assert_eq!(costs.order_key(2.0, 0.0), 0.5, "no area: the mean");
        // Without the rule a small pair is keyed by its area-weighted error alone, at a
        // fraction of the key its distance deserves.
        costs.rules = Rules::ALL.without(Rule::SmallPairs);
        assert_eq!(costs.order_key(2.0, weight), 0.5);
    }

    #[test]
    fn the_relaxed_quadric_lies_between_the_geometric_and_the_total() {
        let grid = grid();
        let (mesh, mut costs) = costs(&grid);
        costs.relax_all(&mesh.classes);
        let points = [DVec3::ZERO, DVec3::new(1.0, 1.0, 0.4), DVec3::new(-2.0, 3.0, 1.5)];
        for c in 0..mesh.classes.count() {
            for p in points {
                let (geometric, relaxed, total) =
                    (costs.geometric[c].error(p), costs.relaxed[c].error(p), costs.total[c].error(p));
                let slack = 1e-9 * (1.0 + total.abs());
                assert!(geometric <= relaxed + slack && relaxed <= total + slack, "class {c} at {p}");
            }
        }
        assert!((0..9).any(|c| costs.relaxed[c].error(points[2]) < costs.total[c].error(points[2])));
    }

    #[test]
    fn a_merged_class_takes_both_quadrics() {
        let grid = grid();
        let (mesh, mut costs) = costs(&grid);
        costs.relax_all(&mesh.classes);
        let (u, v) = (mesh.classes.class_of[4] as usize, mesh.classes.class_of[5] as usize);
        let mut geometric = costs.geometric[u];
        geometric += &costs.geometric[v];
        let mut total = costs.total[u];
        total += &costs.total[v];
        let p = DVec3::new(1.5, 1.0, 0.4);
        let distance = costs.merge_classes(&mesh.classes, u, v, p);
        assert_eq!(costs.geometric[v], geometric);
        assert_eq!(costs.total[v], total);
        assert_eq!(distance, (geometric.error(p).max(0.0) / geometric.weight).sqrt());
        assert_eq!(costs.relaxed[v], costs.relaxed_quadric(&mesh.classes, v), "the relaxed quadric follows");
    }
}
