//! The viewer page's API (feature `web`): `Viewer.create(canvas, glbBytes, options)` loads a
//! character, builds its articulated progressive mesh and LOD chain, and sets up the renderer;
//! `viewer.frame(nowMs)` advances the shared clock, camera and LOD schedule and draws the three
//! views; `viewer.setState({...})` changes settings (the page's controls and the tests' hook use
//! the same call); `viewer.state()` reports what each view shows for the labels.
//!
//! Times are milliseconds from JavaScript (`performance.now()`), seconds inside. Distances given
//! to and reported by the page are multiples of the *framing distance* (the character's animated
//! bounding sphere fills the view at 1).
//!
//! The application model is [`ViewerModel`] (pure, tested natively); this module only carries
//! JavaScript values in and out and hands the model's plans to the renderer. No call throws
//! "busy" at the page: while `readPixels` or `measurePopSpike` holds the viewer, `setState` and
//! `resize` are queued and applied at the next frame, `frame` draws nothing, `state` returns the
//! last state read, and the other asynchronous calls wait their turn.

mod link;
mod pop_spike;
mod replay;
mod state;

use std::cell::{RefCell, RefMut};
use std::rc::Rc;

use glam::Mat4;
use wasm_bindgen::prelude::*;

use crate::character::Character;
use crate::clod::{self, Clod, ClodOptions};
use crate::import;
use crate::js_api::read::{read, to_js};
use crate::js_api::viewer_settings::{Backend, CreateOptions, ViewerSettings};
use crate::js_api::viewer_state::{FlipResult, Num, ViewerState};
use crate::render::crowd::PosePalette;
use crate::render::gpu::{next_task, BackendChoice, FrameInput, Renderer};
use crate::render::lod_source::LodSource;
use crate::render::meter::{frame_difference, FrameDifference, MeterFrames, MeterSample, TransitionMeter};
use crate::render::overlay::bone_segments;
use crate::render::replay::ReplayRecorder;
use crate::render::schedule::Transition;
use crate::render::uniforms::CameraRaw;
use crate::render::viewer::settings::{Settings, Update};
use crate::render::viewer::{animated_bounds, animated_sphere, ViewerModel};

/// The warning when the morph deltas do not fit the GPU's largest texture.
const MORPHS_DROPPED: &str =
    "this character's morph targets have more deltas than this GPU's largest texture holds: the views draw the base shape";

/// One viewer on one canvas.
#[wasm_bindgen]
pub struct Viewer {
    inner: Rc<RefCell<Inner>>,
    /// What arrived while a measurement or readback held `inner`.
    queue: Rc<RefCell<Queue>>,
}

/// Calls that found the viewer busy, applied at the next frame, the last state read (the
/// state the viewer was created with until a state is read), and the settings as of the last
/// update applied (what a viewer replacing this one keeps, even while this one is busy).
struct Queue {
    updates: Vec<Update>,
    size: Option<(u32, u32)>,
    clips: Vec<String>,
    last_state: ViewerState,
    settings: Settings,
}

/// What one frame draws besides the model's plans: the camera and the pose's skin matrices,
/// morph weights and bone lines, made by `Inner::advance`.
struct Posed {
    camera: CameraRaw,
    skin: Vec<Mat4>,
    /// Morph-target weights of the same pose, one per target.
    morph_weights: Vec<f32>,
    /// The skeleton overlay's line list of the same pose (model space; see `bone_segments`).
    bones: Vec<[f32; 3]>,
}

impl Posed {
    /// What the renderer draws this frame: this pose and camera, and each view's plan of `m`.
    fn frame_input<'a>(&'a self, m: &'a ViewerModel) -> FrameInput<'a> {
        let crowd = m.crowd.as_ref().map(|c| &c.frame);
        FrameInput {
            camera: self.camera,
            skin: &self.skin,
            morph_weights: &self.morph_weights,
            // The skeleton is one pose in model space: the single character's overlay only.
            bones: if crowd.is_some() { &[] } else { &self.bones },
            views: [0, 1, 2].map(|i| (m.layout.views[i], &m.plans[i])),
            overlay: m.settings.overlay,
            meter: None,
            flip: m.settings.flip,
            controls: None,
            crowd,
        }
    }
}

