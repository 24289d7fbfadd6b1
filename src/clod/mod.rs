//! The articulated progressive mesh of a character (Houle & Poulin 2001) and the discrete LOD chain
//! extracted from it, in pipeline order:
//!
//! 1. pose the skinned mesh in the simplification pose `P0` with CPU skinning ([`poses`]);
//!    for multi-pose, sum plane quadrics over animation frames pulled back into `P0`;
//! 2. simplify the static `P0` mesh by quadric edge collapses with attribute quadrics (normals,
//!    uv, colour), recording the progressive mesh ([`crate::simplify`], [`crate::progressive`]);
//! 3. carry every moved vertex back into bind space through the inverse of its blended skin
//!    matrix at `P0`; the new vertex keeps the skin weights of the vertex it inherits identity from
//!    (the collapse's survivor, as in the paper), so every level animates with every clip;
//! 4. extract discrete levels with ancestor tables for geomorphs ([`chain`]).
//!
//! Positions are in the character's units; errors are distances in those units.

pub mod chain;
pub mod poses;

use glam::{Mat4, Vec2, Vec3, Vec4};
use thiserror::Error;

use crate::character::Character;
use crate::progressive::ProgressiveMesh;
use crate::simplify::{self, CollapseMode, Quadric, SimplifyError, SimplifyInput, SimplifyOptions};
use crate::skinning;
pub use chain::LodLevel;
pub use poses::SimplificationPose;

/// What to build.
#[derive(Clone, Debug, PartialEq)]
pub struct ClodOptions {
    /// The static pose simplification runs in.
    pub pose: SimplificationPose,
    /// Triangle counts of the discrete levels, finest first; `None` for [`default_level_triangles`].
    pub level_triangles: Option<Vec<usize>>,
    /// Optimal placement, or half-edge collapses (every level a subset of the input vertices).
    pub mode: CollapseMode,
}

impl Default for ClodOptions {
    fn default() -> Self {
        Self {
            pose: SimplificationPose::MultiPose { frames_per_clip: poses::DEFAULT_FRAMES_PER_CLIP },
            level_triangles: None,
            mode: CollapseMode::Full,
        }
    }
}

/// Why a build could not start.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ClodError {
    #[error("the character has no triangles to simplify")]
    EmptyMesh,
    #[error("no clip named {name:?} for the simplification pose; this character has {available:?}")]
    UnknownClip { name: String, available: Vec<String> },
    #[error("the simplification pose time must be a finite number of seconds, got {0}")]
    BadTime(f32),
    #[error("level triangle counts must be positive and decreasing, got {0:?}")]
    BadLevels(Vec<usize>),
    #[error("simplification failed: {0}")]
    Simplify(#[from] SimplifyError),
}

/// The progressive mesh with bind-space data for every vertex id (input and created).
#[derive(Clone, Debug)]
pub struct ArticulatedPm {
    /// Positions (`pm.positions`) are in the simplification pose `P0`.
    pub pm: ProgressiveMesh,
    pub bind_positions: Vec<Vec3>,
    pub bind_normals: Vec<Vec3>,
    pub uvs: Option<Vec<Vec2>>,
    pub colors: Option<Vec<Vec4>>,
    pub joints: Vec<[u16; 4]>,
    pub weights: Vec<[f32; 4]>,
    /// Created vertices whose blended skin matrix at `P0` was singular, so they kept their
    /// survivor's bind position offset by the `P0` displacement instead of an exact inverse.
    pub singular_back_propagations: usize,
}

/// An articulated progressive mesh and its discrete levels.
#[derive(Clone, Debug)]
pub struct Clod {
    pub apm: ArticulatedPm,
    /// Finest first; level `i`'s ancestor table points into level `i + 1`.
    pub levels: Vec<LodLevel>,
    pub pose: SimplificationPose,
}

/// Attribute channel layout handed to the simplifier: normal xyz first, then uv, then rgba.
struct AttributeLayout {
    uv: Option<usize>,
    color: Option<usize>,
    weights: Vec<f32>,
}

/// Default discrete levels: the full mesh, then about half the triangles of the previous level,
/// down to a floor of 1 % of the input or 64 triangles (whichever is more): below that a character
/// is a few pixels tall and loses limbs.
pub fn default_level_triangles(triangles: usize) -> Vec<usize> {
    let floor = (triangles / 100).max(64);
    let mut levels = vec![triangles];
    let mut t = triangles / 2;
    while t >= floor {
        levels.push(t);
        t /= 2;
    }
    levels
}

