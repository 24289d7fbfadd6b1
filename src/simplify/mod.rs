//! Quadric-error edge-collapse simplification that records a progressive mesh.
//!
//! The pipeline, in file order:
//! 1. [`simplify`] validates the explicit input arrays ([`SimplifyInput`]);
//! 2. `topology` groups vertices into position classes (wedges sharing a position, Hoppe 1999),
//!    builds per-class corner lists and classifies every class as interior, line (on a border,
//!    material border or attribute seam) or locked;
//! 3. `channels` picks the attribute channels worth pricing (constant ones carry no error,
//!    duplicates are priced once), and `vertex_quadrics` builds the initial quadrics:
//!    area-weighted face planes (Garland & Heckbert 1997) or the caller's, penalty planes along
//!    constraint edges, and Hoppe's (1999) attribute quadrics per wedge;
//! 4. `collapse` collapses position edges strictly cheapest first from a heap (or, as an option,
//!    in batched passes of rising cost: [`Schedule`]), rejecting collapses that break the link
//!    condition, tear seams, merge constraint lines, or fold triangles; a closed part may go away
//!    whole, priced by its distance to the other parts (`clearance`);
//! 5. [`crate::progressive`] turns the collapse log into a [`ProgressiveMesh`] (Hoppe 1996): a
//!    collapse forest over vertex ids with a prefix order on triangles and vertex slots.
//!
//! Units: positions in the caller's units; errors are mean squared distances (position units²),
//! reported distances are their square roots.

mod channels;
mod clearance;
mod collapse;
pub mod quadric;
mod queue;
pub mod rules;
mod topology;
mod vertex_quadrics;

pub use collapse::{pricing_stats, PricingStats};
pub use quadric::Quadric;
pub use rules::{Rule, Rules};

use crate::progressive::ProgressiveMesh;
pub use crate::progressive::StopReason;
use glam::Vec3;

/// The mesh to simplify, as explicit arrays.
#[derive(Clone, Copy, Debug)]
pub struct SimplifyInput<'a> {
    /// Vertex positions: the space where placement and fold checks happen.
    pub positions: &'a [Vec3],
    /// `attribute_weights.len()` floats per vertex (normal xyz, uv, rgba, …); may be empty.
    pub attributes: &'a [f32],
    /// Weight of each attribute channel: a channel contributes `weight × area × (difference)²`
    /// to a vertex's error, so `weight` converts attribute units² into position units². `0`
    /// disables a channel (its values are then interpolated along the collapsed edge).
    pub attribute_weights: &'a [f32],
    /// Triangle list.
    pub indices: &'a [u32],
    /// One material id per triangle (or empty for a single material). Edges between triangles
    /// of different materials are kept like mesh borders.
    pub triangle_materials: &'a [u32],
    /// If given, the geometric (plane) quadric of each vertex, replacing the area-weighted face
    /// quadrics built from `positions`; quadrics of vertices that share a position are summed.
    /// Each should cover the triangles that use its vertex, e.g. by adding
    /// [`Quadric::from_triangle`] of every triangle to each of its three corners. `weight` should
    /// be the summed area: errors are divided by it.
    pub vertex_quadrics: Option<&'a [Quadric]>,
}

/// Where a collapsed edge's surviving vertex goes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CollapseMode {
    /// Optimal placement: the minimiser of the summed quadric (geometry and attributes), and new
    /// attributes from the attribute quadrics. Vertices on borders, seams and material borders
    /// collapse only along them, held near them by penalty planes; a collapse onto a corner,
    /// junction or locked vertex keeps that vertex's position.
    #[default]
    Full,
    /// The survivor keeps its position and attributes: every level uses a subset of the input
    /// positions.
    HalfEdge,
}