struct Inner {
    character: Character,
    clod: Option<Clod>,
    lod: LodSource,
    renderer: Renderer,
    model: ViewerModel,
    last_now_ms: Option<f64>,
    /// The slider's `(finer, coarser)` states the renderer holds as its continuous levels.
    continuous_uploaded: Option<(usize, usize)>,
    /// The camera, skin, morph weights and bones of the frame `advance` made.
    posed: Posed,
    /// The live transition meter, and the measured frames whose pictures are not back yet with
    /// the controls of the next.
    meter: TransitionMeter,
    meter_frames: MeterFrames,
    /// The last transition's film strip (see [`crate::render::replay`]).
    replay: ReplayRecorder,
    frames: u64,
    errors: Vec<String>,
    warnings: Vec<String>,
    lod_origin: LodOrigin,
}

/// Where the levels on screen came from, as `state()` reports it.
struct LodOrigin {
    /// `"build"` (a worker), `"cache"`, `"inline"` (this thread), or `None` while only the full
    /// mesh is drawn.
    from: Option<&'static str>,
    /// How long building them took (ms), where they were built.
    build_ms: f64,
    /// Whether the chain came from `options.clod` (a worker) rather than this thread.
    off_main_thread: bool,
}

/// An `Error` whose `code` says what kind of failure it is, for the page to act on without
/// reading the message: `"model"` (the file cannot be shown), `"levels"` (LOD bytes that do not
/// belong to the file), `"no-gpu"` (this backend has no GPU here), `"backend"` (a backend this
/// build does not have).
fn coded_error(code: &str, message: impl std::fmt::Display) -> JsValue {
    let error = js_sys::Error::new(&message.to_string());
    let _ = js_sys::Reflect::set(&error, &"code".into(), &code.into());
    error.into()
}

