//! The viewer page's API (feature `web`): `Viewer.create(canvas, glbBytes, options)` loads a
//! character, builds its articulated progressive mesh and LOD chain, and sets up the renderer;
//! `viewer.frame(nowMs)` advances the shared clock, camera and LOD schedule and draws the three
//! views; `viewer.setState({...})` changes settings (the page's controls and the tests' hook use
//! the same call); `viewer.state()` reports what each view shows for the labels.
//!
//! Times are milliseconds from JavaScript (`performance.now()`), seconds inside. Distances given
//! to and reported by the page are multiples of the *framing distance* (the character's bounding
//! sphere fills the view's height at 1).

mod pop_spike;
mod settings;

use std::cell::RefCell;
use std::rc::Rc;

use glam::{Mat4, Vec3};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use crate::character::Character;
use crate::clod::{self, Clod, ClodOptions};
use crate::import;
use crate::render::camera::{self, OrbitCamera, FOVY};
use crate::render::gpu::{next_task, BackendChoice, FrameInput, Renderer};
use crate::render::layout::{layout, Layout};
use crate::render::lod_source::LodSource;
use crate::render::overlay::bone_segments;
use crate::render::plan::{plan_view, Method, ViewPlan};
use crate::render::schedule::{self, Schedule};
use crate::render::uniforms::CameraRaw;
use settings::{DistanceMode, Settings};

/// Longest step of the clocks per frame, seconds: a tab that was hidden for a minute resumes
/// where it was instead of jumping.
const MAX_STEP: f64 = 0.1;

/// One viewer on one canvas.
#[wasm_bindgen]
pub struct Viewer {
    inner: Rc<RefCell<Inner>>,
}

struct Inner {
    character: Character,
    clod: Option<Clod>,
    lod: LodSource,
    renderer: Renderer,
    settings: Settings,
    schedule: Schedule,
    /// Animation clock, seconds.
    anim_time: f64,
    /// Dolly clock, seconds (runs while the animation is paused, so a paused pose can be dollied).
    dolly_time: f64,
    last_now_ms: Option<f64>,
    camera: OrbitCamera,
    framing: f32,
    distance: f32,
    layout: Layout,
    plans: [ViewPlan; 3],
    camera_raw: CameraRaw,
    skin: Vec<Mat4>,
    /// The skeleton overlay's line list of the same pose (model space; see `bone_segments`).
    bones: Vec<[f32; 3]>,
    frames: u64,
    errors: Vec<String>,
    warnings: Vec<String>,
    build_ms: f64,
    /// Whether the LOD chain came from `options.clod` (a worker) rather than this thread.
    built_off_main_thread: bool,
}

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

