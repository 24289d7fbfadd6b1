//! LDR-FLIP on the GPU ([`crate::render::flip`], `flip.wgsl`): per picture one pass of the
//! horizontal filters into two `rgba32float` targets, per pair one pass of the vertical filters
//! and the error into an `rgba8unorm` target (16 bits in red and green). Fragment passes only, so
//! WebGL2 runs them too where it can render to float targets (`EXT_color_buffer_float`, which
//! SwiftShader and current desktop browsers have); elsewhere FLIP is off and says so.

use wgpu::util::DeviceExt;

use super::resources::uniform_buffer;
use super::{readback, RenderError, Renderer};
use crate::render::flip::{FlipKernels, FlipKernelsRaw, FLIP_WGSL};

const FILTERED: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The error map's format: 16 bits of error in red (high byte) and green (low byte).
pub(super) const ERROR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The two pipelines and the kernels' uniform.
pub(super) struct FlipGpu {
    horizontal: wgpu::RenderPipeline,
    error: wgpu::RenderPipeline,
    horizontal_layout: wgpu::BindGroupLayout,
    error_layout: wgpu::BindGroupLayout,
    kernels: wgpu::Buffer,
    /// The kernels in the uniform: ppd and whether the pictures are sRGB-encoded.
    written: Option<(f32, bool)>,
}

/// A picture's horizontal filters (see `fs_horizontal`).
pub(super) struct Filtered {
    _textures: [wgpu::Texture; 2],
    spatial: wgpu::TextureView,
    feature: wgpu::TextureView,
}

/// A texture `width` × `height` of `format` that passes render into and read from.
pub(super) fn target(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("flip target"),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

impl Filtered {
    pub(super) fn new(device: &wgpu::Device, width: u32, height: u32) -> Self {
        let textures = [target(device, FILTERED, width, height), target(device, FILTERED, width, height)];
        let spatial = textures[0].create_view(&Default::default());
        let feature = textures[1].create_view(&Default::default());
        Self { _textures: textures, spatial, feature }
    }
}

fn layout(device: &wgpu::Device, label: &str, textures: &[u32]) -> wgpu::BindGroupLayout {
    let mut entries = vec![wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }];
    entries.extend(textures.iter().map(|&binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        // Read with textureLoad only: float targets cannot be filtered everywhere.
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }));
    device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries })
}

fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    entry: &str,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_flip"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl FlipGpu {
    /// The pipelines, or `None` where float targets cannot be rendered into (`renderable`).
    pub(super) fn new(device: &wgpu::Device, renderable: bool) -> Option<Self> {
        if !renderable {
            return None;
        }
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("flip.wgsl"),
            source: wgpu::ShaderSource::Wgsl(FLIP_WGSL.into()),
        });
        let horizontal_layout = layout(device, "flip horizontal", &[1]);
        let error_layout = layout(device, "flip error", &[2, 3, 4, 5]);
        let float = Some(wgpu::ColorTargetState {
            format: FILTERED,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
        let horizontal =
            pipeline(device, &module, &horizontal_layout, "fs_horizontal", &[float.clone(), float]);
        let error = pipeline(
            device,
            &module,
            &error_layout,
            "fs_error",
            &[Some(wgpu::ColorTargetState {
                format: ERROR_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        );
        let kernels = uniform_buffer(device, "flip kernels", std::mem::size_of::<FlipKernelsRaw>() as u64);
        Some(Self {
            horizontal,
            error,
            horizontal_layout,
            error_layout,
            kernels,
            written: Default::default(),
        })
    }

    /// Writes the kernels for `ppd` (clamped to what the shader holds) and whether the pictures'
    /// values are sRGB-encoded; returns the ppd used.
    pub(super) fn set_kernels(&mut self, queue: &wgpu::Queue, ppd: f32, encoded: bool) -> f32 {
        let ppd = ppd.clamp(1.0, MAX_PPD);
        if self.written != Some((ppd, encoded)) {
            let mut raw = FlipKernels::new(ppd).raw().expect("the ppd is clamped to fit");
            raw.radii[2] = u32::from(encoded);
            queue.write_buffer(&self.kernels, 0, bytemuck::bytes_of(&raw));
            self.written = Some((ppd, encoded));
        }
        ppd
    }

    /// The pixels per degree of the kernels in the uniform (see [`FlipGpu::set_kernels`]).
    pub(super) fn ppd(&self) -> Option<f32> {
        self.written.map(|(ppd, _)| ppd)
    }

    fn pass<'e>(
        encoder: &'e mut wgpu::CommandEncoder,
        targets: &[&wgpu::TextureView],
    ) -> wgpu::RenderPass<'e> {
        let attachments: Vec<_> = targets
            .iter()
            .map(|view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("flip"),
            color_attachments: &attachments,
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Records the horizontal filters of `picture` into `out` (the picture's size).
    pub(super) fn encode_horizontal(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        picture: &wgpu::TextureView,
        out: &Filtered,
    ) {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("flip horizontal"),
            layout: &self.horizontal_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.kernels.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(picture) },
            ],
        });
        let mut pass = Self::pass(encoder, &[&out.spatial, &out.feature]);
        pass.set_pipeline(&self.horizontal);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Records the error of `test` against `reference` into `out` ([`ERROR_FORMAT`], their size).
    pub(super) fn encode_error(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        reference: &Filtered,
        test: &Filtered,
        out: &wgpu::TextureView,
    ) {
        let view = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("flip error"),
            layout: &self.error_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.kernels.as_entire_binding() },
                view(2, &reference.spatial),
                view(3, &reference.feature),
                view(4, &test.spatial),
                view(5, &test.feature),
            ],
        });
        let mut pass = Self::pass(encoder, &[out]);
        pass.set_pipeline(&self.error);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The largest ppd the shader's kernels hold ([`crate::render::flip::MAX_RADIUS`] taps a side).
pub const MAX_PPD: f32 = 110.0;

impl Renderer {
    /// LDR-FLIP of two RGBA8 sRGB pictures of `width` × `height` at `ppd` on this GPU: the error
    /// map (0..1 per pixel, 16-bit steps, rows top first), or `None` where this GPU cannot render
    /// into float targets.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the map cannot be read back.
    pub async fn flip_map(
        &mut self,
        reference: &[u8],
        test: &[u8],
        width: u32,
        height: u32,
        ppd: f32,
    ) -> Result<Option<Vec<f32>>, RenderError> {
        let Some(flip) = self.flip.as_mut() else { return Ok(None) };
        let upload = |pixels: &[u8]| {
            self.device.create_texture_with_data(
                &self.queue,
                &wgpu::TextureDescriptor {
                    label: Some("flip picture"),
                    size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::Rgba8Unorm,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                pixels,
            )
        };
        let pictures = [upload(reference), upload(test)];
        flip.set_kernels(&self.queue, ppd, true);
        let filtered =
            [Filtered::new(&self.device, width, height), Filtered::new(&self.device, width, height)];
        let out = target(&self.device, ERROR_FORMAT, width, height);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        for (picture, filtered) in pictures.iter().zip(&filtered) {
            flip.encode_horizontal(
                &self.device,
                &mut encoder,
                &picture.create_view(&Default::default()),
                filtered,
            );
        }
        flip.encode_error(
            &self.device,
            &mut encoder,
            &filtered[0],
            &filtered[1],
            &out.create_view(&Default::default()),
        );
        let texels =
            readback::read_texture_level(&self.device, &self.queue, &out, 0, Some(encoder.finish())).await?;
        Ok(Some(texels.chunks_exact(4).map(|t| crate::render::flip::unpack_error(t[0], t[1])).collect()))
    }
}
