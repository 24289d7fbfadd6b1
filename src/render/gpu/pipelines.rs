//! Bind group layouts, vertex layouts and the render pipelines of `skin.wgsl`: one per pass kind,
//! vertex shader (level or geomorph) and culling mode, the wireframe overlay's line pipelines and
//! the skeleton overlay's; and the crowd's instanced twins of the shaded pipelines
//! (`crowd.wgsl`).

use std::collections::HashMap;

use super::{PipelineKey, BONE_VERTEX_STRIDE, DEPTH_FORMAT};
use crate::render::crowd::{InstanceRaw, INSTANCE_OFFSETS};
use crate::render::lod_source::{GeomorphVertexRaw, VertexRaw};
use crate::render::plan::PassKind;
use crate::render::uniforms::{CROWD_WGSL, SKIN_WGSL};

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
        let vertex = wgpu::ShaderStages::VERTEX;
        let frame = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[
                uniform(0, both, false),
                float_texture_entry(1),
                uniform(2, vertex, false),
                float_texture_entry(3),
            ],
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

/// A vertex shader's `rgba32float` texture at `binding` ([`super::resources::float_texture`]):
/// read with `textureLoad` only, so 32-bit floats need not be filterable.
pub(super) fn float_texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// The attributes a level's [`GeomorphVertexRaw`] buffer gives its vertex shader: the drawn
/// vertex (locations 0..=5) and its morph row (12); and for a geomorph also its ancestor (6..=11)
/// and the ancestor's morph row (13).
fn level_attributes() -> (Vec<wgpu::VertexAttribute>, Vec<wgpu::VertexAttribute>) {
    let vertex_size = std::mem::size_of::<VertexRaw>() as u64;
    let morph_row = |base: u64, location: u32| wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Uint32x2,
        offset: base + std::mem::offset_of!(VertexRaw, morph) as u64,
        shader_location: location,
    };
    let mut fine = vertex_attributes(0, 0).to_vec();
    fine.push(morph_row(0, 12));
    let mut both = fine.clone();
    both.extend(vertex_attributes(vertex_size, 6));
    both.push(morph_row(vertex_size, 13));
    (fine, both)
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

/// What differs between the renderer's pipelines.
struct Spec {
    /// Geomorph vertex shader (both vertices of each pair) or the level's own.
    geomorph: bool,
    /// Wireframe lines (line list, `vs_wire_*` and `fs_wire`) or shaded triangles.
    wire: bool,
    cull: bool,
    blend: bool,
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
}

/// The shaded pipelines by [`PipelineKey`], the wireframe ones (level, geomorph), and the
/// skeleton overlay's bone lines.
pub(super) struct Pipelines {
    pub(super) shaded: HashMap<PipelineKey, wgpu::RenderPipeline>,
    pub(super) wire: [wgpu::RenderPipeline; 2],
    pub(super) bone: wgpu::RenderPipeline,
}

pub(super) fn create_pipelines(
    device: &wgpu::Device,
    layouts: &BindLayouts,
    color_format: wgpu::TextureFormat,
    sample_count: u32,
) -> Pipelines {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("skin.wgsl"),
        source: wgpu::ShaderSource::Wgsl(SKIN_WGSL.into()),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("skin"),
        bind_group_layouts: &[Some(&layouts.frame), Some(&layouts.material), Some(&layouts.draw)],
        immediate_size: 0,
    });
    let (fine, both) = level_attributes();
    let stride = std::mem::size_of::<GeomorphVertexRaw>() as u64;
    let create = |spec: Spec| {
        let attributes: &[wgpu::VertexAttribute] = if spec.geomorph { &both } else { &fine };
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: stride,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes,
        })];
        let (vertex, fragment, topology) = match (spec.wire, spec.geomorph) {
            (false, false) => ("vs_level", "fs_main", wgpu::PrimitiveTopology::TriangleList),
            (false, true) => ("vs_geomorph", "fs_main", wgpu::PrimitiveTopology::TriangleList),
            (true, false) => ("vs_wire_level", "fs_wire", wgpu::PrimitiveTopology::LineList),
            (true, true) => ("vs_wire_geomorph", "fs_wire", wgpu::PrimitiveTopology::LineList),
        };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("{vertex} {fragment} cull={} blend={}", spec.cull, spec.blend)),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vertex),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: spec.cull.then_some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(depth_state(spec.depth_write, spec.depth_compare)),
            multisample: multisample_state(sample_count),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fragment),
                compilation_options: Default::default(),
                targets: &[Some(color_target(color_format, spec.blend))],
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let shaded = shaded_keys()
        .map(|(pass, geomorph, cull)| ((pass, geomorph, cull), create(shaded_spec(pass, geomorph, cull))))
        .collect();
    // Lines blend over the shading and leave depth alone, so a level fading in keeps its own.
    let wire = [false, true].map(|geomorph| {
        create(Spec {
            geomorph,
            wire: true,
            cull: false,
            blend: true,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::LessEqual,
        })
    });
    let bone = bone_pipeline(device, layouts, &module, color_format, sample_count);
    Pipelines { shaded, wire, bone }
}

/// Every shaded pipeline's key: pass kind, geomorph vertex shader, back-face culling.
fn shaded_keys() -> impl Iterator<Item = PipelineKey> {
    [PassKind::Opaque, PassKind::BlendOver, PassKind::BlendNaive].into_iter().flat_map(|pass| {
        [false, true].into_iter().flat_map(move |g| [false, true].map(move |c| (pass, g, c)))
    })
}

