//! Render targets: the canvas ([`Canvas`]: its surface, configured sRGB where possible, and what
//! the views draw into), the depth and MSAA targets, the per-view textures of the composed path,
//! and the render pass that clears them.

use std::sync::Mutex;

use super::{push_error, BackendChoice, RenderError, BACKGROUND, DEPTH_FORMAT, NO_FRAME};
use crate::render::layout::Rect;

/// The canvas the views end on, and the targets they draw into on the way.
pub(super) struct Canvas {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// Format the pipelines render to (the surface's, or its sRGB view).
    pub(super) color_format: wgpu::TextureFormat,
    /// MSAA samples: 4, or 1 where the format cannot multisample.
    pub(super) sample_count: u32,
    /// Whether views are drawn separately and copied into the frame. Drawing every view at the
    /// same origin makes equal views bit-identical (the viewport transform's rounding depends on
    /// the view's offset); it needs a canvas that accepts copies, which WebGPU's always does.
    pub(super) composed: bool,
    /// Full-canvas depth and MSAA targets, when views draw straight into the canvas.
    pub(super) direct: Option<(wgpu::TextureView, Option<wgpu::TextureView>)>,
    /// View-size targets, when each view draws at the origin of its own texture and is copied
    /// into place (`composed`); made for the first frame, and again when the views' size changes.
    pub(super) view_targets: Option<ViewTargets>,
}

impl Canvas {
    /// Configures `surface` for `device` at `width` × `height` (see [`surface_config`]).
    ///
    /// # Errors
    /// [`RenderError::Surface`] when the surface offers no format.
    pub(super) fn new(
        surface: wgpu::Surface<'static>,
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        (choice, backend): (BackendChoice, &'static str),
        (width, height): (u32, u32),
    ) -> Result<Canvas, RenderError> {
        let caps = surface.get_capabilities(adapter);
        let (config, color_format) = surface_config(&caps, choice, width, height)
            .ok_or_else(|| RenderError::Surface(backend, "no usable surface format".into()))?;
        surface.configure(device, &config);
        let multisamples = adapter.get_texture_format_features(color_format).flags.sample_count_supported(4);
        let sample_count = if multisamples { 4 } else { 1 };
        let composed = config.usage.contains(wgpu::TextureUsages::COPY_DST);
        let direct = (!composed).then(|| targets(device, color_format, sample_count, width, height));
        Ok(Canvas { surface, config, color_format, sample_count, composed, direct, view_targets: None })
    }

    /// The canvas's size in pixels.
    pub(super) fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Resizes the surface and the full-canvas targets; a zero size, or the current one, is
    /// ignored, and one over the device's largest texture is clamped to it.
    pub(super) fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        let max = device.limits().max_texture_dimension_2d;
        let (width, height) = (width.min(max), height.min(max));
        if width == 0 || height == 0 || (width, height) == self.size() {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(device, &self.config);
        if !self.composed {
            self.direct = Some(targets(device, self.color_format, self.sample_count, width, height));
        }
    }

    /// The texture to draw this frame into, or `None` (nothing drawn this frame): a lost or
    /// outdated surface is configured again for the next frame, and any other failure is
    /// reported into `errors`.
    pub(super) fn current_texture(
        &mut self,
        device: &wgpu::Device,
        errors: &Mutex<Vec<String>>,
    ) -> Option<wgpu::SurfaceTexture> {
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => Some(t),
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => None,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // Reconfigure and draw next frame; a surface that stays lost shows up as errors.
                self.surface.configure(device, &self.config);
                None
            }
            other => {
                push_error(errors, NO_FRAME, &format!("the canvas could not give a frame: {other:?}"));
                None
            }
        }
    }

    /// Makes the views' own targets `size` large when the views are composed (none for an empty
    /// view).
    pub(super) fn fit_view_targets(&mut self, device: &wgpu::Device, size: Rect) {
        let fits = |t: &ViewTargets| (t.width, t.height) == (size.width, size.height);
        if self.composed && !self.view_targets.as_ref().is_some_and(fits) {
            self.view_targets = (size.width > 0 && size.height > 0)
                .then(|| ViewTargets::new(device, self.color_format, self.sample_count, size));
        }
    }
}

/// A render pass clearing colour to `background` and depth to 1.
pub(super) fn begin_pass<'e>(
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
pub(super) struct ViewTargets {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) textures: [wgpu::Texture; 3],
    pub(super) views: [wgpu::TextureView; 3],
    pub(super) msaa: Option<wgpu::TextureView>,
    pub(super) depth: wgpu::TextureView,
}

impl ViewTargets {
    pub(super) fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        sample_count: u32,
        size: Rect,
    ) -> Self {
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

/// Surface configuration and the format the views render in (sRGB where possible, so blending and
/// MSAA resolve happen in linear light):
/// - the surface offers an sRGB format: use it;
/// - it accepts copies (WebGPU canvases): views render into sRGB textures whose bytes are copied
///   into the plain-format canvas (formats that differ only in sRGB-ness are copy-compatible);
/// - otherwise the plain format, and the shader encodes sRGB itself.
pub(super) fn surface_config(
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
pub(super) fn background_for(format: wgpu::TextureFormat) -> wgpu::Color {
    if format.is_srgb() {
        return BACKGROUND;
    }
    let encode = |c: f64| if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    wgpu::Color { r: encode(BACKGROUND.r), g: encode(BACKGROUND.g), b: encode(BACKGROUND.b), a: 1.0 }
}

pub(super) fn targets(
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
