//! Build script: the identity of the sources this library is built from, for the page's cache of
//! LOD chains (`clod::bytes::SOURCE_TAG`). A chain's bytes decode with any build of the same
//! format version, but a build whose simplifier changed makes other levels from the same file: a
//! cache keyed by the file alone would attach levels the running code did not make. So the key
//! carries this tag, FNV-1a (64 bits) over every file under `src/` (path and contents, in path
//! order) and `Cargo.lock`: any change to them gives a new tag, and the next visit builds again.
//!
//! It also writes the renderer's shaders (`src/render/*.wgsl`) into `OUT_DIR` without their `//`
//! comments, which the wasm would otherwise carry to every reader (4.4 KB of the WebGPU page's
//! gzip, measured 2026-11-29): line for line, so a shader error's line number is the source
//! file's. WGSL has no string literals, so `//` always starts a comment.

use std::fs;
use std::path::{Path, PathBuf};

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

fn fnv1a(mut hash: u64, bytes: &[u8]) -> u64 {
    for &byte in bytes {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(FNV_PRIME);
    }
    hash
}

/// Every file under `dir`, recursively.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files_under(&path, out);
        } else {
            out.push(path);
        }
    }
}

/// Writes every `.wgsl` file of `dir` into `OUT_DIR` with its line comments removed (and the
/// spaces before them), keeping every line.
fn write_shaders(dir: &Path) {
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let Ok(entries) = fs::read_dir(dir) else { return };
    for path in entries.flatten().map(|e| e.path()) {
        if path.extension().is_some_and(|x| x == "wgsl") {
            let source = fs::read_to_string(&path).expect("a shader is UTF-8 text");
            let code: Vec<&str> =
                source.lines().map(|line| line.split("//").next().unwrap_or("").trim_end()).collect();
            let name = path.file_name().expect("a file has a name");
            fs::write(out.join(name), code.join("\n") + "\n").expect("OUT_DIR is writable");
        }
    }
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    files_under(&root.join("src"), &mut files);
    files.push(root.join("Cargo.lock"));
    files.sort();
    let mut hash = FNV_OFFSET;
    for file in &files {
        let relative = file.strip_prefix(&root).unwrap_or(file);
        // Separators as '/' so the tag is the same on every platform.
        hash = fnv1a(hash, relative.to_string_lossy().replace('\\', "/").as_bytes());
        hash = fnv1a(hash, &[0]);
        hash = fnv1a(hash, &fs::read(file).unwrap_or_default());
    }
    println!("cargo:rustc-env=CLOD_SOURCE_TAG={hash:016x}");
    write_shaders(&root.join("src/render"));
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=Cargo.lock");
}
