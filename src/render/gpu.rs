//! The wgpu side of the renderer: device and surface set-up (WebGPU, or WebGL2 in the `webgl`
//! build), GPU buffers of every level, materials with their decoded textures, the pipelines of
//! `skin.wgsl`, and the execution of a frame's [`ViewPlan`]s: one render pass, one viewport per
//! view, 4× MSAA where the format allows it, into an sRGB target.
//!
//! Joint matrices live in a uniform block on both backends (WebGL2 has no storage buffers in
//! vertex shaders; doing the same on WebGPU keeps the comparison fair). Errors the device reports
//! asynchronously (validation, out of memory, device loss) are collected and handed to the page
//! by [`Renderer::take_errors`].

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use bytemuck::Zeroable;
use glam::Mat4;
use thiserror::Error;
use wasm_bindgen::JsCast;
use wgpu::util::DeviceExt;

use super::layout::Rect;
use super::lod_source::{GeomorphVertexRaw, LevelData, LodSource, VertexRaw};
use super::plan::{PassKind, ViewPlan};
use super::uniforms::{CameraRaw, DrawRaw, JointsRaw, MaterialRaw, MAX_JOINTS, SKIN_WGSL};
use crate::character::{AlphaMode, Character};

/// Why the renderer could not start or draw.
#[derive(Debug, Error)]
pub enum RenderError {
    #[error("no {0} adapter: this browser or GPU cannot run it")]
    NoAdapter(&'static str),
    #[error("the canvas cannot be used for {0}: {1}")]
    Surface(&'static str, String),
    #[error("the GPU refused a device: {0}")]
    Device(String),
    #[error("the character has {0} joints; the viewer draws at most {MAX_JOINTS}")]
    TooManyJoints(usize),
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

/// Draw-call slots of the per-draw uniform buffer: 3 views × 2 draws at most.
const DRAW_SLOTS: u64 = 6;
/// WebGPU's and WebGL2's minimum uniform offset alignment: the stride of the draw slots.
const DRAW_STRIDE: u64 = 256;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;
/// Background: a cool mid grey, linear (drawn as about #8a96a6 in sRGB), light enough that dark
/// clothes stand out and dark enough that light skin does.
const BACKGROUND: wgpu::Color = wgpu::Color { r: 0.25, g: 0.3, b: 0.38, a: 1.0 };

struct LevelGpu {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// `(first_index, index_count, material slot)`.
    ranges: Vec<(u32, u32, usize)>,
}

struct MaterialGpu {
    bind_group: wgpu::BindGroup,
    double_sided: bool,
}

/// Pipeline key: pass kind, geomorph vertex shader, back-face culling.
type PipelineKey = (PassKind, bool, bool);

/// Everything a frame needs besides the plans: shared camera and the pose.
pub struct FrameInput<'a> {
    pub camera: CameraRaw,
    pub skin: &'a [Mat4],
    pub views: [(Rect, &'a ViewPlan); 3],
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
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// Format the pipelines render to (the surface's, or its sRGB view).
    color_format: wgpu::TextureFormat,
    sample_count: u32,
    /// Full-canvas depth and MSAA targets, when views draw straight into the canvas.
    direct: Option<(wgpu::TextureView, Option<wgpu::TextureView>)>,
    /// View-size targets, when each view draws at the origin of its own texture and is copied
    /// into place (see [`Renderer::composed`]).
    view_targets: std::cell::RefCell<Option<ViewTargets>>,
    /// Whether views are drawn separately and copied into the frame. Drawing every view at the
    /// same origin makes equal views bit-identical (the viewport transform's rounding depends on
    /// the view's offset); it needs a canvas that accepts copies, which WebGPU's always does.
    composed: bool,
    camera_buffer: wgpu::Buffer,
    joints_buffer: wgpu::Buffer,
    draw_buffer: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    draw_group: wgpu::BindGroup,
    materials: Vec<MaterialGpu>,
    levels: Vec<LevelGpu>,
    /// The continuous-LOD mesh, drawn as level `levels.len()`.
    continuous: Option<LevelGpu>,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    errors: Arc<Mutex<Vec<String>>>,
    /// `webgpu` or `webgl2`, and the adapter's name.
    pub backend: &'static str,
    pub adapter_name: String,
}

impl Renderer {
    /// Sets up the device on `canvas`, uploads the levels and decodes the textures.
    ///
    /// # Errors
    /// [`RenderError`]: no adapter for the backend, a canvas or device the browser refuses, more
    /// than [`MAX_JOINTS`] joints, or a texture the browser cannot decode.
    pub async fn new(
        canvas: web_sys::HtmlCanvasElement,
        choice: BackendChoice,
        character: &Character,
        lod: &LodSource,
    ) -> Result<Self, RenderError> {
        let joint_count = character.skeleton.joints.len();
        if joint_count > MAX_JOINTS {
            return Err(RenderError::TooManyJoints(joint_count));
        }
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
        // WebGL2's limits on both backends: the same work, and the joint block (16 KiB) fits.
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
            push_error(&sink, format!("GPU error: {e}"))
        }));
        let sink = Arc::clone(&errors);
        device.set_device_lost_callback(move |reason, message| {
            push_error(&sink, format!("the GPU device was lost ({reason:?}): {message}"));
        });

        let caps = surface.get_capabilities(&adapter);
        let (config, color_format) = surface_config(&caps, choice, width, height)
            .ok_or_else(|| RenderError::Surface(backend, "no usable surface format".into()))?;
        surface.configure(&device, &config);
        let sample_count =
            if adapter.get_texture_format_features(color_format).flags.sample_count_supported(4) {
                4
            } else {
                1
            };

        let camera_buffer = uniform_buffer(&device, "camera", std::mem::size_of::<CameraRaw>() as u64);
        let joints_buffer = uniform_buffer(&device, "joints", std::mem::size_of::<JointsRaw>() as u64);
        let draw_buffer = uniform_buffer(&device, "draws", DRAW_SLOTS * DRAW_STRIDE);
        let layouts = BindLayouts::new(&device);
        let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &layouts.frame,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: camera_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: joints_buffer.as_entire_binding() },
            ],
        });
        let draw_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("draw"),
            layout: &layouts.draw,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &draw_buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<DrawRaw>() as u64),
                }),
            }],
        });
        let materials = upload_materials(&device, &queue, &layouts.material, character).await?;
        let default_slot = materials.len() - 1;
        let levels = lod.levels.iter().map(|level| upload_level(&device, level, default_slot)).collect();
        let pipelines = create_pipelines(&device, &layouts, color_format, sample_count);
        let composed = config.usage.contains(wgpu::TextureUsages::COPY_DST);
        let direct = (!composed).then(|| targets(&device, color_format, sample_count, width, height));
        let info = adapter.get_info();
        Ok(Self {
            device,
            queue,
            surface,
            config,
            color_format,
            sample_count,
            direct,
            view_targets: Default::default(),
            composed,
            camera_buffer,
            joints_buffer,
            draw_buffer,
            frame_group,
            draw_group,
            materials,
            levels,
            continuous: None,
            pipelines,
            errors,
            backend,
            adapter_name: info.name,
        })
    }

    /// Whether the shader must encode sRGB itself (the target format is not sRGB).
    pub fn encodes_srgb_in_shader(&self) -> bool {
        !self.color_format.is_srgb()
    }

    /// MSAA sample count in use (4, or 1 where the format cannot multisample).
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Whether views are drawn apart and copied into the frame (see the field's docs).
    pub fn composed(&self) -> bool {
        self.composed
    }

    /// Name of the colour format the views render in.
    pub fn color_format_name(&self) -> String {
        format!("{:?}", self.color_format)
    }

    /// Current framebuffer size.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Errors reported since the last call (validation, device loss, surface trouble).
    pub fn take_errors(&self) -> Vec<String> {
        std::mem::take(&mut *self.errors.lock().unwrap_or_else(|p| p.into_inner()))
    }

    /// Uploads the continuous-LOD mesh (drawn as level `levels`), or drops it.
    pub fn set_continuous_level(&mut self, level: Option<&LevelData>) {
        let default_slot = self.materials.len() - 1;
        self.continuous = level.map(|l| upload_level(&self.device, l, default_slot));
    }

    /// Resizes the surface and the depth and MSAA targets; a zero size is ignored.
    pub fn resize(&mut self, width: u32, height: u32) {
        let max = self.device.limits().max_texture_dimension_2d;
        let (width, height) = (width.min(max), height.min(max));
        if width == 0 || height == 0 || (width, height) == (self.config.width, self.config.height) {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
        if !self.composed {
            self.direct = Some(targets(&self.device, self.color_format, self.sample_count, width, height));
        }
    }

    /// Draws a frame to the canvas.
    pub fn render(&self, frame: &FrameInput) {
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // Reconfigure and draw next frame; a surface that stays lost shows up as errors.
                self.surface.configure(&self.device, &self.config);
                return;
            }
            other => {
                push_error(&self.errors, format!("the canvas could not give a frame: {other:?}"));
                return;
            }
        };
        let commands = self.encode(frame, &texture.texture);
        self.queue.submit([commands]);
        self.queue.present(texture);
    }

    /// Draws a frame offscreen at the canvas size and reads it back.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU cannot map the copy.
    pub async fn read_pixels(&self, frame: &FrameInput<'_>) -> Result<Pixels, RenderError> {
        let (width, height) = (self.config.width, self.config.height);
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("readback target"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.color_format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let mut commands = vec![self.encode(frame, &texture)];
        // Rows of a texture-to-buffer copy are padded to 256 bytes (WebGPU's rule).
        let row = 4 * width as u64;
        let padded = row.div_ceil(256) * 256;
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: padded * height as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded as u32),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
        commands.push(encoder.finish());
        self.queue.submit(commands);
        map_read(&self.device, &buffer).await?;
        let mapped = buffer.get_mapped_range(..).map_err(|e| RenderError::Readback(e.to_string()))?;
        let bgra = matches!(
            self.color_format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let mut rgba = Vec::with_capacity((row * height as u64) as usize);
        for y in 0..height as usize {
            let line = &mapped[y * padded as usize..y * padded as usize + row as usize];
            if bgra {
                rgba.extend(line.chunks_exact(4).flat_map(|p| [p[2], p[1], p[0], p[3]]));
            } else {
                rgba.extend_from_slice(line);
            }
        }
        drop(mapped);
        buffer.unmap();
        Ok(Pixels { width, height, rgba })
    }

    /// Resolves once the GPU has finished everything submitted so far (for frame timing).
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU cannot map the fence buffer.
    pub async fn finish(&self) -> Result<(), RenderError> {
        let fence = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fence"),
            size: 4,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.draw_buffer, 0, &fence, 0, 4);
        self.queue.submit([encoder.finish()]);
        map_read(&self.device, &fence).await
    }

    fn encode(&self, frame: &FrameInput, target: &wgpu::Texture) -> wgpu::CommandBuffer {
        let mut joints = JointsRaw::zeroed();
        for (slot, m) in joints.model_from_bind.iter_mut().zip(frame.skin) {
            *slot = m.to_cols_array_2d();
        }
        let mut camera = frame.camera;
        camera.encode_srgb = u32::from(self.encodes_srgb_in_shader());
        self.queue.write_buffer(&self.camera_buffer, 0, bytemuck::bytes_of(&camera));
        self.queue.write_buffer(&self.joints_buffer, 0, bytemuck::bytes_of(&joints));
        let target_view = target.create_view(&Default::default());
        let (fw, fh) = (target.width(), target.height());
        let visible = |r: &Rect| r.width > 0 && r.height > 0 && r.x + r.width <= fw && r.y + r.height <= fh;
        let mut encoder =
            self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let mut slot = 0u64;
        if self.composed {
            // The background (gaps between views), then each view drawn at its texture's origin
            // and copied into place.
            drop(begin_pass(&mut encoder, &target_view, None, None, background_for(target.format())));
            let size = frame.views[0].0;
            let mut cache = self.view_targets.borrow_mut();
            if cache.as_ref().is_none_or(|t| (t.width, t.height) != (size.width, size.height)) {
                *cache = (size.width > 0 && size.height > 0)
                    .then(|| ViewTargets::new(&self.device, self.color_format, self.sample_count, size));
            }
            let Some(targets) = cache.as_ref() else { return encoder.finish() };
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
                    self.draw_view(&mut pass, plan, [0.0; 2], &mut slot);
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
        } else if let Some((depth, msaa)) = &self.direct {
            let (color, resolve_target) = match msaa {
                Some(msaa) => (msaa, Some(&target_view)),
                None => (&target_view, None),
            };
            let mut pass = begin_pass(
                &mut encoder,
                color,
                resolve_target,
                Some(depth),
                background_for(self.color_format),
            );
            for (rect, plan) in &frame.views {
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
                self.draw_view(&mut pass, plan, [rect.x as f32, rect.y as f32], &mut slot);
            }
            // WebGL2 resolves MSAA (and clears next frame) through the scissor: leave it whole.
            pass.set_scissor_rect(0, 0, fw, fh);
        }
        encoder.finish()
    }

    /// Records one view's draws; `slot` counts the draw-uniform slots used so far this frame.
    fn draw_view(&self, pass: &mut wgpu::RenderPass, plan: &ViewPlan, origin: [f32; 2], slot: &mut u64) {
        pass.set_bind_group(0, &self.frame_group, &[]);
        for draw in &plan.draws {
            let offset = (*slot % DRAW_SLOTS) * DRAW_STRIDE;
            *slot += 1;
            let raw = DrawRaw {
                morph_t: draw.morph_t.unwrap_or(0.0),
                opacity: draw.opacity,
                dither_mode: draw.dither_mode,
                dither_threshold: draw.dither_threshold,
                viewport_origin: origin,
                ..DrawRaw::default()
            };
            self.queue.write_buffer(&self.draw_buffer, offset, bytemuck::bytes_of(&raw));
            let level = match self.levels.get(draw.level) {
                Some(level) => level,
                None if draw.level == self.levels.len() => match &self.continuous {
                    Some(level) => level,
                    None => continue,
                },
                None => continue,
            };
            pass.set_bind_group(2, &self.draw_group, &[offset as u32]);
            pass.set_vertex_buffer(0, level.vertices.slice(..));
            pass.set_index_buffer(level.indices.slice(..), wgpu::IndexFormat::Uint32);
            for &(first, count, material) in &level.ranges {
                let m = &self.materials[material];
                let key = (draw.pass, draw.morph_t.is_some(), !m.double_sided);
                pass.set_pipeline(&self.pipelines[&key]);
                pass.set_bind_group(1, &m.bind_group, &[]);
                pass.draw_indexed(first..first + count, 0, 0..1);
            }
        }
    }
}

