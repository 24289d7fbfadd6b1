//! The committed characters (`assets/*.glb`) are byte for byte what the generator makes: runs the
//! generator's own `--check` on each, so the test command needs no build of the generator beside
//! the workspace's tests (a separate `cargo run -p make-character` resolves the crates' features
//! differently and rebuilt the whole library, four minutes on 2 cores).

use std::process::Command;

/// Runs the generator's `--check` on the committed file `name` and fails with its output unless it passes.
fn check(name: &str) {
    let path = format!("{}/../../assets/{name}", env!("CARGO_MANIFEST_DIR"));
    let output = Command::new(env!("CARGO_BIN_EXE_make-character"))
        .args(["--check", &path])
        .output()
        .expect("the generator runs");
    assert!(
        output.status.success(),
        "{name} differs from what the generator makes:\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn character_glb_is_what_the_generator_makes() {
    check("character.glb");
}

#[test]
fn robot_glb_is_what_the_generator_makes() {
    check("robot.glb");
}

#[test]
fn parts_glb_is_what_the_generator_makes() {
    check("parts.glb");
}

#[test]
fn critter_glb_is_what_the_generator_makes() {
    check("critter.glb");
}