#[wasm_bindgen]
impl Viewer {
    /// Loads a character, builds (or takes) its LOD chain and starts the renderer on `canvas`.
    ///
    /// `bytes` is a `.glb`, or a `.gltf`'s JSON whose external buffers and images come from
    /// `options.resolve(uri) → Uint8Array | null`. Other options: `backend`, `"webgpu"` (default)
    /// or `"webgl2"` (the `webgl` build only); `clod`, the bytes of `Character.buildClodBytes` for
    /// this same file (built in a worker, so the page never freezes), with `buildMs` its build
    /// time; without `clod` the chain is built here, on the calling thread.
    ///
    /// Rejects with an `Error` naming the problem: a file the importer refuses, LOD bytes that do
    /// not belong to this file, no adapter or device for the backend, too many joints, an
    /// undecodable texture.
    pub async fn create(
        canvas: web_sys::HtmlCanvasElement,
        bytes: Vec<u8>,
        options: JsValue,
    ) -> Result<Viewer, JsError> {
        let backend = settings::get_string(&options, "backend").unwrap_or_else(|| "webgpu".into());
        let choice = match backend.as_str() {
            "webgpu" => BackendChoice::WebGpu,
            "webgl2" if cfg!(feature = "webgl") => BackendChoice::WebGl2,
            "webgl2" => return Err(JsError::new("this build has no WebGL2 backend; load the webgl build")),
            other => {
                return Err(JsError::new(&format!("unknown backend {other:?}; use \"webgpu\" or \"webgl2\"")))
            }
        };
        let resolve = settings::get(&options, "resolve").and_then(|f| f.dyn_into::<js_sys::Function>().ok());
        let mut resolver = |uri: &str| -> Option<Vec<u8>> {
            let value = resolve.as_ref()?.call1(&JsValue::NULL, &JsValue::from_str(uri)).ok()?;
            let array = value.dyn_into::<js_sys::Uint8Array>().ok()?;
            Some(array.to_vec())
        };
        let character = import::from_bytes(&bytes, &mut resolver).map_err(js_error)?;
        drop(bytes);
        next_task().await;
        let mut warnings = character.warnings.clone();
        let prebuilt = settings::get(&options, "clod").and_then(|c| c.dyn_into::<js_sys::Uint8Array>().ok());
        let built_off_main_thread = prebuilt.is_some();
        let started = js_sys::Date::now();
        let clod = match prebuilt {
            Some(encoded) => Some(clod::bytes::decode(&encoded.to_vec(), &character).map_err(|e| {
                JsError::new(&format!("the LOD chain built in the worker does not fit: {e}"))
            })?),
            None => match clod::build(&character, &ClodOptions::default(), &mut |_| {}) {
                Ok(c) => Some(c),
                Err(e) => {
                    warnings.push(format!("no LOD chain ({e}); showing the full mesh only"));
                    None
                }
            },
        };
        next_task().await;
        let lod = match &clod {
            Some(c) => LodSource::from_clod(&character, c),
            None => LodSource::full_mesh(&character),
        };
        next_task().await;
        let build_ms = match settings::get(&options, "buildMs").and_then(|v| v.as_f64()) {
            Some(ms) if built_off_main_thread => ms,
            _ => js_sys::Date::now() - started,
        };
        let renderer = Renderer::new(canvas, choice, &character, &lod).await.map_err(js_error)?;
        let (center, radius) = rest_sphere(&character);
        let framing = camera::framing_distance(radius);
        let camera = OrbitCamera {
            target: center,
            radius,
            distance: framing,
            yaw: 0.0,
            pitch: camera::DEFAULT_PITCH,
            pan: glam::Vec2::ZERO,
        };
        let (w, h) = renderer.size();
        let empty = ViewPlan { draws: Vec::new(), level: 0, t: 0.0 };
        let inner = Inner {
            character,
            clod,
            lod,
            renderer,
            settings: Settings::default(),
            schedule: Schedule::FINEST,
            anim_time: 0.0,
            dolly_time: 0.0,
            last_now_ms: None,
            camera,
            framing,
            distance: framing,
            layout: layout(w, h, 3),
            plans: [empty.clone(), empty.clone(), empty],
            camera_raw: CameraRaw::zeroed(),
            skin: Vec::new(),
            bones: Vec::new(),
            frames: 0,
            errors: Vec::new(),
            warnings,
            build_ms,
            built_off_main_thread,
        };
        Ok(Viewer { inner: Rc::new(RefCell::new(inner)) })
    }

    /// Advances the clocks to `now_ms` (milliseconds, e.g. `performance.now()`) and draws.
    ///
    /// Throws only when called while `readPixels` or `measurePopSpike` is still running.
    pub fn frame(&self, now_ms: f64) -> Result<(), JsError> {
        let mut inner = self
            .inner
            .try_borrow_mut()
            .map_err(|_| JsError::new("viewer busy (readPixels or measurePopSpike running)"))?;
        inner.advance(now_ms);
        inner.draw();
        Ok(())
    }

    /// Resizes the drawing buffer (framebuffer pixels: CSS size × devicePixelRatio).
    pub fn resize(&self, width: u32, height: u32) -> Result<(), JsError> {
        let mut inner = self.inner.try_borrow_mut().map_err(|_| JsError::new("viewer busy"))?;
        inner.renderer.resize(width, height);
        let (w, h) = inner.renderer.size();
        let count = inner.settings.view_count;
        inner.layout = layout(w, h, count);
        Ok(())
    }

    /// Changes settings; unknown keys are an error (a typo should not pass silently).
    /// Keys: `paused`, `time` (animation seconds), `speed`, `clip`, `distanceMode`
    /// (`"dolly"|"manual"`), `distance` (× framing distance), `dollyPeriod`, `yaw` (degrees),
    /// `pitch` (degrees, clamped to ±85), `pan` (`[x, y]`, × framing distance, moves the point
    /// looked at along the view's right and up), `resetCamera` (`true`: yaw, pitch, pan and the
    /// manual distance back to their defaults, before the call's other keys),
    /// `tolerance` (pixels), `hysteresis` (fraction), `transition` (`"time"|"distance"`),
    /// `duration` (seconds per level), `zone` (fraction), `variant`
    /// (`"naive"|"opaque-first"|"dither"`), `methods` (one to three of
    /// `"popping"|"alpha"|"geomorph"`: the views, in order), `continuousTriangles` (number, or null
    /// for off), `overlay` (`"none"|"wireframe"|"levels"|"skeleton"`: triangle edges, a colour per level,
    /// or the bones of the current pose, on every view).
    #[wasm_bindgen(js_name = setState)]
    pub fn set_state(&self, state: JsValue) -> Result<(), JsError> {
        let mut inner = self.inner.try_borrow_mut().map_err(|_| JsError::new("viewer busy"))?;
        let clips: Vec<String> = inner.character.clips.iter().map(|c| c.name.clone()).collect();
        let update = settings::parse_update(&state, &clips).map_err(|e| JsError::new(&e))?;
        if let Some(time) = update.time {
            inner.anim_time = time;
        }
        if let Some(triangles) = update.continuous_triangles {
            inner.set_continuous(triangles);
        }
        update.apply(&mut inner.settings);
        let (w, h) = inner.renderer.size();
        let count = inner.settings.view_count;
        inner.layout = layout(w, h, count);
        Ok(())
    }

