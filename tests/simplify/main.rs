//! Hand-drawn inputs with exact expected simplification results.

mod parts;

use crate::meshgen;

use clod_viewer::metrics::closest_point_on_triangle;
use clod_viewer::progressive::ProgressiveMesh;
use clod_viewer::simplify::{
    simplify, CollapseMode, Quadric, Rule, Rules, Schedule, SimplifyError, SimplifyOptions, StopReason,
};
use glam::{DVec3, Vec3};
use meshgen::{check_invariants, grid, spread_levels, Mesh};
use parts::tetrahedron;
use std::collections::HashSet;

fn options(mode: CollapseMode, target: usize) -> SimplifyOptions {
    SimplifyOptions { mode, target_triangles: target, ..SimplifyOptions::default() }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn flat_grid_collapses_to_two_triangles_without_error() {
    let mesh = grid(6, 5, |_, _| 0.0);
    for mode in [CollapseMode::Full, CollapseMode::HalfEdge] {
        let pm = mesh.simplify(&options(mode, 2));
        assert_eq!(pm.stop, StopReason::TargetReached, "{mode:?}");
        let k = pm.collapse_count();
        assert_eq!(pm.triangle_count_after(k), 2, "{mode:?}");
        assert!(pm.error_after(k) <= 1e-12, "{mode:?}: error {}", pm.error_after(k));
        // The two triangles span the grid's four corners (−0.0, which a merged corner may get,
        // counts as 0.0).
        let corners: HashSet<[u32; 3]> = pm
            .indices_at(k)
            .iter()
            .map(|&v| pm.positions[v as usize].to_array().map(|x| (x + 0.0).to_bits()))
            .collect();
        let expected: HashSet<[u32; 3]> = [[0.0, 0.0], [6.0, 0.0], [0.0, 5.0], [6.0, 5.0]]
            .iter()
            .map(|&[x, y]| [x, y, 0.0f32].map(f32::to_bits))
            .collect();
        assert_eq!(corners, expected, "{mode:?}");
        check_invariants(&mesh, &pm, &(0..=k).collect::<Vec<_>>(), false);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn single_triangle_is_left_alone() {
    let mesh =
        Mesh { positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y], indices: vec![0, 1, 2], ..Mesh::default() };
    let pm = mesh.simplify(&SimplifyOptions::default());
    assert_eq!(pm.collapse_count(), 0);
    assert_eq!(pm.indices_at(0), vec![0, 1, 2]);
    assert_eq!(pm.vertex_count_after(0), 3);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn interior_vertex_of_a_planar_quad_collapses_onto_the_first_corner() {
    // Square with an off-centre interior vertex 4. Its four collapses onto the corners all cost
    // exactly 0 (planar; a corner keeps its position), so the tie-break picks corner 0.
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 2.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.5, 0.7, 0.0),
    ];
    let mesh = Mesh { positions, indices: vec![0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4], ..Mesh::default() };
    let pm = mesh.simplify(&options(CollapseMode::Full, 2));
    assert_eq!(pm.collapse_count(), 1);
    let record = pm.collapses[0];
    assert_eq!(record.cost, 0.0);
    assert_eq!(record.new_vertex_count, 1);
    let new = record.first_new_vertex;
    assert_eq!(pm.positions[new as usize], Vec3::ZERO);
    assert_eq!(pm.parent[0], new);
    assert_eq!(pm.parent[4], new);
    assert_eq!(pm.survivor_source[new as usize], 0, "the corner survives");
    let mut tris: Vec<[u32; 3]> = pm.indices_at(1).chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    tris.sort();
    assert_eq!(tris, vec![[1, 2, new], [2, 3, new]]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn octahedron_edge_collapses_to_its_quadric_minimiser() {
    // Regular octahedron: for edge (+x, +y) the summed quadric is minimal at the midpoint
    // (0.5, 0.5, 0), where four of the eight face planes pass at distance 1/√3: the mean squared
    // distance is (4 · area / 3) / (8 · area) = 1/6.
    let positions = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let mut indices = Vec::new();
    for &x in &[0u32, 1] {
        for &y in &[2u32, 3] {
            for &z in &[4u32, 5] {
                // Orient outward: the sign of x·y·z decides the winding.
                let positive = (x == 0) ^ (y == 3) ^ (z == 5);
                indices.extend_from_slice(&if positive { [x, y, z] } else { [x, z, y] });
            }
        }
    }
    let mesh = Mesh { positions, indices, ..Mesh::default() };
    let pm = mesh.simplify(&options(CollapseMode::Full, 6));
    assert_eq!(pm.collapse_count(), 1);
    let record = pm.collapses[0];
    assert!((record.cost - 1.0 / 6.0).abs() < 1e-6, "cost {}", record.cost);
    assert!((record.distance - (1.0f32 / 6.0).sqrt()).abs() < 1e-6);
    let new = record.first_new_vertex as usize;
    let children: Vec<usize> = (0..6).filter(|&v| pm.parent[v] == new as u32).collect();
    assert_eq!(children.len(), 2);
    let midpoint = (pm.positions[children[0]] + pm.positions[children[1]]) * 0.5;
    assert!((pm.positions[new] - midpoint).length() < 1e-6, "{} vs {midpoint}", pm.positions[new]);
    check_invariants(&mesh, &pm, &[0, 1], true);
}

/// Splits the grid `mesh` (`nx` quads wide, from [`grid`]) along its column `x = column`: the
/// triangles right of it use duplicates of the column's vertices, appended in row order. Returns
/// the first duplicate's id.
fn split_column(mesh: &mut Mesh, nx: u32, column: u32) -> u32 {
    let base = mesh.positions.len() as u32;
    let rows = base / (nx + 1);
    let mut duplicate = vec![u32::MAX; base as usize];
    for j in 0..rows {
        let v = j * (nx + 1) + column;
        duplicate[v as usize] = base + j;
        mesh.positions.push(mesh.positions[v as usize]);
    }
    for tri in mesh.indices.chunks_exact_mut(3) {
        if tri.iter().any(|&v| v % (nx + 1) > column) {
            for v in tri.iter_mut().filter(|v| duplicate[**v as usize] != u32::MAX) {
                *v = duplicate[*v as usize];
            }
        }
    }
    base
}

/// A 4×4-quad grid whose middle column x = 2 is split: the right side's triangles use duplicate
/// vertices (ids 25..30) with a different u coordinate.
fn seam_grid() -> Mesh {
    let mut mesh = grid(4, 4, |_, _| 0.0);
    let base = split_column(&mut mesh, 4, 2);
    mesh.weights = vec![1.0];
    mesh.attributes = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(v, p)| if v as u32 >= base { p.x / 4.0 + 1.0 } else { p.x / 4.0 })
        .collect();
    mesh
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn seam_wedges_collapse_together() {
    let mesh = seam_grid();
    for mode in [CollapseMode::Full, CollapseMode::HalfEdge] {
        let pm = mesh.simplify(&options(mode, 0));
        let k_end = pm.collapse_count();
        assert!(pm.triangle_count_after(k_end) <= 8, "{mode:?}: {}", pm.triangle_count_after(k_end));
        // Some collapse slides the seam: two wedge pairs at x = 2 merge into two new vertices at
        // one position.
        let pm_ref = &pm;
        let children = |x: u32| (0..pm_ref.vertex_total()).filter(move |&y| pm_ref.parent[y] == x);
        let on_seam = |v: usize| pm_ref.positions[v].x == 2.0;
        let step = pm
            .collapses
            .iter()
            .find(|c| {
                c.new_vertex_count == 2
                    && (c.first_new_vertex..c.first_new_vertex + 2)
                        .all(|x| on_seam(x as usize) && children(x).filter(|&y| on_seam(y)).count() == 2)
            })
            .expect("the seam gets simplified");
        let (a, b) = (step.first_new_vertex as usize, step.first_new_vertex as usize + 1);
        assert_eq!(pm.positions[a], pm.positions[b]);
        // u stays on its side of the seam: the left wedge < 1, the right one ≥ 1.
        let (ua, ub) = (pm.attributes[a], pm.attributes[b]);
        assert!((ua < 1.0) != (ub < 1.0), "{mode:?}: {ua} {ub}");
        // No crack at any level: seam edges are shared by a triangle on each side.
        for k in 0..=k_end {
            let mut edges = std::collections::HashMap::<[u32; 4], i32>::new();
            for t in pm.indices_at(k).chunks_exact(3) {
                for e in 0..3 {
                    let (p, q) = (pm.positions[t[e] as usize], pm.positions[t[(e + 1) % 3] as usize]);
                    let (p, q) = ([p.x, p.y].map(f32::to_bits), [q.x, q.y].map(f32::to_bits));
                    let key = if p < q { [p[0], p[1], q[0], q[1]] } else { [q[0], q[1], p[0], p[1]] };
                    *edges.entry(key).or_default() += 1;
                }
            }
            for (key, count) in edges {
                let on_rim = |x: u32, y: u32| {
                    let (x, y) = (f32::from_bits(x), f32::from_bits(y));
                    x == 0.0 || x == 4.0 || y == 0.0 || y == 4.0
                };
                let rim = on_rim(key[0], key[1]) && on_rim(key[2], key[3]);
                assert!(count == 2 || (rim && count == 1), "{mode:?} level {k}: edge {key:?} has {count}");
            }
        }
        check_invariants(&mesh, &pm, &(0..=k_end).collect::<Vec<_>>(), false);
    }
}

/// A bumpy 6×6-quad grid split along its column x = 3 ([`split_column`]), with four channels
/// (normal xyz, u): the left side's vertices have `left` as normal, the right side's `right`, and
/// the right side's u is offset by `u_offset`.
fn split_grid(left: Vec3, right: Vec3, u_offset: f32) -> Mesh {
    let mut mesh = grid(6, 6, |i, j| 0.4 * ((i as f32 * 1.3).sin() + (j as f32 * 0.9).cos()));
    let base = split_column(&mut mesh, 6, 3);
    let right_side = |v: usize| v as u32 >= base || v % 7 > 3;
    mesh.attributes = (0..mesh.positions.len())
        .flat_map(|v| {
            let (normal, u) = if right_side(v) { (right, u_offset) } else { (left, 0.0) };
            let [x, y, z] = normal.normalize().to_array();
            [x, y, z, mesh.positions[v].x / 6.0 + u]
        })
        .collect();
    mesh.weights = vec![0.01, 0.01, 0.01, 1.0];
    mesh
}

/// Whether some collapse moved a wedge that merged with nothing. On [`split_grid`] only the split
/// column's vertices have two wedges, and along the column both pair up: so an interior vertex
/// collapsed onto the column and the survivor went to a free point.
fn wedge_moved_alone(pm: &clod_viewer::progressive::ProgressiveMesh) -> bool {
    (pm.input_vertex_count..pm.vertex_total()).any(|x| {
        let children: Vec<usize> = (0..pm.vertex_total()).filter(|&y| pm.parent[y] == x as u32).collect();
        matches!(children[..], [y] if pm.positions[y] != pm.positions[x])
    })
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_seam_moves_with_its_surface_and_a_crease_stays() {
    let opts = SimplifyOptions { normal_channel: Some(0), ..SimplifyOptions::default() };
    // One normal across the column, u split: a uv seam inside a smooth surface. Interior vertices
    // that collapse onto it go to their quadric's minimiser, carrying the seam along.
    let seam = split_grid(Vec3::Z, Vec3::Z, 1.0);
    let pm = seam.simplify(&opts);
    assert!(wedge_moved_alone(&pm), "no collapse onto the seam moved it");
    let rules = Rules::ALL.without(Rule::SeamsMoveWithSurface);
    assert!(
        !wedge_moved_alone(&seam.simplify(&SimplifyOptions { rules, ..opts })),
        "without the rule the seam stays"
    );
    check_invariants(&seam, &pm, &(0..=pm.collapse_count()).collect::<Vec<_>>(), false);
    // The normal turns by 74° across the column, u continuous: a crease. A collapse onto it keeps
    // the crease vertex where it is (its own line may still move along itself).
    let crease = split_grid(Vec3::new(-0.6, 0.0, 0.8), Vec3::new(0.6, 0.0, 0.8), 0.0);
    let pm = crease.simplify(&opts);
    assert!(!wedge_moved_alone(&pm), "a collapse onto the crease moved it");
    check_invariants(&crease, &pm, &(0..=pm.collapse_count()).collect::<Vec<_>>(), false);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn material_border_stays_where_it_is() {
    // Bumpy 8×6 grid, material 1 on the right of x = 3.
    let mut mesh = grid(8, 6, |i, j| {
        if i == 0 || j == 0 || i == 8 || j == 6 {
            0.0
        } else {
            ((i * 7 + j * 3) % 5) as f32 * 0.1
        }
    });
    mesh.materials = mesh.indices.chunks_exact(3).map(|t| u32::from(t.iter().any(|&v| v % 9 > 3))).collect();
    let pm = mesh.simplify(&options(CollapseMode::Full, 0));
    let k_end = pm.collapse_count();
    assert!(pm.triangle_count_after(k_end) < 20);
    for k in 0..=k_end {
        let tris = pm.indices_at(k);
        let mut edge_materials = std::collections::HashMap::<(u32, u32), Vec<u32>>::new();
        for (i, t) in tris.chunks_exact(3).enumerate() {
            let material = mesh.materials[pm.triangle_source[i] as usize];
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                edge_materials.entry((a.min(b), a.max(b))).or_default().push(material);
            }
        }
        for ((a, b), materials) in edge_materials {
            if materials.len() == 2 && materials[0] != materials[1] {
                for v in [a, b] {
                    assert_eq!(pm.positions[v as usize].x, 3.0, "level {k}: material border moved");
                }
            }
        }
    }
    check_invariants(&mesh, &pm, &(0..=k_end).collect::<Vec<_>>(), false);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn border_stays_straight() {
    let mut rng = meshgen::Rng(7);
    let heights: Vec<f32> = (0..13 * 11).map(|_| rng.signed() * 0.3).collect();
    let mesh = grid(12, 10, |i, j| {
        if i == 0 || j == 0 || i == 12 || j == 10 {
            0.0
        } else {
            heights[(j * 13 + i) as usize]
        }
    });
    // The rim's four sides: (axis held, its value).
    let sides = [(0, 0.0), (0, 12.0), (1, 0.0), (1, 10.0)];
    // How far `p` is from side `s` (a segment of the rectangle at z = 0).
    let off_side = |p: Vec3, (axis, value): (usize, f32)| {
        let (along, length) = if axis == 0 { (p.y, 10.0) } else { (p.x, 12.0) };
        let across = if axis == 0 { p.x } else { p.y } - value;
        let beyond = (-along).max(along - length).max(0.0);
        (across * across + p.z * p.z + beyond * beyond).sqrt()
    };
    let rim_corners =
        [Vec3::ZERO, Vec3::new(12.0, 0.0, 0.0), Vec3::new(0.0, 10.0, 0.0), Vec3::new(12.0, 10.0, 0.0)];
    for mode in [CollapseMode::Full, CollapseMode::HalfEdge] {
        let pm = mesh.simplify(&options(mode, 0));
        let k_end = pm.collapse_count();
        // Half-edge collapses keep input positions: border vertices stay on the rim exactly. With
        // optimal placement two border vertices merge at their quadric's minimiser, which the
        // border's penalty planes hold near the rim: off it by less than the bumps beside it
        // (0.3) rise.
        let tolerance = if mode == CollapseMode::HalfEdge { 0.0 } else { 0.3 };
        let mut fewest_with_corners = usize::MAX;
        for k in 0..=k_end {
            let tris = pm.indices_at(k);
            let mut edges = std::collections::HashMap::<(u32, u32), u32>::new();
            for t in tris.chunks_exact(3) {
                for e in 0..3 {
                    let (a, b) = (t[e], t[(e + 1) % 3]);
                    *edges.entry((a.min(b), a.max(b))).or_default() += 1;
                }
            }
            // Until a rim corner is cut away (no vertex within the tolerance of it; it costs a
            // penalty, so it comes last), every border edge follows one side of the rim.
            let kept_corners = rim_corners
                .iter()
                .filter(|&&corner| {
                    tris.iter().any(|&v| pm.positions[v as usize].distance(corner) <= tolerance)
                })
                .count();
            if kept_corners < 4 {
                continue;
            }
            fewest_with_corners = fewest_with_corners.min(tris.len() / 3);
            for ((a, b), count) in edges {
                if count == 1 {
                    let (p, q) = (pm.positions[a as usize], pm.positions[b as usize]);
                    let off =
                        sides.iter().map(|&s| off_side(p, s).max(off_side(q, s))).fold(f32::MAX, f32::min);
                    assert!(off <= tolerance, "{mode:?} level {k}: border edge {p} {q} is {off} off the rim");
                }
            }
        }
        assert!(fewest_with_corners <= 40, "{mode:?}: corners cut early, at {fewest_with_corners} triangles");
        check_invariants(&mesh, &pm, &(0..=k_end).collect::<Vec<_>>(), false);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_bent_plate_keeps_its_bulge() {
    // An open plate bent around the z axis: a 120° arc of radius 1, 8 facets around, 1 long. Its
    // long borders are lines whose vertices merge into free points: a least-squares fit of an
    // arc by fewer facets lies partly outside it, so merged border vertices leave the arc
    // outward, where points of the chords through the input vertices (radius < 1) never go.
    let mut positions = Vec::new();
    for z in [0.0, 1.0] {
        for i in 0..=8 {
            let angle = (-60.0 + 15.0 * i as f32).to_radians();
            positions.push(Vec3::new(angle.cos(), angle.sin(), z));
        }
    }
    let mut indices = Vec::new();
    for i in 0..8 {
        let (a, b, c, d) = (i, i + 1, i + 10, i + 9);
        indices.extend([a, b, c, a, c, d]);
    }
    let mesh = Mesh { positions, indices, ..Mesh::default() };
    let pm = mesh.simplify(&options(CollapseMode::Full, 2));
    let k_end = pm.collapse_count();
    assert_eq!(pm.triangle_count_after(k_end), 2);
    let radius = |v: u32| pm.positions[v as usize].truncate().length();
    let outermost = (0..=k_end).flat_map(|k| pm.indices_at(k)).map(radius).fold(0.0, f32::max);
    assert!(outermost > 1.001, "every vertex stayed on or inside the arc: {outermost}");
    // Not far out: the arc's sagitta over its whole 120° is 0.5.
    assert!(outermost < 1.5, "{outermost}");
    check_invariants(&mesh, &pm, &(0..=k_end).collect::<Vec<_>>(), false);
    // Without the rule the border vertices keep to their edges: chords, inside the arc.
    let rules = Rules::ALL.without(Rule::LinesMergeFree);
    let pm = mesh.simplify(&SimplifyOptions { rules, ..options(CollapseMode::Full, 2) });
    let outermost = (0..=pm.collapse_count())
        .flat_map(|k| pm.indices_at(k))
        .map(|v| pm.positions[v as usize].truncate().length())
        .fold(0.0, f32::max);
    assert!(outermost <= 1.0001, "without the rule a vertex left the arc: {outermost}");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn half_edge_mode_keeps_a_subset_of_input_vertices() {
    let mesh = meshgen::torus(16, 12, 0.02, 3);
    let pm = mesh.simplify(&options(CollapseMode::HalfEdge, 0));
    assert!(pm.collapse_count() > 100);
    let m = pm.attribute_count;
    for x in pm.input_vertex_count..pm.vertex_total() {
        let source = pm.survivor_source[x] as usize;
        assert_eq!(pm.positions[x], pm.positions[source]);
        assert_eq!(&pm.attributes[x * m..x * m + m], &pm.attributes[source * m..source * m + m]);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn full_mode_renormalises_normals() {
    let mesh = meshgen::torus(16, 12, 0.02, 5);
    let opts = SimplifyOptions { normal_channel: Some(0), ..SimplifyOptions::default() };
    let pm = mesh.simplify(&opts);
    for x in pm.input_vertex_count..pm.vertex_total() {
        let n = Vec3::from_slice(&pm.attributes[x * 5..x * 5 + 3]);
        assert!((n.length() - 1.0).abs() < 1e-5, "vertex {x}: {n}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn caller_quadrics_equal_to_the_default_give_the_same_result() {
    // No seams: one wedge per position, so both ways sum the same planes in the same order.
    let mut rng = meshgen::Rng(9);
    let heights: Vec<f32> = (0..15 * 15).map(|_| rng.signed() * 0.3).collect();
    let mesh = grid(14, 14, |i, j| heights[(j * 15 + i) as usize]);
    let mut quadrics = vec![Quadric::ZERO; mesh.positions.len()];
    for t in mesh.indices.chunks_exact(3) {
        let p = [0, 1, 2].map(|k| mesh.positions[t[k] as usize].as_dvec3());
        let q = Quadric::from_triangle(p[0], p[1], p[2]);
        for &v in t {
            quadrics[v as usize] += &q;
        }
    }
    let mut input = mesh.input();
    input.vertex_quadrics = Some(&quadrics);
    let given = simplify(&input, &SimplifyOptions::default()).unwrap();
    let default = mesh.simplify(&SimplifyOptions::default());
    assert_eq!(given.collapse_count(), default.collapse_count());
    assert_eq!(given.indices_at(given.collapse_count()), default.indices_at(default.collapse_count()));
    // A quadric pulling everything towards a far plane changes the result.
    let far = Quadric::from_plane(DVec3::Z, -5.0, 1.0);
    let skewed: Vec<Quadric> = quadrics
        .iter()
        .map(|q| {
            let mut q = *q;
            q += &far;
            q
        })
        .collect();
    input.vertex_quadrics = Some(&skewed);
    let other = simplify(&input, &SimplifyOptions::default()).unwrap();
    assert_ne!(other.positions, default.positions);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn max_error_and_target_stop_early() {
    let mesh = meshgen::torus(20, 14, 0.02, 11);
    // Both orders: the pass schedule ignores the target and the limit, so it holds for passes too.
    for schedule in [Schedule::Passes, Schedule::Strict] {
        let with = |options: SimplifyOptions| mesh.simplify(&SimplifyOptions { schedule, ..options });
        let full = with(SimplifyOptions::default());
        let k_mid = full.collapse_count() / 2;
        let limit = full.collapses[k_mid].cost;
        let limited = with(SimplifyOptions { max_mean_squared_error: limit, ..SimplifyOptions::default() });
        assert_eq!(limited.stop, StopReason::MaxErrorReached, "{schedule:?}");
        assert!(limited.collapses.iter().all(|c| c.cost <= limit), "{schedule:?}");
        // The same order up to the first collapse over the limit, which is skipped.
        let first_over = full.collapses.iter().position(|c| c.cost > limit).unwrap();
        assert!(limited.collapse_count() >= first_over, "{schedule:?}");
        assert_eq!(limited.collapses[..first_over], full.collapses[..first_over], "{schedule:?}");
        let targeted = with(options(CollapseMode::Full, 100));
        assert_eq!(targeted.stop, StopReason::TargetReached, "{schedule:?}");
        assert!(targeted.triangle_count_after(targeted.collapse_count()) <= 100);
        assert!(targeted.triangle_count_after(targeted.collapse_count() - 1) > 100);
        assert_eq!(targeted.collapses[..], full.collapses[..targeted.collapse_count()], "{schedule:?}");
    }
}

/// `max_distance` skips a collapse that would leave an input vertex farther than it from the
/// surface, which the mean squared error lets through: a plate with a ridge 1 high and 8 long,
/// held to 0.5 by the quadric floor alone, cuts the ridge down to 0.57–0.59 off; with the
/// distance floor too, it stops with every input vertex within 0.5.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn max_distance_keeps_a_ridge_that_the_quadric_floor_cuts() {
    let mesh = grid(14, 4, |i, j| if j == 2 && (2..=10).contains(&i) { 1.0 } else { 0.0 });
    // The farthest input vertex from the coarsest mesh.
    let farthest = |pm: &ProgressiveMesh| {
        let indices = pm.indices_at(pm.collapse_count());
        mesh.positions
            .iter()
            .map(|&q| {
                indices.chunks_exact(3).fold(f32::INFINITY, |nearest, t| {
                    let [a, b, c] = [0, 1, 2].map(|k| pm.positions[t[k] as usize]);
                    nearest.min(q.distance(closest_point_on_triangle(q, a, b, c)))
                })
            })
            .fold(0.0f32, f32::max)
    };
    let limit = 0.5;
    for schedule in [Schedule::Passes, Schedule::Strict] {
        let floor =
            SimplifyOptions { schedule, max_mean_squared_error: limit * limit, ..SimplifyOptions::default() };
        let quadric_only = mesh.simplify(&floor);
        assert!(farthest(&quadric_only) > 1.1 * limit, "{schedule:?}: {}", farthest(&quadric_only));
        let both = mesh.simplify(&SimplifyOptions { max_distance: limit, ..floor });
        assert_eq!(both.stop, StopReason::MaxErrorReached, "{schedule:?}");
        assert!(farthest(&both) <= limit, "{schedule:?}: {}", farthest(&both));
        // The rule is what holds it: left out, the distance is only measured.
        let rules = Rules::ALL.without(Rule::DistanceFloor);
        let unruled = mesh.simplify(&SimplifyOptions { max_distance: limit, rules, ..floor });
        assert_eq!(unruled.collapses, quadric_only.collapses, "{schedule:?}");
        // The same collapses up to the first one the distance floor skips.
        let same = both.collapses.iter().zip(&quadric_only.collapses).take_while(|(a, b)| a == b).count();
        assert!(same > 0 && same < quadric_only.collapse_count(), "{schedule:?}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn bad_input_is_an_error() {
    let mesh = tetrahedron();
    let run = |f: &dyn Fn(&mut Mesh)| {
        let mut m = mesh.clone();
        f(&mut m);
        simplify(&m.input(), &SimplifyOptions::default()).err()
    };
    assert_eq!(run(&|m| m.indices.push(0)), Some(SimplifyError::IndexCount(13)));
    assert!(matches!(
        run(&|m| m.indices[4] = 9),
        Some(SimplifyError::IndexOutOfRange { index: 9, triangle: 1, .. })
    ));
    assert_eq!(run(&|m| m.positions[2].y = f32::NAN), Some(SimplifyError::NonFinitePosition(2)));
    assert!(matches!(
        run(&|m| m.weights = vec![1.0]),
        Some(SimplifyError::AttributeLength { expected: 4, .. })
    ));
    assert_eq!(
        run(&|m| m.materials = vec![0, 1]),
        Some(SimplifyError::MaterialCount { found: 2, triangles: 4 })
    );
    let opts = SimplifyOptions { normal_channel: Some(0), ..SimplifyOptions::default() };
    assert!(matches!(simplify(&mesh.input(), &opts), Err(SimplifyError::NormalChannel { .. })));
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn progress_rises_to_the_target_about_fifty_times_and_changes_nothing() {
    let mesh = meshgen::torus(32, 24, 0.02, 9);
    let options = options(CollapseMode::Full, 100);
    let mut reports = Vec::new();
    let pm = clod_viewer::simplify::simplify_with_progress(&mesh.input(), &options, &mut |f| reports.push(f))
        .expect("valid input");
    assert!((40..=51).contains(&reports.len()), "{} reports", reports.len());
    assert!(reports.windows(2).all(|w| w[0] < w[1]), "{reports:?}");
    assert!(
        reports[0] > 0.0 && *reports.last().unwrap() >= 0.98 && *reports.last().unwrap() <= 1.0,
        "{reports:?}"
    );
    assert_eq!(pm, mesh.simplify(&options), "progress reporting changed the result");
}

/// A surface drawn twice (one mesh on two nodes) or doubled by a reversed copy (a double-sided
/// card) puts four triangles on every edge. Each copy is simplified as a surface of its own
/// (`clod_viewer::twins`): twice the triangles reach the single surface's error, where the copies
/// used to keep every edge, and with them the whole mesh, at full detail.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_doubled_surface_simplifies_like_the_single_one() {
    let single = grid(8, 8, |i, j| ((i * 7 + j * 3) % 5) as f32 * 0.1);
    let n = single.positions.len() as u32;
    let single_pm = single.simplify(&options(CollapseMode::Full, 16));
    let single_error = single_pm.error_after(single_pm.collapse_count());
    for reversed in [false, true] {
        let mut doubled = single.clone();
        doubled.positions.extend_from_within(..);
        for t in single.indices.chunks_exact(3) {
            let copy = if reversed { [t[0], t[2], t[1]] } else { [t[0], t[1], t[2]] };
            doubled.indices.extend(copy.map(|v| v + n));
        }
        let pm = doubled.simplify(&options(CollapseMode::Full, 32));
        let k = pm.collapse_count();
        assert_eq!(pm.triangle_count_after(k), 32, "reversed {reversed}: stopped at {:?}", pm.stop);
        let error = pm.error_after(k);
        assert!(error <= 1.05 * single_error, "reversed {reversed}: error {error} against {single_error}");
        check_invariants(&doubled, &pm, &spread_levels(&pm, 6), false);
    }
}
