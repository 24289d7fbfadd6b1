//! `tests/js/types/api-samples.json`: the JS layer's types ([`super::viewer_state`],
//! [`super::viewer_settings`], [`super::build_options`]) serialized with serde, each fully
//! populated (every key present, every list non-empty, every optional value set), once more with
//! every optional value absent, and the names each named value takes. `tests/js/dts.test.mjs`
//! checks `www/clod-viewer.d.ts` against it with the TypeScript compiler: every key declared, no
//! key declared that is not produced or taken, every value of a declared type.
//!
//! The samples are struct literals, so a field added to a type does not compile here until it has
//! a sample value. The test below fails when the committed file differs from what the types write;
//! `UPDATE_API_SAMPLES=1 cargo test --lib api_samples` writes it.

use serde_json::{json, Value};

use super::build_options::{BuildOptions, Pose, PoseName, TriangleCount};
use super::read::{Flag, List, Names, Number, OneOf, Text};
use super::viewer_settings::{SpikeOptions, ViewerSettings};
use super::viewer_state::*;
use crate::render::overlay::Overlay;
use crate::render::plan::{BlendVariant, Method};
use crate::render::viewer::preset::Preset;
use crate::render::viewer::settings::DistanceMode;
use crate::simplify::{CollapseMode, Schedule};

fn state(full: bool) -> ViewerState {
    let pop = MethodPop {
        silhouette: Num(0.098),
        shading: Num(0.423),
        transitions: 3,
        uncontrolled: UncontrolledPop { silhouette: Num(0.21), shading: Num(0.9) },
    };
    let by_method = |x: f32| FlipByMethod {
        popping: some(full, Num(x)),
        alpha: some(full, Num(x / 4.0)),
        geomorph: some(full, Num(x / 8.0)),
    };
    let flip = MeterFlip {
        ppd: Num(42.6),
        views: vec![Num(0.012), Num(0.004), Num(0.003)],
        pop: by_method(0.0134),
        uncontrolled: by_method(0.05),
    };
    let change = MeterChange {
        silhouette_mean: Num(0.01),
        silhouette_peak: Num(0.1),
        silhouette_per_second: Num(0.2),
        shading_mean: Num(0.05),
        shading_peak: Num(0.4),
        shading_per_second: Num(0.8),
    };
    let crowd = CrowdState {
        instances: 400,
        drawn: 380,
        per_level: vec![10, 370],
        transitions: 4,
        triangles_drawn: 120_000,
        triangles_full: 20_000_000,
        view_triangles: vec![40_000, 40_000, 40_000],
        palette_rows: 96,
    };
    fn some<T>(full: bool, x: T) -> Option<T> {
        full.then_some(x)
    }
    ViewerState {
        backend: "webgpu",
        adapter: "SwiftShader".into(),
        format: "bgra8unorm".into(),
        msaa: 4,
        composed: false,
        width: 1240,
        height: 420,
        triangles: 50_972,
        joints: 23,
        clips: vec!["Walk".into()],
        clip_durations: vec![Num(1.2)],
        clip: some(full, 0),
        levels: vec![LevelState { triangles: 50_972, error: Num(0.0) }],
        switch: vec![Num(12.5)],
        levels_stop: some(full, "the levels stop at 988 of 3840 triangles (26 %)".to_string()),
        build_ms: Num(812.5),
        built_off_main_thread: true,
        lod_from: some(full, "build"),
        selected: 0,
        distance: Num(1.5),
        fovy: Num(0.83),
        anim_time: Num(0.4),
        paused: false,
        speed: Num(1.0),
        yaw: Num(30.0),
        pitch: Num(8.6),
        pan: [Num(0.0), Num(0.1)],
        distance_mode: OneOf(DistanceMode::Dolly),
        overlay: OneOf(Overlay::None),
        transition: OneOf(TransitionBy::Time),
        duration: Num(0.5),
        zone: Num(0.2),
        variant: OneOf(BlendVariant::OpaqueFirst),
        transition_speed: Num(1.0),
        magnify: Num(1.0),
        meter: MeterState {
            on: true,
            flip_on: true,
            size: [Num(256.0), Num(256.0)],
            transitions: 3,
            samples: 600,
            gaps: 0,
            popping: some(full, pop),
            alpha: some(full, pop),
            geomorph: some(full, pop),
            changes: vec![change],
            flip: some(full, flip),
        },
        continuous_triangles: some(full, 4000),
        max_triangles: 50_972,
        stacked: false,
        views: vec![ViewState {
            method: "popping",
            level: 2,
            to: 3,
            t: Num(0.25),
            triangles: 6000,
            draws: 2,
            rect: [0, 0, 413, 420],
        }],
        frames: 120,
        morph_targets: 0,
        morphs: true,
        mode: OneOf(ViewerMode::Single),
        crowd: some(full, crowd),
        preset: PresetState {
            name: some(full, OneOf(Preset::Demonstration)),
            tolerance_px: Num(2.4),
            values: vec![PresetValueState {
                key: OneOf(PresetKey("tolerance")),
                label: "screen-space error allowed",
                value: Num(2.4),
                demonstration: Num(2.4),
                realistic: Num(0.5),
            }],
        },
        errors: vec!["the GPU reported an error".into()],
        warnings: vec!["dropped 2 point primitives".into()],
    }
}

