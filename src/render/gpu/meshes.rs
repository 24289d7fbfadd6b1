//! The character's meshes on the GPU: its materials, the discrete levels, the continuous
//! slider's two meshes, and the level-skipping geomorph buffers, with the rule that numbers them
//! (levels `0..n` are the discrete ones, `n` and `n + 1` the slider's finer and coarser states).

use wgpu::util::DeviceExt;

use super::next_task;
use super::resources::upload_level;
use crate::render::lod_source::{GeomorphVertexRaw, LevelData, LodSource};

/// Level-skipping geomorph buffers kept: a dolly moves between neighbouring pairs, so a few
/// cover it, and each costs as much as its fine level's vertex buffer (3.7 MB for the built-in
/// character's finest level).
const MORPH_PAIRS: usize = 4;

/// One level's buffers.
pub(super) struct LevelGpu {
    pub(super) vertices: wgpu::Buffer,
    pub(super) indices: wgpu::Buffer,
    /// Line list of the level's edges (the wireframe overlay).
    pub(super) edges: wgpu::Buffer,
    pub(super) edge_count: u32,
    /// `(first_index, index_count, material slot)`.
    pub(super) ranges: Vec<(u32, u32, usize)>,
}

/// One material's bind group.
pub(super) struct MaterialGpu {
    pub(super) bind_group: wgpu::BindGroup,
    pub(super) double_sided: bool,
    /// The decoded base-colour texture with its mip levels (`None`: the default white texel).
    pub(super) texture: Option<wgpu::Texture>,
}

/// What the views draw of the character.
pub(super) struct CharacterMeshes {
    /// The file's materials, then the default one (the last slot).
    pub(super) materials: Vec<MaterialGpu>,
    levels: Vec<LevelGpu>,
    /// The continuous slider's meshes, drawn as levels `levels.len()` (the finer state, its
    /// vertices paired with their ancestors in the coarser) and `levels.len() + 1` (the coarser).
    continuous: Vec<LevelGpu>,
    /// Vertex buffers of level `fine` paired with its ancestors in level `coarse > fine + 1`, for
    /// geomorphs that skip levels; most recently used last, at most [`MORPH_PAIRS`].
    morph_pairs: Vec<((usize, usize), wgpu::Buffer)>,
}

impl CharacterMeshes {
    /// `materials` (the default last) and `lod`'s levels, uploaded one level per browser task.
    pub(super) async fn new(device: &wgpu::Device, materials: Vec<MaterialGpu>, lod: &LodSource) -> Self {
        let mut meshes = CharacterMeshes {
            materials,
            levels: Vec::new(),
            continuous: Vec::new(),
            morph_pairs: Vec::new(),
        };
        meshes.set_levels(device, lod).await;
        meshes
    }

    /// The material slot of a range without a material of its own.
    fn default_slot(&self) -> usize {
        self.materials.len() - 1
    }

    /// Replaces the discrete levels, yielding to the browser between levels; drops the slider's
    /// meshes and the level-skipping geomorphs.
    pub(super) async fn set_levels(&mut self, device: &wgpu::Device, lod: &LodSource) {
        let default_slot = self.default_slot();
        let mut levels = Vec::with_capacity(lod.levels.len());
        for level in &lod.levels {
            next_task().await;
            levels.push(upload_level(device, level, default_slot));
        }
        self.levels = levels;
        self.continuous.clear();
        self.morph_pairs.clear();
    }

    /// Uploads the continuous slider's meshes, or drops them (empty).
    pub(super) fn set_continuous(&mut self, device: &wgpu::Device, levels: &[LevelData]) {
        let default_slot = self.default_slot();
        self.continuous = levels.iter().map(|l| upload_level(device, l, default_slot)).collect();
    }

    /// Discrete level `level`.
    pub(super) fn discrete(&self, level: usize) -> Option<&LevelGpu> {
        self.levels.get(level)
    }

    /// The mesh drawn as `level`: a discrete level or one of the slider's.
    pub(super) fn level(&self, level: usize) -> Option<&LevelGpu> {
        self.levels.get(level).or_else(|| self.continuous.get(level.checked_sub(self.levels.len())?))
    }

    /// The geomorph buffer of level `fine` towards level `coarse`, if uploaded.
    pub(super) fn morph_pair(&self, fine: usize, coarse: usize) -> Option<&wgpu::Buffer> {
        self.morph_pairs.iter().find(|(key, _)| *key == (fine, coarse)).map(|(_, buffer)| buffer)
    }

    /// Uploads level `fine`'s vertices paired with their ancestors in level `coarse`, dropping
    /// the least recently used pair beyond [`MORPH_PAIRS`].
    pub(super) fn add_morph_pair(
        &mut self,
        device: &wgpu::Device,
        (fine, coarse): (usize, usize),
        vertices: &[GeomorphVertexRaw],
    ) {
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("level-skipping geomorph"),
            contents: bytemuck::cast_slice(vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let pairs = &mut self.morph_pairs;
        pairs.retain(|(key, _)| *key != (fine, coarse));
        if pairs.len() >= MORPH_PAIRS {
            pairs.remove(0);
        }
        pairs.push(((fine, coarse), buffer));
    }
}
