//! Planning and pricing one collapse: the wedge pairing of its two classes (seams follow the
//! edge), the placement (quadric minimiser, best point of the edge, or the survivor's position)
//! and its cost in f64 (Garland & Heckbert's quadric plus Hoppe's 1999 attribute quadrics, with
//! the attributes reduced out at their optimum): the area-weighted error that orders collapses,
//! and the mean squared error over the pair's area that the floor and the records use. Part of
//! the collapse engine in `mod.rs`.
//!
//! Also a cheap lower bound of that cost for an edge whose pricing the strict order defers
//! (`Order::queue_bounds`): a class's *relaxed* quadric gives each of its wedges its own best
//! attributes, so it lies pointwise below the part of any pricing it enters (merging wedges or
//! fixing their attributes only adds error), and the minimum of two relaxed quadrics' sum bounds
//! every collapse along their edge, whatever its pairing and placement. Collapses only ever add
//! planes and wedge sums to a class, so a bound stays valid until the edge is priced.

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::quadric::Quadric;
use super::super::topology::{other_corners, Kind, NONE};
use super::super::{CollapseMode, Rule};
use super::costs::Costs;
use super::floors::Floors;
use super::mesh::Mesh;
use super::scratch::Pairing;
use super::{Engine, Placement, Plan, PricingStats};
use glam::DVec3;

/// What pricing a collapse reads and writes: it reads the mesh and the costs, leaves the wedge
/// pairing for the collapse that applies the plan, counts its pricings, and asks the floors about
/// a part that vanishes (they remember the answers, and the open parts left waiting).
pub(super) struct Pricing<'e, 'a> {
    pub(super) mesh: &'e Mesh<'a>,
    pub(super) costs: &'e Costs,
    pub(super) floors: &'e mut Floors<'a>,
    pub(super) pairing: &'e mut Pairing,
    pub(super) stats: &'e mut PricingStats,
    /// The collapses logged so far: the state of `mesh`, as the floors' memory knows it.
    pub(super) steps: usize,
}

impl<'a> Engine<'a> {
    /// The parts pricing borrows (see [`Pricing`]).
    pub(super) fn pricing(&mut self) -> Pricing<'_, 'a> {
        let steps = self.record.steps();
        Pricing {
            mesh: &self.mesh,
            costs: &self.costs,
            floors: &mut self.floors,
            pairing: &mut self.scratch.pairing,
            stats: &mut self.record.stats,
            steps,
        }
    }
}

impl Pricing<'_, '_> {
    /// Pairs the wedges of `u` with those of `v` and prices the collapse `u → v`; `None` when the
    /// kinds forbid it, the classes no longer share an edge, or the pairing would tear a seam.
    /// Leaves the pairing (see [`pair_wedges`]) for [`Engine::apply`].
    pub(super) fn plan(&mut self, u: u32, v: u32) -> Option<Plan> {
        let (ku, kv, material_edge) = pair_wedges(self.mesh, self.pairing, u, v)?;
        self.stats.pricings += 1;
        self.price(u, v, ku, kv, material_edge)
    }

