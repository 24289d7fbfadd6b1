//! The crowd's GPU side: the pose palette as two `rgba32float` textures, joint matrices and morph
//! weights (bind group 3 of `crowd.wgsl`), one vertex buffer of instance records rewritten each frame, and the instanced
//! draws of a view: per [`InstancedDraw`], the level's own vertex and index buffers, the
//! records' range as the instance buffer, one `draw_indexed` per material range.

use std::collections::HashMap;

use super::pipelines::{create_crowd_pipelines, create_ground_pipeline, float_texture_entry};
use super::resources::float_texture;
use super::{PipelineKey, Renderer, DRAW_SLOTS, DRAW_STRIDE};
use crate::render::crowd::{CrowdFrame, InstanceRaw, InstancedDraw, PosePalette};
use crate::render::uniforms::DrawRaw;

/// Records the instance buffer holds at first; it doubles when a frame needs more.
const FIRST_CAPACITY: u64 = 1024;

pub(super) struct CrowdGpu {
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    palette_layout: wgpu::BindGroupLayout,
    palette_group: wgpu::BindGroup,
    /// What the palette textures hold: joints, rows, clip and whether the weights apply.
    palette_key: PaletteKey,
    instances: wgpu::Buffer,
    /// Records `instances` holds.
    capacity: u64,
    ground_pipeline: wgpu::RenderPipeline,
    /// The ground's six corners ([`CrowdFrame::ground`]), rewritten with the records.
    ground: wgpu::Buffer,
}

type PaletteKey = (usize, usize, Option<usize>, bool);

fn palette_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("crowd palette"),
        entries: &[float_texture_entry(0), float_texture_entry(1)],
    })
}

/// The palette's bind group: its matrices, and its morph weights or zeros where `morphs` is false.
fn palette_group(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layout: &wgpu::BindGroupLayout,
    palette: &PosePalette,
    morphs: bool,
) -> wgpu::BindGroup {
    let rows = palette.rows as u32;
    let (width, height) = palette.texture_size();
    let matrices = float_texture(device, queue, "crowd palette", width, height, &palette.texels());
    let weights = float_texture(
        device,
        queue,
        "crowd morph weights",
        palette.weight_texels_per_row() as u32,
        rows,
        &palette.weight_texels(morphs),
    );
    let entry =
        |binding, view| wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(view) };
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("crowd palette"),
        layout,
        entries: &[entry(0, &matrices), entry(1, &weights)],
    })
}

fn instance_buffer(device: &wgpu::Device, capacity: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("crowd instances"),
        size: capacity * std::mem::size_of::<InstanceRaw>() as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl Renderer {
    /// Whether the crowd's pipelines are made and its palette uploaded.
    pub fn has_crowd(&self) -> bool {
        self.crowd.is_some()
    }

    /// Uploads `palette` for the crowd (making the crowd's pipelines on first use), its morph
    /// weights applied when `morphs` is true and the renderer binds the character's targets; a
    /// palette equal in joints, rows, clip and that choice to the one uploaded is not uploaded
    /// again.
    pub fn set_crowd_palette(&mut self, palette: &PosePalette, morphs: bool) {
        let morphs = morphs && !self.uniforms.morphs_dropped;
        let key = (palette.joints, palette.rows, palette.clip, morphs);
        if let Some(crowd) = &mut self.crowd {
            if crowd.palette_key != key {
                crowd.palette_group =
                    palette_group(&self.device, &self.queue, &crowd.palette_layout, palette, morphs);
                crowd.palette_key = key;
            }
            return;
        }
        let layout = palette_layout(&self.device);
        let pipelines = create_crowd_pipelines(
            &self.device,
            &self.layouts,
            &layout,
            self.canvas.color_format,
            self.canvas.sample_count,
        );
        self.crowd = Some(CrowdGpu {
            pipelines,
            palette_group: palette_group(&self.device, &self.queue, &layout, palette, morphs),
            palette_layout: layout,
            palette_key: key,
            instances: instance_buffer(&self.device, FIRST_CAPACITY),
            capacity: FIRST_CAPACITY,
            ground_pipeline: create_ground_pipeline(
                &self.device,
                &self.layouts,
                self.canvas.color_format,
                self.canvas.sample_count,
            ),
            ground: self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("crowd ground"),
                size: std::mem::size_of::<[[f32; 4]; 6]>() as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        });
    }

    /// Drops the crowd's GPU state (back to the single character).
    pub fn drop_crowd(&mut self) {
        self.crowd = None;
    }

    /// Writes the frame's instance records (growing the buffer when they do not fit).
    pub fn set_crowd_instances(&mut self, frame: &CrowdFrame) {
        let Some(crowd) = &mut self.crowd else { return };
        let needed = frame.instances.len() as u64;
        if needed > crowd.capacity {
            crowd.capacity = needed.next_power_of_two();
            crowd.instances = instance_buffer(&self.device, crowd.capacity);
        }
        if needed > 0 {
            self.queue.write_buffer(&crowd.instances, 0, bytemuck::cast_slice(&frame.instances));
        }
        self.queue.write_buffer(&crowd.ground, 0, bytemuck::cast_slice(&frame.ground));
    }

    /// Records one crowd view's instanced draws; the draw uniform carries only the view's origin
    /// (for the dither pattern), the rest is per instance.
    pub(super) fn draw_crowd_view(
        &self,
        pass: &mut wgpu::RenderPass,
        draws: &[InstancedDraw],
        origin: [f32; 2],
        slot: &mut u64,
    ) {
        let Some(crowd) = &self.crowd else { return };
        let offset = (*slot % DRAW_SLOTS) * DRAW_STRIDE;
        *slot += 1;
        let raw = DrawRaw { viewport_origin: origin, opacity: 1.0, ..DrawRaw::default() };
        self.queue.write_buffer(&self.uniforms.draws, offset, bytemuck::bytes_of(&raw));
        pass.set_bind_group(0, &self.uniforms.frame_group, &[]);
        // The ground first: instances in front of it pass the depth test.
        pass.set_pipeline(&crowd.ground_pipeline);
        pass.set_vertex_buffer(0, crowd.ground.slice(..));
        pass.draw(0..6, 0..1);
        pass.set_bind_group(2, &self.uniforms.draw_group, &[offset as u32]);
        pass.set_bind_group(3, &crowd.palette_group, &[]);
        let stride = std::mem::size_of::<InstanceRaw>() as u64;
        for draw in draws {
            let Some(level) = self.meshes.discrete(draw.level) else { continue };
            // A level's own buffer pairs each vertex with its ancestor one level coarser: the only
            // geomorph a crowd draws.
            if draw.morph_coarse.is_some_and(|c| c != draw.level + 1) || draw.count == 0 {
                continue;
            }
            let records = u64::from(draw.first) * stride..u64::from(draw.first + draw.count) * stride;
            pass.set_vertex_buffer(0, level.vertices.slice(..));
            pass.set_vertex_buffer(1, crowd.instances.slice(records));
            pass.set_index_buffer(level.indices.slice(..), wgpu::IndexFormat::Uint32);
            for &(first, count, material) in &level.ranges {
                let m = &self.meshes.materials[material];
                let key = (draw.pass, draw.morph_coarse.is_some(), !m.double_sided);
                pass.set_pipeline(&crowd.pipelines[&key]);
                pass.set_bind_group(1, &m.bind_group, &[]);
                pass.draw_indexed(first..first + count, 0, 0..draw.count);
            }
        }
    }
}