/// The state of a shaded pipeline of `pass`.
fn shaded_spec(pass: PassKind, geomorph: bool, cull: bool) -> Spec {
    Spec {
        geomorph,
        wire: false,
        cull,
        blend: pass != PassKind::Opaque,
        depth_write: pass != PassKind::BlendOver,
        // The fading level lies on the opaque one: equal depths must pass.
        depth_compare: if pass == PassKind::BlendOver {
            wgpu::CompareFunction::LessEqual
        } else {
            wgpu::CompareFunction::Less
        },
    }
}

/// The colour target of every shaded pipeline. Colour blends as usual; alpha accumulates coverage
/// ("over"), so a target cleared to alpha 0 ends at alpha ≥ the most opaque layer: the live meter
/// reads the silhouette from it. Views cleared to alpha 1 stay at 1.
fn color_target(format: wgpu::TextureFormat, blend: bool) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format,
        blend: blend.then_some(wgpu::BlendState {
            color: wgpu::BlendState::ALPHA_BLENDING.color,
            alpha: wgpu::BlendComponent::OVER,
        }),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

/// The crowd's shaded pipelines (`crowd.wgsl`), keyed like the single character's: the level's
/// vertices (slot 0, as [`create_pipelines`] reads them) and one [`InstanceRaw`] per instance
/// (slot 1, locations 14 and 15), with the palette textures as bind group 3.
pub(super) fn create_crowd_pipelines(
    device: &wgpu::Device,
    layouts: &BindLayouts,
    palette: &wgpu::BindGroupLayout,
    color_format: wgpu::TextureFormat,
    sample_count: u32,
) -> HashMap<PipelineKey, wgpu::RenderPipeline> {
    use wgpu::VertexFormat as F;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("crowd.wgsl"),
        source: wgpu::ShaderSource::Wgsl(CROWD_WGSL.into()),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("crowd"),
        bind_group_layouts: &[
            Some(&layouts.frame),
            Some(&layouts.material),
            Some(&layouts.draw),
            Some(palette),
        ],
        immediate_size: 0,
    });
    let (fine, both) = level_attributes();
    let formats = [F::Float32x4, F::Uint32x4];
    let instance: Vec<wgpu::VertexAttribute> = (0..2)
        .map(|i| wgpu::VertexAttribute {
            format: formats[i],
            offset: INSTANCE_OFFSETS[i],
            shader_location: 14 + i as u32,
        })
        .collect();
    let create = |spec: Spec| {
        let buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<GeomorphVertexRaw>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: if spec.geomorph { &both } else { &fine },
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<InstanceRaw>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &instance,
            }),
        ];
        let vertex = if spec.geomorph { "vs_crowd_geomorph" } else { "vs_crowd_level" };
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("{vertex} fs_crowd cull={} blend={}", spec.cull, spec.blend)),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vertex),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: spec.cull.then_some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(depth_state(spec.depth_write, spec.depth_compare)),
            multisample: multisample_state(sample_count),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_crowd"),
                compilation_options: Default::default(),
                targets: &[Some(color_target(color_format, spec.blend))],
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    shaded_keys().map(|key| (key, create(shaded_spec(key.0, key.1, key.2)))).collect()
}

/// The crowd's ground (`vs_ground`, `fs_ground` in `crowd.wgsl`): a triangle list of
/// `[x, y, z, cell]` corners, depth-tested and written like any surface, colour written but not
/// alpha (the live meter reads coverage from alpha: the ground is background to it).
pub(super) fn create_ground_pipeline(
    device: &wgpu::Device,
    layouts: &BindLayouts,
    color_format: wgpu::TextureFormat,
    sample_count: u32,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("crowd.wgsl ground"),
        source: wgpu::ShaderSource::Wgsl(CROWD_WGSL.into()),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("ground"),
        bind_group_layouts: &[Some(&layouts.frame)],
        immediate_size: 0,
    });
    let attributes =
        [wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x4, offset: 0, shader_location: 0 }];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("vs_ground fs_ground"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_ground"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: 16,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            ..Default::default()
        },
        depth_stencil: Some(depth_state(true, wgpu::CompareFunction::Less)),
        multisample: multisample_state(sample_count),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_ground"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: color_format,
                blend: None,
                write_mask: wgpu::ColorWrites::COLOR,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Bone lines (`vs_bone`, `fs_bone`): a line list of model-space points, `BONE_VERTEX_STRIDE`
/// bytes each, over everything drawn before. The depth test always passes and writes nothing, so
/// bones show through the body and leave the view's depth as the mesh made it. Its layout binds
/// the frame group only (the camera), so it draws in views whose plan drew nothing.
fn bone_pipeline(
    device: &wgpu::Device,
    layouts: &BindLayouts,
    module: &wgpu::ShaderModule,
    color_format: wgpu::TextureFormat,
    sample_count: u32,
) -> wgpu::RenderPipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("bone"),
        bind_group_layouts: &[Some(&layouts.frame)],
        immediate_size: 0,
    });
    let attributes =
        [wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 }];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("vs_bone fs_bone"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_bone"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: BONE_VERTEX_STRIDE,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState { topology: wgpu::PrimitiveTopology::LineList, ..Default::default() },
        depth_stencil: Some(depth_state(false, wgpu::CompareFunction::Always)),
        multisample: multisample_state(sample_count),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_bone"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: color_format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The depth test every pipeline uses, with its own write flag and comparison.
fn depth_state(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// Multisampling of every pipeline: all samples, no alpha-to-coverage.
fn multisample_state(count: u32) -> wgpu::MultisampleState {
    wgpu::MultisampleState { count, mask: !0, alpha_to_coverage_enabled: false }
}
