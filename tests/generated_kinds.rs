//! The kinds of character made for the benchmark against meshoptimizer (issue 47; see
//! assets/README.md) through the importer and the LOD chain, each holding the chain's invariants
//! (`common::chain`): `assets/critter.glb` (committed: a 512-triangle faceted animal with a long
//! tail, blended skin) here and under node; `lowpoly-robot.glb` (every edge a normal seam, morph
//! targets) and `hardsurface.glb` at `--detail 0.25` (60 smooth parts, open and closed, about 15k
//! triangles: the 62k file is for the benchmark), which are not committed, natively only: each
//! test runs the generator (`cargo run -p make-character`) into the test's scratch folder first.

mod common;

use clod_viewer::clod::{self, Clod, ClodOptions};
use clod_viewer::import::from_glb;
use clod_viewer::metrics::bounds_diagonal;
use clod_viewer::render::lod_source::LodSource;
use clod_viewer::Character;

use common::chain::{
    assert_level_zero_is_the_input, assert_levels_skin_to_their_static_positions, check_chain,
};

/// The default chain of `character` with every invariant checked, the back-propagation identity
/// in the bind pose (the multi-pose build's simplification pose) and every level finite under
/// every clip. Returns it and its level triangle counts.
fn build_and_check(name: &str, character: &Character) -> (Clod, Vec<usize>) {
    let built = clod::build(character, &ClodOptions::default(), &mut |_| {}).expect("it builds");
    let counts: Vec<usize> = built.levels.iter().map(|l| l.triangle_count()).collect();
    eprintln!("{name}: levels {counts:?}, stop {:?}", built.apm.pm.stop);
    check_chain(name, &built);
    assert_level_zero_is_the_input(name, &built, character);
    let rest = character.skin_matrices(&character.skeleton.rest_pose());
    assert_levels_skin_to_their_static_positions(
        name,
        &built,
        &rest,
        bounds_diagonal(&character.mesh.positions),
    );
    assert_eq!(built.apm.singular_back_propagations, 0, "{name}");
    for clip in &character.clips {
        let skin = character.skin_matrices(&character.pose_at(clip, clip.duration() * 0.3));
        for i in 0..built.levels.len() {
            let posed = built.level_skinned_positions(i, &skin);
            assert!(posed.iter().all(|p| p.is_finite()), "{name} {} level {i}", clip.name);
        }
    }
    (built, counts)
}

/// Every corner the coarsest level draws is faceted: a flat-shaded file stays flat.
fn assert_coarsest_is_faceted(name: &str, character: &Character, built: &Clod) {
    let source = LodSource::from_clod(character, built);
    let last = source.levels.last().expect("levels");
    assert!(
        last.indices.iter().all(|&v| last.faceted[v as usize]),
        "{name}: a smooth corner at the coarsest level"
    );
}

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

/// `target/tmp/generated-kinds/FILE` made now by the generator (with `--detail` when given).
#[cfg(not(target_arch = "wasm32"))]
fn generated(file: &str, detail: Option<&str>) -> Character {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("generated-kinds");
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join(file);
    let mut generator = std::process::Command::new(env!("CARGO"));
    generator.args(["run", "--quiet", "-p", "make-character", "--"]).current_dir(env!("CARGO_MANIFEST_DIR"));
    if let Some(detail) = detail {
        generator.args(["--detail", detail]);
    }
    let out = generator.arg(&path).output().expect("cargo runs");
    assert!(out.status.success(), "make-character {file}: {}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&path).expect("the generator wrote it");
    from_glb(&bytes).unwrap_or_else(|e| panic!("{file} does not import: {e}"))
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn lowpoly_robot_chain_holds_its_invariants_and_stays_faceted() {
    let robot = generated("lowpoly-robot.glb", None);
    assert!((2_800..=3_600).contains(&robot.mesh.triangle_count()), "{}", robot.mesh.triangle_count());
    assert!(robot.mesh.weights.iter().all(|w| *w == [1.0, 0.0, 0.0, 0.0]), "rigid skinning");
    assert!(!robot.morph_targets.is_empty(), "morph targets");
    let (built, counts) = build_and_check("lowpoly-robot", &robot);
    assert!(counts.len() >= 2, "lowpoly-robot: levels {counts:?}");
    assert_coarsest_is_faceted("lowpoly-robot", &robot, &built);
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn hardsurface_chain_holds_its_invariants() {
    let robot = generated("hardsurface-d0.25.glb", Some("0.25"));
    assert_eq!(robot.mesh.primitives.len(), 60);
    assert_eq!(robot.skeleton.joints.len(), 18);
    let (_, counts) = build_and_check("hardsurface", &robot);
    assert!(counts.len() >= 2, "hardsurface: levels {counts:?}");
}