/// The identity of the code that builds and reads LOD chains ([`crate::clod::bytes::SOURCE_TAG`]):
/// the page keys its chain cache on it, so an updated viewer never attaches levels its own
/// simplifier did not make.
#[wasm_bindgen(js_name = chainCacheTag)]
pub fn chain_cache_tag() -> String {
    crate::clod::bytes::SOURCE_TAG.to_owned()
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
    /// undecodable texture. The error's `code` says which: `"model"` (the file or this GPU's
    /// limits), `"levels"` (the LOD bytes), `"backend"` (a backend this build lacks), and
    /// `"no-gpu"` when the browser gives this backend no GPU at all (no adapter, context or
    /// device), so the page can try another backend without reading the message; the backend's
    /// own report goes to the console.
    pub async fn create(
        canvas: web_sys::HtmlCanvasElement,
        bytes: Vec<u8>,
        options: JsValue,
    ) -> Result<Viewer, JsValue> {
        let options: CreateOptions = if options.is_undefined() || options.is_null() {
            CreateOptions::default()
        } else {
            read("Viewer.create", options, "{ backend: 'webgpu' }").map_err(|e| js_sys::Error::new(&e))?
        };
        let choice = match options.backend.map_or(Backend::WebGpu, |b| b.0) {
            Backend::WebGpu => BackendChoice::WebGpu,
            Backend::WebGl2 if cfg!(feature = "webgl") => BackendChoice::WebGl2,
            Backend::WebGl2 => {
                return Err(coded_error("backend", "this build has no WebGL2 backend; load the webgl build"))
            }
        };
        let mut resolver = crate::js_api::resolver(options.resolve.as_ref().map(|r| &r.0));
        let mut draco = options.draco.as_ref().map(|d| crate::js_api::draco_decoder(&d.0));
        let character = import::from_bytes_with(
            &bytes,
            &mut resolver,
            draco.as_mut().map(|d| d as &mut import::DracoDecoder),
        )
        .map_err(|e| coded_error("model", e))?;
        drop(draco);
        drop(bytes);
        next_task().await;
        let mut warnings = character.warnings.clone();
        let prebuilt = options.clod.map(|c| c.0);
        let later = options.lod.is_some();
        let built_off_main_thread = prebuilt.is_some();
        let started = js_sys::Date::now();
        let clod = match prebuilt {
            Some(encoded) => Some(decode_chain(&encoded, &character)?),
            // The levels arrive later (`attachLod`): the full mesh is drawn meanwhile.
            None if later => None,
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
        let build_ms = match options.build_ms {
            Some(ms) if built_off_main_thread => ms.0,
            _ if later => 0.0,
            _ => js_sys::Date::now() - started,
        };
        let from = match (&clod, built_off_main_thread) {
            (None, _) => None,
            (Some(_), true) => Some("build"),
            (Some(_), false) => Some("inline"),
        };
        let lod_origin = LodOrigin { from, build_ms, off_main_thread: built_off_main_thread };
        let renderer = Renderer::new(canvas, choice, &character, &lod).await.map_err(|e| {
            if e.is_unavailable() {
                web_sys::console::warn_1(&format!("clod-viewer: {e}: {}", e.detail()).into());
                coded_error("no-gpu", e)
            } else {
                coded_error("model", e)
            }
        })?;
        if renderer.morphs_dropped() {
            warnings.push(MORPHS_DROPPED.into());
        }
        let (w, h) = renderer.size();
        let model = ViewerModel::new(animated_sphere(&character), lod.errors(), w, h);
        let clips = character.clips.iter().map(|c| c.name.clone()).collect();
        let inner = Inner {
            character,
            clod,
            lod,
            renderer,
            model,
            last_now_ms: None,
            continuous_uploaded: None,
            posed: Posed {
                camera: CameraRaw::zeroed(),
                skin: Vec::new(),
                morph_weights: Vec::new(),
                bones: Vec::new(),
            },
            meter: TransitionMeter::default(),
            meter_frames: MeterFrames::default(),
            replay: ReplayRecorder::default(),
            frames: 0,
            errors: Vec::new(),
            warnings,
            lod_origin,
        };
        // The viewer answers `state()` from birth: a page that asks while the first frame or the
        // levels hold it gets the state it was created with, never null.
        let queue = Queue {
            updates: Vec::new(),
            size: None,
            clips,
            last_state: inner.state(),
            settings: inner.model.settings.clone(),
        };
        Ok(Viewer { inner: Rc::new(RefCell::new(inner)), queue: Rc::new(RefCell::new(queue)) })
    }

    /// Advances the clocks to `now_ms` (milliseconds, e.g. `performance.now()`) and draws. While
    /// `readPixels` or `measurePopSpike` holds the viewer it draws nothing (they draw their own
    /// frames); the clocks catch up at the next frame, at most [`crate::render::viewer::MAX_STEP`].
    pub fn frame(&self, now_ms: f64) {
        let Some(mut inner) = self.lock() else { return };
        inner.advance(now_ms);
        inner.draw();
    }

    /// Resizes the drawing buffer (framebuffer pixels: CSS size × devicePixelRatio).
    pub fn resize(&self, width: u32, height: u32) {
        match self.inner.try_borrow_mut() {
            Ok(mut inner) => inner.resize(width, height),
            Err(_) => self.queue.borrow_mut().size = Some((width, height)),
        }
    }

    /// Changes settings: any keys of [`ViewerSettings`] (the README lists them, and
    /// `www/clod-viewer.d.ts` types them); unknown keys are an error (a typo should not pass
    /// silently).
    ///
    /// # Errors
    /// A message naming the first unknown key or bad value and what it accepts; nothing is
    /// changed then.
    #[wasm_bindgen(js_name = setState)]
    pub fn set_state(&self, state: JsValue) -> Result<(), JsError> {
        let clips = self.queue.borrow().clips.clone();
        let settings: ViewerSettings =
            read("setState", state, "{ paused: true }").map_err(|e| JsError::new(&e))?;
        self.push(settings.update(&clips).map_err(|e| JsError::new(&e))?);
        Ok(())
    }

    /// Takes the comparison settings of `previous`, the viewer this one replaces on another model:
    /// thresholds, transitions, methods, distance, magnifier, overlay, meter, FLIP, crowd
    /// ([`Settings::keep_from`] lists them), with the changes queued while a measurement holds
    /// `previous`. Before this viewer's first frame: it starts at rest at the level they select.
    #[wasm_bindgen(js_name = keepSettingsOf)]
    pub fn keep_settings_of(&self, previous: &Viewer) {
        let settings = previous.settings_now();
        // A new viewer is not busy: nothing has been asked of it yet.
        if let Some(mut inner) = self.lock() {
            inner.model.keep_settings_from(&settings);
            self.queue.borrow_mut().settings.clone_from(&inner.model.settings);
        }
    }

    /// Applies the `<clod-viewer>` attribute `name` with `value` (`null` or `undefined`: the
    /// attribute is absent) on an element whose `preset` attribute is `preset`, as
    /// [`crate::js_api::attributes::attribute_update`] reads it.
    ///
    /// # Errors
    /// A sentence quoting the attribute and saying what it takes; nothing is changed then.
    #[wasm_bindgen(js_name = applyAttribute)]
    pub fn apply_attribute(
        &self,
        name: &str,
        value: Option<String>,
        preset: Option<String>,
    ) -> Result<(), JsError> {
        let clips = self.queue.borrow().clips.clone();
        let update =
            crate::js_api::attributes::attribute_update(name, value.as_deref(), preset.as_deref(), &clips)
                .map_err(|e| JsError::new(&e))?;
        self.push(update);
        Ok(())
    }

    /// What the views show, for the page: a [`ViewerState`] (`{ backend, adapter, levels,
    /// switch, selected, distance, stacked, views: [{method, level, to, t, triangles, rect}],
    /// frames, errors, warnings, ... }`). Every view reports the same `level`, `to` and `t`: the
    /// transition they all show. While a measurement holds the viewer: the last state read.
    pub fn state(&self) -> Result<JsValue, JsError> {
        let state = match self.lock() {
            Some(mut inner) => {
                // Each problem once, however often the GPU repeats it.
                for error in inner.renderer.take_errors() {
                    if !inner.errors.contains(&error) {
                        inner.errors.push(error);
                    }
                }
                let state = inner.state();
                self.queue.borrow_mut().last_state.clone_from(&state);
                state
            }
            None => self.queue.borrow().last_state.clone(),
        };
        to_js(&state)
    }

    /// Attaches the LOD chain of this same file once it is ready (`Character.buildClodBytes` in a
    /// worker, or bytes kept from an earlier visit): decodes it against the character, uploads
    /// its levels and starts the transitions, yielding to the browser between steps. `from` is
    /// `"build"` or `"cache"` (reported as `state().lodFrom`), `buildMs` the build's time.
    ///
    /// Rejects when the bytes do not belong to this file (a stale cache entry, say): the viewer
    /// keeps drawing the full mesh.
    #[wasm_bindgen(js_name = attachLod)]
    #[allow(clippy::await_holding_refcell_ref)] // as in read_pixels: frames wait meanwhile
    pub fn attach_lod(&self, clod: Vec<u8>, build_ms: f64, from: String) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let from = match from.as_str() {
                "build" => "build",
                "cache" => "cache",
                other => {
                    return Err(
                        JsError::new(&format!("from must be \"build\" or \"cache\", got {other:?}")).into()
                    )
                }
            };
            let mut guard = wait_for(&inner).await;
            let inner = &mut *guard;
            let chain = decode_chain(&clod, &inner.character)?;
            drop(clod);
            next_task().await;
            let lod = LodSource::from_clod(&inner.character, &chain);
            next_task().await;
            inner.renderer.set_levels(&lod).await;
            if inner.renderer.morphs_dropped() && !inner.warnings.iter().any(|w| w == MORPHS_DROPPED) {
                inner.warnings.push(MORPHS_DROPPED.into());
            }
            inner.model.set_levels(lod.errors());
            inner.lod = lod;
            inner.clod = Some(chain);
            inner.continuous_uploaded = None;
            inner.lod_origin = LodOrigin { from: Some(from), build_ms, off_main_thread: from == "build" };
            inner.meter_frames.controls = None;
            Ok(JsValue::UNDEFINED)
        })
    }

    /// The live meter's recent samples (about the last ten seconds of frames) for a strip chart:
    /// `{ methods: [name per view], samples: [[seconds, transitionRunning, silhouette %,
    /// shading, … per view]], steps: [[silhouette %, shading, … per view]], flip: [[FLIP, FLIP of
    /// the step, … per view]] }` ([`crate::js_api::viewer_state::MeterHistory`]). While a
    /// measurement holds the viewer: empty.
    #[wasm_bindgen(js_name = meterHistory)]
    pub fn meter_history(&self) -> Result<JsValue, JsError> {
        to_js(&self.lock().map_or_else(Default::default, |inner| inner.meter_history()))
    }

    /// Draws the current frame again offscreen and resolves to `{ width, height, data }` (RGBA8,
    /// sRGB, top row first). Waits for a running measurement first.
    #[wasm_bindgen(js_name = readPixels)]
    // The borrow is held across the readback on purpose: `frame` draws nothing and the setters
    // queue until the copy is read.
    #[allow(clippy::await_holding_refcell_ref)]
    pub fn read_pixels(&self) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let mut guard = wait_for(&inner).await;
            let Inner { posed, model, renderer, .. } = &mut *guard;
            let pixels = renderer
                .read_pixels(&posed.frame_input(model))
                .await
                .map_err(|e| JsValue::from_str(&e.to_string()))?;
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
            let guard = wait_for(&inner).await;
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

    /// LDR-FLIP of two RGBA8 sRGB pictures (`width` × `height`, alpha ignored) seen at `ppd`
    /// pixels per degree, on this viewer's GPU (`flip.wgsl`): resolves to `{ mean, p99, max, ppd }`
    /// of the error map, or null where this GPU cannot render into float targets. For checking
    /// the shader against the reference's numbers, and for a page comparing two pictures.
    #[wasm_bindgen(js_name = flipImages)]
    #[allow(clippy::await_holding_refcell_ref)] // as in read_pixels: the viewer stays locked meanwhile
    pub fn flip_images(
        &self,
        reference: Vec<u8>,
        test: Vec<u8>,
        width: u32,
        height: u32,
        ppd: f32,
    ) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let pixels = 4 * width as usize * height as usize;
            if width == 0 || height == 0 || reference.len() != pixels || test.len() != pixels {
                return Err(JsError::new("flipImages: two RGBA8 pictures of width × height pixels").into());
            }
            if !(ppd > 0.0 && ppd <= crate::render::gpu::MAX_PPD) {
                let max = crate::render::gpu::MAX_PPD;
                return Err(JsError::new(&format!("flipImages: ppd in (0, {max}]")).into());
            }
            let mut guard = wait_for(&inner).await;
            let map = guard
                .renderer
                .flip_map(&reference, &test, width, height, ppd)
                .await
                .map_err(|e| JsValue::from_str(&e.to_string()))?;
            let Some(map) = map else { return Ok(JsValue::NULL) };
            let stats = crate::render::flip::FlipStats::of(&map);
            let max = map.iter().copied().fold(0.0f32, f32::max);
            Ok(to_js(&FlipResult {
                mean: Num(stats.mean),
                p99: Num(stats.p99),
                max: Num(max),
                ppd: Num(ppd),
            })?)
        })
    }

    /// Resolves when the GPU has finished all submitted frames (for timing).
    #[allow(clippy::await_holding_refcell_ref)] // as in read_pixels: the viewer stays locked meanwhile
    pub fn finish(&self) -> js_sys::Promise {
        let inner = Rc::clone(&self.inner);
        wasm_bindgen_futures::future_to_promise(async move {
            let guard = wait_for(&inner).await;
            guard.renderer.finish().await.map_err(|e| JsValue::from_str(&e.to_string()))?;
            Ok(JsValue::UNDEFINED)
        })
    }
}