    /// Places and prices the collapse `u → v` whose wedge pairing [`Pricing::plan`] just made;
    /// `material_edge`: the edge separates two materials.
    fn price(&mut self, u: u32, v: u32, ku: Kind, kv: Kind, material_edge: bool) -> Option<Plan> {
        let (ui, vi) = (u as usize, v as usize);
        let u_wedges = self.mesh.classes.wedges_of(u);
        let v_wedges = self.mesh.classes.wedges_of(v);

        // Two vertices of a border or seam line, corners included, merge into a free point too:
        // the line's penalty planes keep it near the line (at a corner, the two lines' planes
        // keep it near the corner), and off it only as far as the surface on both sides pays
        // for. Held on the edge instead, a coarse open plate is a chord through its border and
        // misses its bulge, and a corner moved onto its neighbour is cut off (parts.glb: animated
        // error 0.167 → 0.087 % at 228 triangles, bench/README). A material line keeps to its
        // edges: a colour outline shows before the shape does.
        //
        // An interior vertex onto a line vertex or a junction whose lines are all uv or colour
        // seams (no border, material line or crease: `on_outline`) merges at a free point too.
        // Such a seam splits attributes inside one continuous surface, so the merged point is
        // priced like an interior one, and the seam, whose wedges move together, goes along
        // (bench/README, 2026-11-26 evening: CesiumMan's 10 % level 0.063 → 0.050 % in the bind
        // pose, Fox's 72-triangle level 1.071 → 0.856 % under animation, though Fox's 144-triangle
        // Hausdorff distance rose). Onto an outline the survivor stays put: a border or crease that
        // moves changes the silhouette or the shading's edges, and letting it move raised
        // parts.glb's 228-triangle Hausdorff distance (1.02 %, meshoptimizer 0.81) and
        // RiggedSimple's 1 % level under animation by 47 %.

        let rules = self.costs.rules;
        let placement = match (self.costs.mode, ku, kv) {
            (CollapseMode::Full, Kind::Interior, Kind::Interior) => Placement::Free,
            (CollapseMode::Full, Kind::Line, Kind::Line) if material_edge => Placement::Segment,
            (CollapseMode::Full, Kind::Line | Kind::Corner, Kind::Line | Kind::Corner) if !material_edge => {
                if rules.has(Rule::LinesMergeFree) {
                    Placement::Free
                } else {
                    Placement::Segment
                }
            }
            (CollapseMode::Full, Kind::Interior, Kind::Line | Kind::Corner | Kind::Junction)
                if !self.mesh.on_outline[vi] && rules.has(Rule::SeamsMoveWithSurface) =>
            {
                Placement::Free
            }
            _ => Placement::Fixed,
        };
        let mut total = self.costs.total[ui];
        total += &self.costs.total[vi];
        let stride = self.costs.priced.stride();
        let sums_of = |w: u32| &self.costs.wedge_sums[w as usize * stride..(w as usize + 1) * stride];
        for (iv, &wv) in v_wedges.iter().enumerate() {
            let partner = self.pairing.v_partner[iv];
            let wu = if partner == NONE { NONE } else { u_wedges[partner as usize] };
            // HalfEdge: the survivor keeps its attributes. Full: merged wedges get the best
            // attributes; an unmerged wedge keeps its own unless it moves.
            let optimal =
                self.costs.mode == CollapseMode::Full && (wu != NONE || placement != Placement::Fixed);
            // Per channel `(Σ area·w·g, Σ area·w·d)` of the merged pair (or the lone wedge), and
            // the pair's area `α`.
            let sv = sums_of(wv);
            let su = if wu == NONE { &self.costs.zero_sums[..] } else { sums_of(wu) };
            let alpha = sv[0] + su[0];
            let channels = sv[1..]
                .chunks_exact(4)
                .zip(su[1..].chunks_exact(4))
                .map(|(v, u)| (DVec3::new(v[0] + u[0], v[1] + u[1], v[2] + u[2]), v[3] + u[3]));
            if optimal {
                if !(alpha > 0.0) {
                    continue;
                }
                // One division per wedge: 1 / (α w_j) = (1 / α) · (1 / w_j).
                let inverse_alpha = 1.0 / alpha;
                let mut optimum = Quadric::ZERO;
                for ((g, d), &inverse_weight) in channels.zip(&self.costs.inverse_weights) {
                    optimum.add_optimal_attribute(g, d, inverse_alpha * inverse_weight);
                }
                total.subtract(&optimum);
            } else {
                let own = &self.costs.wedge_attributes
                    [wv as usize * self.costs.channels..(wv as usize + 1) * self.costs.channels];
                for ((g, d), &(j, w)) in channels.zip(&self.costs.priced.priced) {
                    total.add_fixed_attribute(g, d, alpha * w as f64, own[j] as f64);
                }
            }
        }
        // Canonical order for the symmetric placements, so both directions agree bit for bit.
        let (lo, hi) = (self.mesh.position[u.min(v) as usize], self.mesh.position[u.max(v) as usize]);
        let p = match placement {
            Placement::Fixed => self.mesh.position[vi],
            Placement::Segment => total.minimize_on_segment(lo, hi),
            Placement::Free => match total.minimize() {
                // Beyond one edge length from the midpoint the minimiser has left the
                // neighbourhood: the quadric is nearly flat there and only extrapolates.
                Some(p) if (p - 0.5 * (lo + hi)).length() <= (hi - lo).length() => p,
                _ => total.minimize_on_segment(lo, hi),
            },
        };
        // The stored position is f32: price and check exactly the point that will be output.
        let p = p.as_vec3().as_dvec3();
        // The order key is the area-weighted error (see the module docs); the floor and the
        // recorded error are its mean over the pair's own area.
        let mut error = total.error(p).max(0.0);
        if let Some(x) = self.mesh.vanishing_corner(u, v) {
            error = error.max(self.vanishing_error(u, v, x));
        }
        let weight = if total.weight > 0.0 { total.weight } else { 1.0 };
        let (cost, mean_squared) = (self.costs.order_key(error, total.weight), error / weight);
        (cost.is_finite() && mean_squared.is_finite()).then_some(Plan {
            u,
            v,
            p,
            cost,
            mean_squared,
            placement,
        })
    }