/// A render pass clearing colour to `background` and depth to 1.
fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    color: &wgpu::TextureView,
    resolve_target: Option<&wgpu::TextureView>,
    depth: Option<&wgpu::TextureView>,
    background: wgpu::Color,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("view"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(background), store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: depth.map(|view| wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// One colour texture per view (the views' sRGB format, copied into the canvas), and the MSAA and depth
/// targets the three views share, all of the view size.
struct ViewTargets {
    width: u32,
    height: u32,
    textures: [wgpu::Texture; 3],
    views: [wgpu::TextureView; 3],
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
}

impl ViewTargets {
    fn new(device: &wgpu::Device, color_format: wgpu::TextureFormat, sample_count: u32, size: Rect) -> Self {
        let textures = [0, 1, 2].map(|_| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("view colour"),
                size: wgpu::Extent3d { width: size.width, height: size.height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: color_format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        });
        let views = [0, 1, 2].map(|i| textures[i].create_view(&Default::default()));
        let (depth, msaa) = targets(device, color_format, sample_count, size.width, size.height);
        Self { width: size.width, height: size.height, textures, views, msaa, depth }
    }
}

fn push_error(sink: &Mutex<Vec<String>>, message: String) {
    let mut errors = sink.lock().unwrap_or_else(|p| p.into_inner());
    // Keep the first few: a broken pipeline repeats the same error every frame.
    if errors.len() < 16 {
        errors.push(message);
    }
}

/// Maps `buffer` for reading and waits for it. WebGPU resolves the map from the browser's event
/// loop; the GL backend only when polled after its fence has signalled, which WebGL cannot block
/// on — so this polls, yielding to the event loop between tries, for at most [`MAP_TIMEOUT_MS`].
async fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<(), RenderError> {
    let result: std::rc::Rc<std::cell::Cell<Option<bool>>> = Default::default();
    let done = std::rc::Rc::clone(&result);
    buffer.map_async(wgpu::MapMode::Read, .., move |r| done.set(Some(r.is_ok())));
    let started = js_sys::Date::now();
    loop {
        let _ = device.poll(wgpu::PollType::Poll);
        match result.get() {
            Some(true) => return Ok(()),
            Some(false) => return Err(RenderError::Readback("the buffer could not be mapped".into())),
            None if js_sys::Date::now() - started > MAP_TIMEOUT_MS => {
                return Err(RenderError::Readback(format!(
                    "the GPU did not finish within {MAP_TIMEOUT_MS} ms"
                )));
            }
            None => yield_to_event_loop().await,
        }
    }
}

/// Longest wait for a readback: SwiftShader draws a large frame in well under a second.
const MAP_TIMEOUT_MS: f64 = 20_000.0;

/// Resolves on the next turn of the event loop (a zero-delay timeout).
async fn yield_to_event_loop() {
    let promise = js_sys::Promise::new(&mut |resolve, _reject| {
        let set_timeout =
            web_sys::window().map(|w| w.set_timeout_with_callback_and_timeout_and_arguments_0(&resolve, 0));
        if !matches!(set_timeout, Some(Ok(_))) {
            // No window (a worker): resolve at once; the loop's deadline still bounds the wait.
            let _ = resolve.call0(&wasm_bindgen::JsValue::NULL);
        }
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}

/// Vertex and index buffers of a level; materials outside the table use the default material.
fn upload_level(device: &wgpu::Device, level: &LevelData, default_slot: usize) -> LevelGpu {
    LevelGpu {
        vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("level vertices"),
            contents: bytemuck::cast_slice(&level.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        }),
        indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("level indices"),
            // An empty buffer is valid but an empty init slice is not mappable everywhere.
            contents: if level.indices.is_empty() { &[0; 4] } else { bytemuck::cast_slice(&level.indices) },
            usage: wgpu::BufferUsages::INDEX,
        }),
        ranges: level
            .ranges
            .iter()
            .map(|r| (r.first_index, r.index_count, r.material.unwrap_or(default_slot).min(default_slot)))
            .collect(),
    }
}

fn uniform_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Surface configuration and the format the views render in (sRGB where possible, so blending and
/// MSAA resolve happen in linear light):
/// - the surface offers an sRGB format: use it;
/// - it accepts copies (WebGPU canvases): views render into sRGB textures whose bytes are copied
///   into the plain-format canvas (formats that differ only in sRGB-ness are copy-compatible);
/// - otherwise the plain format, and the shader encodes sRGB itself.
fn surface_config(
    caps: &wgpu::SurfaceCapabilities,
    choice: BackendChoice,
    width: u32,
    height: u32,
) -> Option<(wgpu::SurfaceConfiguration, wgpu::TextureFormat)> {
    let first = *caps.formats.first()?;
    let srgb = caps.formats.iter().copied().find(|f| f.is_srgb());
    // WebGPU canvases take any usage (wgpu reports only RENDER_ATTACHMENT for them).
    let copies = caps.usages.contains(wgpu::TextureUsages::COPY_DST) || choice == BackendChoice::WebGpu;
    let (format, color_format) = match srgb {
        Some(f) => (f, f),
        None if copies => (first, first.add_srgb_suffix()),
        None => (first, first),
    };
    // Views are copied into the canvas where it accepts copies (see `Renderer::composed`).
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | if copies { wgpu::TextureUsages::COPY_DST } else { wgpu::TextureUsages::empty() };
    let config = wgpu::SurfaceConfiguration {
        usage,
        format,
        color_space: Default::default(),
        width,
        height,
        present_mode: wgpu::PresentMode::Fifo,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
    };
    Some((config, color_format))
}

/// The background in a target's own encoding: linear for sRGB formats (the hardware encodes),
/// encoded by hand for plain ones.
fn background_for(format: wgpu::TextureFormat) -> wgpu::Color {
    if format.is_srgb() {
        return BACKGROUND;
    }
    let encode = |c: f64| if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    wgpu::Color { r: encode(BACKGROUND.r), g: encode(BACKGROUND.g), b: encode(BACKGROUND.b), a: 1.0 }
}

fn targets(
    device: &wgpu::Device,
    color_format: wgpu::TextureFormat,
    sample_count: u32,
    width: u32,
    height: u32,
) -> (wgpu::TextureView, Option<wgpu::TextureView>) {
    let texture = |label, format| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&Default::default())
    };
    let msaa = (sample_count > 1).then(|| texture("msaa colour", color_format));
    (texture("depth", DEPTH_FORMAT), msaa)
}

