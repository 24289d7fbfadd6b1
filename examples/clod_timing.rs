//! Native build time of the articulated progressive mesh, for the benchmark's "native next to
//! wasm" column: `cargo run --release --example clod_timing -- FILE.glb...` prints one JSON line
//! per file: `{"file": ..., "triangles": ..., "ms": ...}` (best of three builds, the same level
//! counts as bench/lod-vs-meshoptimizer.mjs: 50/25/10/5/1 %).

use std::time::Instant;

use clod_viewer::clod::{self, ClodOptions};
use clod_viewer::import;

const FRACTIONS: [f64; 5] = [0.5, 0.25, 0.1, 0.05, 0.01];

fn main() {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: clod_timing FILE.glb...");
        std::process::exit(2);
    }
    for file in files {
        let character = match std::fs::read(&file)
            .map_err(|e| e.to_string())
            .and_then(|b| import::from_glb(&b).map_err(|e| e.to_string()))
        {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{file}: {e}");
                std::process::exit(1);
            }
        };
        let n = character.mesh.triangle_count();
        let levels = FRACTIONS.iter().map(|f| ((n as f64 * f).round() as usize).max(1)).collect();
        let options = ClodOptions { level_triangles: Some(levels), ..ClodOptions::default() };
        let mut best = f64::INFINITY;
        for _ in 0..3 {
            let started = Instant::now();
            let built = clod::build(&character, &options, &mut |_| {}).expect("build");
            best = best.min(started.elapsed().as_secs_f64() * 1000.0);
            std::hint::black_box(built);
        }
        println!("{{\"file\": {file:?}, \"triangles\": {n}, \"ms\": {best:.2}}}");
    }
}
