//! The collapse engine: quadric set-up, the order of position-edge collapses, the validity checks
//! (`checks.rs`), and the collapse itself, which appends to a [`CollapseLog`].
//!
//! The engine is six owned parts, each in its own file with its invariants, built in this order
//! from the input (`Engine::new`):
//! * `mesh.rs`, the mesh's topology and state: position classes and their kinds, corner lists,
//!   every corner's wedge and class, live triangles, positions, versions;
//! * `costs.rs`, what collapses are priced with: quadrics, wedge sums, priced channels;
//! * `order.rs`, the candidates in their order (the strict heap, the passes' candidates) and the
//!   classes parked by a failed check;
//! * `floors.rs`, the floors besides the error limit and what they remember: the distance floor,
//!   the clearance of parts (`clearance.rs`), how far the level has reached and the open parts
//!   waiting for it;
//! * `scratch.rs`, buffers one step fills and the next reuses;
//! * `record.rs`, the log, the wedges' vertex ids in it, and the counts (`stats.rs`).
//!
//! A run queues every edge, then loops: the schedule (`strict.rs` or `passes.rs`) picks a
//! candidate, and one step (`Engine::try_collapse`, `apply.rs`) re-plans it (`plan.rs`: pricing
//! reads the mesh and the costs and writes the pairing), holds it to the error limit, checks it
//! (`checks.rs`), holds it to the distance floor, and commits it (`apply.rs`), re-queueing the
//! edges it changed. Work that needs several parts borrows each as it needs it.
//!
//! A collapse `u → v` removes position class `u`; every wedge of `u` merges with the wedge of `v`
//! it shares the edge's triangles with (one edge collapse on positions merges every pair of wedges
//! along it), so seams stay closed. Placement ([`Placement`], `plan.rs`): the quadric minimiser
//! for interior–interior edges, for edges along a border or seam line, and for an interior vertex
//! onto a seam that is on no outline (a uv or colour seam inside a smooth surface, which moves
//! with it); the best point of the edge along a material line; `v`'s position for everything
//! else (onto a border, material line or crease, onto a locked vertex, and every half-edge
//! collapse). Planning and f64 pricing are in `plan.rs`.
//!
//! Cost. A collapse's quadric error is an area-weighted sum of squared distances (Garland &
//! Heckbert 1997: each face plane weighs its area), so it approximates the squared distance
//! integrated over the surface the collapse changes. Collapses are ordered by that integral, not
//! by its mean over the pair's area (the RMS distance, meshoptimizer's normalised error): at one
//! distance a small part goes before a large one, as the sampled surface distance the benchmarks
//! measure (a mean over the surface) would have it. Measured with
//! `bench/animated-vs-meshoptimizer.mjs` against the RMS order (animated error over the better
//! meshoptimizer, mean over levels; both orders against the benchmark's meshoptimizer input of
//! 2026-11-23, before it was compacted, so the ratios are stale and their comparison is not):
//! 0.10 → 0.08 on CesiumMan, 0.78 → 0.70 on Fox, 0.42 → 0.41 on
//! RiggedSimple, 0.67 → 0.55 on the built-in character and 1.52 → 1.25 on `parts.glb`, whose 57
//! open plates of different sizes now go down unevenly, large ones keeping more triangles. The
//! floor (`max_mean_squared_error`) and the recorded error stay RMS, so a level's error is still a distance.
//! A pair smaller than [`SMALL_PAIR`](costs::SMALL_PAIR) of the mean area is ordered as if it were that large, so a
//! small part does not go at several times the distance of the rest.
//! Since the order is not the RMS order, a collapse over the floor is skipped rather than ending
//! the run: the run ends when every collapse left is over it, as it did before. A second floor is
//! a distance ([`SimplifyOptions::max_distance`]): a collapse that would leave the input vertex
//! either end tracks (of those it stands for, the one left farthest from the surface) farther
//! than it from the triangles around the merged vertex is skipped the same way (`checks.rs`);
//! the RMS misses a small part cut short, a toe merged with its heel.
//!
//! Two orders ([`Schedule`]), both deterministic (every choice follows a total order on
//! (cost, u, v), u scrambled (`queue.rs`), and thresholds derived from the mesh state alone,
//! never from the target, so a run stopped at a target is a prefix of one that goes on; a
//! collapse over the error limit is skipped, never made, and a limited run is the unlimited
//! one's prefix up to the first such collapse):
//! * `strict.rs` (the default): one collapse at a time from a heap (`queue.rs`), always the
//!   cheapest; an edge is priced only when a lower bound of its cost reaches the top of the heap
//!   (`plan.rs`), which leaves the order as it is and skips four pricings in five;
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

mod apply;
mod checks;
mod costs;
mod floors;
mod mesh;
mod order;
mod passes;
mod plan;
mod record;
mod scratch;
mod stats;
mod strict;

pub use stats::{pricing_stats, PricingStats};

