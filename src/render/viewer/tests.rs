use super::settings::{DistanceMode, Update};
use super::*;
use crate::render::plan::{DrawCall, Method, Morph};
use crate::render::schedule::distance_coordinate;
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

const ERRORS: [f32; 5] = [0.0, 0.001, 0.002, 0.004, 0.008];

fn model() -> ViewerModel {
    ViewerModel::new((Vec3::ZERO, 1.0), ERRORS.to_vec(), 900, 300)
}

/// A tiny deterministic generator (xorshift), so the random tests replay exactly.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

#[test]
fn the_first_frame_frames_the_character_at_rest() {
    let m = model();
    assert_eq!(m.distance, m.framing, "the dolly starts at the framing distance");
    let selected = m.schedule.selected;
    assert!(selected > 0, "these tiny errors allow a coarse level at once");
    let shown = m.plans.iter().map(|p| p.transition).collect::<Vec<_>>();
    assert_eq!(shown, [Transition::at(selected); 3], "the first frame is not a transition");
}

#[test]
fn every_view_makes_the_same_change_at_the_same_moment() {
    let mut m = model();
    m.apply(&Update { duration: Some(0.5), ..Default::default() });
    let switch = m.switch_distances();
    let framing = m.framing;
    // A camera that jumps several levels at once, back and forth, every 0.3 s.
    let script = [0.5, 3.5, 0.2, 2.5, 3.5, 0.5, 0.1, 3.5];
    let dt = 1.0 / 30.0;
    let mut behind = 0;
    for (step, &levels_out) in script.iter().cycle().take(40).enumerate() {
        let target = switch[(levels_out as usize).min(switch.len() - 1)].max(framing * 0.2) * 1.2;
        m.apply(&Update { distance: Some(target / framing), ..Default::default() });
        for _ in 0..9 {
            m.advance(dt);
            let shown = m.plans[0].transition;
            for (plan, method) in m.plans.iter().zip(m.settings.methods) {
                assert_eq!(plan.transition, shown, "step {step}: views disagree");
                match method {
                    Method::Popping => assert_eq!(plan.draws, vec![DrawCall::opaque_level(shown.to)]),
                    Method::Geomorph if shown.is_running() && shown.t > 0.0 => {
                        let (fine, coarse, t) = shown.fine_coarse();
                        assert_eq!(plan.draws[0].level, fine);
                        assert_eq!(plan.draws[0].morph, Some(Morph { coarse, t }));
                    }
                    _ => {}
                }
            }
            let state = m.state();
            assert!(state.views.iter().all(|v| v.transition == shown), "state() reports one change");
            assert_eq!(
                state.views.iter().map(|v| v.method).collect::<Vec<_>>(),
                ["popping", "alpha", "geomorph"]
            );
            // The shown level trails the selection by one running transition at most.
            behind = if m.schedule.selected != shown.to { behind + 1 } else { 0 };
            assert!(behind as f64 * dt <= 0.5 + dt, "step {step}: {behind} frames behind the selection");
        }
    }
}

#[test]
fn the_zone_coordinate_is_continuous_for_any_switches() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..200 {
        let mut switch = vec![0.0, 0.5 + 10.0 * rng.next()];
        for _ in 0..(1 + (rng.next() * 5.0) as usize) {
            // Equal switch distances a fifth of the time.
            let step = if rng.next() < 0.2 { 0.0 } else { 1.0 + 20.0 * rng.next() };
            switch.push(switch.last().unwrap() + step);
        }
        let zone = rng.next();
        let slope: f32 = switch.iter().skip(1).map(|&d| 1.0 / (d * zone.max(1e-6))).sum();
        let delta = 1e-3;
        let far = switch.last().unwrap() * 1.2;
        let mut x0 = distance_coordinate(0.0, &switch, zone);
        let mut d = 0.0;
        while d < far {
            d += delta;
            let x = distance_coordinate(d, &switch, zone);
            assert!(x >= x0, "non-decreasing: {switch:?} zone {zone} at {d}");
            if zone > 0.01 {
                assert!(
                    x - x0 <= slope * delta * 1.01 + 1e-4,
                    "jump {} at {d}: {switch:?} zone {zone}",
                    x - x0
                );
            }
            x0 = x;
        }
        assert!((x0 - (switch.len() - 1) as f32).abs() < 1e-4, "reaches the coarsest level");
    }
}