use bytemuck::Zeroable;

impl Viewer {
    /// Applies `update` now, or at the next frame while a measurement or readback holds the viewer.
    fn push(&self, update: Update) {
        match self.inner.try_borrow_mut() {
            Ok(mut inner) => {
                inner.apply(update);
                self.queue.borrow_mut().settings.clone_from(&inner.model.settings);
            }
            Err(_) => self.queue.borrow_mut().updates.push(update),
        }
    }

    /// The settings with the changes queued while a measurement holds the viewer applied.
    fn settings_now(&self) -> Settings {
        let queue = self.queue.borrow();
        let mut settings = queue.settings.clone();
        queue.updates.iter().for_each(|update| update.apply(&mut settings));
        settings
    }

    /// The viewer with the calls queued while it was busy applied, or `None` while busy.
    fn lock(&self) -> Option<RefMut<'_, Inner>> {
        let mut inner = self.inner.try_borrow_mut().ok()?;
        let mut queue = self.queue.borrow_mut();
        if let Some((w, h)) = queue.size.take() {
            inner.resize(w, h);
        }
        for update in queue.updates.drain(..) {
            inner.apply(update);
        }
        queue.settings.clone_from(&inner.model.settings);
        Some(inner)
    }
}

/// Decodes LOD chain bytes made for `character` (by a worker or an earlier visit).
fn decode_chain(bytes: &[u8], character: &Character) -> Result<Clod, JsValue> {
    clod::bytes::decode(bytes, character)
        .map_err(|e| coded_error("levels", format!("the LOD chain does not fit this file: {e}")))
}

