//! The wgpu side of the renderer: device and surface set-up (WebGPU, or WebGL2 in the `webgl`
//! build), GPU buffers of every level, materials with their decoded textures, the pipelines of
//! `skin.wgsl`, and the execution of a frame's [`ViewPlan`]s: one render pass, one viewport per
//! view, 4× MSAA where the format allows it, into an sRGB target.
//!
//! Joint matrices live in a texture on both backends (WebGL2 has no storage buffers in vertex
//! shaders and 16 KiB uniform blocks; doing the same on WebGPU keeps the comparison fair). Errors the device reports
//! asynchronously (validation, out of memory, device loss) are collected and handed to the page
//! by [`Renderer::take_errors`].

use std::sync::{Arc, Mutex};

use glam::Mat4;
use thiserror::Error;

mod crowd;
mod difference;
mod flip;
pub use flip::MAX_PPD;
mod frame_targets;
mod frame_uniforms;
mod joints;
mod meshes;
mod meter;
pub use meter::{MeterFrame, METER_HEIGHT};
mod mipmaps;
mod morph;
pub use mipmaps::TextureLevel;
mod pipelines;
mod readback;
mod resources;

use frame_targets::{background_for, begin_pass, Canvas};
use frame_uniforms::FrameUniforms;
use meshes::CharacterMeshes;
use pipelines::{create_pipelines, BindLayouts, Pipelines};
use resources::upload_materials;

use super::crowd::CrowdFrame;
use super::layout::Rect;
use super::lod_source::{GeomorphVertexRaw, LevelData, LodSource};
use super::overlay::{draw_tint, Overlay};
use super::plan::{PassKind, ViewPlan};
use super::uniforms::{CameraRaw, DrawRaw};
use crate::character::Character;