/// The order in which collapses are chosen. Both are deterministic; a run stopped by the target
/// is a prefix of the untargeted run, and a run with an error limit is the unlimited run's prefix
/// up to its first collapse over the limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Schedule {
    /// Always the cheapest valid collapse next, from a heap with lazy invalidation.
    #[default]
    Strict,
    /// Batched passes (meshoptimizer's scheme): each pass commits the candidates up to 1.5× its
    /// k-th cheapest cost, in cost order, with the ends of every collapse locked until the pass
    /// ends, then re-prices the changed edges in bulk. Collapse costs are not monotone (their
    /// running maximum is). Not the default: since `Strict` prices an edge only when a lower
    /// bound of its cost comes up, passes are no faster (the whole build 0.84–1.25× `Strict`'s
    /// time by model, `bench/README.md`), and their animated error is higher. Committing each
    /// pass in class (memory) order rather than cost order made the built-in character's
    /// simplification 1.3× faster natively (205 → 155 ms, `clod_timing`, best of five
    /// interleaved runs) but lost a level each on CesiumMan, robot.glb and parts.glb against
    /// meshoptimizer (`bench/animated-vs-meshoptimizer.mjs --short`); with the goal at 1.2× the
    /// k-th cost it was no faster than `Strict` (2026-11-29).
    Passes,
}

/// Parameters of [`simplify`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimplifyOptions {
    /// Vertex placement.
    ///
    /// Default value: [`CollapseMode::Full`].
    pub mode: CollapseMode,
    /// Stop once at most this many triangles are left; `0` simplifies as far as possible.
    ///
    /// Default value: `0`.
    pub target_triangles: usize,
    /// Make no collapse whose mean squared error (over the area of its two classes, position
    /// units²) exceeds this: such collapses are skipped, and the run ends when only they (and
    /// those [`SimplifyOptions::max_distance`] skips) are left.
    ///
    /// Default value: `f32::INFINITY`.
    pub max_mean_squared_error: f32,
    /// Make no collapse that leaves a tracked input vertex farther than this (position units)
    /// from the triangles around the merged vertex. Each position class tracks one input vertex,
    /// of those it stands for the one left farthest from the surface (its own until its first
    /// collapse), so this is a heuristic, not a bound on every input vertex; a part that goes
    /// away whole is not held by it. The mean squared error misses a small part cut short (the
    /// toe of a sliver foot merged with its heel); this does not.
    ///
    /// Default value: `f32::INFINITY`.
    pub max_distance: f32,
    /// First of three attribute channels holding a normal, renormalised after interpolation.
    ///
    /// Default value: `None`.
    pub normal_channel: Option<usize>,
    /// The order of collapses.
    ///
    /// Default value: [`Schedule::Strict`].
    pub schedule: Schedule,
    /// The special rules the engine applies (see [`rules`]); leaving one out is for measuring
    /// what it pays.
    ///
    /// Default value: [`Rules::ALL`].
    pub rules: Rules,
}

impl Default for SimplifyOptions {
    fn default() -> Self {
        SimplifyOptions {
            mode: CollapseMode::Full,
            target_triangles: 0,
            max_mean_squared_error: f32::INFINITY,
            max_distance: f32::INFINITY,
            normal_channel: None,
            schedule: Schedule::Strict,
            rules: Rules::ALL,
        }
    }
}

/// Invalid input to [`simplify`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SimplifyError {
    #[error("the index count {0} is not a multiple of 3")]
    IndexCount(usize),
    #[error("index {index} (triangle {triangle}) is out of range for {vertex_count} vertices")]
    IndexOutOfRange { index: u32, triangle: usize, vertex_count: usize },
    #[error("too many vertices or triangles: {0} (the limit is 2^30)")]
    TooLarge(usize),
    #[error("position of vertex {0} is not finite")]
    NonFinitePosition(usize),
    #[error(
        "{found} attribute floats given, but {vertex_count} vertices × {channels} channels need {expected}"
    )]
    AttributeLength { found: usize, vertex_count: usize, channels: usize, expected: usize },
    #[error("attribute {0} is not finite")]
    NonFiniteAttribute(usize),
    #[error("attribute weight {0} is negative or not finite")]
    BadAttributeWeight(usize),
    #[error("{found} triangle materials given for {triangles} triangles")]
    MaterialCount { found: usize, triangles: usize },
    #[error("{found} vertex quadrics given for {vertices} vertices")]
    QuadricCount { found: usize, vertices: usize },
    #[error("vertex quadric {0} has a coefficient that is not finite")]
    NonFiniteQuadric(usize),
    #[error("normal channel {channel} needs channels {channel}..{channel}+3 but there are {channels}")]
    NormalChannel { channel: usize, channels: usize },
}