/// Waits (yielding to the browser) until nothing else holds the viewer.
async fn wait_for(inner: &Rc<RefCell<Inner>>) -> RefMut<'_, Inner> {
    loop {
        if let Ok(guard) = inner.try_borrow_mut() {
            return guard;
        }
        next_task().await;
    }
}

impl Inner {
    fn resize(&mut self, width: u32, height: u32) {
        self.renderer.resize(width, height);
        let (w, h) = self.renderer.size();
        self.model.resize(w, h);
    }

    /// Applies an update; a continuous triangle count is snapped to the progressive mesh's
    /// state with at most that many triangles (no chain: the slider stays off).
    fn apply(&mut self, mut update: Update) {
        if let Some(Some(requested)) = update.continuous_triangles {
            update.continuous_triangles = Some(self.clod.as_ref().map(|clod| {
                let mut cursor = clod.apm.pm.cursor();
                cursor.set_triangle_count(requested as usize);
                (cursor.indices().len() / 3) as u32
            }));
        }
        self.model.apply(&update);
    }

    fn advance(&mut self, now_ms: f64) {
        let dt = match self.last_now_ms {
            Some(last) => (now_ms - last) / 1000.0,
            None => 0.0,
        };
        self.last_now_ms = Some(now_ms);
        self.sync_crowd();
        self.model.advance(dt);
        self.upload_continuous();
        self.upload_morph_pairs();
        self.posed.camera = match &self.model.crowd {
            Some(c) => {
                self.renderer.set_crowd_palette(&c.palette, self.model.settings.morphs);
                self.renderer.set_crowd_instances(&c.frame);
                // The crowd's camera is in world space, lit as the single view is.
                let crowd = &c.crowd;
                CameraRaw::lit(crowd.clip_from_world, crowd.eye, crowd.eye + crowd.forward())
            }
            None => {
                let camera = &self.model.camera;
                let aspect = self.model.layout.views[0].aspect();
                CameraRaw::lit(camera.clip_from_model(aspect), camera.eye(), camera.target)
            }
        };
        let clip = self.model.settings.clip.and_then(|c| self.character.clips.get(c));
        let time = self.model.anim_time as f32;
        let pose = match clip {
            Some(clip) => self.character.pose_at(clip, time),
            None => self.character.skeleton.rest_pose(),
        };
        self.posed.morph_weights = match clip {
            _ if !self.model.settings.morphs => Vec::new(),
            Some(clip) => self.character.morph_weights_at(clip, time),
            None => self.character.default_morph_weights(),
        };
        // `Character::skin_matrices` in two steps, so the bones share the pose's node matrices.
        let skeleton = &self.character.skeleton;
        let model_from_node = skeleton.model_from_node(&pose);
        self.posed.skin = skeleton.skin_matrices(&model_from_node);
        self.posed.bones = bone_segments(skeleton, &model_from_node);
    }