use super::queue::Candidate;
use super::{Schedule, SimplifyInput, SimplifyOptions};
use crate::progressive::CollapseLog;
use costs::Costs;
use floors::Floors;
use glam::DVec3;
use mesh::Mesh;
use order::Order;
use record::Record;
use scratch::Scratch;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Placement {
    /// The survivor keeps its position.
    Fixed,
    /// The best point of the edge: two line vertices of one material line, so that a colour
    /// outline stays where it is.
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
    /// The order key: the quadric error (area-weighted squared distance, position units² ×
    /// area) divided by the mean area of a collapsing pair, a constant of the mesh that only
    /// sets the scale (see the module docs).
    cost: f64,
    /// The quadric error divided by the pair's own area: its mean squared error (position
    /// units²), which the error floor and the collapse records use.
    mean_squared: f64,
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
    let (target, max_mean_squared_error) = (options.target_triangles, options.max_mean_squared_error);
    let stop = match options.schedule {
        Schedule::Passes => engine.collapse_in_passes(target, max_mean_squared_error, progress),
        Schedule::Strict => engine.collapse_until(target, max_mean_squared_error, progress),
    };
    let Record { mut log, mut stats, .. } = engine.record;
    log.stop = stop;
    stats.collapses = log.steps.len() as u64;
    stats::add(&stats);
    log
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
            // The last collapse may remove one triangle more than the target asks: still 1.
            progress(((self.start - live_triangles) as f32 / self.span as f32).min(1.0));
            self.next_report = self.next_report.saturating_sub(self.step);
        }
    }
}

/// The collapse engine: a few owned parts, each with its own module and invariants. Work that
/// needs several of them borrows each as it needs it: pricing reads the mesh and the costs and
/// writes the pairing (`Pricing` in `plan.rs`), the checks read the mesh and ask the floors
/// (`checks.rs`).
struct Engine<'a> {
    /// The mesh's topology and state (`mesh.rs`).
    mesh: Mesh<'a>,
    /// What collapses are priced with (`costs.rs`).
    costs: Costs,
    /// The candidates in their order, and the parked classes (`order.rs`).
    order: Order,
    /// The floors besides the error limit, and what they remember (`floors.rs`).
    floors: Floors<'a>,
    /// Buffers one step fills and the next reuses (`scratch.rs`).
    scratch: Scratch,
    /// The log, the wedges' vertex ids in it, and the counts (`record.rs`).
    record: Record,
}

impl<'a> Engine<'a> {
    /// Every part at the start of a run over `input`: no collapse made, nothing queued.
    fn new(input: &SimplifyInput<'a>, options: &SimplifyOptions) -> Engine<'a> {
        let (mesh, sides) = Mesh::new(input, options.normal_channel);
        let class_count = mesh.classes.count();
        Engine {
            costs: Costs::new(&mesh.classes, &sides, &mesh.input_normal, input, options),
            order: Order::new(options.schedule, class_count),
            floors: Floors::new(input, options, &mesh.classes),
            scratch: Scratch::new(class_count, input.attribute_weights.len()),
            record: Record::new(input),
            mesh,
        }
    }

    fn queue_all_edges(&mut self) {
        if self.order.schedule == Schedule::Strict {
            self.costs.relax_all(&self.mesh.classes);
        }
        let mut neighbours = std::mem::take(&mut self.scratch.neighbours);
        for c in 0..self.mesh.classes.count() as u32 {
            self.mesh.neighbours_into(c, &mut self.scratch.marks, &mut neighbours);
            neighbours.retain(|&x| c < x);
            match self.order.schedule {
                Schedule::Strict => {
                    self.order.queue_bounds(&self.mesh, &self.costs, &mut self.record.stats, c, &neighbours)
                }
                Schedule::Passes => {
                    for &x in &neighbours {
                        self.queue_edge(c, x, 0.0);
                    }
                }
            }
        }
        self.scratch.neighbours = neighbours;
    }

    /// Queues the valid collapses of edge `a`–`b`: one entry for a symmetric placement, else one
    /// per valid direction. `bound` is a lower bound of their costs that deferred this pricing
    /// (0 if none), checked in debug builds.
    fn queue_edge(&mut self, a: u32, b: u32, bound: f32) {
        if let Some(plan) = self.pricing().plan(a, b) {
            debug_assert!(plan.cost as f32 >= bound, "{a}-{b}: cost {} below its bound {bound}", plan.cost);
            self.order.push(&self.mesh, &plan);
            if plan.placement != Placement::Fixed {
                return;
            }
        }
        if let Some(plan) = self.pricing().plan(b, a) {
            debug_assert!(plan.cost as f32 >= bound, "{b}-{a}: cost {} below its bound {bound}", plan.cost);
            self.order.push(&self.mesh, &plan);
        }
    }

    /// Prices edge `a`–`b` again after a collapse changed it: at once in the strict order, at
    /// the end of the pass otherwise (in bulk, sorted, so the pricings walk memory in order).
    fn requeue(&mut self, a: u32, b: u32) {
        match self.order.schedule {
            Schedule::Strict => self.queue_edge(a, b, 0.0),
            Schedule::Passes => self.order.pending.push((a.min(b), a.max(b))),
        }
    }
}
