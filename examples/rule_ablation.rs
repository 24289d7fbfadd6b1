//! What each of the simplifier's special rules pays (`src/simplify/rules.rs`): builds every file's
//! default chain (multi-pose, the default levels) with every rule, then once without each rule, and
//! prints per variant the animated error at the default chain's levels, how far the levels go, and
//! the build time. `cargo run --release --features wasm-math --example rule_ablation -- [--rule NAME]...
//! FILE.glb|FILE.gltf...` (`--rule` limits the variants to those rules).
//!
//! Animated error as `examples/animated_error.rs` measures it (the benchmark's numbers): each level
//! skinned at `t = duration · (f + 0.5) / 4` of the first two clips and compared with the full mesh
//! skinned at the same frame, symmetric sampled surface distance (5,000 samples, seed 12345), in %
//! of the bind-pose bounding-box diagonal. Per variant: the mean over levels and frames of the mean
//! distance, the worst Hausdorff distance, and per level the ratio of its mean to the all-rules
//! build's at the same level (`x` where the variant stops short of it). A rule pays where leaving it
//! out raises a level's error or stops the levels sooner; it costs what leaving it out saves in time.

use clod_viewer::character::Character;
use clod_viewer::clod::{self, Clod, ClodOptions};
use clod_viewer::import;
use clod_viewer::metrics::{bounds_diagonal, surface_distance};
use clod_viewer::simplify::rules::{Rule, Rules, RULES};
use glam::{Mat4, Vec3};
use std::path::Path;
use std::time::Instant;

const SAMPLES: usize = 5_000;
const SEED: u64 = 12345;
const FRAMES: usize = 4;
const CLIPS: usize = 2;

fn main() {
    let mut only: Vec<Rule> = Vec::new();
    let mut files = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--rule" {
            let name = args.next().unwrap_or_default();
            only.push(Rules::parse(&name).unwrap_or_else(|| fail(&format!("unknown rule {name:?}"))));
        } else {
            files.push(arg);
        }
    }
    if files.is_empty() {
        let names: Vec<&str> = RULES.iter().map(|r| r.name).collect();
        fail(&format!("usage: rule_ablation [--rule NAME]... FILE.glb...  (rules: {})", names.join(", ")));
    }
    for file in files {
        let character = import::from_file(Path::new(&file)).unwrap_or_else(|e| fail(&format!("{file}: {e}")));
        report(&file, &character, &only);
    }
}

fn fail(message: &str) -> ! {
    eprintln!("{message}");
    std::process::exit(2);
}

/// The chain at `levels` (or the default levels) with `rules`, and its best build time of three.
fn build(character: &Character, levels: Option<&[usize]>, rules: Rules) -> (Clod, f64) {
    let options =
        ClodOptions { level_triangles: levels.map(<[usize]>::to_vec), rules, ..ClodOptions::default() };
    let mut best = f64::INFINITY;
    let mut chain = None;
    for _ in 0..3 {
        let started = Instant::now();
        let built =
            clod::build(character, &options, &mut |_| {}).unwrap_or_else(|e| fail(&format!("build: {e}")));
        best = best.min(started.elapsed().as_secs_f64() * 1e3);
        chain = Some(built);
    }
    (chain.expect("three builds"), best)
}

fn report(file: &str, character: &Character, only: &[Rule]) {
    let mesh = &character.mesh;
    let diag = f64::from(bounds_diagonal(&mesh.positions));
    let pct = |d: f64| 100.0 * d / diag;
    let (all, all_ms) = build(character, None, Rules::ALL);
    // Level 0 is the input: the levels compared are the default chain's others.
    let counts: Vec<usize> = all.levels.iter().skip(1).map(|l| l.triangle_count()).collect();
    println!("\n## {file}: {} triangles, levels {counts:?}", mesh.triangle_count());
    if counts.is_empty() || character.clips.is_empty() {
        println!("nothing to compare (no levels or no clips)");
        return;
    }
    let frames: Vec<(Vec<Mat4>, Vec<Vec3>)> = character
        .clips
        .iter()
        .take(CLIPS)
        .flat_map(|clip| {
            (0..FRAMES).map(move |f| {
                let t = (clip.duration() as f64 * (f as f64 + 0.5) / FRAMES as f64) as f32;
                let pose = character.pose_at(clip, t);
                (character.skin_matrices(&pose), character.skinned_positions(&pose))
            })
        })
        .collect();
    // Per level of `chain` (level 0 skipped): the mean over frames of the mean distance, and the
    // worst Hausdorff distance.
    let measure = |chain: &Clod| -> Vec<(f64, f64)> {
        (1..chain.levels.len())
            .map(|i| {
                let mut mean = 0.0;
                let mut worst = 0.0f64;
                for (skin, full) in &frames {
                    let posed = chain.level_skinned_positions(i, skin);
                    let d = surface_distance(
                        (full, &mesh.indices),
                        (&posed, &chain.levels[i].indices),
                        SAMPLES,
                        SEED,
                    )
                    .expect("both meshes have area");
                    mean += f64::from(d.mean) / frames.len() as f64;
                    worst = worst.max(f64::from(d.hausdorff));
                }
                (mean, worst)
            })
            .collect()
    };
    let reference = measure(&all);
    println!("| without | levels reached (coarsest) | mean % | worst hausdorff % | mean ratio per level | build ms (÷ all) |");
    println!("|---|---|---|---|---|---|");
    let row = |label: &str, chain: &Clod, ms: f64, errors: &[(f64, f64)]| {
        let mean = errors.iter().map(|e| e.0).sum::<f64>() / errors.len().max(1) as f64;
        let worst = errors.iter().map(|e| e.1).fold(0.0, f64::max);
        let ratios: Vec<String> = (0..reference.len())
            .map(|i| errors.get(i).map_or("x".into(), |e| format!("{:.2}", e.0 / reference[i].0)))
            .collect();
        let coarsest = chain.levels.last().map_or(0, |l| l.triangle_count());
        println!(
            "| {label} | {} of {} ({coarsest}) | {:.4} | {:.3} | {} | {ms:.1} ({:.2}) |",
            chain.levels.len() - 1,
            counts.len(),
            pct(mean),
            pct(worst),
            ratios.join(" "),
            ms / all_ms,
        );
    };
    row("(nothing: all rules)", &all, all_ms, &reference);
    let requested: Vec<usize> = all.levels.iter().map(|l| l.triangle_count()).collect();
    for info in RULES.iter().filter(|info| only.is_empty() || only.contains(&info.rule)) {
        let (chain, ms) = build(character, Some(&requested), Rules::ALL.without(info.rule));
        row(info.name, &chain, ms, &measure(&chain));
    }
}