    /// Starts or stops crowd mode as the settings ask, and samples the pose palette again when
    /// the clip changes.
    fn sync_crowd(&mut self) {
        let clip = self.model.settings.clip;
        match (self.model.settings.crowd, &self.model.crowd) {
            // The crowd starts when the levels arrive: one LOD build serves every instance, and
            // hundreds of full meshes meanwhile would only make the first frames slow.
            (true, None) if self.lod_origin.from.is_none() => {}
            (true, None) => {
                let triangles = self.lod.levels.iter().map(|l| l.triangle_count()).collect();
                let floor =
                    animated_bounds(&self.character).map_or(self.model.camera.target.y, |(lo, _)| lo.y);
                self.model.start_crowd(PosePalette::sample(&self.character, clip), triangles, floor);
            }
            (true, Some(c)) if c.palette.clip != clip => {
                self.model.set_crowd_palette(PosePalette::sample(&self.character, clip));
            }
            (false, Some(_)) => {
                self.model.stop_crowd();
                self.renderer.drop_crowd();
            }
            _ => {}
        }
    }

    /// Keeps the renderer's continuous levels on the slider's two states: the finer one paired
    /// with its ancestors in the coarser (one geomorph), and the coarser one.
    fn upload_continuous(&mut self) {
        let pair = self.model.continuous_pair();
        if pair == self.continuous_uploaded {
            return;
        }
        self.continuous_uploaded = pair;
        let (Some((finer, coarser)), Some(clod)) = (pair, &self.clod) else {
            self.renderer.set_continuous_levels(&[]);
            return;
        };
        let pm = &clod.apm.pm;
        let mut cursor = pm.cursor();
        let coarse_collapses = cursor.set_triangle_count(coarser);
        let coarse = LodSource::from_cursor(&self.character, clod, &cursor, coarse_collapses);
        cursor.set_triangle_count(finer);
        let fine = LodSource::from_cursor(&self.character, clod, &cursor, coarse_collapses);
        self.renderer.set_continuous_levels(&[fine, coarse]);
    }