fn settings() -> ViewerSettings {
    let n = |x| Some(Number(x));
    ViewerSettings {
        paused: Some(Flag(true)),
        time: n(1.5),
        speed: n(0.5),
        clip: Some(Some(Text("Walk".into()))),
        distance_mode: Some(OneOf(DistanceMode::Manual)),
        distance: n(2.0),
        dolly_period: n(12.0),
        yaw: n(30.0),
        pitch: n(10.0),
        pan: Some(List(vec![Number(0.1), Number(-0.2)])),
        reset_camera: Some(Flag(true)),
        tolerance: n(4.0),
        hysteresis: n(0.1),
        transition: Some(OneOf(TransitionBy::Distance)),
        duration: n(0.5),
        zone: n(0.2),
        transition_speed: n(0.25),
        magnify: n(4.0),
        meter: Some(Flag(false)),
        flip: Some(Flag(false)),
        variant: Some(OneOf(BlendVariant::Dither)),
        methods: Some(List(vec![OneOf(Method::Popping), OneOf(Method::Geomorph)])),
        continuous_triangles: Some(Some(Number(4000.0))),
        overlay: Some(OneOf(Overlay::Wireframe)),
        mode: Some(OneOf(ViewerMode::Crowd)),
        count: n(400.0),
        crowd_lod: Some(Flag(false)),
        morphs: Some(Flag(true)),
        preset: Some(OneOf(Preset::Realistic)),
    }
}

fn names<T: Names>() -> Value {
    json!(T::NAMES)
}