struct BindLayouts {
    frame: wgpu::BindGroupLayout,
    material: wgpu::BindGroupLayout,
    draw: wgpu::BindGroupLayout,
}

impl BindLayouts {
    fn new(device: &wgpu::Device) -> Self {
        let uniform = |binding, visibility, dynamic| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: dynamic,
                min_binding_size: None,
            },
            count: None,
        };
        let both = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let frame = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[uniform(0, both, false), uniform(1, wgpu::ShaderStages::VERTEX, false)],
        });
        let material = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material"),
            entries: &[
                uniform(0, wgpu::ShaderStages::FRAGMENT, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let draw = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("draw"),
            entries: &[uniform(0, both, true)],
        });
        Self { frame, material, draw }
    }
}

/// Vertex attributes of one [`VertexRaw`] at `base` bytes, shader locations from `location`.
fn vertex_attributes(base: u64, location: u32) -> [wgpu::VertexAttribute; 6] {
    use wgpu::VertexFormat as F;
    let formats = [F::Float32x3, F::Float32x3, F::Float32x2, F::Float32x4, F::Uint16x4, F::Float32x4];
    let offsets = [0u64, 12, 24, 32, 48, 56];
    std::array::from_fn(|i| wgpu::VertexAttribute {
        format: formats[i],
        offset: base + offsets[i],
        shader_location: location + i as u32,
    })
}