    /// What the views show, for the page: `{ backend, adapter, levels: [{triangles, error}],
    /// switch (each level's switch distance, × framing), selected, coordinate, distance (× framing),
    /// stacked, views: [{method, level, triangles, t, rect}], frames, errors, warnings, ... }`
    /// (see `Inner::state_json`).
    pub fn state(&self) -> Result<JsValue, JsError> {
        let mut inner = self.inner.try_borrow_mut().map_err(|_| JsError::new("viewer busy"))?;
        let errors = inner.renderer.take_errors();
        inner.errors.extend(errors);
        js_sys::JSON::parse(&inner.state_json()).map_err(|_| JsError::new("state is not JSON"))
    }

    /// Draws the current frame again offscreen and resolves to `{ width, height, data }` (RGBA8,
    /// sRGB, top row first). Nothing else may be called on the viewer until it resolves.
    #[wasm_bindgen(js_name = readPixels)]
    // The borrow is held across the readback on purpose: it keeps `frame` and the setters out
    // (they get a "busy" error from `try_borrow_mut`) until the copy is read.
    #[allow(clippy::await_holding_refcell_ref)]
    pub fn read_pixels(&self) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let guard = inner.try_borrow_mut().map_err(|_| JsValue::from_str("viewer busy"))?;
            let input = guard.frame_input();
            let pixels =
                guard.renderer.read_pixels(&input).await.map_err(|e| JsValue::from_str(&e.to_string()))?;
            let out = js_sys::Object::new();
            let set = |k: &str, v: JsValue| js_sys::Reflect::set(&out, &k.into(), &v).map(|_| ());
            set("width", pixels.width.into())?;
            set("height", pixels.height.into())?;
            set("data", js_sys::Uint8Array::from(pixels.rgba.as_slice()).into())?;
            Ok(out.into())
        })
    }

    /// Reads back the mip levels of material `material`'s base-colour texture and resolves to an
    /// array of `{ width, height, mean: [r, g, b, a] }`, level 0 first, means in linear light
    /// (0–1); empty for a material without a texture. For tests: the levels are made on the GPU.
    #[wasm_bindgen(js_name = textureLevels)]
    #[allow(clippy::await_holding_refcell_ref)] // as in read_pixels: the viewer stays locked meanwhile
    pub fn texture_levels(&self, material: usize) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let guard = inner.try_borrow().map_err(|_| JsValue::from_str("viewer busy"))?;
            let levels = guard
                .renderer
                .texture_levels(material)
                .await
                .map_err(|e| JsValue::from_str(&e.to_string()))?;
            let out = js_sys::Array::new();
            for level in levels {
                let item = js_sys::Object::new();
                let set = |k: &str, v: JsValue| js_sys::Reflect::set(&item, &k.into(), &v).map(|_| ());
                set("width", level.width.into())?;
                set("height", level.height.into())?;
                set("mean", js_sys::Float32Array::from(level.mean_linear.as_slice()).into())?;
                out.push(&item);
            }
            Ok(out.into())
        })
    }

    /// Resolves when the GPU has finished all submitted frames (for timing).
    #[allow(clippy::await_holding_refcell_ref)] // as in read_pixels: the viewer stays locked meanwhile
    pub fn finish(&self) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let guard = inner.try_borrow().map_err(|_| JsValue::from_str("viewer busy"))?;
            guard.renderer.finish().await.map_err(|e| JsValue::from_str(&e.to_string()))?;
            Ok(JsValue::UNDEFINED)
        })
    }
}

use bytemuck::Zeroable;