    /// The area-weighted error of a part that vanishes when the sheet `u`, `v`, `x` collapses:
    /// its area (every surface merged into the sheet) times the mean squared clearance of the
    /// sheet's corners, their distance to the input's other parts (`clearance.rs`). An open
    /// part's last triangle (`u`, `v`, `x` on it alone) is priced otherwise, against the level
    /// ([`Pricing::open_part_vanishing_error`]). The plane quadric alone cannot see a part go: a sheet lies in its own planes, and a finger's side
    /// planes pass a point on its axis at half its thickness however long it is, so fingers
    /// vanished at robot.glb's 656-triangle level (4.1 % of the diagonal, Hausdorff). A part
    /// alone in its mesh is priced by the sheet's own spread instead (the mean squared distance
    /// of its corners from their centroid): it leaves nothing behind.
    /// Without [`Rule::OpenPartsWithinReach`] (`Floors::open_parts_within_reach`) or
    /// [`Rule::ClosedPartsByClearance`] a part of that kind costs nothing beyond its plane quadric.
    fn vanishing_error(&mut self, u: u32, v: u32, x: u32) -> f64 {
        let corners = [u, v, x].map(|c| self.mesh.position[c as usize]);
        let area: f64 = [u, v, x].iter().map(|&c| self.costs.geometric[c as usize].weight).sum();
        if self.mesh.lists.has_one(u) {
            return if self.floors.open_parts_within_reach {
                self.open_part_vanishing_error(u, v)
            } else {
                0.0
            };
        }
        if !self.costs.rules.has(Rule::ClosedPartsByClearance) {
            return 0.0;
        }
        let clearance: Option<f64> = [u, v, x]
            .iter()
            .zip(corners)
            .map(|(&c, at)| {
                self.floors
                    .clearance
                    .squared_to_other_parts(&self.mesh.classes, c, at.as_vec3())
                    .map(f64::from)
            })
            .sum();
        let mean_squared = clearance.map(|sum| sum / 3.0).unwrap_or_else(|| {
            let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
            corners.iter().map(|&c| c.distance_squared(centroid)).sum::<f64>() / 3.0
        });
        area * mean_squared
    }

    /// The error of an open part vanishing with its last triangle, `u`–`v`'s collapse: none
    /// beyond its plane quadric's once every point of the part lies within the distance the
    /// level has already left some input point from it ([`Floors::open_part_within`](super::floors::Floors::open_part_within)), so that
    /// its vanishing raises no distance the level has not reached. Until then the part waits
    /// for the level to reach as far as its farthest point found (`Engine::reach` prices it
    /// again), and its collapse is not queued; beyond the floor it never goes. Priced instead by
    /// its area times its corners' mean squared distance from the level, at any reach, parts
    /// went later and kept triangles a bigger part's collapse would have bought more with; let
    /// go at a discount at any reach, one plate of parts.glb left its points farther from the
    /// 114-triangle level than anything else (bench/README.md, 2026-11-27, last run).
    fn open_part_vanishing_error(&mut self, u: u32, v: u32) -> f64 {
        let floors = &mut self.floors;
        match floors.open_part_within(self.mesh, self.steps, u, floors.reached_distance) {
            Ok(()) => 0.0,
            Err(Some(farther)) => {
                floors.waiting.wait((u.min(v), u.max(v)), farther);
                f64::INFINITY
            }
            Err(None) => f64::INFINITY,
        }
    }
}