fn create_pipelines(
    device: &wgpu::Device,
    layouts: &BindLayouts,
    color_format: wgpu::TextureFormat,
    sample_count: u32,
) -> HashMap<PipelineKey, wgpu::RenderPipeline> {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("skin.wgsl"),
        source: wgpu::ShaderSource::Wgsl(SKIN_WGSL.into()),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("skin"),
        bind_group_layouts: &[Some(&layouts.frame), Some(&layouts.material), Some(&layouts.draw)],
        immediate_size: 0,
    });
    let fine = vertex_attributes(0, 0);
    let mut both = fine.to_vec();
    both.extend(vertex_attributes(std::mem::size_of::<VertexRaw>() as u64, 6));
    let stride = std::mem::size_of::<GeomorphVertexRaw>() as u64;
    let mut out = HashMap::new();
    for pass in [PassKind::Opaque, PassKind::BlendOver, PassKind::BlendNaive] {
        for geomorph in [false, true] {
            for cull in [false, true] {
                let attributes: &[wgpu::VertexAttribute] = if geomorph { &both } else { &fine };
                let buffers = [Some(wgpu::VertexBufferLayout {
                    array_stride: stride,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes,
                })];
                let blend = (pass != PassKind::Opaque).then_some(wgpu::BlendState::ALPHA_BLENDING);
                let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(&format!("{pass:?} geomorph={geomorph} cull={cull}")),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(if geomorph { "vs_geomorph" } else { "vs_level" }),
                        compilation_options: Default::default(),
                        buffers: &buffers,
                    },
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        front_face: wgpu::FrontFace::Ccw,
                        cull_mode: cull.then_some(wgpu::Face::Back),
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(pass != PassKind::BlendOver),
                        // The fading level lies on the opaque one: equal depths must pass.
                        depth_compare: Some(if pass == PassKind::BlendOver {
                            wgpu::CompareFunction::LessEqual
                        } else {
                            wgpu::CompareFunction::Less
                        }),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: wgpu::MultisampleState {
                        count: sample_count,
                        mask: !0,
                        alpha_to_coverage_enabled: false,
                    },
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_main"),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format: color_format,
                            blend,
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    multiview_mask: None,
                    cache: None,
                });
                out.insert((pass, geomorph, cull), pipeline);
            }
        }
    }
    out
}