    /// Uploads the vertex pairs of geomorphs that skip levels (ancestor tables chained), once.
    fn upload_morph_pairs(&mut self) {
        for plan in &self.model.plans {
            for draw in &plan.draws {
                let Some(morph) = draw.morph else { continue };
                let (fine, coarse) = (draw.level, morph.coarse);
                if coarse > fine + 1 && !self.renderer.has_morph_pair(fine, coarse) {
                    if let Some(vertices) = self.lod.morph_vertices(fine, coarse) {
                        self.renderer.add_morph_pair(fine, coarse, &vertices);
                    }
                }
            }
        }
    }

    fn draw(&mut self) {
        self.collect_meter();
        let tag = self.model.settings.meter.then_some(self.frames);
        let controls = self.meter_frames.controls.clone().unwrap_or_else(|| self.model.plans.clone());
        let mut input = self.posed.frame_input(&self.model);
        input.meter = tag;
        input.controls = Some([&controls[0], &controls[1], &controls[2]]);
        let measured = self.renderer.render(&input);
        if let Some(tag) = tag.filter(|_| measured) {
            // A crowd's transitions are its instances' (many at once): the meter records its
            // differences and their frame-to-frame changes, not one transition's pop.
            let transition = match &self.model.crowd {
                Some(_) => Transition::at(0),
                None => self.model.plans[0].transition,
            };
            let plans = self.model.plans.clone();
            self.meter_frames.sent(tag, self.model.dolly_time, transition, self.model.scene, plans);
        }
        self.frames += 1;
    }

    /// Turns the meter pictures that have come back into samples of the transition meter.
    fn collect_meter(&mut self) {
        for frame in self.renderer.take_meter_frames() {
            let Some(sent) = self.meter_frames.returned(frame.tag) else { continue };
            let tag = frame.tag;
            let Some(reference) = frame.pictures.first() else { continue };
            // The mean FLIP error of a pair of pictures (0 for a picture against itself).
            let flip =
                |pair: (usize, usize)| frame.flip.iter().find(|(p, _)| *p == pair).map_or(0.0, |f| f.1);
            let mut differences = vec![None; frame.pictures.len()];
            let views = frame
                .view_picture
                .iter()
                .map(|&p| {
                    *differences[p].get_or_insert_with(|| FrameDifference {
                        flip: flip((0, p)),
                        ..frame_difference(reference, &frame.pictures[p])
                    })
                })
                .collect();
            // Each view against its control: the same picture (the plan held) steps by nothing.
            let steps = frame
                .view_picture
                .iter()
                .zip(&frame.control_picture)
                .map(|(&v, &c)| match v == c {
                    true => Default::default(),
                    false => FrameDifference {
                        flip: flip((c, v)),
                        ..frame_difference(&frame.pictures[c], &frame.pictures[v])
                    },
                })
                .collect();
            if frame.flip_ppd.is_some() {
                self.meter_frames.flip_ppd = frame.flip_ppd;
            }
            let sample = MeterSample {
                frame: tag,
                time: sent.time,
                transition: sent.transition,
                scene: sent.scene,
                views,
                steps,
            };
            self.record_replay(&frame, &sample);
            self.meter.push(sample);
        }
    }

    /// Triangles of a drawn level: a discrete one, or the slider's finer (`levels`) or coarser
    /// (`levels + 1`) state.
    fn level_triangles(&self, level: usize) -> usize {
        let levels = self.lod.levels.len();
        match (level.checked_sub(levels), self.model.continuous_pair()) {
            (Some(0), Some((finer, _))) => finer,
            (Some(1), Some((_, coarser))) => coarser,
            _ => self.lod.levels.get(level).map_or(0, |l| l.triangle_count()),
        }
    }
}
