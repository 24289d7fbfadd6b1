//! The committed generated kind `assets/critter.glb` (a 512-triangle faceted animal with a long
//! tail, blended skin; see assets/README.md) through the importer and the LOD chain, holding the
//! chain's invariants (`common::chain`), natively and under node. The uncommitted kinds
//! (`lowpoly-robot.glb`, `hardsurface.glb`) are tested by the generator's own tests
//! (`tools/make-character/tests/generated_kinds.rs`), which run its binary.

use crate::common;

use clod_viewer::import::from_glb;

use common::chain::{assert_coarsest_is_faceted, build_and_check};

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn critter_chain_holds_its_invariants() {
    let critter = from_glb(include_bytes!("../assets/critter.glb")).expect("critter.glb imports");
    assert!((400..=650).contains(&critter.mesh.triangle_count()), "{}", critter.mesh.triangle_count());
    assert!((20..=30).contains(&critter.skeleton.joints.len()));
    assert!(critter.mesh.weights.iter().any(|w| w[1] > 0.0), "blended skinning");
    let (built, counts) = build_and_check("critter", &critter);
    assert!(counts.len() >= 2, "critter: levels {counts:?}");
    assert_coarsest_is_faceted("critter", &critter, &built);
}
