//! LDR-FLIP (`clod_viewer::render::flip`) against NVIDIA's reference implementation: the fixture
//! pairs in `tests/fixtures/flip/` (made by `make_pairs.py`) and the reference's mean error and
//! 99th percentile of its error map (`reference.json`, written by `reference.py` with
//! `flip-evaluator` 1.7 at 67.02 pixels per degree). The browser test checks the GPU's version
//! (`flip.wgsl`) against the same numbers.

use clod_viewer::render::flip::{flip_map, FlipStats, DEFAULT_PPD};

/// The fixtures: name, reference PNG, test PNG.
const PAIRS: [(&str, &[u8], &[u8]); 3] = [
    (
        "silhouette",
        include_bytes!("fixtures/flip/silhouette-reference.png"),
        include_bytes!("fixtures/flip/silhouette-test.png"),
    ),
    (
        "shading",
        include_bytes!("fixtures/flip/shading-reference.png"),
        include_bytes!("fixtures/flip/shading-test.png"),
    ),
    (
        "texture",
        include_bytes!("fixtures/flip/texture-reference.png"),
        include_bytes!("fixtures/flip/texture-test.png"),
    ),
];
const REFERENCE: &str = include_str!("fixtures/flip/reference.json");

/// An 8-bit RGB PNG whose zlib stream holds stored blocks and whose rows use no filter (what
/// `make_pairs.py` writes), as RGBA8 with alpha 255: `(width, height, pixels)`.
fn read_png(bytes: &[u8]) -> (usize, usize, Vec<u8>) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let (mut at, mut size, mut zlib) = (8, (0, 0), Vec::new());
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let (kind, body) = (&bytes[at + 4..at + 8], &bytes[at + 8..at + 8 + len]);
        match kind {
            b"IHDR" => {
                let n = |i: usize| u32::from_be_bytes(body[i..i + 4].try_into().unwrap()) as usize;
                assert_eq!((body[8], body[9]), (8, 2), "8-bit RGB");
                size = (n(0), n(4));
            }
            b"IDAT" => zlib.extend_from_slice(body),
            _ => {}
        }
        at += 12 + len;
    }
    let mut raw = Vec::new();
    let mut block = 2; // past the zlib header
    loop {
        let header = zlib[block];
        assert_eq!(header & 0b110, 0, "a stored block");
        let len = u16::from_le_bytes([zlib[block + 1], zlib[block + 2]]) as usize;
        raw.extend_from_slice(&zlib[block + 5..block + 5 + len]);
        block += 5 + len;
        if header & 1 == 1 {
            break;
        }
    }
    let (w, h) = size;
    let mut rgba = Vec::with_capacity(4 * w * h);
    for row in raw.chunks_exact(1 + 3 * w) {
        assert_eq!(row[0], 0, "rows without a filter");
        rgba.extend(row[1..].chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]));
    }
    assert_eq!(rgba.len(), 4 * w * h);
    (w, h, rgba)
}

/// The number after `"key": ` in the reference's entry for `name`.
fn reference_number(name: &str, key: &str) -> f32 {
    let entry = &REFERENCE[REFERENCE.find(&format!("\"name\": \"{name}\"")).expect("the pair")..];
    let value = &entry[entry.find(&format!("\"{key}\": ")).expect("the key") + key.len() + 4..];
    value[..value.find([',', '\n', '}']).unwrap()].trim().parse().unwrap()
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ldr_flip_matches_the_reference_implementation_on_the_fixtures() {
    assert!(REFERENCE.contains("flip-evaluator 1.7"));
    let ppd: f32 =
        REFERENCE[REFERENCE.find("\"ppd\": ").unwrap() + 7..].split(',').next().unwrap().parse().unwrap();
    assert!((ppd - DEFAULT_PPD).abs() < 1e-3, "the reference ran at FLIP's default {ppd}");
    for (name, reference, test) in PAIRS {
        let (w, h, reference) = read_png(reference);
        let (_, _, test) = read_png(test);
        let ours = FlipStats::of(&flip_map(&reference, &test, w, h, DEFAULT_PPD));
        let (mean, p99) = (reference_number(name, "mean"), reference_number(name, "p99"));
        println!(
            "{name}: mean {:.5} (reference {mean:.5}), p99 {:.5} (reference {p99:.5})",
            ours.mean, ours.p99
        );
        assert!((ours.mean - mean).abs() <= 0.01, "{name}: mean {} vs {mean}", ours.mean);
        assert!((ours.p99 - p99).abs() <= 0.02, "{name}: p99 {} vs {p99}", ours.p99);
        assert!(mean > 0.005, "{name}: a pair that differs");
    }
}
