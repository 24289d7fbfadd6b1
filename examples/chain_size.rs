//! Size of the encoded LOD chain (`clod::bytes`) next to its `.glb`, and the time to encode and
//! decode it: `cargo run --release --example chain_size -- FILE.glb...` prints one line per file
//! for the default build (multi-pose, default levels). Decoding recomputes what the bytes leave
//! out, so its time is part of what a cached or transferred chain costs the page.

use std::time::Instant;

use clod_viewer::clod::{self, ClodOptions};
use clod_viewer::import;

fn main() {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: chain_size FILE.glb...");
        std::process::exit(2);
    }
    for file in files {
        let result = std::fs::read(&file)
            .map_err(|e| e.to_string())
            .and_then(|glb| import::from_glb(&glb).map(|c| (glb, c)).map_err(|e| e.to_string()));
        let (glb, character) = match result {
            Ok(loaded) => loaded,
            Err(e) => {
                eprintln!("{file}: {e}");
                std::process::exit(1);
            }
        };
        let started = Instant::now();
        let built = clod::build(&character, &ClodOptions::default(), &mut |_| {}).expect("build");
        let build_ms = started.elapsed().as_secs_f64() * 1e3;
        let started = Instant::now();
        let bytes = clod::bytes::encode(&built);
        let encode_ms = started.elapsed().as_secs_f64() * 1e3;
        let started = Instant::now();
        let decoded = clod::bytes::decode(&bytes, &character).expect("a chain decodes against its character");
        let decode_ms = started.elapsed().as_secs_f64() * 1e3;
        assert!(decoded == built, "{file}: the decoded chain differs from the built one");
        println!(
            "{file}: {} triangles, {} levels; glb {} bytes, chain {} bytes ({:.2} ×); \
             build {build_ms:.1} ms, encode {encode_ms:.1} ms, decode {decode_ms:.1} ms",
            character.mesh.triangle_count(),
            built.levels.len(),
            glb.len(),
            bytes.len(),
            bytes.len() as f64 / glb.len() as f64,
        );
    }
}