/// Why the renderer could not start or draw.
#[derive(Debug, Error)]
pub enum RenderError {
    #[error("this browser gives no {0} adapter (no GPU it can use for {0})")]
    NoAdapter(&'static str),
    /// The backend's own report is kept for the console, not the sentence.
    #[error("this browser gives the canvas no {0} context")]
    Surface(&'static str, String),
    #[error("the GPU refused a device: {0}")]
    Device(String),
    #[error("the character has {0} joints; this GPU's largest texture holds the matrices of at most {1}")]
    TooManyJoints(usize, usize),
    #[error("texture of material {material:?} could not be decoded: {reason}")]
    Texture { material: String, reason: String },
    #[error("reading the picture back failed: {0}")]
    Readback(String),
}

/// Which backend to ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendChoice {
    WebGpu,
    WebGl2,
}

/// Bytes per bone-line vertex: one model-space `vec3<f32>`.
const BONE_VERTEX_STRIDE: u64 = 12;
/// Draw-call slots of the per-draw uniform buffer, all written before one submit: 3 views × 2
/// draws, and the live meter's reference, 3 views × 2 draws and their 3 controls × 2 draws.
const DRAW_SLOTS: u64 = 19;
/// WebGPU's and WebGL2's minimum uniform offset alignment: the stride of the draw slots.
const DRAW_STRIDE: u64 = 256;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;
/// Background: a cool mid grey, linear (drawn as about #8a96a6 in sRGB), light enough that dark
/// clothes stand out and dark enough that light skin does.
const BACKGROUND: wgpu::Color = wgpu::Color { r: 0.25, g: 0.3, b: 0.38, a: 1.0 };

/// Pipeline key: pass kind, geomorph vertex shader, back-face culling.
type PipelineKey = (PassKind, bool, bool);

/// Everything a frame needs besides the plans: shared camera and the pose.
pub struct FrameInput<'a> {
    pub camera: CameraRaw,
    pub skin: &'a [Mat4],
    /// Morph-target weights of the same pose, one per target (fewer: the rest are 0).
    pub morph_weights: &'a [f32],
    /// The skeleton overlay's line list (model space, two points per bone) in the same pose;
    /// drawn only with [`Overlay::Skeleton`], and only as many points as two per joint.
    pub bones: &'a [[f32; 3]],
    pub views: [(Rect, &'a ViewPlan); 3],
    /// Drawn over every view alike.
    pub overlay: Overlay,
    /// Measure this frame for the live meter, tagged with this number (see `meter`).
    pub meter: Option<u64>,
    /// The meter's measured frames also compute LDR-FLIP (see `meter`).
    pub flip: bool,
    /// Each view's control for the meter: its plan of the previous measured frame, drawn at this
    /// frame's pose and camera (see [`crate::render::meter`]); `None` measures no steps.
    pub controls: Option<[&'a ViewPlan; 3]>,
    /// Crowd mode: each view draws the crowd's instanced draws instead of its plan (whose
    /// records [`Renderer::set_crowd_instances`] has written), the meter's reference too.
    pub crowd: Option<&'a CrowdFrame>,
}

/// Pixels read back from an offscreen render of a frame: RGBA8, sRGB-encoded, rows top first.
pub struct Pixels {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// The GPU state of one viewer.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// The canvas's surface and the targets the views draw into (`frame_targets.rs`).
    canvas: Canvas,
    /// The uniforms every draw reads, and their bind groups (`frame_uniforms.rs`).
    uniforms: FrameUniforms,
    /// The character's materials and levels (`meshes.rs`).
    meshes: CharacterMeshes,
    /// The live meter's targets and readbacks, made on first use.
    meter: Option<meter::MeterGpu>,
    /// The difference overlay's pipeline.
    difference: Option<difference::DifferenceGpu>,
    /// LDR-FLIP's pipelines, where float targets can be rendered into.
    flip: Option<flip::FlipGpu>,
    pipelines: Pipelines,
    /// Kept for the pipelines made later (the crowd's).
    layouts: BindLayouts,
    /// The crowd's pipelines, palette and instance records, while in crowd mode.
    crowd: Option<crowd::CrowdGpu>,
    errors: Arc<Mutex<Vec<String>>>,
    /// `webgpu` or `webgl2`, and the adapter's name.
    pub backend: &'static str,
    pub adapter_name: String,
}

impl RenderError {
    /// Whether the browser cannot give this backend a GPU at all (no adapter, context or
    /// device), as opposed to a problem with this character: another backend may work.
    pub fn is_unavailable(&self) -> bool {
        matches!(self, Self::NoAdapter(_) | Self::Surface(..) | Self::Device(_))
    }

    /// The backend's own words, for the console (empty when the message says it all).
    pub fn detail(&self) -> &str {
        match self {
            Self::Surface(_, detail) => detail,
            _ => "",
        }
    }
}

impl Renderer {
    /// Sets up the device on `canvas`, uploads the levels and decodes the textures.
    ///
    /// # Errors
    /// [`RenderError`]: no adapter for the backend, a canvas or device the browser refuses, more
    /// joints than the device's largest texture holds, or a texture the browser cannot decode.
    pub async fn new(
        canvas: web_sys::HtmlCanvasElement,
        choice: BackendChoice,
        character: &Character,
        lod: &LodSource,
    ) -> Result<Self, RenderError> {
        let (backends, backend) = match choice {
            BackendChoice::WebGpu => (wgpu::Backends::BROWSER_WEBGPU, "webgpu"),
            BackendChoice::WebGl2 => (wgpu::Backends::GL, "webgl2"),
        };
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
            .map_err(|e| RenderError::Surface(backend, e.to_string()))?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                compatible_surface: Some(&surface),
                ..Default::default()
            })
            .await
            .map_err(|_| RenderError::NoAdapter(backend))?;
        // WebGL2's limits on both backends: the same work.
        let limits = wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits());
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("clod-viewer"),
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&errors);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            push_error(&sink, GPU_ERROR, &format!("GPU error: {e}"))
        }));
        let sink = Arc::clone(&errors);
        device.set_device_lost_callback(move |reason, message| {
            // Dropping the viewer destroys its device too: that is no failure.
            if reason != wgpu::DeviceLostReason::Destroyed {
                push_error(&sink, DEVICE_LOST, &format!("the GPU device was lost ({reason:?}): {message}"));
            }
        });

        let canvas = Canvas::new(surface, &adapter, &device, (choice, backend), (width, height))?;

        let layouts = BindLayouts::new(&device);
        let uniforms = FrameUniforms::new(
            &device,
            &queue,
            &layouts,
            character.skeleton.joints.len(),
            &lod.morph_texels,
        )?;
        let materials = upload_materials(&device, &queue, &layouts.material, character).await?;
        let meshes = CharacterMeshes::new(&device, materials, lod).await;
        next_task().await;
        let pipelines = create_pipelines(&device, &layouts, canvas.color_format, canvas.sample_count);
        let info = adapter.get_info();
        let difference =
            Some(difference::DifferenceGpu::new(&device, canvas.color_format, canvas.sample_count));
        let float_targets = adapter
            .get_texture_format_features(wgpu::TextureFormat::Rgba32Float)
            .allowed_usages
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT);
        let flip = flip::FlipGpu::new(&device, float_targets);
        Ok(Self {
            device,
            queue,
            canvas,
            uniforms,
            meshes,
            meter: Default::default(),
            difference,
            flip,
            pipelines,
            layouts,
            crowd: None,
            errors,
            backend,
            adapter_name: info.name,
        })
    }

    /// Whether the shader must encode sRGB itself (the target format is not sRGB).
    pub fn encodes_srgb_in_shader(&self) -> bool {
        !self.canvas.color_format.is_srgb()
    }

    /// MSAA sample count in use (4, or 1 where the format cannot multisample).
    pub fn sample_count(&self) -> u32 {
        self.canvas.sample_count
    }

    /// Whether views are drawn apart and copied into the frame: equal views are then
    /// bit-identical (see `Canvas::composed`).
    pub fn composed(&self) -> bool {
        self.canvas.composed
    }

    /// Name of the colour format the views render in.
    pub fn color_format_name(&self) -> String {
        format!("{:?}", self.canvas.color_format)
    }

    /// Current framebuffer size.
    pub fn size(&self) -> (u32, u32) {
        self.canvas.size()
    }

    /// Errors reported since the last call (validation, device loss, surface trouble).
    pub fn take_errors(&self) -> Vec<String> {
        std::mem::take(&mut *self.errors.lock().unwrap_or_else(|p| p.into_inner()))
    }

    /// Replaces the discrete levels (the LOD chain arriving after the full mesh), yielding to the
    /// browser between levels; drops the slider's meshes and the level-skipping geomorphs.
    pub async fn set_levels(&mut self, lod: &LodSource) {
        self.meshes.set_levels(&self.device, lod).await;
        self.set_morph_deltas(lod);
    }

    /// Uploads the continuous slider's meshes (drawn as levels `levels`, `levels + 1`, …), or
    /// drops them (empty).
    pub fn set_continuous_levels(&mut self, levels: &[LevelData]) {
        self.meshes.set_continuous(&self.device, levels);
    }

    /// Whether the geomorph buffer of level `fine` towards level `coarse` is uploaded.
    pub fn has_morph_pair(&self, fine: usize, coarse: usize) -> bool {
        self.meshes.morph_pair(fine, coarse).is_some()
    }

    /// Uploads level `fine`'s vertices paired with their ancestors in level `coarse`
    /// ([`LodSource::morph_vertices`]), dropping the least recently used pair beyond
    /// `MORPH_PAIRS`.
    pub fn add_morph_pair(&mut self, fine: usize, coarse: usize, vertices: &[GeomorphVertexRaw]) {
        self.meshes.add_morph_pair(&self.device, (fine, coarse), vertices);
    }

    /// Resizes the surface and the depth and MSAA targets; a zero size is ignored.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.canvas.resize(&self.device, width, height);
    }

    /// Draws a frame to the canvas; returns whether its meter pictures will be read back (a
    /// frame that finds every readback in flight is not measured).
    pub fn render(&mut self, frame: &FrameInput) -> bool {
        let Some(texture) = self.canvas.current_texture(&self.device, &self.errors) else { return false };
        let buffer = self.prepare(frame);
        let (commands, readback) = self.encode(frame, &texture.texture, buffer);
        self.queue.submit([commands]);
        let measured = readback.is_some();
        if let Some(readback) = readback {
            self.start_readback(readback);
        }
        self.queue.present(texture);
        measured
    }

    /// Sizes what `frame` draws into before it is recorded: the views' targets (composed
    /// drawing), and the meter's pictures and FLIP kernels when the frame is measured or shows
    /// the difference overlay. Returns a readback buffer for a measured frame, unless every
    /// readback is in flight.
    fn prepare(&mut self, frame: &FrameInput) -> Option<wgpu::Buffer> {
        self.canvas.fit_view_targets(&self.device, frame.views[0].0);
        if frame.meter.is_some() || frame.overlay == Overlay::Difference {
            self.prepare_meter(frame)
        } else {
            None
        }
    }

    /// Records a frame into `target` (sized by [`Renderer::prepare`] first), with `readback` the
    /// buffer `prepare` gave; returns the readback to start after the submit, if the frame is
    /// measured.
    fn encode(
        &self,
        frame: &FrameInput,
        target: &wgpu::Texture,
        readback: Option<wgpu::Buffer>,
    ) -> (wgpu::CommandBuffer, Option<meter::Readback>) {
        let bones = self.uniforms.write(&self.queue, frame, self.encodes_srgb_in_shader());
        let target_view = target.create_view(&Default::default());
        let (fw, fh) = (target.width(), target.height());
        let visible = |r: &Rect| r.width > 0 && r.height > 0 && r.x + r.width <= fw && r.y + r.height <= fh;
        let mut encoder =
            self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let mut slot = 0u64;
        // The meter's pictures first: the difference overlay reads them in the views' passes.
        let difference = frame.overlay == Overlay::Difference;
        let (pictures, readback) = if frame.meter.is_some() || difference {
            self.encode_meter(&mut encoder, frame, readback, &mut slot)
        } else {
            (Vec::new(), None)
        };
        let heat = |pass: &mut wgpu::RenderPass, i: usize, origin: [f32; 2], rect: &Rect| {
            if let Some(&picture) = pictures.get(i).filter(|_| difference) {
                self.draw_difference(pass, i, origin, rect, picture);
            }
        };
        if self.canvas.composed {
            // The background (gaps between views), then each view drawn at its texture's origin
            // and copied into place.
            drop(begin_pass(&mut encoder, &target_view, None, None, background_for(target.format())));
            let Some(targets) = self.canvas.view_targets.as_ref() else {
                return (encoder.finish(), readback);
            };
            for (i, (rect, plan)) in frame.views.iter().enumerate() {
                if !visible(rect) || (rect.width, rect.height) != (targets.width, targets.height) {
                    continue;
                }
                let resolve = &targets.views[i];
                let (color, resolve_target) = match &targets.msaa {
                    Some(msaa) => (msaa, Some(resolve)),
                    None => (resolve, None),
                };
                {
                    let mut pass =
                        begin_pass(&mut encoder, color, resolve_target, Some(&targets.depth), BACKGROUND);
                    self.draw_content(&mut pass, frame, i, plan, [0.0; 2], &mut slot);
                    heat(&mut pass, i, [0.0; 2], rect);
                    self.draw_bones(&mut pass, bones);
                }
                encoder.copy_texture_to_texture(
                    targets.textures[i].as_image_copy(),
                    wgpu::TexelCopyTextureInfo {
                        texture: target,
                        mip_level: 0,
                        origin: wgpu::Origin3d { x: rect.x, y: rect.y, z: 0 },
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::Extent3d { width: rect.width, height: rect.height, depth_or_array_layers: 1 },
                );
            }
        } else if let Some((depth, msaa)) = &self.canvas.direct {
            let (color, resolve_target) = match msaa {
                Some(msaa) => (msaa, Some(&target_view)),
                None => (&target_view, None),
            };
            let mut pass = begin_pass(
                &mut encoder,
                color,
                resolve_target,
                Some(depth),
                background_for(self.canvas.color_format),
            );
            for (i, (rect, plan)) in frame.views.iter().enumerate() {
                if !visible(rect) {
                    continue;
                }
                pass.set_viewport(
                    rect.x as f32,
                    rect.y as f32,
                    rect.width as f32,
                    rect.height as f32,
                    0.0,
                    1.0,
                );
                pass.set_scissor_rect(rect.x, rect.y, rect.width, rect.height);
                self.draw_content(&mut pass, frame, i, plan, [rect.x as f32, rect.y as f32], &mut slot);
                heat(&mut pass, i, [rect.x as f32, rect.y as f32], rect);
                self.draw_bones(&mut pass, bones);
            }
            // WebGL2 resolves MSAA (and clears next frame) through the scissor: leave it whole.
            pass.set_scissor_rect(0, 0, fw, fh);
        }
        (encoder.finish(), readback)
    }

    /// Records view `i` of `frame`: the crowd's instanced draws in crowd mode, else its `plan`.
    fn draw_content(
        &self,
        pass: &mut wgpu::RenderPass,
        frame: &FrameInput,
        i: usize,
        plan: &ViewPlan,
        origin: [f32; 2],
        slot: &mut u64,
    ) {
        match frame.crowd {
            Some(crowd) => {
                self.draw_crowd_view(pass, crowd.views.get(i).map_or(&[], Vec::as_slice), origin, slot)
            }
            None => self.draw_view(pass, plan, frame.overlay, origin, slot),
        }
    }

    /// Records one view's draws; `slot` counts the draw-uniform slots used so far this frame.
    fn draw_view(
        &self,
        pass: &mut wgpu::RenderPass,
        plan: &ViewPlan,
        overlay: Overlay,
        origin: [f32; 2],
        slot: &mut u64,
    ) {
        pass.set_bind_group(0, &self.uniforms.frame_group, &[]);
        for draw in &plan.draws {
            let offset = (*slot % DRAW_SLOTS) * DRAW_STRIDE;
            *slot += 1;
            let raw = DrawRaw {
                morph_t: draw.morph.map_or(0.0, |m| m.t),
                opacity: draw.opacity,
                dither_mode: draw.dither_mode,
                dither_threshold: draw.dither_threshold,
                viewport_origin: origin,
                tint: draw_tint(overlay, draw.level, draw.morph),
                ..DrawRaw::default()
            };
            self.queue.write_buffer(&self.uniforms.draws, offset, bytemuck::bytes_of(&raw));
            let Some(level) = self.meshes.level(draw.level) else { continue };
            // A level's own buffer pairs each vertex with its ancestor one level coarser; a
            // geomorph that skips levels reads its uploaded pair buffer.
            let vertices = match draw.morph {
                Some(m) if m.coarse != draw.level + 1 => match self.meshes.morph_pair(draw.level, m.coarse) {
                    Some(buffer) => buffer,
                    None => continue,
                },
                _ => &level.vertices,
            };
            pass.set_bind_group(2, &self.uniforms.draw_group, &[offset as u32]);
            pass.set_vertex_buffer(0, vertices.slice(..));
            pass.set_index_buffer(level.indices.slice(..), wgpu::IndexFormat::Uint32);
            for &(first, count, material) in &level.ranges {
                let m = &self.meshes.materials[material];
                let key = (draw.pass, draw.morph.is_some(), !m.double_sided);
                pass.set_pipeline(&self.pipelines.shaded[&key]);
                pass.set_bind_group(1, &m.bind_group, &[]);
                pass.draw_indexed(first..first + count, 0, 0..1);
            }
            if overlay == Overlay::Wireframe && !level.ranges.is_empty() {
                // The same vertices and draw uniforms (morph, opacity, dither) as the triangles.
                pass.set_pipeline(&self.pipelines.wire[usize::from(draw.morph.is_some())]);
                pass.set_index_buffer(level.edges.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..level.edge_count, 0, 0..1);
            }
        }
    }

    /// Records the skeleton overlay's `points` bone-line vertices (0: nothing) over a view.
    fn draw_bones(&self, pass: &mut wgpu::RenderPass, points: u32) {
        if points == 0 {
            return;
        }
        pass.set_pipeline(&self.pipelines.bone);
        pass.set_bind_group(0, &self.uniforms.frame_group, &[]);
        pass.set_vertex_buffer(0, self.uniforms.bones.slice(..u64::from(points) * BONE_VERTEX_STRIDE));
        pass.draw(0..points, 0..1);
    }
}

