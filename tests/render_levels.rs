//! The renderer's level arrays on real models: each vertex's ancestor attributes are exactly the
//! coarser level's vertex (so a geomorph at t = 1 draws the coarser level), material ranges cover
//! every triangle, and the full-mesh source is the mesh itself.

use crate::common;

use clod_viewer::clod::shading::face_normal;
use clod_viewer::clod::{self, ClodOptions};
use clod_viewer::import;
use clod_viewer::render::lod_source::{LevelData, LodSource};
use glam::Vec3;

fn check_ranges(source: &LodSource) {
    for (i, level) in source.levels.iter().enumerate() {
        let mut next = 0;
        for r in &level.ranges {
            assert_eq!(r.first_index, next, "level {i}: ranges are contiguous");
            next += r.index_count;
        }
        assert_eq!(next as usize, level.indices.len(), "level {i}: ranges cover the indices");
        assert!(level.indices.iter().all(|&v| (v as usize) < level.vertices.len()));
    }
}

/// Every corner whose vertex or ancestor is faceted is used once; a faceted vertex carries its
/// triangle's face normal, and a corner whose ancestor (in `coarse`, the next level) is faceted
/// carries the face normal at its ancestors' positions (the fine one where that degenerated).
fn check_facets(name: &str, i: usize, level: &LevelData, coarse: Option<&LevelData>) {
    let faceted_ancestor = |v: usize| coarse.is_some_and(|c| c.faceted[level.next[v] as usize]);
    let mut uses = vec![0; level.vertices.len()];
    for t in level.indices.chunks_exact(3) {
        let end = |k: usize, coarse: bool| {
            let v = &level.vertices[t[k] as usize];
            Vec3::from(if coarse { v.coarse.position } else { v.fine.position })
        };
        let fine = face_normal(end(0, false), end(1, false), end(2, false));
        let at_coarse = face_normal(end(0, true), end(1, true), end(2, true)).or(fine);
        for &v in t {
            let (own, ancestor) = (level.faceted[v as usize], faceted_ancestor(v as usize));
            if !(own || ancestor) {
                continue;
            }
            uses[v as usize] += 1;
            let vertex = &level.vertices[v as usize];
            if let (true, Some(f)) = (own, fine) {
                assert_eq!(vertex.fine.normal, f.to_array(), "{name} level {i} vertex {v}");
            }
            if let (true, Some(c)) = (ancestor, at_coarse) {
                assert_eq!(vertex.coarse.normal, c.to_array(), "{name} level {i} vertex {v}: coarse end");
            }
        }
    }
    assert!(uses.iter().all(|&u| u <= 1), "{name} level {i}: a faceted vertex is shared");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn clod_levels_carry_their_ancestors() {
    for name in ["CesiumMan.glb", "RiggedSimple.glb"] {
        let Some(bytes) = common::model_bytes(name) else { continue };
        let character = import::from_glb(&bytes).expect("import");
        let built = clod::build(&character, &ClodOptions::default(), &mut |_| {}).expect("build");
        let source = LodSource::from_clod(&character, &built);
        assert_eq!(source.levels.len(), built.levels.len());
        check_ranges(&source);
        for (i, pair) in source.levels.windows(2).enumerate() {
            let (fine, coarse) = (&pair[0], &pair[1]);
            assert_eq!(&fine.next[..built.levels[i].ancestors.len()], &built.levels[i].ancestors[..]);
            for (k, v) in fine.vertices.iter().enumerate() {
                let mut ancestor = coarse.vertices[fine.next[k] as usize].fine;
                if coarse.faceted[fine.next[k] as usize] {
                    // A faceted ancestor's normal is the corner's own triangle's (checked below).
                    ancestor.normal = v.coarse.normal;
                }
                assert_eq!(v.coarse, ancestor, "{name} level {i} vertex {k}");
            }
            check_facets(name, i, fine, Some(coarse));
            assert!(fine.triangle_count() > coarse.triangle_count());
            assert!(fine.error <= coarse.error);
        }
        let last = source.levels.last().expect("levels");
        check_facets(name, source.levels.len() - 1, last, None);
        assert!(last.vertices.iter().all(|v| v.fine == v.coarse), "{name}: the coarsest is its own ancestor");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn full_mesh_source_is_the_mesh() {
    let Some(bytes) = common::model_bytes("Fox.glb") else { return };
    let character = import::from_glb(&bytes).expect("import");
    let source = LodSource::full_mesh(&character);
    assert_eq!(source.levels.len(), 1);
    check_ranges(&source);
    let level = &source.levels[0];
    assert_eq!(level.triangle_count(), character.mesh.triangle_count());
    for (k, v) in level.vertices.iter().enumerate() {
        assert_eq!(v.fine.position, character.mesh.positions[k].to_array());
        assert_eq!(v.fine, v.coarse);
    }
}