/// Simplifies a mesh by quadric-error edge collapses, recording every collapse.
///
/// The result can be rebuilt at any number of collapses (see [`ProgressiveMesh`]); refining it
/// fully gives back the input triangles. Unreferenced vertices stay in the vertex list but take
/// part in nothing. The result is deterministic: every choice of the collapse order follows a
/// total order on (cost, vertex ids) and thresholds taken from the mesh state (see [`Schedule`]).
///
/// # Errors
/// Any [`SimplifyError`]: inconsistent array lengths, out-of-range indices, non-finite values,
/// more than 2^30 vertices or triangles.
pub fn simplify(input: &SimplifyInput, options: &SimplifyOptions) -> Result<ProgressiveMesh, SimplifyError> {
    simplify_with_progress(input, options, &mut |_| {})
}

/// [`simplify`], calling `progress` with the fraction (0..1, rising) of the triangles to remove
/// that are gone, about fifty times over a run.
///
/// # Errors
/// As [`simplify`].
pub fn simplify_with_progress(
    input: &SimplifyInput,
    options: &SimplifyOptions,
    progress: &mut dyn FnMut(f32),
) -> Result<ProgressiveMesh, SimplifyError> {
    validate(input, options)?;
    let log = collapse::run(input, options, progress);
    Ok(ProgressiveMesh::from_log(log, input.indices, input.attribute_weights.len(), input.positions.len()))
}

fn validate(input: &SimplifyInput, options: &SimplifyOptions) -> Result<(), SimplifyError> {
    const LIMIT: usize = 1 << 30;
    let n = input.positions.len();
    if n > LIMIT {
        return Err(SimplifyError::TooLarge(n));
    }
    if input.indices.len() % 3 != 0 {
        return Err(SimplifyError::IndexCount(input.indices.len()));
    }
    let triangles = input.indices.len() / 3;
    if triangles > LIMIT {
        return Err(SimplifyError::TooLarge(triangles));
    }
    if let Some(k) = input.indices.iter().position(|&i| i as usize >= n) {
        return Err(SimplifyError::IndexOutOfRange {
            index: input.indices[k],
            triangle: k / 3,
            vertex_count: n,
        });
    }
    if let Some(v) = input.positions.iter().position(|p| !p.is_finite()) {
        return Err(SimplifyError::NonFinitePosition(v));
    }
    let channels = input.attribute_weights.len();
    let expected = n * channels;
    if input.attributes.len() != expected {
        return Err(SimplifyError::AttributeLength {
            found: input.attributes.len(),
            vertex_count: n,
            channels,
            expected,
        });
    }
    if let Some(k) = input.attributes.iter().position(|a| !a.is_finite()) {
        return Err(SimplifyError::NonFiniteAttribute(k));
    }
    if let Some(k) = input.attribute_weights.iter().position(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(SimplifyError::BadAttributeWeight(k));
    }
    if !input.triangle_materials.is_empty() && input.triangle_materials.len() != triangles {
        return Err(SimplifyError::MaterialCount { found: input.triangle_materials.len(), triangles });
    }
    if let Some(quadrics) = input.vertex_quadrics {
        if quadrics.len() != n {
            return Err(SimplifyError::QuadricCount { found: quadrics.len(), vertices: n });
        }
        let finite = |q: &Quadric| q.a.iter().chain(&q.b).chain([&q.c, &q.weight]).all(|x| x.is_finite());
        if let Some(v) = quadrics.iter().position(|q| !finite(q)) {
            return Err(SimplifyError::NonFiniteQuadric(v));
        }
    }
    if let Some(channel) = options.normal_channel {
        if channel.checked_add(3).is_none_or(|end| end > channels) {
            return Err(SimplifyError::NormalChannel { channel, channels });
        }
    }
    Ok(())
}