/// What a reader is told when the GPU reports a problem while drawing; the GPU's own report (a
/// validation dump, say) goes to the console.
const GPU_ERROR: &str =
    "the GPU reported an error while drawing, so the views may be wrong (details in the console)";
const DEVICE_LOST: &str =
    "the GPU stopped drawing this viewer (its device was lost); reload the page to draw again";
const NO_FRAME: &str = "the canvas could not give a frame to draw into (details in the console)";

/// Records a problem for `state().errors` once (a broken pipeline repeats the same report every
/// frame) and logs the GPU's own report to the console.
fn push_error(sink: &Mutex<Vec<String>>, reader: &str, detail: &str) {
    web_sys::console::warn_1(&format!("clod-viewer: {detail}").into());
    let mut errors = sink.lock().unwrap_or_else(|p| p.into_inner());
    if !errors.iter().any(|e| e == reader) {
        errors.push(reader.to_owned());
    }
}

/// Lets the browser run other tasks (input, drawing, other elements) before the next step of a
/// long setup, so that no single task blocks the page for long: decoding the built-in
/// character's LOD chain, building its level buffers and starting the GPU are each ~50–100 ms.
pub async fn next_task() {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        let scheduled = web_sys::window().map(|w| w.set_timeout_with_callback(&resolve));
        if !matches!(scheduled, Some(Ok(_))) {
            let _ = resolve.call0(&wasm_bindgen::JsValue::NULL);
        }
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}
