use glam::camera::rh::{proj::directx, view};
use glam::{Mat4, Vec3};

use super::*;
use crate::render::plan::{BlendVariant, PassKind};
use crate::render::schedule::TransitionMode;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

/// A character of radius 1 at the origin whose 4 levels switch at 0, 20, 40 and 80 units.
const SWITCH: [f32; 4] = [0.0, 20.0, 40.0, 80.0];
const TRIANGLES: [usize; 4] = [1000, 500, 250, 125];
const METHODS: [Method; 3] =
    [Method::Popping, Method::AlphaBlend(BlendVariant::OpaqueFirst), Method::Geomorph];

fn palette() -> PosePalette {
    PosePalette {
        joints: 1,
        rows: 30,
        duration: 1.0,
        matrices: vec![Mat4::IDENTITY; 30],
        targets: 0,
        weights: Vec::new(),
        clip: Some(0),
    }
}

fn params() -> CrowdParams {
    CrowdParams {
        mode: TransitionMode::Time { seconds: 0.5 },
        hysteresis: 0.1,
        dolly: true,
        dolly_period: 16.0,
        tint_levels: false,
        full_detail: false,
    }
}

fn crowd(count: usize, seed: u64) -> Crowd {
    Crowd::new(count, (Vec3::new(0.0, 1.0, 0.0), 1.0), &SWITCH, 0.6, 1.0, seed)
}

/// Runs `seconds` of frames at 30 fps and returns the last frame.
fn run(c: &mut Crowd, seconds: f32, methods: &[Method]) -> CrowdFrame {
    let mut frame = CrowdFrame::default();
    let steps = (seconds * 30.0) as usize;
    for s in 0..=steps {
        let time = f64::from(s as f32 / 30.0);
        frame = c.advance(&params(), 1.0 / 30.0, time, time, 0.6, &SWITCH, &TRIANGLES, &palette(), methods);
    }
    frame
}

#[test]
fn a_seed_gives_the_same_crowd_and_frames() {
    let (mut a, mut b) = (crowd(300, 7), crowd(300, 7));
    assert_eq!(a, b);
    assert_eq!(run(&mut a, 3.0, &METHODS), run(&mut b, 3.0, &METHODS));
    assert_ne!(crowd(300, 8).instances, a.instances, "another seed, another crowd");
}

#[test]
fn the_crowd_has_its_count_and_spans_every_level() {
    for count in [1, 100, 400, 2000] {
        let c = crowd(count, 1);
        assert_eq!(c.instances.len(), count);
        if count >= 100 {
            let levels: std::collections::BTreeSet<usize> = c.instances.iter().map(|i| i.selected).collect();
            assert_eq!(levels.len(), SWITCH.len(), "{count} instances cover every level: {levels:?}");
        }
    }
    assert_eq!(crowd(1_000_000, 1).instances.len(), MAX_INSTANCES);
}

#[test]
fn neighbours_keep_their_distance() {
    let c = crowd(400, 3);
    for (k, a) in c.instances.iter().enumerate() {
        for b in &c.instances[k + 1..] {
            let d = (a.position - b.position).length();
            assert!(d >= MIN_SPACING * (1.0 - 2.0 * JITTER) - 1e-4, "{d}");
        }
    }
}

#[test]
fn per_level_counts_add_up_to_the_instances_drawn() {
    let mut c = crowd(400, 5);
    for seconds in [0.0, 1.0, 4.0, 8.0] {
        let f = run(&mut c, seconds, &METHODS);
        assert_eq!(f.stats.per_level.iter().sum::<usize>(), f.stats.drawn);
        assert!(f.stats.drawn > 0 && f.stats.drawn <= f.stats.instances);
        assert_eq!(f.views.len(), 3);
        for view in &f.views {
            for d in view {
                assert!((d.first + d.count) as usize <= f.instances.len());
            }
        }
        // Popping draws each visible instance once.
        assert_eq!(f.views[0].iter().map(|d| d.count).sum::<u32>() as usize, f.stats.drawn);
        assert_eq!(f.stats.triangles_full, f.stats.drawn * TRIANGLES[0]);
        assert!(f.stats.triangles[0] < f.stats.triangles_full, "LOD draws fewer triangles than full detail");
    }
}

#[test]
fn the_dolly_makes_transitions_and_each_moves_one_level() {
    let mut c = crowd(400, 9);
    let mut seen = 0;
    for s in 0..(16 * 30) {
        let time = f64::from(s as f32 / 30.0);
        let f = c.advance(&params(), 1.0 / 30.0, time, time, 0.6, &SWITCH, &TRIANGLES, &palette(), &METHODS);
        seen += f.stats.transitions;
        for i in &c.instances {
            assert!(i.transition.from.abs_diff(i.transition.to) <= 1, "{:?}", i.transition);
        }
        for d in f.views.iter().flatten() {
            if let Some(coarse) = d.morph_coarse {
                assert_eq!(coarse, d.level + 1, "geomorphs read the level's own ancestors");
            }
        }
    }
    assert!(seen > 100, "the dolly moves instances across switch distances: {seen}");
}

