//! Parts that go away whole: a closed part through a tetrahedron and a sheet to nothing, priced by
//! its clearance from the other parts (`Rule::ClosedPartsByClearance`), and open parts vanishing
//! within the level's reach (`Rule::OpenPartsWithinReach`), each held to the distance floor.

use super::options;
use crate::meshgen::{check_cursor, check_invariants, grid, Mesh};
use clod_viewer::metrics::closest_point_on_triangle;
use clod_viewer::simplify::{CollapseMode, Rule, Rules, Schedule, SimplifyOptions, StopReason};
use glam::Vec3;
pub(crate) fn tetrahedron() -> Mesh {
    Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
        indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
        ..Mesh::default()
    }
}

fn cube() -> Mesh {
    let positions =
        (0..8).map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32)).collect();
    // Outward-facing quads, two triangles each.
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let indices = quads.iter().flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]]).collect();
    Mesh { positions, indices, ..Mesh::default() }
}
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn tetrahedron_becomes_a_two_sided_sheet_then_vanishes() {
    // A closed part may go away whole: its first collapse leaves two triangles on the same three
    // corners facing opposite ways, its second removes both.
    let mesh = tetrahedron();
    let runs = [
        (CollapseMode::Full, Schedule::Strict),
        (CollapseMode::HalfEdge, Schedule::Strict),
        (CollapseMode::Full, Schedule::Passes),
    ];
    for (mode, schedule) in runs {
        let pm = mesh.simplify(&SimplifyOptions { schedule, ..options(mode, 1) });
        assert_eq!(pm.stop, StopReason::TargetReached, "{mode:?}");
        assert_eq!(pm.collapse_count(), 2, "{mode:?}");
        assert_eq!([0, 1, 2].map(|k| pm.triangle_count_after(k)), [4, 2, 0], "{mode:?}");
        let sheet = pm.indices_at(1);
        let (front, back) = (&sheet[..3], &sheet[3..]);
        assert!(
            [0, 1, 2].iter().any(|&r| [back[r], back[(r + 2) % 3], back[(r + 1) % 3]] == front),
            "{mode:?}: {sheet:?} is not one triangle facing both ways"
        );
        // Vanishing costs what the part spans: the unit tetrahedron's size, not nothing.
        assert!(pm.distance_after(2) > 0.1, "{mode:?}: {}", pm.distance_after(2));
        check_invariants(&mesh, &pm, &[0, 1, 2], true);
        check_cursor(&pm, &[2, 0, 1, 2]);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn closed_cube_goes_through_a_tetrahedron_and_a_sheet_to_nothing() {
    let mesh = cube();
    for mode in [CollapseMode::Full, CollapseMode::HalfEdge] {
        // Target 0 is "as far as it goes": the run ends when no collapse is left.
        let pm = mesh.simplify(&options(mode, 0));
        let k = pm.collapse_count();
        assert_eq!(pm.stop, StopReason::NoValidCollapse, "{mode:?}");
        assert_eq!(k, 6, "{mode:?}");
        assert_eq!((0..=k).map(|j| pm.triangle_count_after(j)).collect::<Vec<_>>(), [12, 10, 8, 6, 4, 2, 0]);
        check_invariants(&mesh, &pm, &(0..=k).collect::<Vec<_>>(), true);
        check_cursor(&pm, &[k, 0, 2, 1, k, 3, 5]);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_part_beside_another_vanishes_before_one_standing_alone() {
    // Two equal unit tetrahedra and a cube of side 10: one tetrahedron 0.1 from the cube's
    // face, the other 20 away from everything. A vanishing part costs its area times its
    // clearance², so the one beside the cube goes first (its surface is then still within about
    // its size of a surface), although the lone one comes first in the input, which breaks ties.
    let place = |mesh: Mesh, scale: f32, offset: Vec3| Mesh {
        positions: mesh.positions.iter().map(|&p| p * scale + offset).collect(),
        ..mesh
    };
    let parts = [
        place(tetrahedron(), 1.0, Vec3::new(30.0, 0.0, 0.0)),
        place(tetrahedron(), 1.0, Vec3::new(10.1, 0.0, 0.0)),
        place(cube(), 10.0, Vec3::ZERO),
    ];
    let mut mesh = Mesh::default();
    for part in &parts {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(&part.positions);
        mesh.indices.extend(part.indices.iter().map(|&i| i + base));
    }
    for schedule in [Schedule::Strict, Schedule::Passes] {
        // Both tetrahedra become sheets, then one of them vanishes: 20 → 18 → 16 → 14.
        let pm = mesh.simplify(&SimplifyOptions { schedule, ..options(CollapseMode::Full, 14) });
        let k = pm.collapse_count();
        assert_eq!(pm.triangle_count_after(k), 14, "{schedule:?}");
        let xs: Vec<f32> = pm.indices_at(k).iter().map(|&v| pm.positions[v as usize].x).collect();
        assert!(xs.iter().any(|&x| x >= 30.0), "{schedule:?}: the lone part vanished: {xs:?}");
        assert!(
            xs.iter().all(|&x| x >= 30.0 || x <= 10.0),
            "{schedule:?}: the part beside the cube is left: {xs:?}"
        );
        check_invariants(&mesh, &pm, &(0..=k).collect::<Vec<_>>(), true);
    }
    // The lone tetrahedron half as large: by its planes alone it is the cheaper part to lose, and
    // without the rule it goes first; priced by clearance, the one beside the cube still does.
    let mut small_lone = Mesh::default();
    for part in [
        place(tetrahedron(), 0.5, Vec3::new(30.0, 0.0, 0.0)),
        place(tetrahedron(), 1.0, Vec3::new(10.1, 0.0, 0.0)),
        place(cube(), 10.0, Vec3::ZERO),
    ] {
        let base = small_lone.positions.len() as u32;
        small_lone.positions.extend(&part.positions);
        small_lone.indices.extend(part.indices.iter().map(|&i| i + base));
    }
    let lone_left = |rules: Rules| {
        let pm = small_lone.simplify(&SimplifyOptions { rules, ..options(CollapseMode::Full, 14) });
        pm.indices_at(pm.collapse_count()).iter().any(|&v| pm.positions[v as usize].x >= 30.0)
    };
    assert!(lone_left(Rules::ALL), "priced by clearance, the part beside the cube goes first");
    assert!(
        !lone_left(Rules::ALL.without(Rule::ClosedPartsByClearance)),
        "without the rule the small lone part goes first"
    );
}

/// A flat 6 × 5 plate at z = 0 (60 triangles) and `triangles`, each a lone open part.
fn plate_with_triangles(triangles: &[[Vec3; 3]]) -> Mesh {
    let mut mesh = grid(6, 5, |_, _| 0.0);
    for triangle in triangles {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(triangle);
        mesh.indices.extend([base, base + 1, base + 2]);
    }
    mesh
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_open_part_vanishes_onto_a_surface_within_the_floor_and_not_beyond() {
    // A flat 6 × 5 plate (it goes down to two triangles without error), a lone triangle 0.5
    // above it and another 14 beyond its edge, both open parts. Under a floor of 1 the near one
    // goes (its points stay 0.5 from the plate's live triangles), the far one stays: 60 + 2
    // triangles become 3.
    let mesh = plate_with_triangles(&[
        [Vec3::new(2.0, 2.0, 0.5), Vec3::new(3.0, 2.0, 0.5), Vec3::new(2.0, 3.0, 0.5)],
        [Vec3::new(20.0, 0.0, 0.0), Vec3::new(21.0, 0.0, 0.0), Vec3::new(20.0, 1.0, 0.0)],
    ]);
    let runs = [
        (CollapseMode::Full, Schedule::Strict),
        (CollapseMode::HalfEdge, Schedule::Strict),
        (CollapseMode::Full, Schedule::Passes),
    ];
    for (mode, schedule) in runs {
        let pm = mesh.simplify(&SimplifyOptions { schedule, max_distance: 1.0, ..options(mode, 0) });
        let k = pm.collapse_count();
        assert_eq!(pm.triangle_count_after(k), 3, "{mode:?} {schedule:?}");
        let last = pm.indices_at(k);
        let zs: Vec<f32> = last.iter().map(|&v| pm.positions[v as usize].z).collect();
        assert!(zs.iter().all(|&z| z == 0.0), "{mode:?} {schedule:?}: the near triangle is left: {zs:?}");
        let far = last.iter().filter(|&&v| pm.positions[v as usize].x >= 20.0).count();
        assert_eq!(far, 3, "{mode:?} {schedule:?}: the far triangle vanished");
        check_invariants(&mesh, &pm, &(0..=k).collect::<Vec<_>>(), false);
        // Without the floor one of the plate and the far triangle goes onto the other (in the
        // strict order the far one, the plate having come down to one triangle between its
        // locked corners; in passes the plate), and the last part left cannot vanish.
        let pm =
            mesh.simplify(&SimplifyOptions { schedule, max_distance: f32::INFINITY, ..options(mode, 0) });
        let k = pm.collapse_count();
        assert_eq!(pm.triangle_count_after(k), 1, "{mode:?} {schedule:?}");
        let on_plate = pm.indices_at(k).iter().all(|&v| pm.positions[v as usize].x <= 6.0);
        assert!(schedule == Schedule::Passes || on_plate, "{mode:?} {schedule:?}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn parts_reaching_out_do_not_vanish_onto_each_other_past_the_floor() {
    // A cube of side 10, a rod (a tetrahedron from 0.1 to 2 beyond its face x = 10) and a knob
    // past the rod's tip (from 2.1 to 3 beyond it): an antenna with its ball. The knob may go
    // onto the rod, 0.1 away, but then the rod may not go: the knob's tip would stand 3 from
    // the cube, past the floor of 2.5. Priced against each other's input surface, both went.
    let tetrahedron_at = |x: f32, apex: f32| Mesh {
        positions: vec![
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(x, 1.0, 0.0),
            Vec3::new(x, 0.0, 1.0),
            Vec3::new(apex, 0.3, 0.3),
        ],
        ..tetrahedron()
    };
    let big_cube = Mesh {
        positions: cube().positions.iter().map(|&p| p * 10.0 - Vec3::new(0.0, 4.5, 4.5)).collect(),
        ..cube()
    };
    let mut mesh = Mesh::default();
    for part in [big_cube, tetrahedron_at(10.1, 12.0), tetrahedron_at(12.1, 13.0)] {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(&part.positions);
        mesh.indices.extend(part.indices.iter().map(|&i| i + base));
    }
    let tip = Vec3::new(13.0, 0.3, 0.3);
    for schedule in [Schedule::Strict, Schedule::Passes] {
        let floor = SimplifyOptions { schedule, max_distance: 2.5, ..options(CollapseMode::Full, 0) };
        let pm = mesh.simplify(&floor);
        let k = pm.collapse_count();
        let last = pm.indices_at(k);
        let from_tip = last
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|i| pm.positions[t[i] as usize]);
                closest_point_on_triangle(tip, a, b, c).distance(tip)
            })
            .fold(f32::INFINITY, f32::min);
        assert!(
            from_tip <= 2.5,
            "{schedule:?}: the knob's tip is {from_tip} from the last level ({} triangles)",
            last.len() / 3
        );
        assert!(last.len() / 3 > 12, "{schedule:?}: only the cube is left");
        check_invariants(&mesh, &pm, &(0..=k).collect::<Vec<_>>(), true);
        // Without the floor, in the strict order, everything but the cube goes (in passes the
        // cube goes instead: the last part standing cannot vanish).
        let pm = mesh.simplify(&SimplifyOptions { max_distance: f32::INFINITY, ..floor });
        let xs: Vec<f32> =
            pm.indices_at(pm.collapse_count()).iter().map(|&v| pm.positions[v as usize].x).collect();
        assert!(schedule == Schedule::Passes || xs.iter().all(|&x| x <= 10.0), "{schedule:?}: {xs:?}");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn open_parts_vanish_nearest_the_level_first() {
    // A flat 6 × 5 plate (down to two triangles without moving a point), a big lone triangle
    // 0.3 above it and a small one 0.6 above it. Priced by area times squared distance the small
    // one would go first (0.045 × 0.36 < 0.5 × 0.09); but each would leave its points farther
    // from the level than anything has been left, so both wait until nothing else can
    // collapse, and then the nearer goes first: at 3 triangles the small one is left.
    let mesh = plate_with_triangles(&[
        [Vec3::new(2.0, 2.0, 0.3), Vec3::new(3.0, 2.0, 0.3), Vec3::new(2.0, 3.0, 0.3)],
        [Vec3::new(4.0, 2.0, 0.6), Vec3::new(4.3, 2.0, 0.6), Vec3::new(4.0, 2.3, 0.6)],
    ]);
    for schedule in [Schedule::Strict, Schedule::Passes] {
        for mode in [CollapseMode::Full, CollapseMode::HalfEdge] {
            let floor = SimplifyOptions { schedule, max_distance: 1.0, ..options(mode, 3) };
            let pm = mesh.simplify(&floor);
            let k = pm.collapse_count();
            assert_eq!(pm.triangle_count_after(k), 3, "{mode:?} {schedule:?}");
            let zs: Vec<f32> = pm.indices_at(k).iter().map(|&v| pm.positions[v as usize].z).collect();
            let small = zs.iter().filter(|&&z| z == 0.6).count();
            assert_eq!(small, 3, "{mode:?} {schedule:?}: the small, far triangle is left: {zs:?}");
            check_invariants(&mesh, &pm, &(0..=k).collect::<Vec<_>>(), false);
        }
    }
    // The same parts, the small far triangle first in the input, where ties favour it going
    // first: the rule still lets the nearer one go first. Without it a vanishing triangle leaves
    // its points with no surface around them, which the distance floor measures as infinitely
    // far: neither goes, and the run stops at the floor with both.
    let reversed = plate_with_triangles(&[
        [Vec3::new(4.0, 2.0, 0.6), Vec3::new(4.3, 2.0, 0.6), Vec3::new(4.0, 2.3, 0.6)],
        [Vec3::new(2.0, 2.0, 0.3), Vec3::new(3.0, 2.0, 0.3), Vec3::new(2.0, 3.0, 0.3)],
    ]);
    let end = |rules: Rules| {
        let pm = reversed.simplify(&SimplifyOptions {
            max_distance: 1.0,
            rules,
            ..options(CollapseMode::Full, 3)
        });
        let zs: Vec<f32> =
            pm.indices_at(pm.collapse_count()).iter().map(|&v| pm.positions[v as usize].z).collect();
        (pm.stop, zs.iter().filter(|&&z| z == 0.6).count(), zs.iter().filter(|&&z| z == 0.3).count())
    };
    assert_eq!(end(Rules::ALL), (StopReason::TargetReached, 3, 0), "the small, far triangle is left");
    assert_eq!(end(Rules::ALL.without(Rule::OpenPartsWithinReach)), (StopReason::MaxErrorReached, 3, 3));
}
