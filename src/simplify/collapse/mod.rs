//! The collapse engine: quadric set-up, the order of position-edge collapses, the validity checks
//! (`checks.rs`), and the collapse itself, which appends to a [`CollapseLog`].
//!
//! A collapse `u → v` removes position class `u`; every wedge of `u` merges with the wedge of `v`
//! it shares the edge's triangles with (one edge collapse on positions merges every pair of wedges
//! along it), so seams stay closed. Placement ([`Placement`]): interior–interior edges get the
//! quadric minimiser, line–line edges (along a border, seam or material line) the best point of
//! the edge, everything else (corners, locked vertices, and every half-edge collapse) keeps `v`'s
//! position. Planning and f64 pricing are in `plan.rs`.
//!
//! Two orders ([`Schedule`]), both deterministic (every choice follows a total order on
//! (cost, u, v) and thresholds derived from the mesh state alone, never from the target or the
//! error limit, so a limited run is a prefix of an unlimited one):
//! * `strict.rs` (the default): one collapse at a time from a heap (`queue.rs`), always the
//!   cheapest;
//! * `passes.rs` (opt-in): batched passes in meshoptimizer's style — rank the priced
//!   candidates, commit the cheap ones in cost order with both ends locked for the rest of the
//!   pass, then re-price the edges the pass changed in bulk, in class order.
//!
//! Candidates are invalidated lazily by per-class version counters. A collapse that fails a
//! check marks both ends *parked* and remembers the edge at both; when a later collapse changes a
//! parked class's neighbourhood, its failed edges are priced again (its other entries are still
//! exact and stay).

// `!(x > limit)` is deliberate throughout: unlike `x <= limit` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod checks;
mod passes;
mod plan;
mod strict;

use super::channels::Channels;
use super::quadric::Quadric;
use super::queue::{Candidate, Queue};
use super::topology::{classify, other_corners, position_classes, CornerLists, Kind, PositionClasses, NONE};
use super::vertex_quadrics::{attribute_quadrics, geometric_quadrics};
use super::{CollapseMode, Schedule, SimplifyInput, SimplifyOptions, StopReason};
use crate::progressive::{CollapseLog, RawCornerChange, RawStep};
use glam::{DVec3, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Placement {
    /// The survivor keeps its position.
    Fixed,
    /// The best point of the edge (both ends on one constraint line).
    Segment,
    /// The quadric minimiser, or the best point of the edge when that is singular or far away.
    Free,
}

/// A collapse of class `u` into class `v` at position `p`.
#[derive(Clone, Copy, Debug)]
struct Plan {
    u: u32,
    v: u32,
    p: DVec3,
    cost: f64,
    placement: Placement,
}

/// How often a run reports progress: often enough for a smooth progress bar, rarely enough that
/// the calls (into JavaScript, in the browser's worker) cost nothing measurable.
pub(crate) const PROGRESS_STEPS: usize = 50;

/// Runs the whole simplification on validated input.
/// `progress` receives the fraction of the triangles to remove that are gone, rising, at most
/// [`PROGRESS_STEPS`] times.
pub(crate) fn run(
    input: &SimplifyInput,
    options: &SimplifyOptions,
    progress: &mut dyn FnMut(f32),
) -> CollapseLog {
    let mut engine = Engine::new(input, options);
    engine.queue_all_edges();
    let (target, max_error) = (options.target_triangles, options.max_error);
    let stop = match options.schedule {
        Schedule::Passes => engine.collapse_in_passes(target, max_error, progress),
        Schedule::Strict => engine.collapse_until(target, max_error, progress),
    };
    engine.log.stop = stop;
    engine.log
}

/// Reports progress at most [`PROGRESS_STEPS`] times as the live triangle count falls towards the
/// target.
struct Progress {
    start: usize,
    span: usize,
    step: usize,
    next_report: usize,
}

impl Progress {
    fn new(start: usize, target: usize) -> Progress {
        let span = start.saturating_sub(target).max(1);
        let step = span.div_ceil(PROGRESS_STEPS).max(1);
        Progress { start, span, step, next_report: start.saturating_sub(step) }
    }

    fn update(&mut self, live_triangles: usize, progress: &mut dyn FnMut(f32)) {
        if live_triangles <= self.next_report {
            progress((self.start - live_triangles) as f32 / self.span as f32);
            self.next_report = self.next_report.saturating_sub(self.step);
        }
    }
}

/// Low 16 bits of both versions.
fn stamp(version_u: u32, version_v: u32) -> u32 {
    (version_u & 0xFFFF) | (version_v << 16)
}

struct Engine<'a> {
    /// The priced attribute channels (see [`Channels`]).
    priced: Channels,
    /// `1 / weight` per priced channel.
    inverse_weights: Vec<f64>,
    /// Wedge sums of nothing: the partner of a wedge that merges with none.
    zero_sums: Vec<f64>,
    materials: &'a [u32],
    mode: CollapseMode,
    channels: usize,
    normal_channel: Option<usize>,
    // Static structure.
    classes: PositionClasses,
    kind: Vec<Kind>,
    input_normal: Vec<DVec3>,
    // Mesh state.
    lists: CornerLists,
    corner_wedge: Vec<u32>,
    triangle_alive: Vec<bool>,
    live_triangles: usize,
    position: Vec<DVec3>,
    /// Geometric quadric per class (face and penalty planes).
    geometric: Vec<Quadric>,
    /// Geometric plus attribute quadric per class; its weight is the geometric weight.
    total: Vec<Quadric>,
    /// Per wedge: `[Σ area, then per priced channel Σ area·w·g (3), Σ area·w·d]`, stride
    /// `priced.stride()`.
    wedge_sums: Vec<f64>,
    wedge_attributes: Vec<f32>,
    vertex_id: Vec<u32>,
    alive: Vec<bool>,
    version: Vec<u32>,
    /// Per class, the head of its list of failed partners in `failed` (NONE: not parked).
    failed_head: Vec<u32>,
    /// Failed-edge records: (partner class, next record or NONE).
    failed: Vec<(u32, u32)>,
    // Order.
    schedule: Schedule,
    /// The heap of [`Schedule::Strict`].
    queue: Queue,
    /// Queue length after the last purge of stale entries.
    purged_length: usize,
    /// The priced candidates of [`Schedule::Passes`], in no particular order between passes.
    candidates: Vec<Candidate>,
    /// Edges (lower class first) to price at the end of the pass.
    pending: Vec<(u32, u32)>,
    /// Scratch of the pass threshold: the candidates' cost bits.
    keys: Vec<u32>,
    // Scratch (reused, never reallocated once grown).
    mark: Vec<u32>,
    stamp: u32,
    u_pair: Vec<u32>,
    u_seen: Vec<bool>,
    v_partner: Vec<u32>,
    neighbours: Vec<u32>,
    second_neighbours: Vec<u32>,
    new_attributes: Vec<f32>,
    log: CollapseLog,
}