#[test]
fn views_order_opaque_draws_first_and_group_by_level() {
    let mut c = crowd(600, 11);
    let mut blended = false;
    for s in 0..(8 * 30) {
        let time = f64::from(s as f32 / 30.0);
        let f = c.advance(&params(), 1.0 / 30.0, time, time, 0.6, &SWITCH, &TRIANGLES, &palette(), &METHODS);
        let alpha = &f.views[1];
        let first_blend = alpha.iter().position(|d| d.pass != PassKind::Opaque).unwrap_or(alpha.len());
        assert!(alpha[first_blend..].iter().all(|d| d.pass != PassKind::Opaque), "{alpha:?}");
        blended |= first_blend < alpha.len();
        // Draws of one view cover disjoint, consecutive record ranges.
        for view in &f.views {
            for w in view.windows(2) {
                assert_eq!(w[0].first + w[0].count, w[1].first);
            }
        }
    }
    assert!(blended, "alpha-blending blends during transitions");
}

#[test]
fn one_method_in_every_view_gives_identical_records() {
    let mut c = crowd(300, 13);
    let f = run(&mut c, 5.0, &[Method::Geomorph; 3]);
    let records = |v: usize| -> Vec<InstanceRaw> {
        f.views[v]
            .iter()
            .flat_map(|d| f.instances[d.first as usize..(d.first + d.count) as usize].to_vec())
            .collect()
    };
    assert_eq!(records(0), records(1));
    assert_eq!(records(0), records(2));
}