/// Everything `api-samples.json` holds.
fn samples() -> Value {
    let history = MeterHistory {
        methods: vec!["popping", "alpha"],
        samples: vec![HistorySample {
            time: Num(1.25),
            transition_running: true,
            views: vec![(Num(0.1), Num(0.4)), (Num(0.01), Num(0.03))],
        }],
        steps: vec![vec![Num(0.05), Num(0.2), Num(0.0), Num(0.0)]],
        flip: vec![vec![Num(0.012), Num(0.01), Num(0.003), Num(0.0)]],
    };
    let replay = Replay {
        methods: vec!["popping", "geomorph"],
        levels: [2, 3],
        size: [256, 256],
        region: [40, 60, 85, 85],
        frames: vec![ReplayFrame {
            frame: 118,
            time: 3.25,
            t: 0.5,
            views: vec![Rgba8(vec![255, 0, 0, 255])],
        }],
        curves: ReplayCurves {
            frame: vec![118, 119],
            time: vec![3.25, 3.5],
            running: vec![false, true],
            silhouette: vec![vec![0.1, 0.2]],
            shading: vec![vec![0.5, 0.6]],
            flip: vec![vec![0.01, 0.02]],
            step_silhouette: vec![vec![0.0, 0.1]],
            step_flip: vec![vec![0.0, 0.01]],
        },
    };
    let flip = FlipResult { mean: Num(0.04781), p99: Num(0.2715), max: Num(0.5), ppd: Num(67.02) };
    let spike = PopSpike {
        popping: Some(Num(4.5)),
        alpha: Some(Num(0.4)),
        geomorph: Some(Num(0.3)),
        variant: OneOf(BlendVariant::OpaqueFirst),
        level: 6,
        frames: 96,
        at: Num(1.0),
        sweep: Num(0.008),
        duration: Num(0.8),
        views: vec![SpikeView { method: "popping", largest: Num(4.5), series: vec![Num(0.0), Num(4.5)] }],
    };
    let spike_none = PopSpike { popping: None, alpha: None, geomorph: None, ..spike.clone() };
    let build = BuildOptions {
        pose: Some(Pose::ClipFrame { clip: "Walk".into(), time: 0.5 }),
        levels: Some(List(vec![TriangleCount(4000), TriangleCount(1000)])),
        mode: Some(OneOf(CollapseMode::HalfEdge)),
        weights: Some(OneOf(WeightRule::Survivor)),
        schedule: Some(OneOf(Schedule::Passes)),
        max_error: Some(Number(0.05)),
        on_progress: None,
    };
    let build_named = BuildOptions { pose: Some(Pose::Named(OneOf(PoseName::Bind))), ..Default::default() };
    json!({
        "about": "Written by `cargo test` (src/js_api/samples.rs) from the JS layer's Rust types; checked against www/clod-viewer.d.ts by tests/js/dts.test.mjs. Do not edit: UPDATE_API_SAMPLES=1 cargo test --lib api_samples",
        "ViewerState": { "full": state(true), "empty": state(false), "names": {
            "distanceMode": names::<DistanceMode>(), "overlay": names::<Overlay>(),
            "transition": names::<TransitionBy>(), "mode": names::<ViewerMode>(),
            "preset.name": names::<Preset>(), "preset.values.key": names::<PresetKey>(),
        } },
        "ViewerSettings": { "full": settings(),
            "nulls": { "clip": null, "continuousTriangles": null },
            "names": {
                "distanceMode": names::<DistanceMode>(), "transition": names::<TransitionBy>(),
                "variant": names::<BlendVariant>(), "overlay": names::<Overlay>(),
                "mode": names::<ViewerMode>(), "methods": names::<Method>(),
                "preset": names::<Preset>(),
            } },
        "MeterHistory": { "full": history },
        "Replay": { "full": replay },
        "FlipResult": { "full": flip },
        "PopSpike": { "full": spike, "empty": spike_none, "names": { "variant": names::<BlendVariant>() } },
        "PopSpikeOptions": { "full": SpikeOptions { level: Some(Number(3.0)), frames: Some(Number(48.0)), sweep: Some(Number(0.01)), at: Some(Number(1.0)) } },
        "BuildOptions": { "full": build, "empty": BuildOptions::default(), "named": build_named, "names": {
            "pose": names::<PoseName>(), "mode": names::<CollapseMode>(),
            "weights": names::<WeightRule>(), "schedule": names::<Schedule>(),
        } },
    })
}

use crate::clod::WeightRule;

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn api_samples_are_what_the_types_write() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/js/types/api-samples.json");
    let written = serde_json::to_string_pretty(&samples()).unwrap() + "\n";
    if std::env::var_os("UPDATE_API_SAMPLES").is_some() {
        std::fs::write(path, &written).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == written,
        "tests/js/types/api-samples.json is not what the JS layer's types write: run\n  UPDATE_API_SAMPLES=1 cargo test --lib api_samples\nthen update www/clod-viewer.d.ts until `node --test tests/js/dts.test.mjs` passes"
    );
}

/// The samples read back as the options they are: every key of the full settings, spike options
/// and build options is taken, and the full settings become an update without error.
#[test]
fn the_samples_of_what_javascript_passes_in_are_accepted() {
    use super::read::read_json;
    let s = samples();
    let text = |v: &Value| v.to_string();
    let settings: ViewerSettings = read_json("setState", &text(&s["ViewerSettings"]["full"])).unwrap();
    assert_eq!(settings, self::settings());
    settings.update(&["Walk".to_string()]).unwrap();
    let nulls: ViewerSettings = read_json("setState", &text(&s["ViewerSettings"]["nulls"])).unwrap();
    assert_eq!((nulls.clip, nulls.continuous_triangles), (Some(None), Some(None)));
    let _: SpikeOptions = read_json("measurePopSpike", &text(&s["PopSpikeOptions"]["full"])).unwrap();
    for which in ["full", "named", "empty"] {
        let build: BuildOptions = read_json("buildClod", &text(&s["BuildOptions"][which])).unwrap();
        assert_eq!(serde_json::to_value(&build).unwrap(), s["BuildOptions"][which]);
    }
}