#[test]
fn the_slider_morphs_between_states_with_exact_ends() {
    let mut m = model();
    let levels = m.level_count();
    m.apply(&Update { continuous_triangles: Some(Some(1000)), duration: Some(1.0), ..Default::default() });
    m.advance(0.0);
    assert_eq!(m.continuous_pair(), Some((1000, 1000)));
    assert_eq!(m.plans[2].draws, vec![DrawCall::opaque_level(levels)]);
    // Coarsening 1000 → 300: the geomorph starts exactly at 1000 and ends exactly at 300.
    m.apply(&Update { continuous_triangles: Some(Some(300)), ..Default::default() });
    m.advance(0.0);
    assert_eq!(m.continuous_pair(), Some((1000, 300)));
    assert_eq!(m.plans[2].draws, vec![DrawCall::opaque_level(levels)], "t = 0 is state n");
    assert_eq!(m.plans[0].draws, vec![DrawCall::opaque_level(levels + 1)], "popping switched");
    m.advance(0.05);
    assert_eq!(m.plans[2].draws[0].morph, Some(Morph { coarse: levels + 1, t: 0.05 }));
    for _ in 0..20 {
        m.advance(0.05);
    }
    assert_eq!(m.continuous_triangles(), Some(300));
    assert_eq!(m.plans[2].draws, vec![DrawCall::opaque_level(levels)], "t = 1 is state m, alone");
    assert_eq!(m.continuous_pair(), Some((300, 300)));
    // Refining 300 → 2000 starts exactly at 300 (the coarser end of the morph).
    m.apply(&Update { continuous_triangles: Some(Some(2000)), ..Default::default() });
    m.advance(0.0);
    assert_eq!(m.continuous_pair(), Some((2000, 300)));
    assert_eq!(m.plans[2].draws[0].morph, Some(Morph { coarse: levels + 1, t: 1.0 }));
    // Dragging on: the next state waits for this morph, and the views never freeze.
    m.apply(&Update { continuous_triangles: Some(Some(2500)), ..Default::default() });
    for _ in 0..5 {
        m.advance(0.1);
    }
    assert_eq!(m.continuous_triangles(), Some(2000));
    for _ in 0..6 {
        m.advance(0.1);
    }
    assert_eq!(m.slider.map(|s| (s.from, s.to)), Some((2000, 2500)));
    m.apply(&Update { continuous_triangles: Some(None), ..Default::default() });
    m.advance(0.0);
    assert_eq!(m.continuous_pair(), None);
}

#[test]
fn slow_motion_slows_the_transition_only() {
    let mut m = model();
    m.apply(&Update {
        distance_mode: Some(DistanceMode::Manual),
        distance: Some(100.0),
        transition_speed: Some(0.1),
        duration: Some(0.5),
        ..Default::default()
    });
    m.advance(0.0);
    assert!(m.plans[0].transition.is_running());
    m.advance(0.1);
    assert!((m.plans[0].transition.t - 0.02).abs() < 1e-6, "{:?}", m.plans[0].transition);
    assert!((m.anim_time - 0.1).abs() < 1e-9, "the animation keeps its pace");
}

#[test]
fn the_magnifier_enlarges_without_changing_the_level() {
    let mut m = model();
    m.apply(&Update { distance_mode: Some(DistanceMode::Manual), distance: Some(3.0), ..Default::default() });
    m.advance(0.0);
    let plain = (m.schedule, m.switch_distances());
    m.apply(&Update { magnify: Some(4.0), ..Default::default() });
    m.advance(0.0);
    assert_eq!((m.schedule, m.switch_distances()), plain, "levels are chosen for the real size");
    assert_eq!(m.camera.zoom, 4.0);
}

#[test]
fn levels_arriving_later_start_at_the_selected_level() {
    let mut m = ViewerModel::new((Vec3::ZERO, 1.0), vec![0.0], 900, 300);
    assert_eq!((m.level_count(), m.plans[0].transition), (1, Transition::at(0)), "the full mesh alone");
    m.apply(&Update { distance_mode: Some(DistanceMode::Manual), distance: Some(3.0), ..Default::default() });
    m.advance(0.1);
    m.set_levels(ERRORS.to_vec());
    let selected = m.schedule.selected;
    assert!(selected > 0);
    assert!(
        m.plans.iter().all(|p| p.transition == Transition::at(selected)),
        "no transition from the finest"
    );
}

#[test]
fn the_dolly_sweeps_from_the_start_when_the_levels_arrive() {
    let mut m = ViewerModel::new((Vec3::ZERO, 1.0), vec![0.0], 900, 300);
    for _ in 0..30 {
        m.advance(0.1);
    }
    assert!(m.distance > 1.01 * m.framing, "the dolly moved while the full mesh was shown alone");
    m.set_levels(ERRORS.to_vec());
    assert_eq!((m.dolly_time, m.distance), (0.0, m.framing));
}

