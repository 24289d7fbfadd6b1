//! The generated kinds that are not committed, through clod-viewer's importer and LOD chain,
//! each holding the chain's invariants (the checks of `tests/common/chain.rs`, shared with the
//! library's tests): `lowpoly-robot.glb` (every edge a normal seam, morph targets) and
//! `hardsurface.glb` at `--detail 0.25` (60 smooth parts, open and closed, about 15k triangles:
//! the 62k file is for the benchmark) and `fingers.glb` (65 joints, 40 of them in thin fingers,
//! smooth skinning). Each test runs this crate's generator into the test's scratch folder first.

#[path = "../../../tests/common/chain.rs"]
mod chain;

use clod_viewer::import::from_glb;
use clod_viewer::Character;

use chain::{assert_coarsest_is_faceted, build_and_check};

/// `target/tmp/generated-kinds/FILE` made now by the generator (with `--detail` when given).
fn generated(file: &str, detail: Option<&str>) -> Character {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("generated-kinds");
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join(file);
    let mut generator = std::process::Command::new(env!("CARGO_BIN_EXE_make-character"));
    if let Some(detail) = detail {
        generator.args(["--detail", detail]);
    }
    let out = generator.arg(&path).output().expect("cargo runs");
    assert!(out.status.success(), "make-character {file}: {}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&path).expect("the generator wrote it");
    from_glb(&bytes).unwrap_or_else(|e| panic!("{file} does not import: {e}"))
}

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

#[test]
fn hardsurface_chain_holds_its_invariants() {
    let robot = generated("hardsurface-d0.25.glb", Some("0.25"));
    assert_eq!(robot.mesh.primitives.len(), 60);
    assert_eq!(robot.skeleton.joints.len(), 18);
    let (_, counts) = build_and_check("hardsurface", &robot);
    assert!(counts.len() >= 2, "hardsurface: levels {counts:?}");
}

#[test]
fn fingers_chain_holds_its_invariants() {
    let character = generated("fingers.glb", None);
    assert_eq!(character.skeleton.joints.len(), 65);
    assert!(character.mesh.weights.iter().any(|w| w[1] > 0.0), "blended skinning");
    let (_, counts) = build_and_check("fingers", &character);
    assert!(counts.len() >= 6, "fingers: levels {counts:?}");
}
