//! Process-wide counters of the collapse engine's work, for measurements (`examples/clod_timing.rs
//! --counts`): how many collapses it made and how many edges it priced exactly. A run counts in
//! its own [`PricingStats`] and adds it here once, when it ends, so counting costs nothing in the
//! loop. Concurrent runs (tests) add up.

use std::sync::atomic::{AtomicU64, Ordering};

/// Counts of one or more simplification runs (see [`pricing_stats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PricingStats {
    /// Collapses performed.
    pub collapses: u64,
    /// Exact f64 pricings of a collapse (initial, re-pricings, and the re-plan of every current
    /// entry before it is committed).
    pub pricings: u64,
    /// Edges queued under a lower bound of their cost instead of priced (the strict order's
    /// deferred re-pricing); those that reach the top are priced then and counted in `pricings`.
    pub bounds: u64,
}

static COLLAPSES: AtomicU64 = AtomicU64::new(0);
static PRICINGS: AtomicU64 = AtomicU64::new(0);
static BOUNDS: AtomicU64 = AtomicU64::new(0);

/// Adds one run's counts to the process-wide totals.
pub(super) fn add(run: &PricingStats) {
    COLLAPSES.fetch_add(run.collapses, Ordering::Relaxed);
    PRICINGS.fetch_add(run.pricings, Ordering::Relaxed);
    BOUNDS.fetch_add(run.bounds, Ordering::Relaxed);
}

/// The totals over every run of this process so far; the difference of two readings counts the
/// runs between them.
pub fn pricing_stats() -> PricingStats {
    PricingStats {
        collapses: COLLAPSES.load(Ordering::Relaxed),
        pricings: PRICINGS.load(Ordering::Relaxed),
        bounds: BOUNDS.load(Ordering::Relaxed),
    }
}