/// Builds the articulated progressive mesh and its levels. `progress` receives fractions in
/// `[0, 1]`, ending with 1.
///
/// # Errors
/// [`ClodError`]: an empty mesh, an unknown clip or bad time for the pose, level counts that are
/// not positive and decreasing, or input the simplifier rejects.
pub fn build(
    character: &Character,
    options: &ClodOptions,
    progress: &mut dyn FnMut(f32),
) -> Result<Clod, ClodError> {
    let mesh = &character.mesh;
    if mesh.triangle_count() == 0 {
        return Err(ClodError::EmptyMesh);
    }
    let levels = match &options.level_triangles {
        Some(levels) => {
            if levels.is_empty() || levels.contains(&0) || levels.windows(2).any(|w| w[1] >= w[0]) {
                return Err(ClodError::BadLevels(levels.clone()));
            }
            levels.clone()
        }
        None => default_level_triangles(mesh.triangle_count()),
    };
    progress(0.0);

    // 1. The simplification pose P0 and its per-vertex matrices.
    let p0_skin = p0_skin_matrices(character, &options.pose)?;
    let p0_matrices = p0_skin.as_deref().map(|skin| poses::vertex_matrices(character, skin));
    let p0_positions: Vec<Vec3> = match &p0_matrices {
        Some(m) => mesh.positions.iter().zip(m).map(|(&b, m)| m.transform_point3(b)).collect(),
        None => mesh.positions.clone(),
    };
    let p0_normals = match &p0_skin {
        Some(skin) => skinning::skin_normals(&mesh.normals, &mesh.joints, &mesh.weights, skin),
        None => mesh.normals.clone(),
    };
    let vertex_quadrics = match &options.pose {
        SimplificationPose::MultiPose { frames_per_clip } => multi_pose_quadrics(character, *frames_per_clip),
        _ => None,
    };
    progress(0.15);

    // 2. Simplify the static P0 mesh.
    let layout = attribute_layout(character, &p0_positions);
    let attributes = interleave_attributes(character, &p0_normals, &layout);
    let triangle_materials = triangle_materials(character);
    let input = SimplifyInput {
        positions: &p0_positions,
        attributes: &attributes,
        attribute_weights: &layout.weights,
        indices: &mesh.indices,
        triangle_materials: &triangle_materials,
        vertex_quadrics: vertex_quadrics.as_deref(),
    };
    let simplify_options = SimplifyOptions {
        mode: options.mode,
        target_triangles: *levels.last().expect("levels are not empty"),
        normal_channel: Some(0),
        ..SimplifyOptions::default()
    };
    let pm = simplify::simplify(&input, &simplify_options)?;
    progress(0.8);

    // 3. Bind-space data of every vertex id.
    let apm = back_propagate(character, pm, p0_matrices.as_deref(), &layout);
    progress(0.9);

    // 4. Discrete levels and their ancestor tables.
    let levels = chain::build_levels(&apm.pm, &levels);
    progress(1.0);
    Ok(Clod { apm, levels, pose: options.pose.clone() })
}

/// Skin matrices of `P0`, or `None` for the bind pose (all identity) and multi-pose (which
/// simplifies in the bind pose).
fn p0_skin_matrices(
    character: &Character,
    pose: &SimplificationPose,
) -> Result<Option<Vec<Mat4>>, ClodError> {
    match pose {
        SimplificationPose::Bind | SimplificationPose::MultiPose { .. } => Ok(None),
        SimplificationPose::ClipFrame { clip, time } => {
            if !time.is_finite() {
                return Err(ClodError::BadTime(*time));
            }
            let found = character.clip(clip).ok_or_else(|| ClodError::UnknownClip {
                name: clip.clone(),
                available: character.clips.iter().map(|c| c.name.clone()).collect(),
            })?;
            Ok(Some(character.skin_matrices(&character.pose_at(found, *time))))
        }
    }
}

/// Plane quadrics averaged over frames of every clip, in bind space (`P0` of multi-pose); `None`
/// when the character has no clip, so the simplifier uses the bind pose's own planes.
fn multi_pose_quadrics(character: &Character, frames_per_clip: usize) -> Option<Vec<Quadric>> {
    let frames = poses::multi_pose_frames(character, frames_per_clip);
    if frames.is_empty() {
        return None;
    }
    let mesh = &character.mesh;
    let mut quadrics = vec![Quadric::ZERO; mesh.vertex_count()];
    let weight = 1.0 / frames.len() as f64;
    for skin in &frames {
        let matrices = poses::vertex_matrices(character, skin);
        poses::add_frame_quadrics(&mut quadrics, &mesh.positions, &mesh.indices, None, &matrices, weight);
    }
    Some(quadrics)
}

/// Attribute channels and their weights. A weight converts attribute units² into position
/// units² (see [`SimplifyInput::attribute_weights`]), so each is a squared length relative to the
/// model's size `d` (bounding-box diagonal):
/// - normals: a unit normal difference (60°) costs like a `d / 50` displacement — shading
///   matters, but never more than the silhouette;
/// - uv: a full texture width costs like `d / 10`; seams are kept by topology anyway;
/// - colour: a full channel swing costs like `d / 50`, as normals.
fn attribute_layout(character: &Character, positions: &[Vec3]) -> AttributeLayout {
    let d = crate::metrics::bounds_diagonal(positions).max(f32::MIN_POSITIVE);
    let mut weights = vec![(d / 50.0).powi(2); 3];
    let uv = character.mesh.uvs.as_ref().map(|_| {
        weights.extend([(d / 10.0).powi(2); 2]);
        weights.len() - 2
    });
    let color = character.mesh.colors.as_ref().map(|_| {
        weights.extend([(d / 50.0).powi(2); 4]);
        weights.len() - 4
    });
    AttributeLayout { uv, color, weights }
}

