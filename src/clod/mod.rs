//! The articulated progressive mesh of a character (Houle & Poulin 2001) and the discrete LOD chain
//! extracted from it, in pipeline order:
//!
//! 1. pose the skinned mesh in the simplification pose `P0` with CPU skinning ([`poses`]);
//!    for multi-pose, sum plane quadrics over animation frames pulled back into `P0`;
//! 2. simplify the static `P0` mesh by quadric edge collapses with attribute quadrics (normals,
//!    uv, colour), recording the progressive mesh ([`crate::simplify`](mod@crate::simplify),
//!    [`crate::progressive`]);
//! 3. carry every moved vertex back into bind space through the inverse of its blended skin
//!    matrix at `P0`; the new vertex's skin weights blend the two merged vertices' by where it
//!    lies on their edge ([`WeightRule::Blend`], the default), or are those of the vertex it
//!    inherits identity from (the collapse's survivor, as in the paper: [`WeightRule::Survivor`]),
//!    so every level animates with every clip;
//! 4. extract discrete levels with ancestor tables for geomorphs ([`chain`]).
//!
//! Morph target deltas ride along: every vertex id carries its bind-space deltas (input vertices
//! the file's, created vertices their children's blended where the vertex moved, see `morph`),
//! so every level morphs with every clip's weights.
//!
//! Positions are in the character's units; errors are distances in those units.

pub mod bytes;
pub mod chain;
pub mod frame_quadrics;
mod morph;
pub mod poses;
pub mod shading;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use thiserror::Error;

use crate::character::Character;
use crate::morph::MorphDeltas;
use crate::progressive::{ProgressiveMesh, NONE};
use crate::simplify::{self, CollapseMode, Rules, Schedule, SimplifyError, SimplifyInput, SimplifyOptions};
use crate::skinning;
pub use chain::{LodLevel, StoppedShort};
pub use poses::SimplificationPose;

/// What to build.
#[derive(Clone, Debug, PartialEq)]
pub struct ClodOptions {
    /// The static pose simplification runs in.
    ///
    /// Default value: [`SimplificationPose::MultiPose`] with
    /// [`poses::DEFAULT_FRAMES_PER_CLIP`] frames of each clip.
    pub pose: SimplificationPose,
    /// Triangle counts of the discrete levels, finest first.
    ///
    /// Default value: `None`, for [`default_level_triangles`].
    pub level_triangles: Option<Vec<usize>>,
    /// Optimal placement, or half-edge collapses (every level a subset of the input vertices).
    ///
    /// Default value: [`CollapseMode::Full`].
    pub mode: CollapseMode,
    /// Skin weights of the vertices collapses create.
    ///
    /// Default value: [`WeightRule::Blend`].
    pub weights: WeightRule,
    /// The floor of the progressive mesh, as a fraction of the bounding-box diagonal (a
    /// distance, not its square; the simplifier's [`SimplifyOptions::max_mean_squared_error`]
    /// is this times the diagonal, squared): simplification makes no collapse whose error (root
    /// mean square over the collapsing pair's area, quadric-measured) exceeds it, nor one that
    /// leaves an input vertex it tracks farther than it from the surface, and ends when only
    /// such collapses are left. `f32::INFINITY` simplifies as far as the topology allows.
    ///
    /// Default value: [`DEFAULT_MAX_ERROR`] (5 %).
    pub max_relative_error: f32,
    /// The order of collapses: strictly cheapest first, or batched passes.
    ///
    /// Default value: [`Schedule::Strict`].
    pub schedule: Schedule,
    /// The simplifier's special rules ([`crate::simplify::rules`]); leaving one out is for
    /// measuring what it pays.
    ///
    /// Default value: [`Rules::ALL`].
    pub rules: Rules,
}

/// Default [`ClodOptions::max_relative_error`]: 5 % of the diagonal. Near the end of a simplification the
/// collapse that removes a whole limb costs far more than the ones before it. Measured on the
/// bind-pose builds (square root of each collapse's cost): CesiumMan's collapses stay at or below
/// 5.1 % until an arm goes at 10 % (at 194 triangles its Hausdorff distance was 12.3 % of the
/// diagonal; stopping at 204 it is 4.8 %), and Fox's at or below 4.7 % until its legs start going
/// at 5.9 %. An error of 5 % of the diagonal is far beyond any useful level anyway: the built-in
/// character's 1 % level costs 0.6 %.
pub const DEFAULT_MAX_ERROR: f32 = 0.05;