/// One bind group per material plus a last one for glTF's default material (white, opaque,
/// single-sided). Textures are decoded by the browser (`createImageBitmap`) and copied in.
async fn upload_materials(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layout: &wgpu::BindGroupLayout,
    character: &Character,
) -> Result<Vec<MaterialGpu>, RenderError> {
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("base colour"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    let white = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("white"),
            size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &[255; 4],
    );
    let mut out = Vec::new();
    let default = crate::character::Material {
        name: "default".into(),
        base_color_factor: glam::Vec4::ONE,
        base_color_texture: None,
        alpha_mode: AlphaMode::Opaque,
        double_sided: false,
    };
    for material in character.materials.iter().chain([&default]) {
        let texture = match &material.base_color_texture {
            Some(image) => decode_texture(device, queue, &image.bytes, &image.mime_type)
                .await
                .map_err(|reason| RenderError::Texture { material: material.name.clone(), reason })?,
            None => white.clone(),
        };
        let raw = MaterialRaw {
            base_color_factor: material.base_color_factor.to_array(),
            alpha_cutoff: match material.alpha_mode {
                AlphaMode::Mask { cutoff } => cutoff,
                _ => 0.0,
            },
            double_sided: u32::from(material.double_sided),
            _pad: [0; 2],
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("material"),
            contents: bytemuck::bytes_of(&raw),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let view = texture.create_view(&Default::default());
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&material.name),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        });
        out.push(MaterialGpu { bind_group, double_sided: material.double_sided });
    }
    Ok(out)
}

