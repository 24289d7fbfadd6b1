//! Bind group layouts, vertex layouts and the render pipelines of `skin.wgsl`: one per pass kind,
//! vertex shader (level or geomorph) and culling mode.

use super::*;

pub(super) struct BindLayouts {
    pub(super) frame: wgpu::BindGroupLayout,
    pub(super) material: wgpu::BindGroupLayout,
    pub(super) draw: wgpu::BindGroupLayout,
}

impl BindLayouts {
    pub(super) fn new(device: &wgpu::Device) -> Self {
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

pub(super) fn create_pipelines(
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
