//! A fingerprint of the encoded LOD chain (`clod::bytes`) of each file, to show that a change
//! leaves every build's result byte for byte as it was:
//! `cargo run --release --example chain_hash -- FILE.glb...` prints one line per file and build,
//! `FILE variant HASH BYTES bytes`, for the default build (`default`), the batched collapse
//! passes (`passes`) and half-edge collapses (`half-edge`). The hash is FNV-1a (64 bits) over the
//! encoded bytes: no dependency, and the same on every machine. Run it before and after a change
//! and `diff` the outputs.

use clod_viewer::clod::{self, ClodOptions};
use clod_viewer::import;
use clod_viewer::{CollapseMode, Schedule};

/// FNV-1a, 64 bits.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(0xcbf2_9ce4_8422_2325, |hash, &b| (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3))
}

fn main() {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: chain_hash FILE.glb...");
        std::process::exit(2);
    }
    let variants = [
        ("default", ClodOptions::default()),
        ("passes", ClodOptions { schedule: Schedule::Passes, ..ClodOptions::default() }),
        ("half-edge", ClodOptions { mode: CollapseMode::HalfEdge, ..ClodOptions::default() }),
    ];
    for file in files {
        let character = match std::fs::read(&file)
            .map_err(|e| e.to_string())
            .and_then(|glb| import::from_glb(&glb).map_err(|e| e.to_string()))
        {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{file}: {e}");
                std::process::exit(1);
            }
        };
        for (name, options) in &variants {
            let built = clod::build(&character, options, &mut |_| {}).expect("build");
            let bytes = clod::bytes::encode(&built);
            println!("{file} {name} {:016x} {} bytes", fnv1a(&bytes), bytes.len());
        }
    }
}