impl<'a> Engine<'a> {
    fn new(input: &SimplifyInput<'a>, options: &SimplifyOptions) -> Engine<'a> {
        let positions = input.positions;
        let indices = input.indices;
        let m = input.attribute_weights.len();
        let triangle_count = indices.len() / 3;
        let classes = position_classes(positions, indices);
        let class_count = classes.count();
        let lists = CornerLists::new(|k| classes.class_of[indices[k] as usize], indices.len(), class_count);
        let (kind, sides) = classify(&classes, positions, &lists, indices, input.triangle_materials);
        let position: Vec<DVec3> =
            classes.representative.iter().map(|&v| positions[v as usize].as_dvec3()).collect();
        let corner_point = |corner: usize| positions[indices[corner] as usize].as_dvec3();
        let input_normal: Vec<DVec3> = (0..triangle_count)
            .map(|t| {
                let (p0, p1, p2) = (corner_point(3 * t), corner_point(3 * t + 1), corner_point(3 * t + 2));
                (p1 - p0).cross(p2 - p0).normalize_or_zero()
            })
            .collect();

        let geometric = geometric_quadrics(&classes, input, &sides, &input_normal);
        let priced = Channels::new(input.attributes, input.attribute_weights);
        let (appearance, wedge_sums) = attribute_quadrics(&classes, input, &priced);
        let mut total = geometric.clone();
        for (t, a) in total.iter_mut().zip(&appearance) {
            *t += a;
        }

        let n = positions.len();
        let log = CollapseLog {
            positions: positions.to_vec(),
            attributes: input.attributes.to_vec(),
            parent: vec![NONE; n],
            born_at: vec![0; n],
            survivor_source: vec![NONE; n],
            triangle_death: vec![NONE; triangle_count],
            corner_changes: Vec::new(),
            steps: Vec::new(),
            stop: StopReason::NoValidCollapse,
        };
        Engine {
            inverse_weights: priced.priced.iter().map(|&(_, w)| 1.0 / w as f64).collect(),
            zero_sums: vec![0.0; priced.stride()],
            priced,
            materials: input.triangle_materials,
            mode: options.mode,
            channels: m,
            normal_channel: options.normal_channel,
            kind,
            input_normal,
            lists,
            corner_wedge: indices.to_vec(),
            triangle_alive: vec![true; triangle_count],
            live_triangles: triangle_count,
            position,
            geometric,
            total,
            wedge_sums,
            wedge_attributes: input.attributes.to_vec(),
            vertex_id: (0..n as u32).collect(),
            alive: vec![true; class_count],
            version: vec![0; class_count],
            failed_head: vec![NONE; class_count],
            failed: Vec::new(),
            schedule: options.schedule,
            queue: Queue::default(),
            purged_length: 0,
            candidates: Vec::new(),
            pending: Vec::new(),
            keys: Vec::new(),
            mark: vec![0; class_count],
            stamp: 0,
            u_pair: Vec::new(),
            u_seen: Vec::new(),
            v_partner: Vec::new(),
            neighbours: Vec::new(),
            second_neighbours: Vec::new(),
            new_attributes: vec![0.0; m],
            log,
            classes,
        }
    }

    #[inline]
    fn class_at(&self, corner: u32) -> u32 {
        self.classes.class_of[self.corner_wedge[corner as usize] as usize]
    }

    fn next_stamp(&mut self) -> u32 {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
        self.stamp
    }

    /// The distinct neighbour classes of `c`, into `out` (cleared first).
    fn neighbours_into(&mut self, c: u32, out: &mut Vec<u32>) {
        out.clear();
        let stamp = self.next_stamp();
        self.mark[c as usize] = stamp;
        for corner in self.lists.iter(c) {
            let (n, p) = other_corners(corner);
            for x in [self.classes.class_of[self.corner_wedge[n as usize] as usize], self.class_at(p)] {
                if self.mark[x as usize] != stamp {
                    self.mark[x as usize] = stamp;
                    out.push(x);
                }
            }
        }
    }

    /// The version stamp of a candidate `u → v`.
    fn stamp_of(&self, u: u32, v: u32) -> u32 {
        stamp(self.version[u as usize], self.version[v as usize])
    }

    fn queue_all_edges(&mut self) {
        let mut neighbours = std::mem::take(&mut self.neighbours);
        for c in 0..self.classes.count() as u32 {
            self.neighbours_into(c, &mut neighbours);
            for &x in &neighbours {
                if c < x {
                    self.queue_edge(c, x);
                }
            }
        }
        self.neighbours = neighbours;
    }

    fn push(&mut self, plan: &Plan) {
        let (u, v) = (plan.u, plan.v);
        let (u, v) = if matches!(plan.placement, Placement::Fixed) {
            (u, v)
        } else {
            // Symmetric placements: both directions give the same point and cost; the end nearer
            // the new point survives (it keeps its skin weights), ties to the lower class id.
            let du = (plan.p - self.position[u as usize]).length_squared();
            let dv = (plan.p - self.position[v as usize]).length_squared();
            if du < dv || (du == dv && u < v) {
                (v, u)
            } else {
                (u, v)
            }
        };
        let candidate = Candidate::new(plan.cost as f32, u, v, self.stamp_of(u, v));
        match self.schedule {
            Schedule::Passes => self.candidates.push(candidate),
            Schedule::Strict => self.queue.push(candidate),
        }
    }

    /// Queues the valid collapses of edge `a`–`b`: one entry for a symmetric placement, else one
    /// per valid direction.
    fn queue_edge(&mut self, a: u32, b: u32) {
        if let Some(plan) = self.plan(a, b) {
            self.push(&plan);
            if plan.placement != Placement::Fixed {
                return;
            }
        }
        if let Some(plan) = self.plan(b, a) {
            self.push(&plan);
        }
    }

    /// Prices edge `a`–`b` again after a collapse changed it: at once in the strict order, at
    /// the end of the pass otherwise (in bulk, sorted, so the pricings walk memory in order).
    fn requeue(&mut self, a: u32, b: u32) {
        match self.schedule {
            Schedule::Strict => self.queue_edge(a, b),
            Schedule::Passes => self.pending.push((a.min(b), a.max(b))),
        }
    }

    /// Performs a planned (and checked) collapse; `plan` must be the latest [`Engine::plan`]
    /// call, whose pairing scratch it uses.
    fn apply(&mut self, plan: &Plan) {
        let (u, v, p) = (plan.u, plan.v, plan.p);
        let (ui, vi) = (u as usize, v as usize);
        let step = self.log.steps.len() as u32 + 1;
        let m = self.channels;
        let stride = self.priced.stride();
        let moved = p != self.position[vi];
        let first_new = self.log.positions.len() as u32;
        let u_range = self.classes.wedge_start[ui] as usize..self.classes.wedge_start[ui + 1] as usize;
        let v_range = self.classes.wedge_start[vi] as usize..self.classes.wedge_start[vi + 1] as usize;

        // New vertices: one per merged wedge pair, and one per unmerged wedge of v that moves.
        let pv = self.position[vi];
        let pu = self.position[ui];
        let edge = pu - pv;
        let t = if edge.length_squared() > 0.0 {
            ((p - pv).dot(edge) / edge.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        for (iv, k) in v_range.clone().enumerate() {
            let wv = self.classes.wedges[k] as usize;
            let partner = self.v_partner[iv];
            let wu = if partner == NONE {
                usize::MAX
            } else {
                self.classes.wedges[u_range.start + partner as usize] as usize
            };
            if wu == usize::MAX && !moved {
                continue;
            }
            if wu != usize::MAX {
                for k in 0..stride {
                    self.wedge_sums[wv * stride + k] += self.wedge_sums[wu * stride + k];
                }
            }
            for j in 0..m {
                let own = self.wedge_attributes[wv * m + j];
                let priced = self.priced.source[j];
                let w = priced.map_or(0.0, |k| self.priced.priced[k].1 as f64);
                let alpha_w = self.wedge_sums[wv * stride] * w;
                let value = if self.mode == CollapseMode::HalfEdge {
                    own
                } else if let (Some(k), true) = (priced, alpha_w > 0.0) {
                    let base = wv * stride + 1 + 4 * k;
                    let g = DVec3::new(
                        self.wedge_sums[base],
                        self.wedge_sums[base + 1],
                        self.wedge_sums[base + 2],
                    );
                    ((g.dot(p) + self.wedge_sums[base + 3]) / alpha_w) as f32
                } else if wu != usize::MAX {
                    let other = self.wedge_attributes[wu * m + j];
                    (own as f64 + (other as f64 - own as f64) * t) as f32
                } else {
                    own
                };
                self.new_attributes[j] = value;
            }
            if let (Some(c), CollapseMode::Full) = (self.normal_channel, self.mode) {
                let normal = Vec3::from_slice(&self.new_attributes[c..c + 3]).normalize_or_zero();
                if normal != Vec3::ZERO {
                    self.new_attributes[c..c + 3].copy_from_slice(&normal.to_array());
                }
            }
            let id = self.log.positions.len() as u32;
            self.log.positions.push(p.as_vec3());
            self.log.attributes.extend_from_slice(&self.new_attributes);
            self.log.parent.push(NONE);
            self.log.born_at.push(step);
            self.log.survivor_source.push(self.vertex_id[wv]);
            self.log.parent[self.vertex_id[wv] as usize] = id;
            if wu != usize::MAX {
                self.log.parent[self.vertex_id[wu] as usize] = id;
            }
            self.vertex_id[wv] = id;
            self.wedge_attributes[wv * m..wv * m + m].copy_from_slice(&self.new_attributes);
        }
        let new_count = self.log.positions.len() as u32 - first_new;
        // Wedges of u that no live triangle uses any more end here too.
        for (iu, k) in u_range.clone().enumerate() {
            let wu = self.classes.wedges[k] as usize;
            if !self.u_seen[iu] && new_count > 0 {
                self.log.parent[self.vertex_id[wu] as usize] = first_new;
            }
        }

        // Triangles: those on the edge die, the others move their u corner to v's wedge.
        let mut thirds = [NONE; 2];
        let mut dead = 0;
        for corner in self.lists.iter(u) {
            let ci = corner as usize;
            let (n, pc) = other_corners(corner);
            let (a, b) = (
                self.classes.class_of[self.corner_wedge[n as usize] as usize],
                self.classes.class_of[self.corner_wedge[pc as usize] as usize],
            );
            if a == v || b == v {
                self.triangle_alive[ci / 3] = false;
                self.log.triangle_death[ci / 3] = step;
                self.live_triangles -= 1;
                if dead < 2 {
                    thirds[dead] = if a == v { b } else { a };
                }
                dead += 1;
                continue;
            }
            let wu = self.corner_wedge[ci];
            let iu = self.classes.wedges[u_range.clone()].iter().position(|&w| w == wu).unwrap_or(0);
            let wv = self.classes.wedges[v_range.start + self.u_pair[iu] as usize];
            self.corner_wedge[ci] = wv;
            self.log.corner_changes.push(RawCornerChange {
                corner,
                from_vertex: self.vertex_id[wu as usize],
                to_vertex: self.vertex_id[wv as usize],
            });
        }
        self.lists.splice(u, v);
        let alive = &self.triangle_alive;
        self.lists.retain(v, |c| alive[c as usize / 3]);
        for x in thirds.into_iter().filter(|&x| x != NONE && x != u && x != v) {
            self.lists.retain(x, |c| alive[c as usize / 3]);
        }

        // Class state.
        let mut geometric = self.geometric[ui];
        geometric += &self.geometric[vi];
        let weight = if geometric.weight > 0.0 { geometric.weight } else { 1.0 };
        let distance = (geometric.error(p).max(0.0) / weight).sqrt();
        self.geometric[vi] = geometric;
        let tu = self.total[ui];
        self.total[vi] += &tu;
        self.position[vi] = p;
        // The survivor of a junction inherits its line ends or meeting lines: it stays put from
        // now on and collapses only under the junction rules (a stale interior or line kind
        // would let it drag those lines freely).
        if self.kind[ui] == Kind::Junction && self.kind[vi] != Kind::Locked {
            self.kind[vi] = Kind::Junction;
        }
        self.alive[ui] = false;
        self.version[ui] = self.version[ui].wrapping_add(1);
        self.version[vi] = self.version[vi].wrapping_add(1);
        self.failed_head[vi] = NONE; // every edge of v is queued again below
        self.log.steps.push(RawStep {
            cost: plan.cost,
            distance,
            triangles_after: self.live_triangles as u32,
            first_new_vertex: first_new,
            new_vertex_count: new_count,
            corner_changes_end: self.log.corner_changes.len() as u32,
        });

        // Re-queue: every edge of v, the failed edges of a parked neighbour (they may pass now),
        // and the edges of a neighbour whose plan this collapse may have changed.
        //
        // A plan along x–y (neither v) pairs the wedges of x and y at their corners in the
        // triangles beside the edge, and needs every wedge of the moving end that a live triangle
        // uses to follow one. This collapse changed no corner of x or y (only corners of u, now
        // v) and removed triangles only at the thirds, so x–y changed only when x or y is a third
        // (one of its wedges may have fallen out of use). A third's edges are priced again when
        // it is a junction or parked, whose plans depend on that (and had been, before this rule:
        // every edge of every junction and parked neighbour); every other queued entry is still
        // exact and stays.
        let mut neighbours = std::mem::take(&mut self.neighbours);
        let mut second = std::mem::take(&mut self.second_neighbours);
        self.neighbours_into(v, &mut neighbours);
        let is_third = |x: u32| x == thirds[0] || x == thirds[1];
        for &x in &neighbours {
            let xi = x as usize;
            let parked = self.failed_head[xi] != NONE;
            if !parked && self.kind[xi] != Kind::Junction {
                continue;
            }
            if is_third(x) {
                self.failed_head[xi] = NONE;
                self.version[xi] = self.version[xi].wrapping_add(1);
                self.neighbours_into(x, &mut second);
                for &y in &second {
                    if y != v {
                        self.requeue(x, y);
                    }
                }
                continue;
            }
            self.neighbours_into(x, &mut second);
            let stamp = self.next_stamp();
            let mut record = std::mem::replace(&mut self.failed_head[xi], NONE);
            while record != NONE {
                let (partner, next) = self.failed[record as usize];
                self.mark[partner as usize] = stamp;
                record = next;
            }
            for &y in &second {
                if y != v && (is_third(y) || self.mark[y as usize] == stamp) {
                    self.requeue(x, y);
                }
            }
        }
        for &x in &neighbours {
            self.requeue(v, x);
        }
        self.neighbours = neighbours;
        self.second_neighbours = second;
    }
}