/// Decodes an encoded image with the browser and copies it into an sRGB texture.
async fn decode_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    bytes: &[u8],
    mime_type: &str,
) -> Result<wgpu::Texture, String> {
    let window = web_sys::window().ok_or("no window")?;
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(mime_type);
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)
        .map_err(|e| format!("{e:?}"))?;
    let bitmap_options = web_sys::ImageBitmapOptions::new();
    // The texture is sRGB and glTF's colours are not premultiplied: take the bytes as they are.
    bitmap_options.set_color_space_conversion(web_sys::ColorSpaceConversion::None);
    bitmap_options.set_premultiply_alpha(web_sys::PremultiplyAlpha::None);
    let promise = window
        .create_image_bitmap_with_blob_and_image_bitmap_options(&blob, &bitmap_options)
        .map_err(|e| format!("{e:?}"))?;
    let bitmap: web_sys::ImageBitmap = wasm_bindgen_futures::JsFuture::from(promise)
        .await
        .map_err(|e| js_sys::Error::from(e).message().as_string().unwrap_or_else(|| "decode failed".into()))?
        .dyn_into()
        .map_err(|_| "createImageBitmap returned something else")?;
    let size = wgpu::Extent3d {
        width: bitmap.width().max(1),
        height: bitmap.height().max(1),
        depth_or_array_layers: 1,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("base colour"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        // copy_external_image_to_texture needs RENDER_ATTACHMENT on WebGPU.
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    queue.copy_external_image_to_texture(
        &wgpu::CopyExternalImageSourceInfo {
            source: wgpu::ExternalImageSource::ImageBitmap(bitmap),
            origin: wgpu::Origin2d::ZERO,
            flip_y: false,
        },
        wgpu::CopyExternalImageDestInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
            color_space: wgpu::PredefinedColorSpace::Srgb,
            premultiplied_alpha: false,
        },
        size,
    );
    Ok(texture)
}