#[test]
fn the_demonstrations_switches_do_not_depend_on_the_window() {
    let demonstration = Update { preset: Some(super::preset::Preset::Demonstration), ..Default::default() };
    let switches = |width: u32, height: u32, update: &Update| {
        let mut m = ViewerModel::new((Vec3::ZERO, 1.0), ERRORS.to_vec(), width, height);
        m.apply(update);
        m.switch_distances().iter().map(|d| d / m.framing).collect::<Vec<f32>>()
    };
    let (small, large) = (switches(900, 300, &demonstration), switches(2700, 900, &demonstration));
    for (a, b) in small.iter().zip(&large) {
        // Within 1 %: the gaps between views make their shapes differ slightly.
        assert!((a - b).abs() <= 0.01 * b.max(0.1), "{small:?} vs {large:?}");
    }
    // In pixels (the realistic preset), a larger view puts them farther.
    let realistic = Update::default();
    assert!(switches(2700, 900, &realistic)[4] > 2.9 * switches(900, 300, &realistic)[4]);
}

#[test]
fn a_new_model_keeps_the_comparison_settings_and_its_own_clip_and_framing() {
    let mut previous = model();
    previous.apply(&Update {
        preset: Some(super::preset::Preset::Demonstration),
        meter: Some(false),
        flip: Some(false),
        methods: Some(([Method::Geomorph, Method::Popping, Method::Popping], 2)),
        speed: Some(0.5),
        by_distance: Some(true),
        clip: Some(None),
        paused: Some(true),
        yaw: Some(90.0),
        ..Default::default()
    });
    let mut next = ViewerModel::new((Vec3::ONE, 2.0), vec![0.0, 0.1], 900, 300);
    next.apply(&Update { clip: Some(Some(1)), ..Default::default() });
    next.keep_settings_from(&previous.settings);
    let (kept, own) = (&next.settings, Settings::default());
    assert_eq!((kept.meter, kept.flip, kept.speed, kept.by_distance), (false, false, 0.5, true));
    assert_eq!((kept.methods, kept.view_count), (previous.settings.methods, 2));
    // The demonstration's threshold still scales with the view, so the preset still shows.
    assert_eq!(
        (kept.tolerance_px, kept.tolerance_height),
        (previous.settings.tolerance_px, previous.settings.tolerance_height)
    );
    assert_eq!(
        (kept.magnify, kept.transition_speed),
        (previous.settings.magnify, previous.settings.transition_speed)
    );
    // The model's own: its clip, playing, framed from the default side.
    assert_eq!((kept.clip, kept.paused, kept.yaw_degrees), (Some(1), own.paused, own.yaw_degrees));
    assert_eq!(next.layout, layout(900, 300, 2), "laid out for the views kept");
    // Before the first frame: at rest at the level the kept settings select, no transition.
    assert_eq!(next.schedule.transition, Transition::at(next.schedule.selected));
    // Everything else is the previous viewer's: keeping twice changes nothing more.
    let once = next.settings.clone();
    next.keep_settings_from(&previous.settings);
    assert_eq!(next.settings, once);
}

#[test]
fn a_new_scene_begins_where_the_views_jump_alike_and_nowhere_else() {
    use crate::render::crowd::PosePalette;
    use glam::Mat4;
    let palette = |clip| PosePalette {
        joints: 1,
        rows: 1,
        duration: 0.0,
        matrices: vec![Mat4::IDENTITY],
        targets: 0,
        weights: Vec::new(),
        clip,
    };
    let mut m = model();
    let mut scenes = vec![m.scene];
    m.advance(0.1);
    scenes.push(m.scene);
    m.start_crowd(palette(None), vec![100, 50, 25, 12, 6], 0.0);
    scenes.push(m.scene);
    m.advance(0.1);
    scenes.push(m.scene);
    m.set_crowd_palette(palette(Some(1)));
    scenes.push(m.scene);
    // Another count lays the crowd out again.
    m.apply(&Update { crowd_count: Some(10), ..Default::default() });
    m.advance(0.1);
    scenes.push(m.scene);
    m.stop_crowd();
    scenes.push(m.scene);
    m.stop_crowd();
    scenes.push(m.scene);
    m.set_levels(ERRORS.to_vec());
    scenes.push(m.scene);
    // Every update resizes to the canvas's size, which is no change.
    m.apply(&Update { duration: Some(1.0), ..Default::default() });
    scenes.push(m.scene);
    m.resize(600, 300);
    scenes.push(m.scene);
    assert_eq!(scenes, [0, 0, 1, 1, 2, 3, 4, 4, 5, 5, 6]);
}