/// How a vertex created by a collapse gets its skin weights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WeightRule {
    /// The weights of the vertex it inherits identity from, as in Houle & Poulin.
    Survivor,
    /// The two merged vertices' weights blended by where the new vertex lies along their edge
    /// (in `P0`), keeping the four largest influences. The default: skinning is linear in the
    /// weights, so a vertex between two others then follows the blend of their motions, where the
    /// survivor's weights make it follow one end alone. Measured against meshoptimizer under
    /// animation (`bench/animated-vs-meshoptimizer.mjs`, 2026-11-25, ours ÷ the better
    /// meshoptimizer, mean over levels): CesiumMan 0.077 → 0.072, Fox 0.919 → 0.918,
    /// RiggedSimple 0.776 → 0.721, the built-in character 0.686 → 0.656 (its animated Hausdorff
    /// distance at 1,592 triangles 1.07 → 0.75 %); robot.glb and parts.glb, whose vertices follow
    /// one joint each, unchanged.
    #[default]
    Blend,
}

impl Default for ClodOptions {
    fn default() -> Self {
        Self {
            pose: SimplificationPose::MultiPose { frames_per_clip: poses::DEFAULT_FRAMES_PER_CLIP },
            level_triangles: None,
            mode: CollapseMode::Full,
            weights: WeightRule::default(),
            max_relative_error: DEFAULT_MAX_ERROR,
            schedule: Schedule::Strict,
            rules: Rules::ALL,
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
    #[error("the maximum error must be a positive fraction of the diagonal, got {0}")]
    BadMaxError(f32),
    #[error("simplification failed: {0}")]
    Simplify(#[from] SimplifyError),
}

/// The progressive mesh with bind-space data for every vertex id (input and created).
#[derive(Clone, Debug, PartialEq)]
pub struct ArticulatedPm {
    /// Positions (`pm.positions`) are in the simplification pose `P0`.
    pub pm: ProgressiveMesh,
    pub bind_positions: Vec<Vec3>,
    pub bind_normals: Vec<Vec3>,
    pub uvs: Option<Vec<Vec2>>,
    pub colors: Option<Vec<Vec4>>,
    pub joints: Vec<[u16; 4]>,
    pub weights: Vec<[f32; 4]>,
    /// Morph deltas of every vertex id (empty when the character has no morph targets).
    pub morph: MorphDeltas,
    /// Created vertices whose blended skin matrix at `P0` was singular, so they kept their
    /// survivor's bind position offset by the `P0` displacement instead of an exact inverse.
    pub singular_back_propagations: usize,
}

/// An articulated progressive mesh and its discrete levels.
#[derive(Clone, Debug, PartialEq)]
pub struct Clod {
    pub apm: ArticulatedPm,
    /// Finest first; level `i`'s ancestor table points into level `i + 1`.
    pub levels: Vec<LodLevel>,
    pub pose: SimplificationPose,
    /// The rule that gave created vertices their skin weights.
    pub weights: WeightRule,
    /// Per vertex id: flat-shaded (rendered with its triangle's face normal at every level; see
    /// [`shading`]). Derived from the character, not stored in the chain's bytes.
    pub flat: Vec<bool>,
}

/// Attribute channel layout handed to the simplifier: normal xyz first, then uv, then rgba.
pub(crate) struct AttributeLayout {
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
/// not positive and decreasing, a maximum error that is not positive, or input the simplifier
/// rejects.
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
    if options.max_relative_error.is_nan() || options.max_relative_error <= 0.0 {
        return Err(ClodError::BadMaxError(options.max_relative_error));
    }
    progress(0.0);

    // 1. The simplification pose P0 (flat-shaded vertices welded across their normal seams, see
    // `shading`), and for multi-pose the plane quadrics of every frame.
    let input = PoseInput::new(character, &options.pose)?;
    let multi_pose = match &options.pose {
        SimplificationPose::MultiPose { frames_per_clip } => {
            let p0_matrices = input.vertex_matrices.as_deref();
            poses::multi_pose_quadrics(
                character,
                &input.indices,
                &input.positions,
                p0_matrices,
                input.bind_scale,
                *frames_per_clip,
            )
        }
        _ => None,
    };
    progress(0.15);

    // 2. Simplify the static P0 mesh.
    let simplify_input = SimplifyInput {
        positions: &input.positions,
        attributes: &input.attributes,
        attribute_weights: &input.layout.weights,
        indices: &input.indices,
        triangle_materials: &input.triangle_materials,
        vertex_quadrics: multi_pose.as_deref(),
    };
    let max_distance = options.max_relative_error * crate::metrics::bounds_diagonal(&input.positions);
    let simplify_options = SimplifyOptions {
        mode: options.mode,
        target_triangles: *levels.last().expect("levels are not empty"),
        normal_channel: Some(0),
        // Costs are mean squared errors in position units².
        max_mean_squared_error: max_distance.powi(2),
        max_distance,
        schedule: options.schedule,
        rules: options.rules,
    };
    let pm = simplify::simplify_with_progress(&simplify_input, &simplify_options, &mut |f| {
        progress(0.15 + 0.65 * f)
    })?;
    progress(0.8);

    // 3. Bind-space data of every vertex id.
    let apm = back_propagate(character, pm, input.skin.as_deref(), options.weights, &input.layout);
    progress(0.9);

    // 4. Discrete levels and their ancestor tables.
    let levels = chain::build_levels(&apm.pm, &levels);
    progress(1.0);
    let flat = shading::flat_ids(&input.weld, &apm.pm);
    Ok(Clod { apm, levels, pose: options.pose.clone(), weights: options.weights, flat })
}

/// What the simplifier sees of the character in the simplification pose `P0`: positions and
/// interleaved attributes of every input vertex, and the skin matrices that posed them.
/// A pure function of the character and the pose, so [`bytes::decode`] recomputes it instead
/// of storing it.
pub(crate) struct PoseInput {
    /// `P0`'s skin matrices; `None` for the bind pose and multi-pose (simplified in bind space,
    /// scaled into model units where the skin holds a change of units).
    skin: Option<Vec<Mat4>>,
    /// Each input vertex's blended skin matrix at `P0` (`None` as `skin`).
    vertex_matrices: Option<Vec<Mat4>>,
    /// The scale from bind space to `P0` where `P0` is the bind pose (1, or the change of units
    /// the skin holds); `None` for a clip frame.
    bind_scale: Option<f32>,
    pub(crate) positions: Vec<Vec3>,
    /// Normals are the simplifier's: zero for flat-shaded vertices ([`shading`]).
    pub(crate) attributes: Vec<f32>,
    pub(crate) layout: AttributeLayout,
    /// The character's triangles with flat-shaded vertices welded, and each one's material.
    pub(crate) indices: Vec<u32>,
    pub(crate) triangle_materials: Vec<u32>,
    pub(crate) weld: shading::ShadingWeld,
}

impl PoseInput {
    /// # Errors
    /// [`ClodError::UnknownClip`] or [`ClodError::BadTime`] for a clip-frame pose the character
    /// cannot take.
    pub(crate) fn new(character: &Character, pose: &SimplificationPose) -> Result<Self, ClodError> {
        let mesh = &character.mesh;
        let p0 = p0_skin_matrices(character, pose)?;
        let bind_scale = match p0 {
            P0::Bind => Some(1.0),
            P0::Scaled(scale) => Some(scale),
            P0::Posed(_) => None,
        };
        let (skin, vertex_matrices, positions, normals) = match p0 {
            P0::Bind => (None, None, mesh.positions.clone(), mesh.normals.clone()),
            P0::Scaled(scale) => {
                // Every vertex scaled alike, not through its blended matrix: weights that sum to
                // 1 within an ulp would scale wedges of one position apart by an ulp, and
                // position classes (bit-identical positions) would split along every seam.
                let m = Mat4::from_scale(Vec3::splat(scale));
                let skin = vec![m; character.skeleton.joints.len()];
                let positions = mesh.positions.iter().map(|&b| b * scale).collect();
                (Some(skin), Some(vec![m; mesh.vertex_count()]), positions, mesh.normals.clone())
            }
            P0::Posed(skin) => {
                let m = poses::vertex_matrices(character, &skin);
                let positions = mesh.positions.iter().zip(&m).map(|(&b, m)| m.transform_point3(b)).collect();
                let normals = skinning::skin_normals(&mesh.normals, &mesh.joints, &mesh.weights, &skin);
                (Some(skin), Some(m), positions, normals)
            }
        };
        let triangle_materials = material_ids(character);
        let weld = shading::ShadingWeld::new(mesh, &triangle_materials);
        let indices = weld.weld_indices(&mesh.indices);
        let normals = weld.simplifier_normals(&normals);
        let layout = attribute_layout(character, &positions);
        let attributes = interleave_attributes(character, &normals, &layout);
        Ok(PoseInput {
            skin,
            vertex_matrices,
            bind_scale,
            positions,
            attributes,
            layout,
            indices,
            triangle_materials,
            weld,
        })
    }
}

/// Steps 3 and 4 of [`build`] for a progressive mesh [`bytes::decode`] read: back-propagation to
/// bind space, then the discrete levels nearest `level_triangles`. Both are deterministic, so
/// the decoded chain equals the built one.
pub(crate) fn articulate(
    character: &Character,
    pm: ProgressiveMesh,
    input: &PoseInput,
    weights: WeightRule,
    level_triangles: &[usize],
    pose: SimplificationPose,
) -> Clod {
    let apm = back_propagate(character, pm, input.skin.as_deref(), weights, &input.layout);
    let levels = chain::build_levels(&apm.pm, level_triangles);
    let flat = shading::flat_ids(&input.weld, &apm.pm);
    Clod { apm, levels, pose, weights, flat }
}

/// Where `P0` is, as [`p0_skin_matrices`] finds it.
enum P0 {
    /// The bind pose as stored (every skin matrix the identity).
    Bind,
    /// The bind pose scaled into model units ([`poses::bind_to_model_scale`]).
    Scaled(f32),
    /// A clip frame: its skin matrices.
    Posed(Vec<Mat4>),
}

/// `P0` of `pose`. The bind pose and multi-pose (which simplifies in the bind pose) are scaled
/// into model units where the skin holds a change of units ([`poses::bind_to_model_scale`]), so
/// that costs, attribute weights and level errors are in model units for every pose.
fn p0_skin_matrices(character: &Character, pose: &SimplificationPose) -> Result<P0, ClodError> {
    match pose {
        SimplificationPose::Bind | SimplificationPose::MultiPose { .. } => {
            Ok(poses::bind_to_model_scale(character).map_or(P0::Bind, P0::Scaled))
        }
        SimplificationPose::MidClip => Ok(character.clips.first().map_or(P0::Bind, |clip| {
            P0::Posed(character.skin_matrices(&character.pose_at(clip, clip.duration() * 0.5)))
        })),
        SimplificationPose::ClipFrame { clip, time } => {
            if !time.is_finite() {
                return Err(ClodError::BadTime(*time));
            }
            let found = character.clip(clip).ok_or_else(|| ClodError::UnknownClip {
                name: clip.clone(),
                available: character.clips.iter().map(|c| c.name.clone()).collect(),
            })?;
            Ok(P0::Posed(character.skin_matrices(&character.pose_at(found, *time))))
        }
    }
}

/// Attribute channels and their weights. A weight converts attribute units² into position
/// units² (see [`SimplifyInput::attribute_weights`]), so each is a squared length relative to the
/// model's size `d` (bounding-box diagonal):
/// - normals: a unit normal difference (60°) costs like a `d / 200` displacement: enough to
///   steer collapses on flat-ish regions, small enough that geometry decides elsewhere. Measured
///   on the built-in character, `d / 50` raised the bind-pose error of levels 25 % to 1 % by 35-65 %
///   (bench/lod-vs-meshoptimizer.mjs) for no visible shading gain;
/// - uv: a full texture width costs like `d / 40`; seams are kept by topology anyway;
/// - colour: a full channel swing costs like `d / 200`, as normals.
fn attribute_layout(character: &Character, positions: &[Vec3]) -> AttributeLayout {
    let d = crate::metrics::bounds_diagonal(positions).max(f32::MIN_POSITIVE);
    let mut weights = vec![(d / 200.0).powi(2); 3];
    let uv = character.mesh.uvs.as_ref().map(|_| {
        weights.extend([(d / 40.0).powi(2); 2]);
        weights.len() - 2
    });
    let color = character.mesh.colors.as_ref().map(|_| {
        weights.extend([(d / 200.0).powi(2); 4]);
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
pub(crate) fn material_ids(character: &Character) -> Vec<u32> {
    let ids = character.mesh.triangle_materials();
    ids.into_iter().map(|m| m.map_or(u32::MAX, |m| m as u32)).collect()
}

/// Step 3 of the pipeline: skin weights, then bind-space position, normal, uv and colour of every
/// created vertex id. Ids are processed in increasing order, so children (smaller ids) are done
/// before their parent.
fn back_propagate(
    character: &Character,
    pm: ProgressiveMesh,
    p0_skin: Option<&[Mat4]>,
    rule: WeightRule,
    layout: &AttributeLayout,
) -> ArticulatedPm {
    let mesh = &character.mesh;
    let inputs = pm.input_vertex_count;
    let total = pm.vertex_total();
    let children = merged_children(&pm);
    let mut apm = ArticulatedPm {
        bind_positions: mesh.positions.clone(),
        bind_normals: mesh.normals.clone(),
        uvs: mesh.uvs.clone(),
        colors: mesh.colors.clone(),
        joints: mesh.joints.clone(),
        weights: mesh.weights.clone(),
        morph: mesh.morph.clone(),
        singular_back_propagations: 0,
        pm,
    };
    let stride = layout.weights.len();
    for x in inputs..total {
        let survivor = apm.pm.survivor_source[x] as usize;
        let (joints, weights) = match (rule, children[x - inputs]) {
            (WeightRule::Blend, [a, b]) if a != NONE && b != NONE => {
                let (a, b) = (a as usize, b as usize);
                let (pa, pb, px) = (apm.pm.positions[a], apm.pm.positions[b], apm.pm.positions[x]);
                let edge = pb - pa;
                let s = if edge.length_squared() > 0.0 {
                    ((px - pa).dot(edge) / edge.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                blend_influences((apm.joints[a], apm.weights[a], 1.0 - s), (apm.joints[b], apm.weights[b], s))
            }
            _ => (apm.joints[survivor], apm.weights[survivor]),
        };
        let attributes = &apm.pm.attributes[x * stride..(x + 1) * stride];
        let p0_position = apm.pm.positions[x];
        let p0_normal = Vec3::from_slice(&attributes[0..3]);
        let (position, normal) = match p0_skin {
            None => (p0_position, p0_normal),
            Some(skin) => {
                let m = skinning::blend_matrix(skin, joints, weights);
                let same_skin = joints == apm.joints[survivor] && weights == apm.weights[survivor];
                if same_skin && p0_position == apm.pm.positions[survivor] {
                    // The vertex did not move and skins like its survivor (every half-edge
                    // collapse, and survivors on pinned vertices): the survivor's bind position,
                    // exactly, instead of a rounded round trip through the inverse.
                    (apm.bind_positions[survivor], Mat4::transpose(&m).transform_vector3(p0_normal))
                } else if skinning::is_invertible(Mat3::from_mat4(m)) {
                    // Houle & Poulin's back-propagation: b = M0(v)⁻¹ x. Normals transform by the
                    // inverse transpose of M0⁻¹, which is M0ᵀ.
                    let normal = Mat4::transpose(&m).transform_vector3(p0_normal);
                    (m.inverse().transform_point3(p0_position), normal)
                } else {
                    // Opposing rotations blended to a singular matrix: keep the survivor's bind
                    // position moved by the P0 displacement, exact for translations.
                    apm.singular_back_propagations += 1;
                    let survivor_p0 = apm.pm.positions[survivor];
                    (apm.bind_positions[survivor] + (p0_position - survivor_p0), apm.bind_normals[survivor])
                }
            }
        };
        let fallback_normal = apm.bind_normals[survivor];
        apm.bind_positions.push(position);
        apm.bind_normals.push(normal.try_normalize().unwrap_or(fallback_normal));
        if let Some(uvs) = &mut apm.uvs {
            let k = layout.uv.expect("uv channels exist when the mesh has uvs");
            uvs.push(Vec2::from_slice(&attributes[k..k + 2]));
        }
        if let Some(colors) = &mut apm.colors {
            let k = layout.color.expect("colour channels exist when the mesh has colours");
            colors.push(Vec4::from_slice(&attributes[k..k + 4]));
        }
        if !apm.morph.is_empty() {
            let row = morph::created_row(
                &apm.morph,
                &apm.pm.positions,
                (&apm.joints, &apm.weights),
                x,
                children[x - inputs],
                survivor,
                (joints, weights),
                p0_skin,
            );
            apm.morph.push_row(row);
        }
        apm.joints.push(joints);
        apm.weights.push(weights);
    }
    apm
}

/// For each created vertex, the (up to two) vertices that merged into it.
fn merged_children(pm: &ProgressiveMesh) -> Vec<[u32; 2]> {
    let inputs = pm.input_vertex_count;
    let mut children = vec![[NONE; 2]; pm.vertex_total() - inputs];
    for (v, &p) in pm.parent.iter().enumerate() {
        if p != NONE {
            let slot = &mut children[p as usize - inputs];
            let k = usize::from(slot[0] != NONE);
            if k < 2 {
                slot[k] = v as u32;
            }
        }
    }
    children
}

/// `wa · a + wb · b` over the union of both influence sets, keeping the four largest, sorted by
/// decreasing weight and renormalized.
fn blend_influences(
    (ja, wa_, sa): ([u16; 4], [f32; 4], f32),
    (jb, wb_, sb): ([u16; 4], [f32; 4], f32),
) -> ([u16; 4], [f32; 4]) {
    let mut merged: Vec<(u16, f32)> = Vec::with_capacity(8);
    for (joints, weights, scale) in [(ja, wa_, sa), (jb, wb_, sb)] {
        for (&j, &w) in joints.iter().zip(&weights) {
            if w > 0.0 {
                match merged.iter_mut().find(|(k, _)| *k == j) {
                    Some((_, sum)) => *sum += w * scale,
                    None => merged.push((j, w * scale)),
                }
            }
        }
    }
    merged.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    merged.truncate(4);
    let total: f32 = merged.iter().map(|(_, w)| w).sum();
    let mut joints = [0u16; 4];
    let mut weights = [0f32; 4];
    for (k, (j, w)) in merged.into_iter().enumerate() {
        joints[k] = j;
        weights[k] = if total > 0.0 { w / total } else { 0.0 };
    }
    if total <= 0.0 {
        return (ja, wa_);
    }
    (joints, weights)
}

impl Clod {
    /// Why the coarsest level has more triangles than the build asked for, if it has: the
    /// error limit ([`ClodOptions::max_relative_error`]) or the mesh's locks stopped the simplifier first.
    pub fn stopped_short(&self) -> Option<StoppedShort> {
        StoppedShort::of(&self.apm.pm)
    }

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
        self.level_morphed_skinned_positions(level, skin, &[])
    }

    /// CPU-skinned positions of a level's vertices with morph `weights` (one per target of the
    /// character) applied to the bind positions before skinning.
    pub fn level_morphed_skinned_positions(&self, level: usize, skin: &[Mat4], weights: &[f32]) -> Vec<Vec3> {
        let apm = &self.apm;
        self.levels[level]
            .vertices
            .iter()
            .map(|&v| {
                let v = v as usize;
                let bind = apm.bind_positions[v] + apm.morph.position_offset(v, weights);
                skinning::blend_matrix(skin, apm.joints[v], apm.weights[v]).transform_point3(bind)
            })
            .collect()
    }

    /// Bind-space morph deltas of a level's vertices, one row per level vertex.
    pub fn level_morph_deltas(&self, level: usize) -> MorphDeltas {
        self.apm.morph.select(self.levels[level].vertices.iter().map(|&v| v as usize))
    }

    /// Total bytes of the ancestor tables of all levels.
    pub fn ancestor_table_bytes(&self) -> usize {
        self.levels.iter().map(|l| l.ancestors.len() * std::mem::size_of::<u32>()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn blended_influences_keep_the_four_largest_renormalized() {
        let a = ([0, 1, 2, 3], [0.4, 0.3, 0.2, 0.1], 0.5);
        let b = ([4, 0, 5, 0], [0.5, 0.5, 0.0, 0.0], 0.5);
        // Sums: j0 0.45, j4 0.25, j1 0.15, j2 0.10, j3 0.05 (dropped); total 0.95.
        let (joints, weights) = blend_influences(a, b);
        assert_eq!(joints, [0, 4, 1, 2]);
        let expected = [0.45, 0.25, 0.15, 0.10].map(|w| w / 0.95);
        assert!(weights.iter().zip(expected).all(|(w, e)| (w - e).abs() < 1e-6), "{weights:?}");
    }

    #[test]
    fn default_levels_halve_down_to_the_floor() {
        assert_eq!(default_level_triangles(1000), vec![1000, 500, 250, 125]);
        assert_eq!(default_level_triangles(50), vec![50]);
        let big = default_level_triangles(51_200);
        assert_eq!(big.last(), Some(&800), "1 % of 51,200 is 512: 800 is the last half above it");
    }
}
