//! Native build time of the articulated progressive mesh, for the benchmark's "native next to
//! wasm" column: `cargo run --release --example clod_timing -- FILE.glb|FILE.gltf...` prints one JSON line
//! per file: `{"file": ..., "triangles": ..., "ms": ..., "builds": ..., "phases": {...}}`.
//! `ms` is the best of at least three builds and of as many as fit in half a second (small
//! models build in a few milliseconds on a shared machine), with the level counts of
//! bench/lod-vs-meshoptimizer.mjs (50/25/10/5/1 %); `phases` splits that best build at the
//! build's progress reports: poses (set-up and multi-pose quadrics), simplify (collapses and
//! progressive mesh), back-propagation, and chain (levels, Tipsify, ancestor tables).
//! `--passes` builds with batched collapse passes instead of the strict one-at-a-time order.
//! `--bind` simplifies in the bind pose alone instead of the default multi-pose, to see what the
//! other poses cost.
//! `--without RULE` (repeatable) leaves out one of the simplifier's special rules
//! (`src/simplify/rules.rs`), to see what it costs.
//! `--counts` adds the collapse engine's counts of one build (`"counts": {...}`, see
//! `simplify::PricingStats`): collapses, exact pricings, and edges queued under a bound.

use std::path::Path;
use std::time::Instant;

use clod_viewer::clod::{self, ClodOptions, SimplificationPose};
use clod_viewer::import;
use clod_viewer::simplify::pricing_stats;
use clod_viewer::simplify::rules::Rules;
use clod_viewer::Schedule;

const FRACTIONS: [f64; 5] = [0.5, 0.25, 0.1, 0.05, 0.01];
const PHASE_MARKS: [f32; 5] = [0.0, 0.15, 0.8, 0.9, 1.0];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let passes = args.iter().any(|a| a == "--passes");
    let counts = args.iter().any(|a| a == "--counts");
    let bind = args.iter().any(|a| a == "--bind");
    let schedule = if passes { Schedule::Passes } else { Schedule::Strict };
    let mut rules = Rules::ALL;
    let mut files = Vec::new();
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        if arg == "--without" {
            let name = args.next().unwrap_or_default();
            let Some(rule) = Rules::parse(&name) else {
                eprintln!("unknown rule {name:?} (see src/simplify/rules.rs)");
                std::process::exit(2);
            };
            rules = rules.without(rule);
        } else if !arg.starts_with("--") {
            files.push(arg);
        }
    }
    if files.is_empty() {
        eprintln!(
            "usage: clod_timing [--passes] [--counts] [--bind] [--without RULE]... FILE.glb|FILE.gltf..."
        );
        std::process::exit(2);
    }
    for file in files {
        let character = match import::from_file(Path::new(&file)) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{file}: {e}");
                std::process::exit(1);
            }
        };
        let n = character.mesh.triangle_count();
        let levels = FRACTIONS.iter().map(|f| ((n as f64 * f).round() as usize).max(1)).collect();
        let mut options =
            ClodOptions { level_triangles: Some(levels), schedule, rules, ..ClodOptions::default() };
        if bind {
            options.pose = SimplificationPose::Bind;
        }
        let mut best = f64::INFINITY;
        let mut best_phases = Vec::new();
        let budget = Instant::now();
        let mut builds = 0;
        let mut one_build = None;
        while builds < 3 || budget.elapsed().as_secs_f64() < 0.5 {
            builds += 1;
            let started = Instant::now();
            // The phases end at these progress fractions (see `clod::build`); the simplifier's own
            // reports fall between 0.15 and 0.8.
            let mut marks = Vec::new();
            let before = pricing_stats();
            let built = clod::build(&character, &options, &mut |f| {
                if PHASE_MARKS.contains(&f) {
                    marks.push(started.elapsed());
                }
            })
            .expect("build");
            let ms = started.elapsed().as_secs_f64() * 1000.0;
            let after = pricing_stats();
            one_build.get_or_insert((
                after.collapses - before.collapses,
                after.pricings - before.pricings,
                after.bounds - before.bounds,
            ));
            if ms < best {
                best = ms;
                best_phases = marks.windows(2).map(|w| (w[1] - w[0]).as_secs_f64() * 1000.0).collect();
            }
            std::hint::black_box(built);
        }
        let phases: Vec<String> = ["poses", "simplify", "back_propagation", "chain"]
            .iter()
            .zip(&best_phases)
            .map(|(name, ms)| format!("\"{name}\": {ms:.2}"))
            .collect();
        let counts = match one_build {
            Some((collapses, pricings, bounds)) if counts => format!(
                ", \"counts\": {{\"collapses\": {collapses}, \"pricings\": {pricings}, \"bounds\": {bounds}}}"
            ),
            _ => String::new(),
        };
        println!(
            "{{\"file\": {file:?}, \"triangles\": {n}, \"ms\": {best:.2}, \"builds\": {builds}, \"phases\": {{{}}}{counts}}}",
            phases.join(", ")
        );
    }
}