/// Pairs the wedges of `u` with those of `v` for the collapse `u → v`: into `pairing`, `u_pair`
/// (per wedge of `u`: index into `v`'s wedges), `u_seen` (the wedge is used by a live triangle)
/// and `v_partner` (per wedge of `v`: index into `u`'s wedges or NONE). Returns the kinds of `u`
/// and `v` and whether the edge separates two materials; `None` when the kinds forbid the
/// collapse, the classes no longer share an edge, or the pairing would tear a seam. (A function
/// of the parts, not a method of [`Pricing`], so that the compiler knows the pairing's writes
/// leave the mesh as it was.)
fn pair_wedges(mesh: &Mesh, pairing: &mut Pairing, u: u32, v: u32) -> Option<(Kind, Kind, bool)> {
    let (ui, vi) = (u as usize, v as usize);
    if u == v || !mesh.alive[ui] || !mesh.alive[vi] || mesh.kind[ui] == Kind::Locked {
        return None;
    }
    let u_wedges = mesh.classes.wedges_of(u);
    let v_wedges = mesh.classes.wedges_of(v);
    pairing.u_pair.clear();
    pairing.u_pair.resize(u_wedges.len(), NONE);
    pairing.u_seen.clear();
    pairing.u_seen.resize(u_wedges.len(), false);
    let ku = mesh.kind[ui];
    let kv = mesh.kind[vi];
    if ku == Kind::Interior && u_wedges.len() == 1 && v_wedges.len() == 1 {
        // The common case needs no scan: one wedge each pairs trivially, and an interior u
        // has no line to stay on. Whether the edge still exists is checked before applying.
        pairing.u_pair[0] = 0;
        pairing.u_seen[0] = true;
        pairing.v_partner.clear();
        pairing.v_partner.push(0);
        return Some((ku, kv, false));
    }
    let mut edge_triangles = 0;
    let mut first_side = (NONE, NONE, NONE);
    let mut constraint = false;
    let mut material_edge = false;
    for corner in mesh.lists.iter(u) {
        let wu = mesh.corner_wedge[corner as usize];
        let iu = u_wedges.iter().position(|&w| w == wu).unwrap_or(0);
        pairing.u_seen[iu] = true;
        let (n, p) = other_corners(corner);
        let v_corner = if mesh.class_at(n) == v {
            n
        } else if mesh.class_at(p) == v {
            p
        } else {
            continue;
        };
        edge_triangles += 1;
        let wv = mesh.corner_wedge[v_corner as usize];
        let iv = v_wedges.iter().position(|&w| w == wv).unwrap_or(0) as u32;
        if pairing.u_pair[iu] == NONE {
            pairing.u_pair[iu] = iv;
        } else if pairing.u_pair[iu] != iv {
            return None; // one wedge of u would have to follow two wedges of v
        }
        let material = mesh.materials.get(corner as usize / 3).copied().unwrap_or(0);
        if edge_triangles == 1 {
            first_side = (wu, wv, material);
        } else {
            constraint |= first_side != (wu, wv, material);
            material_edge |= first_side.2 != material;
        }
    }
    if edge_triangles == 0 || edge_triangles > 2 {
        return None;
    }
    constraint |= edge_triangles == 1;
    if ku.on_line() && !constraint {
        return None; // a line vertex collapses only along its line
    }
    // A junction may go along any edge: the pairing below admits it only when every wedge it
    // uses follows one wedge of v, so a seam end can move onto a neighbour (the seam then
    // ends there) but never merge the two sides of a seam.
    // Every used wedge of u needs its own wedge of v: no seam opens or closes.
    pairing.v_partner.clear();
    pairing.v_partner.resize(v_wedges.len(), NONE);
    for iu in 0..u_wedges.len() {
        if !pairing.u_seen[iu] {
            continue;
        }
        let iv = pairing.u_pair[iu];
        if iv == NONE || pairing.v_partner[iv as usize] != NONE {
            return None;
        }
        pairing.v_partner[iv as usize] = iu as u32;
    }
    Some((ku, kv, material_edge))
}
