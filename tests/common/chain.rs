//! The LOD chain's invariants, for tests that build chains of characters of their own (the same
//! checks as `tests/clod.rs` makes on the shared models): every level a valid, decreasing part of
//! the progressive mesh with valid ancestors and monotone errors, level 0 the input, and the
//! back-propagation identity at the simplification pose.

use std::collections::HashMap;

use clod_viewer::clod::{self, Clod, ClodOptions};
use clod_viewer::metrics::bounds_diagonal;
use clod_viewer::render::lod_source::LodSource;
use clod_viewer::vertex_cache::average_cache_miss_ratio;
use clod_viewer::Character;

/// `t` rotated to start at its smallest index (the winding kept).
pub fn rotated_to_min(mut t: [u32; 3]) -> [u32; 3] {
    let min = (0..3).min_by_key(|&r| t[r]).unwrap();
    t.rotate_left(min);
    t
}

/// Indices in range, no degenerate triangle, no duplicate but a two-sided sheet, the progressive
/// mesh's triangles in the vertex cache's order, ancestors valid, errors monotone.
pub fn check_chain(name: &str, clod: &Clod) {
    let pm = &clod.apm.pm;
    if let Err(broken) = pm.validate() {
        panic!("{name}: the progressive mesh breaks an invariant: {broken}");
    }
    assert!(clod.levels.len() >= 2, "{name}: only {} level(s)", clod.levels.len());
    for (i, level) in clod.levels.iter().enumerate() {
        let n = level.vertices.len() as u32;
        let mut seen = HashMap::new();
        for t in level.indices.chunks_exact(3) {
            assert!(t.iter().all(|&v| v < n), "{name} level {i}: index out of range");
            assert!(
                t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
                "{name} level {i}: degenerate triangle {t:?}"
            );
            let mut key = [t[0], t[1], t[2]];
            key.sort();
            // Two triangles on the same corners must face opposite ways: a two-sided sheet, what
            // a closed part becomes on its way out (a tetrahedron's first collapse).
            let windings: &mut Vec<[u32; 3]> = seen.entry(key).or_default();
            windings.push(rotated_to_min([t[0], t[1], t[2]]));
            assert!(
                windings.len() == 1
                    || (windings.len() == 2 && windings[0] == rotated_to_min([t[0], t[2], t[1]])),
                "{name} level {i}: duplicate triangle {t:?}"
            );
        }
        // The progressive mesh after the level's collapses, triangle for triangle and winding kept,
        // in whatever order the level draws them.
        let active = clod::chain::active_ancestors(pm, level.collapses);
        let live = pm.triangle_count_after(level.collapses);
        let mut expected: Vec<[u32; 3]> = pm.indices[..3 * live]
            .chunks_exact(3)
            .map(|t| rotated_to_min([t[0], t[1], t[2]].map(|v| active[v as usize])))
            .collect();
        let mut drawn: Vec<[u32; 3]> = level
            .indices
            .chunks_exact(3)
            .map(|t| rotated_to_min([t[0], t[1], t[2]].map(|v| level.vertices[v as usize])))
            .collect();
        expected.sort_unstable();
        drawn.sort_unstable();
        assert!(
            drawn == expected,
            "{name} level {i}: not the progressive mesh after {} collapses",
            level.collapses
        );
        // Drawn in vertex-cache order: at 500 triangles and more the progressive mesh's own order
        // (by collapse) transforms 2.0–2.9 vertices per triangle under a 16-entry cache on these
        // models, the levels 0.58–1.12.
        if level.triangle_count() >= 500 {
            let acmr = average_cache_miss_ratio(&level.indices, level.vertices.len(), 16);
            assert!(acmr <= 1.25, "{name} level {i}: {acmr} vertices transformed per triangle");
        }
        if let Some(coarser) = clod.levels.get(i + 1) {
            assert!(
                coarser.triangle_count() < level.triangle_count(),
                "{name}: levels {i}, {} not decreasing",
                i + 1
            );
            assert!(coarser.error >= level.error, "{name}: error decreases after level {i}");
            assert_eq!(
                level.ancestors.len(),
                level.vertices.len(),
                "{name} level {i}: one ancestor per vertex"
            );
            for (v, &a) in level.vertices.iter().zip(&level.ancestors) {
                let a = coarser.vertices.get(a as usize).copied();
                assert_eq!(
                    a,
                    Some(pm.ancestor_at(*v, coarser.collapses)),
                    "{name} level {i}: wrong ancestor of {v}"
                );
            }
        } else {
            assert!(level.ancestors.is_empty());
        }
    }
}

/// Every level of `clod` skinned with `skin` (the simplification pose's) lies within 1e-5 of
/// `diagonal` of its static positions in that pose: the back-propagation identity.
pub fn assert_levels_skin_to_their_static_positions(
    name: &str,
    clod: &Clod,
    skin: &[glam::Mat4],
    diagonal: f32,
) {
    for i in 0..clod.levels.len() {
        let skinned = clod.level_skinned_positions(i, skin);
        let fixed = clod.level_pose_positions(i);
        let worst = skinned.iter().zip(&fixed).map(|(a, b)| a.distance(*b)).fold(0.0f32, f32::max);
        assert!(worst <= 1e-5 * diagonal, "{name} level {i}: skinned differs from static by {worst}");
    }
}

/// Level 0 of a default chain is the input mesh itself, its facet corners welded
/// (`clod::shading`), winding included.
pub fn assert_level_zero_is_the_input(name: &str, clod: &Clod, character: &Character) {
    let full = &clod.levels[0];
    assert_eq!(full.triangle_count(), character.mesh.triangle_count(), "{name}");
    let mut ours: Vec<[u32; 3]> = full
        .indices
        .chunks_exact(3)
        .map(|t| rotated_to_min([t[0], t[1], t[2]].map(|v| full.vertices[v as usize])))
        .collect();
    let welded = clod::shading::ShadingWeld::of_character(character).weld_indices(&character.mesh.indices);
    let mut input: Vec<[u32; 3]> =
        welded.chunks_exact(3).map(|t| rotated_to_min([t[0], t[1], t[2]])).collect();
    ours.sort_unstable();
    input.sort_unstable();
    assert_eq!(ours, input, "{name}: level 0 is not the input (winding included)");
}

/// The default chain of `character` with every invariant checked, the back-propagation identity
/// in the bind pose (the multi-pose build's simplification pose) and every level finite under
/// every clip. Returns it and its level triangle counts.
pub fn build_and_check(name: &str, character: &Character) -> (Clod, Vec<usize>) {
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
pub fn assert_coarsest_is_faceted(name: &str, character: &Character, built: &Clod) {
    let source = LodSource::from_clod(character, built);
    let last = source.levels.last().expect("levels");
    assert!(
        last.indices.iter().all(|&v| last.faceted[v as usize]),
        "{name}: a smooth corner at the coarsest level"
    );
}