impl Inner {
    fn advance(&mut self, now_ms: f64) {
        let dt = match self.last_now_ms {
            Some(last) => ((now_ms - last) / 1000.0).clamp(0.0, MAX_STEP),
            None => 0.0,
        };
        self.last_now_ms = Some(now_ms);
        let s = &self.settings;
        if !s.paused {
            self.anim_time += dt * f64::from(s.speed);
        }
        self.dolly_time += dt;
        let view_height = self.layout.views[0].height.max(1) as f32;
        let switch = schedule::switch_distances(&self.lod.errors(), view_height, FOVY, s.tolerance_px);
        self.distance = match s.distance_mode {
            DistanceMode::Manual => s.manual_distance * self.framing,
            DistanceMode::Dolly => {
                let (near, far) = camera::dolly_range(self.framing, &switch);
                camera::dolly_distance(near, far, s.dolly_period, self.dolly_time)
            }
        };
        let levels = self.lod.levels.len();
        if s.continuous_triangles.is_some() {
            // The continuous level is drawn by every view; the schedule waits at level 0.
            self.schedule = Schedule::FINEST;
        } else {
            self.schedule.step(s.transition, self.distance, &switch, s.hysteresis, dt as f32);
        }
        let continuous = s.continuous_triangles.map(|_| levels);
        self.plans = s.methods.map(|m| match continuous {
            Some(level) => {
                plan_view(Method::Popping, &Schedule { selected: level, coordinate: 0.0 }, level + 1)
            }
            None => plan_view(m, &self.schedule, levels),
        });
        self.camera.distance = self.distance;
        self.camera.yaw = s.yaw_degrees.to_radians();
        self.camera.pitch = s.pitch_degrees.to_radians();
        self.camera.pan = glam::Vec2::from(s.pan) * self.framing;
        self.camera_raw = camera_raw(&self.camera, self.layout.views[0].aspect());
        let pose = match s.clip.and_then(|c| self.character.clips.get(c)) {
            Some(clip) => self.character.pose_at(clip, self.anim_time as f32),
            None => self.character.skeleton.rest_pose(),
        };
        // `Character::skin_matrices` in two steps, so the bones share the pose's node matrices.
        let skeleton = &self.character.skeleton;
        let model_from_node = skeleton.model_from_node(&pose);
        self.skin = skeleton.skin_matrices(&model_from_node);
        self.bones = bone_segments(skeleton, &model_from_node);
    }

