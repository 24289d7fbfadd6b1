//! Seeded mutations of the three shared models — truncations, bit flips in the JSON and binary
//! chunks, inflated accessor counts — must each import to `Ok` or `Err`, never panic, and finish
//! quickly (the whole run is bounded by the test's own runtime: no case may hang).

use crate::common;

use clod_viewer::import::from_glb;
use common::SplitMix;

/// Cases per model and mutation kind: a few thousand in total natively, fewer under wasm (about
/// three times slower there).
#[cfg(not(target_arch = "wasm32"))]
const CASES: usize = 500;
#[cfg(target_arch = "wasm32")]
const CASES: usize = 40;

const MODELS: [&str; 3] = ["CesiumMan.glb", "Fox.glb", "RiggedSimple.glb"];

/// The JSON chunk's byte range within a GLB.
fn json_range(glb: &[u8]) -> std::ops::Range<usize> {
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    20..20 + len
}

/// Runs the importer (the point is that it returns at all), counting `Ok`s, and returns the
/// error message if any. Natively each case must also finish within a second: these models import
/// in about a millisecond, so a slow case means a loop that depends on forged counts.
fn run(bytes: &[u8], oks: &mut usize) -> Option<String> {
    #[cfg(not(target_arch = "wasm32"))]
    let start = std::time::Instant::now();
    let result = from_glb(bytes);
    #[cfg(not(target_arch = "wasm32"))]
    assert!(start.elapsed().as_secs_f32() < 1.0, "a case took {:?}", start.elapsed());
    match result {
        Ok(_) => {
            *oks += 1;
            None
        }
        Err(e) => Some(e.to_string()),
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn truncations() {
    for (m, name) in MODELS.iter().enumerate() {
        let Some(glb) = common::model_bytes(name) else { return };
        let mut rng = SplitMix(100 + m as u64);
        let mut oks = 0;
        for _ in 0..CASES {
            run(&glb[..rng.below(glb.len())], &mut oks);
        }
        // A GLB cut short is always noticed by the header length check.
        assert_eq!(oks, 0, "{name}: a truncated file imported");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn bit_flips_in_json_and_binary_chunks() {
    for (m, name) in MODELS.iter().enumerate() {
        let Some(glb) = common::model_bytes(name) else { return };
        let json = json_range(&glb);
        let mut rng = SplitMix(200 + m as u64);
        let mut oks = 0;
        for case in 0..CASES {
            let mut bytes = glb.clone();
            for _ in 0..1 + rng.below(4) {
                // Alternate between the JSON chunk and the binary chunk (and its header).
                let at = match case % 2 {
                    0 => json.start + rng.below(json.len()),
                    _ => json.end + rng.below(glb.len() - json.end),
                };
                bytes[at] ^= 1 << rng.below(8);
            }
            run(&bytes, &mut oks);
        }
        // Many flips land in texture bytes or animation values that stay valid.
        assert!(oks > 0, "{name}: no mutated file imported; the mutations are too coarse to test much");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn inflated_accessor_counts() {
    for (m, name) in MODELS.iter().enumerate() {
        let Some(glb) = common::model_bytes(name) else { return };
        let json_bytes = &glb[json_range(&glb)];
        let text = std::str::from_utf8(json_bytes).unwrap();
        // Byte ranges of the digits after every `"count":`.
        let counts: Vec<(usize, usize)> = text
            .match_indices("\"count\":")
            .map(|(at, key)| {
                let start = at + key.len();
                let len = text[start..].bytes().take_while(|b| b.is_ascii_digit() || *b == b' ').count();
                (start, start + len)
            })
            .collect();
        assert!(!counts.is_empty());
        let mut rng = SplitMix(300 + m as u64);
        let mut oks = 0;
        let mut accessor_errors = 0;
        for _ in 0..CASES {
            let (start, end) = counts[rng.below(counts.len())];
            let old: u64 = text[start..end].trim().parse().unwrap();
            let new = match rng.below(4) {
                0 => old + 1,
                1 => old * 2 + rng.below(1000) as u64,
                2 => 1 << (20 + rng.below(44)),
                _ => u64::MAX >> rng.below(8),
            };
            let edited = format!("{}{new}{}", &text[..start], &text[end..]);
            // Rebuild the GLB around the edited JSON, padded to 4 bytes as the format wants.
            let mut json = edited.into_bytes();
            json.resize(json.len().next_multiple_of(4), b' ');
            let rest = &glb[20 + json_bytes.len()..];
            let total = 20 + json.len() + rest.len();
            let mut bytes = Vec::with_capacity(total);
            bytes.extend_from_slice(&glb[..8]);
            bytes.extend_from_slice(&(total as u32).to_le_bytes());
            bytes.extend_from_slice(&(json.len() as u32).to_le_bytes());
            bytes.extend_from_slice(b"JSON");
            bytes.extend_from_slice(&json);
            bytes.extend_from_slice(rest);
            if let Some(message) = run(&bytes, &mut oks) {
                if message.contains("accessor") {
                    accessor_errors += 1;
                }
            }
        }
        // Growing a count mostly overruns the accessor's buffer view, which the accessor check
        // must name; the rest break key/value pairing or skin sizes, or read slack bytes.
        assert!(
            accessor_errors > CASES / 2,
            "{name}: only {accessor_errors} accessor errors ({oks} imported)"
        );
    }
}