fn interleave_attributes(character: &Character, normals: &[Vec3], layout: &AttributeLayout) -> Vec<f32> {
    let mesh = &character.mesh;
    let mut out = Vec::with_capacity(mesh.vertex_count() * layout.weights.len());
    for v in 0..mesh.vertex_count() {
        out.extend(normals[v].to_array());
        if let Some(uvs) = &mesh.uvs {
            out.extend(uvs[v].to_array());
        }
        if let Some(colors) = &mesh.colors {
            out.extend(colors[v].to_array());
        }
    }
    out
}

/// One id per triangle: its primitive's material (`u32::MAX` for the default material), so
/// borders between materials are kept and primitives sharing a material may merge.
fn triangle_materials(character: &Character) -> Vec<u32> {
    let mut out = vec![u32::MAX; character.mesh.triangle_count()];
    for range in &character.mesh.primitives {
        let first = range.first_index as usize / 3;
        let count = range.index_count as usize / 3;
        let id = range.material.map_or(u32::MAX, |m| m as u32);
        out[first..first + count].fill(id);
    }
    out
}

/// Step 3 of the pipeline: bind-space position, normal, uv, colour and skin of every vertex id.
fn back_propagate(
    character: &Character,
    pm: ProgressiveMesh,
    p0_matrices: Option<&[Mat4]>,
    layout: &AttributeLayout,
) -> ArticulatedPm {
    let mesh = &character.mesh;
    let inputs = pm.input_vertex_count;
    let total = pm.vertex_total();
    let mut apm = ArticulatedPm {
        bind_positions: mesh.positions.clone(),
        bind_normals: mesh.normals.clone(),
        uvs: mesh.uvs.clone(),
        colors: mesh.colors.clone(),
        joints: mesh.joints.clone(),
        weights: mesh.weights.clone(),
        singular_back_propagations: 0,
        pm,
    };
    let stride = layout.weights.len();
    for x in inputs..total {
        // Skin identity comes from the input vertex at the root of the survivor chain.
        let mut source = apm.pm.survivor_source[x] as usize;
        while source >= inputs {
            source = apm.pm.survivor_source[source] as usize;
        }
        let attributes = &apm.pm.attributes[x * stride..(x + 1) * stride];
        let p0_position = apm.pm.positions[x];
        let p0_normal = Vec3::from_slice(&attributes[0..3]);
        let (position, normal) = match p0_matrices {
            None => (p0_position, p0_normal),
            Some(matrices) => {
                let m = matrices[source];
                if m.determinant().abs() > 1e-12 {
                    // Houle & Poulin's back-propagation: b = M0(v)⁻¹ x. Normals transform by the
                    // inverse transpose of M0⁻¹, which is M0ᵀ.
                    let normal = Mat4::transpose(&m).transform_vector3(p0_normal);
                    (m.inverse().transform_point3(p0_position), normal)
                } else {
                    apm.singular_back_propagations += 1;
                    let source_p0 = m.transform_point3(mesh.positions[source]);
                    (mesh.positions[source] + (p0_position - source_p0), mesh.normals[source])
                }
            }
        };
        apm.bind_positions.push(position);
        apm.bind_normals.push(normal.try_normalize().unwrap_or(mesh.normals[source]));
        if let Some(uvs) = &mut apm.uvs {
            let k = layout.uv.expect("uv channels exist when the mesh has uvs");
            uvs.push(Vec2::from_slice(&attributes[k..k + 2]));
        }
        if let Some(colors) = &mut apm.colors {
            let k = layout.color.expect("colour channels exist when the mesh has colours");
            colors.push(Vec4::from_slice(&attributes[k..k + 4]));
        }
        apm.joints.push(mesh.joints[source]);
        apm.weights.push(mesh.weights[source]);
    }
    apm
}

impl Clod {
    /// Bind positions of a level's vertices.
    pub fn level_bind_positions(&self, level: usize) -> Vec<Vec3> {
        self.levels[level].vertices.iter().map(|&v| self.apm.bind_positions[v as usize]).collect()
    }

    /// `P0` (simplification pose) positions of a level's vertices.
    pub fn level_pose_positions(&self, level: usize) -> Vec<Vec3> {
        self.levels[level].vertices.iter().map(|&v| self.apm.pm.positions[v as usize]).collect()
    }

    /// CPU-skinned positions of a level's vertices, given the skin matrices of a pose.
    pub fn level_skinned_positions(&self, level: usize, skin: &[Mat4]) -> Vec<Vec3> {
        let apm = &self.apm;
        self.levels[level]
            .vertices
            .iter()
            .map(|&v| {
                let v = v as usize;
                skinning::blend_matrix(skin, apm.joints[v], apm.weights[v])
                    .transform_point3(apm.bind_positions[v])
            })
            .collect()
    }

    /// Total bytes of the ancestor tables of all levels.
    pub fn ancestor_table_bytes(&self) -> usize {
        self.levels.iter().map(|l| l.ancestors.len() * std::mem::size_of::<u32>()).sum()
    }
}