    /// What the renderer draws this frame: camera, skin and bone matrices, each view's plan.
    fn frame_input(&self) -> FrameInput<'_> {
        FrameInput {
            camera: self.camera_raw,
            skin: &self.skin,
            bones: &self.bones,
            views: [0, 1, 2].map(|i| (self.layout.views[i], &self.plans[i])),
            overlay: self.settings.overlay,
        }
    }

    fn draw(&mut self) {
        let input = self.frame_input();
        self.renderer.render(&input);
        self.frames += 1;
    }

    /// Moves the progressive mesh to `triangles` (None: off) and uploads that mesh as the
    /// continuous level. Without a LOD chain there is nothing to move through.
    fn set_continuous(&mut self, triangles: Option<u32>) {
        let (Some(t), Some(clod)) = (triangles, &self.clod) else {
            self.settings.continuous_triangles = None;
            self.renderer.set_continuous_level(None);
            return;
        };
        let mut cursor = clod.apm.pm.cursor();
        cursor.set_triangle_count(t as usize);
        let level = LodSource::from_cursor(&self.character, clod, &cursor);
        self.renderer.set_continuous_level(Some(&level));
        self.settings.continuous_triangles = Some(level.triangle_count() as u32);
    }

    fn level_triangles(&self, level: usize) -> usize {
        match self.settings.continuous_triangles {
            Some(t) if level == self.lod.levels.len() => t as usize,
            _ => self.lod.levels.get(level).map_or(0, |l| l.triangle_count()),
        }
    }

    fn state_json(&self) -> String {
        let s = &self.settings;
        let levels: Vec<String> = self
            .lod
            .levels
            .iter()
            .map(|l| format!("{{\"triangles\":{},\"error\":{}}}", l.triangle_count(), num(l.error)))
            .collect();
        let views: Vec<String> = (0..s.view_count)
            .map(|i| {
                let plan = &self.plans[i];
                let r = self.layout.views[i];
                let triangles: usize = plan.draws.iter().map(|d| self.level_triangles(d.level)).sum();
                format!(
                    "{{\"method\":{},\"level\":{},\"triangles\":{},\"t\":{},\"draws\":{},\"rect\":[{},{},{},{}]}}",
                    json_str(settings::method_name(s.methods[i])),
                    plan.level,
                    triangles,
                    num(plan.t),
                    plan.draws.len(),
                    r.x,
                    r.y,
                    r.width,
                    r.height
                )
            })
            .collect();
        let list = |v: &[String]| v.iter().map(|e| json_str(e)).collect::<Vec<_>>().join(",");
        let (w, h) = self.renderer.size();
        let view_height = self.layout.views[0].height.max(1) as f32;
        let switch: Vec<String> =
            schedule::switch_distances(&self.lod.errors(), view_height, FOVY, s.tolerance_px)
                .iter()
                .map(|d| num(d / self.framing))
                .collect();
        format!(
            concat!(
                "{{\"backend\":{},\"adapter\":{},\"format\":{},\"msaa\":{},\"composed\":{},\"width\":{},\"height\":{},",
                "\"triangles\":{},\"joints\":{},\"clips\":[{}],\"clipDurations\":[{}],\"clip\":{},\"levels\":[{}],\"switch\":[{}],\"buildMs\":{},\"builtOffMainThread\":{},",
                "\"selected\":{},\"coordinate\":{},\"distance\":{},\"animTime\":{},\"paused\":{},",
                "\"yaw\":{},\"pitch\":{},\"pan\":[{},{}],\"distanceMode\":{},\"overlay\":{},",
                "\"continuousTriangles\":{},\"maxTriangles\":{},\"stacked\":{},\"views\":[{}],\"frames\":{},",
                "\"errors\":[{}],\"warnings\":[{}]}}"
            ),
            json_str(self.renderer.backend),
            json_str(&self.renderer.adapter_name),
            json_str(&self.renderer.color_format_name()),
            self.renderer.sample_count(),
            self.renderer.composed(),
            w,
            h,
            self.character.mesh.triangle_count(),
            self.character.skeleton.joints.len(),
            list(&self.character.clips.iter().map(|c| c.name.clone()).collect::<Vec<_>>()),
            self.character.clips.iter().map(|c| num(c.duration())).collect::<Vec<_>>().join(","),
            s.clip.map_or("null".to_string(), |c| c.to_string()),
            levels.join(","),
            switch.join(","),
            num(self.build_ms as f32),
            self.built_off_main_thread,
            self.schedule.selected,
            num(self.schedule.coordinate),
            num(self.distance / self.framing),
            num(self.anim_time as f32),
            s.paused,
            num(s.yaw_degrees),
            num(s.pitch_degrees),
            num(s.pan[0]),
            num(s.pan[1]),
            json_str(if s.distance_mode == DistanceMode::Manual { "manual" } else { "dolly" }),
            json_str(settings::overlay_name(s.overlay)),
            s.continuous_triangles.map_or("null".to_string(), |t| t.to_string()),
            self.clod.as_ref().map_or(0, |_| self.character.mesh.triangle_count()),
            self.layout.stacked,
            views.join(","),
            self.frames,
            list(&self.errors),
            list(&self.warnings),
        )
    }
}

/// Centre and radius of the character's rest pose (skinned, model space), with a margin for
/// animation: limbs swing out of the rest pose's box.
fn rest_sphere(character: &Character) -> (Vec3, f32) {
    let positions = character.skinned_positions(&character.skeleton.rest_pose());
    let (lo, hi) = positions
        .iter()
        .filter(|p| p.is_finite())
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    if lo.x > hi.x {
        return (Vec3::ZERO, 1.0);
    }
    // 10 % margin: enough for the sample models' walk cycles.
    let radius = (0.5 * (hi - lo).length() * 1.1).max(1e-3);
    (0.5 * (lo + hi), radius)
}

/// The shared camera and lights. The key light sits above-right of the camera, so the lit side
/// faces the viewer whatever the yaw; colours are linear.
fn camera_raw(camera: &OrbitCamera, aspect: f32) -> CameraRaw {
    let eye = camera.eye();
    let forward = (camera.target - eye).normalize_or(Vec3::NEG_Z);
    let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
    let light = (-forward + 0.9 * Vec3::Y + 0.5 * right).normalize();
    CameraRaw {
        clip_from_model: camera.clip_from_model(aspect).to_cols_array_2d(),
        eye_model: eye.extend(1.0).to_array(),
        light_dir: light.extend(0.85).to_array(),
        sky_color: [0.40, 0.44, 0.52, 1.0],
        ground_color: [0.14, 0.12, 0.10, 1.0],
        up: [0.0, 1.0, 0.0, 0.0],
        encode_srgb: 0,
        _pad: [0; 3],
    }
}

fn num(x: f32) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "null".into()
    }
}

fn json_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