#[test]
fn frustum_test_keeps_what_is_in_front_and_culls_the_rest() {
    let m = directx::perspective(1.0, 1.0, 0.1, 100.0) * view::look_at_mat4(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
    let planes = frustum_planes(&m);
    assert!(sphere_visible(&planes, Vec3::new(0.0, 0.0, -10.0), 1.0));
    assert!(!sphere_visible(&planes, Vec3::new(0.0, 0.0, 10.0), 1.0), "behind the eye");
    assert!(!sphere_visible(&planes, Vec3::new(50.0, 0.0, -10.0), 1.0), "far to the right");
    assert!(sphere_visible(&planes, Vec3::new(6.0, 0.0, -10.0), 1.0), "partly inside the right plane");
    assert!(!sphere_visible(&planes, Vec3::new(0.0, 0.0, -200.0), 1.0), "past the far plane");
}

#[test]
fn placement_turns_about_the_centre() {
    let c = Crowd::new(1, (Vec3::new(0.5, 1.0, 0.25), 1.0), &SWITCH, 1.0, 0.0, 1);
    let mut i = c.instances[0];
    i.heading = 0.9;
    let place = c.placement(&i);
    let turn = Mat4::from_rotation_y(place.w);
    // The character's centre lands on the instance's position.
    let centre = turn.transform_point3(Vec3::new(0.5, 1.0, 0.25)) + place.truncate();
    assert!((centre - i.position).length() < 1e-5, "{centre} vs {}", i.position);
}

#[test]
fn palette_rows_loop_with_the_clip() {
    let p = palette();
    assert_eq!(p.row_at(0.0), 0);
    assert_eq!(p.row_at(0.5), 15);
    assert_eq!(p.row_at(1.0), 0);
    assert_eq!(p.row_at(-0.25), p.row_at(0.75));
    assert_eq!(p.row_at(f64::NAN), 0);
    assert_eq!(p.texels().len(), 4 * 30);
}

#[test]
fn a_palette_of_more_than_512_joints_spans_texture_rows_per_pose() {
    let (joints, rows) = (700, 3);
    let matrices: Vec<Mat4> =
        (0..rows * joints).map(|i| Mat4::from_translation(Vec3::splat(i as f32))).collect();
    let p =
        PosePalette { joints, rows, duration: 1.0, matrices, targets: 0, weights: Vec::new(), clip: Some(0) };
    // Two texture rows of 512 joints per pose, three poses.
    assert_eq!(p.texture_size(), (2048, 6));
    let texels = p.texels();
    assert_eq!(texels.len(), 2048 * 6);
    // What `palette_matrix` in crowd.wgsl reads: rows_per_pose = 6 / 3 (the weights texture's
    // height), joint k of pose r at (4 · (k mod 512), 2r + k / 512).
    for (r, k) in [(0, 0), (1, 511), (1, 512), (2, 699)] {
        let at = (2 * r + k / 512) * 2048 + 4 * (k % 512);
        let m = Mat4::from_cols_array_2d(&[texels[at], texels[at + 1], texels[at + 2], texels[at + 3]]);
        assert_eq!(m, p.matrices[r * joints + k], "pose {r} joint {k}");
    }
    assert_eq!(p.weight_texels(true).len(), rows, "one weights texel row per pose");
}

#[test]
fn instance_record_layout_is_what_the_vertex_layout_reads() {
    assert_eq!(std::mem::size_of::<InstanceRaw>(), 32);
    assert_eq!(std::mem::offset_of!(InstanceRaw, place) as u64, draws::INSTANCE_OFFSETS[0]);
    assert_eq!(std::mem::offset_of!(InstanceRaw, packed) as u64, draws::INSTANCE_OFFSETS[1]);
}

#[test]
fn instance_records_pack_what_the_draw_asks_and_keep_t_and_threshold_to_the_bit() {
    let draw = InstanceDraw {
        row: 2047,
        dither_mode: 2,
        t: 0.123_456_79,
        opacity: 0.25,
        dither_threshold: 0.501,
        tint: [1.0, 0.0, 0.2, 0.35],
    };
    let raw = InstanceRaw::new([1.0, 2.0, 3.0, 0.5], &draw);
    assert_eq!(raw.place, [1.0, 2.0, 3.0, 0.5]);
    let back = raw.draw();
    assert_eq!((back.row, back.dither_mode), (2047, 2));
    assert_eq!(back.t.to_bits(), draw.t.to_bits());
    assert_eq!(back.dither_threshold.to_bits(), draw.dither_threshold.to_bits());
    assert!((back.opacity - 0.25).abs() <= 0.5 / 65535.0, "{}", back.opacity);
    for c in 0..4 {
        assert!((back.tint[c] - draw.tint[c]).abs() <= 0.5 / 255.0, "{:?}", back.tint);
    }
    // The ends are exact; out-of-range and NaN inputs clamp instead of spilling into other fields.
    let ends =
        InstanceRaw::new([0.0; 4], &InstanceDraw { opacity: 1.0, t: 1.0, ..InstanceDraw::default() }).draw();
    assert_eq!((ends.opacity, ends.t, ends.row, ends.dither_mode), (1.0, 1.0, 0, 0));
    let wild = InstanceDraw {
        row: u32::MAX,
        dither_mode: 99,
        opacity: f32::NAN,
        tint: [2.0, -1.0, f32::NAN, 0.0],
        ..draw
    };
    let wild = InstanceRaw::new([0.0; 4], &wild).draw();
    assert_eq!((wild.row, wild.dither_mode, wild.opacity), (4095, 15, 0.0));
    assert_eq!(wild.tint, [1.0, 0.0, 0.0, 0.0]);
}

#[test]
fn every_record_of_a_frame_unpacks_to_a_row_and_an_opacity_the_frame_asked_for() {
    let mut c = crowd(300, 21);
    let f = run(&mut c, 3.0, &METHODS);
    assert!(!f.instances.is_empty());
    for raw in &f.instances {
        let d = raw.draw();
        assert!(d.row < 30, "row {}", d.row);
        assert!(d.dither_mode <= 2 && (0.0..=1.0).contains(&d.opacity) && (0.0..=1.0).contains(&d.t));
    }
}

#[test]
fn morph_zones_move_between_neighbouring_levels() {
    let mut c = crowd(300, 17);
    let zones = CrowdParams { mode: TransitionMode::Distance { zone: 0.25 }, ..params() };
    let mut seen = 0;
    for s in 0..(16 * 30) {
        let time = f64::from(s as f32 / 30.0);
        let f = c.advance(&zones, 1.0 / 30.0, time, time, 0.6, &SWITCH, &TRIANGLES, &palette(), &METHODS);
        seen += f.stats.transitions;
        assert!(c.instances.iter().all(|i| i.transition.to <= i.transition.from + 1));
    }
    assert!(seen > 100, "{seen}");
}

#[test]
fn full_detail_draws_every_instance_at_level_zero() {
    let mut c = crowd(300, 19);
    let full = CrowdParams { full_detail: true, ..params() };
    let f = c.advance(&full, 1.0 / 30.0, 2.0, 2.0, 0.6, &SWITCH, &TRIANGLES, &palette(), &METHODS);
    assert_eq!(f.stats.per_level[0], f.stats.drawn);
    assert_eq!(f.stats.transitions, 0);
    for t in &f.stats.triangles {
        assert_eq!(*t, f.stats.triangles_full);
    }
    // LOD back on: every instance at rest on its level at once, as a new crowd starts.
    let f = c.advance(&params(), 1.0 / 30.0, 2.0, 2.0, 0.6, &SWITCH, &TRIANGLES, &palette(), &METHODS);
    assert_eq!(f.stats.transitions, 0);
    assert!(f.stats.per_level[0] < f.stats.drawn, "{:?}", f.stats.per_level);
}
