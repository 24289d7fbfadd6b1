//! Mesh primitives (glTF 2.0 §3.7.2) of every mesh node merged into one indexed
//! [`SkinnedMesh`] in bind space.
//!
//! Per primitive, in order: read and check the triangles (strips and fans become lists; points and
//! lines are skipped; triangles without area are left out with a warning) and the attributes of
//! the vertices they use (a primitive may index part of a vertex buffer that a whole mesh shares;
//! such an accessor is decoded once, see [`SharedReads`]), resolve skin influences (the four
//! largest of all JOINTS_n/WEIGHTS_n sets, remapped into [`crate::Skeleton::joints`], sorted by
//! decreasing weight, renormalized to sum 1), give a primitive without normals flat ones (one
//! corner per triangle corner, as the spec asks), weld bit-identical corners of non-indexed
//! primitives, replace zero-length normals, move rigid (unskinned) parts into bind space, and
//! append with a [`PrimitiveRange`].
//!
//! Morph targets (§3.7.2.2) come along: each target's POSITION and NORMAL deltas (sparse
//! accessors too) are kept per vertex where non-zero, moved into bind space with their primitive
//! (deltas are directions: the linear part for positions, the normal matrix for normals), and
//! numbered globally ([`crate::morph`]). TANGENT deltas are dropped with a warning: the viewer
//! has no tangents. Counts are capped by [`MAX_MORPH_TARGETS`] and [`MAX_MORPH_DELTAS`].
//!
//! Influences with weight 0 are ignored, so their joint index may be anything. A vertex whose
//! weights are all zero is an error naming it: the spec requires weights summing to 1, and binding
//! it to an arbitrary joint would hide a broken export.

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use super::document::{self, Mode, Semantic, Type};
use glam::{Affine2, Mat2, Mat3, Mat4, Vec2, Vec3, Vec4};

use super::accessor::{pick_rows, Elements, SharedReads, Source};
use super::scene::{node_name, JointTable, MeshInstance, SceneGraph};
use super::{ImportError, MAX_INDICES, MAX_VERTICES};
use crate::mesh::{compute_normals, PrimitiveRange, SkinnedMesh};
use crate::morph::{MorphTarget, MAX_MORPH_DELTAS, MAX_MORPH_TARGETS};
use crate::skeleton::Skeleton;

mod corners;

use self::corners::{flat_shaded, weld};

/// One vertex's morph entries within its primitive: `(local target, position Δ, normal Δ)`.
type MorphRow = Vec<(u16, Vec3, Vec3)>;

/// The morph targets the merge found: the character's targets and, per glTF node, the global
/// targets each of its weight indices drives (for `weights` animation channels).
#[derive(Default)]
pub(crate) struct MorphIndex {
    pub targets: Vec<MorphTarget>,
    pub by_node: HashMap<usize, Vec<Vec<u32>>>,
    /// Stored entries so far, against [`MAX_MORPH_DELTAS`].
    entries: usize,
}

/// One primitive's vertices and triangles, in the space the file stores them.
struct Primitive {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec4>>,
    /// `(JOINTS_n, WEIGHTS_n)` accessor pairs, four components each.
    influence_sets: Vec<(Elements<u32>, Elements<f32>)>,
    /// Triangle list.
    indices: Vec<u32>,
    /// Whether the file gave an index buffer (otherwise corners are welded).
    indexed: bool,
    /// Number of morph targets, and each vertex's non-zero deltas (empty when no targets).
    target_count: usize,
    morph: Vec<MorphRow>,
    /// The accessors' element count, and the element each vertex was read from when the triangles
    /// use only some of them (`None`: vertex `v` is element `v`). For messages and morph targets,
    /// which are read right after; [`weld`] and [`flat_shaded`] renumber and set `None`.
    file_count: usize,
    rows: Option<Vec<u32>>,
}

impl Primitive {
    /// The file's number for vertex `v`, for messages.
    fn file_vertex(&self, v: usize) -> usize {
        self.rows.as_ref().map_or(v, |rows| rows[v] as usize)
    }
}

/// The vertices that `indices` use, ascending, when they are fewer than the `count` the
/// accessors hold; `indices` then number them in that list.
fn used_rows(indices: &mut [u32], count: usize) -> Option<Vec<u32>> {
    let mut rows = indices.to_vec();
    rows.sort_unstable();
    rows.dedup();
    if rows.len() == count {
        return None;
    }
    for i in indices.iter_mut() {
        *i = rows.binary_search(i).expect("every index is in the list") as u32;
    }
    Some(rows)
}

/// Skin data resolved to [`crate::Skeleton::joints`].
struct Influences {
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
}

fn prim_error(label: &str, problem: impl Into<String>) -> ImportError {
    ImportError::Primitive { primitive: label.to_string(), problem: problem.into() }
}

/// Merges every triangle primitive of every mesh node of `graph` into one mesh, filling
/// `skeleton.joints`.
///
/// # Errors
/// Bad accessors, out-of-range indices or joints, non-finite data, all-zero weights, size caps,
/// or a scene without triangles.
pub(crate) fn merge_meshes(
    src: Source,
    graph: &SceneGraph,
    slots: &[Option<usize>],
    skeleton: &mut Skeleton,
    morph: &mut MorphIndex,
    warnings: &mut Vec<String>,
) -> Result<SkinnedMesh, ImportError> {
    let model_from_node = skeleton.model_from_node(&skeleton.rest_pose());
    let mut table = JointTable::default();
    let mut out = SkinnedMesh::default();
    let mut warned_meshes = HashSet::new();
    let warnings_before = warnings.len();
    let mut shared =
        SharedReads::new(graph.instances.iter().flat_map(|inst| vertex_reads(src.root, inst.mesh)));
    for inst in &graph.instances {
        let mesh = src.root.meshes.get(inst.mesh).ok_or_else(|| {
            ImportError::Invalid(format!("node {} uses mesh {} which does not exist", inst.node, inst.mesh))
        })?;
        let mesh_label = match &mesh.name {
            Some(name) => format!("mesh {} ('{name}')", inst.mesh),
            None => format!("mesh {}", inst.mesh),
        };
        let has_tangents =
            mesh.primitives.iter().any(|p| p.targets.iter().flatten().any(|t| t.tangents.is_some()));
        if has_tangents && warned_meshes.insert(inst.mesh) {
            warnings.push(format!("{mesh_label} has TANGENT morph deltas; they are dropped (no tangents)"));
        }
        let node_weights = src.root.nodes.get(inst.node).and_then(|n| n.weights.as_ref());
        let default_weights = node_weights.or(mesh.weights.as_ref());
        for (p, prim_json) in mesh.primitives.iter().enumerate() {
            let label = format!("{mesh_label} primitive {p}");
            let Some(mut prim) = read_primitive(src, &mut shared, prim_json, &label, warnings)? else {
                continue;
            };
            read_targets(src, &mut shared, prim_json, &mut prim, &label, morph)?;
            let skinned = match inst.skin {
                Some(skin) if !prim.influence_sets.is_empty() => {
                    let remap = table.skin(src, slots, skin)?;
                    Some(resolve_influences(&prim.influence_sets, remap, &label, &|v| prim.file_vertex(v))?)
                }
                Some(_) => {
                    warnings
                        .push(format!("{label} is skinned but has no JOINTS_0/WEIGHTS_0; it is kept rigid"));
                    None
                }
                None => None,
            };
            let influences = match skinned {
                Some(influences) => influences,
                None => match bind_rigid(&mut prim, inst, slots, &model_from_node, &mut table, &label)? {
                    Some(influences) => influences,
                    None => {
                        let node = node_name(src.root, inst.node);
                        warnings
                            .push(format!("{label}: node '{node}' has a singular rest transform; skipped"));
                        continue;
                    }
                },
            };
            let (prim, influences) =
                if prim.normals.is_none() { flat_shaded(prim, influences) } else { (prim, influences) };
            let (prim, influences) = if prim.indexed { (prim, influences) } else { weld(prim, influences) };
            let first_target = morph.targets.len();
            for k in 0..prim.target_count {
                let default_weight = default_weights.and_then(|w| w.get(k)).copied().unwrap_or(0.0);
                let default_weight = if default_weight.is_finite() { default_weight } else { 0.0 };
                morph.targets.push(MorphTarget { name: format!("{label} target {k}"), default_weight });
                let per_weight = morph.by_node.entry(inst.node).or_default();
                if per_weight.len() <= k {
                    per_weight.resize(k + 1, Vec::new());
                }
                per_weight[k].push((first_target + k) as u32);
            }
            append(&mut out, prim, influences, prim_json.material, first_target)?;
        }
    }
    if out.indices.is_empty() {
        return Err(ImportError::NoTriangles { skipped: warnings[warnings_before..].to_vec() });
    }
    if !out.morph.is_empty() {
        while out.morph.row_count() < out.positions.len() {
            out.morph.push_row([]);
        }
    } else {
        out.morph = Default::default();
    }
    skeleton.joints = table.joints;
    Ok(out)
}

/// The accessors that reading mesh `mesh` may read: indices, vertex attributes and morph targets
/// of every primitive (for [`SharedReads`]: one that appears more than once is decoded once).
fn vertex_reads(root: &document::Root, mesh: usize) -> impl Iterator<Item = usize> + '_ {
    let primitives = root.meshes.get(mesh).map_or(&[][..], |m| &m.primitives[..]);
    primitives.iter().flat_map(|p| {
        let targets = p.targets.iter().flatten().flat_map(|t| [t.positions, t.normals]).flatten();
        p.attributes.iter().map(|&(_, a)| a).chain(p.indices).chain(targets)
    })
}

/// The `KHR_texture_transform` of `material`'s base colour texture as a matrix on uvs
/// (translation · rotation · scale, the extension's order; rotation counter-clockwise in uv
/// space), the identity without one. The viewer samples only the base colour texture, so its
/// transform is baked into the primitive's uvs: gltfpack stores quantized uvs and their
/// dequantization this way.
fn base_color_uv_transform(root: &document::Root, material: Option<usize>) -> Affine2 {
    let transform = material
        .and_then(|m| root.materials.get(m))
        .and_then(|m| m.base_color_texture.as_ref())
        .and_then(|info| info.transform.as_ref());
    let Some(t) = transform else { return Affine2::IDENTITY };
    let (sin, cos) = t.rotation.sin_cos();
    let [sx, sy] = t.scale;
    let linear = Mat2::from_cols(Vec2::new(cos * sx, -sin * sx), Vec2::new(sin * sy, cos * sy));
    Affine2::from_mat2_translation(linear, Vec2::from_array(t.offset))
}

/// The uv set `material`'s base colour texture samples: `KHR_texture_transform`'s `texCoord`
/// override, else the texture info's `texCoord`, else 0; `None` when it has no base colour
/// texture (or there is no material). The viewer samples only that texture, so its set becomes
/// the primitive's uvs, and without it the primitive has none (see [`read_primitive`]).
fn base_color_uv_set(root: &document::Root, material: Option<usize>) -> Option<u32> {
    let info = material.and_then(|m| root.materials.get(m)).and_then(|m| m.base_color_texture.as_ref())?;
    let over = info.transform.as_ref().and_then(|t| t.tex_coord);
    Some(over.unwrap_or(info.tex_coord))
}

/// Reads one primitive's attributes and triangles, or `None` (with a warning) when it draws no
/// triangles.
fn read_primitive(
    src: Source,
    shared: &mut SharedReads,
    prim: &document::Primitive,
    label: &str,
    warnings: &mut Vec<String>,
) -> Result<Option<Primitive>, ImportError> {
    let mode = prim.mode;
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        warnings.push(format!("{label} draws {mode:?}, not triangles; skipped"));
        return Ok(None);
    }
    let attribute = |s: Semantic| prim.attribute(&s);
    let Some(position_accessor) = attribute(Semantic::Positions) else {
        warnings.push(format!("{label} has no POSITION; skipped"));
        return Ok(None);
    };
    let usage = |name: &str| format!("{name} of {label}");

    // Triangles first: a primitive may index only part of its accessors (a vertex buffer shared
    // by every primitive of a mesh), and only the vertices it uses are read into it.
    let file_positions =
        shared.floats(src, position_accessor, &usage("POSITION"), &[Type::Vec3], MAX_VERTICES)?;
    let count = file_positions.count();
    let (indices, indexed) = match prim.indices {
        Some(a) => {
            let e = shared.uints(src, a, &usage("indices"), &[Type::Scalar], MAX_INDICES)?;
            if let Some(&i) = e.values.iter().find(|&&i| i as usize >= count) {
                return Err(prim_error(label, format!("index {i} is out of range for {count} vertices")));
            }
            (triangle_list(mode, &e.values), true)
        }
        None => (triangle_list(mode, &(0..count as u32).collect::<Vec<_>>()), false),
    };
    if indices.is_empty() {
        warnings.push(format!("{label} has no complete triangle; skipped"));
        return Ok(None);
    }
    let triangles = indices.len() / 3;
    let mut indices = without_arealess_triangles(indices, &file_positions);
    match triangles - indices.len() / 3 {
        0 => {}
        _ if indices.is_empty() => {
            warnings.push(format!("{label} has no triangle with an area; skipped"));
            return Ok(None);
        }
        dropped => warnings.push(format!(
            "{label}: {dropped} of its {triangles} triangles have no area (a repeated corner, or three \
             corners on a line) and are left out"
        )),
    }
    let rows = if indexed { used_rows(&mut indices, count) } else { None };
    let file_vertex = |v: usize| rows.as_ref().map_or(v, |rows| rows[v] as usize);
    let pick = |e: Rc<Elements<f32>>| pick_rows(e, rows.as_deref());

    let positions = to_vec3(&pick(file_positions));
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        let (v, p) = (file_vertex(v), positions[v]);
        return Err(prim_error(label, format!("vertex {v} has a non-finite position {p}")));
    }
    let same_count = |name: &str, elements: usize| match elements == count {
        true => Ok(()),
        false => Err(prim_error(label, format!("{name} has {elements} elements but POSITION has {count}"))),
    };
    // A per-vertex float attribute: one element per vertex, the rows this primitive uses.
    let read_rows = |shared: &mut SharedReads, a: usize, name: &str, types: &[Type]| {
        let e = shared.floats(src, a, &usage(name), types, MAX_VERTICES)?;
        same_count(name, e.count())?;
        Ok::<_, ImportError>(pick(e))
    };
    let finite = |first_bad: Option<usize>, what: &str| match first_bad {
        None => Ok(()),
        Some(v) => Err(prim_error(label, format!("vertex {} has a non-finite {what}", file_vertex(v)))),
    };
    let normals = match attribute(Semantic::Normals) {
        Some(a) => {
            let normals = to_vec3(&read_rows(shared, a, "NORMAL", &[Type::Vec3])?);
            finite(normals.iter().position(|n| !n.is_finite()), "normal")?;
            Some(normals)
        }
        None => None,
    };
    let material = prim.material;
    // Texture coordinates that no texture samples draw nothing, so they are not read: kept, their
    // seams would hold the LOD build's collapses and their values be priced for nothing. Blender
    // writes a uv map into every file whose mesh has one, textured or not, and on a low-poly
    // model its islands split most edges (a per-face-uv tube of 768 triangles gave one level; it
    // now simplifies as its shape allows). gltf-transform's `prune` drops such uvs as well.
    let uvs = match base_color_uv_set(src.root, material) {
        None => None,
        Some(wanted) => {
            let set = match attribute(Semantic::TexCoords(wanted)) {
                Some(_) => wanted,
                None if wanted == 0 => 0,
                None => {
                    warnings.push(format!(
                        "{label}: its material's base colour texture samples TEXCOORD_{wanted}, which it \
                         lacks; TEXCOORD_0 is used"
                    ));
                    0
                }
            };
            match attribute(Semantic::TexCoords(set)) {
                Some(a) => {
                    let transform = base_color_uv_transform(src.root, material);
                    let uvs: Vec<Vec2> = read_rows(shared, a, &format!("TEXCOORD_{set}"), &[Type::Vec2])?
                        .values
                        .chunks_exact(2)
                        .map(|c| transform.transform_point2(Vec2::new(c[0], c[1])))
                        .collect();
                    finite(uvs.iter().position(|t| !t.is_finite()), "texture coordinate")?;
                    Some(uvs)
                }
                None => None,
            }
        }
    };
    let colors = match attribute(Semantic::Colors(0)) {
        Some(a) => {
            let e = read_rows(shared, a, "COLOR_0", &[Type::Vec3, Type::Vec4])?;
            let colors: Vec<Vec4> = match e.components {
                3 => e.values.chunks_exact(3).map(|c| Vec4::new(c[0], c[1], c[2], 1.0)).collect(),
                _ => e.values.chunks_exact(4).map(Vec4::from_slice).collect(),
            };
            finite(colors.iter().position(|c| !c.is_finite()), "colour")?;
            Some(colors)
        }
        None => None,
    };
    let mut influence_sets = Vec::new();
    for set in 0.. {
        let (Some(j), Some(w)) = (attribute(Semantic::Joints(set)), attribute(Semantic::Weights(set))) else {
            break;
        };
        let name = format!("JOINTS_{set}");
        let joints = shared.uints(src, j, &usage(&name), &[Type::Vec4], MAX_VERTICES)?;
        same_count(&name, joints.count())?;
        let weights = read_rows(shared, w, &format!("WEIGHTS_{set}"), &[Type::Vec4])?;
        influence_sets.push((pick_rows(joints, rows.as_deref()), weights));
    }

    Ok(Some(Primitive {
        positions,
        normals,
        uvs,
        colors,
        influence_sets,
        indices,
        indexed,
        target_count: 0,
        morph: Vec::new(),
        file_count: count,
        rows,
    }))
}

/// Reads the morph targets of a primitive into `prim.morph` (non-zero deltas per vertex),
/// counting them against the caps.
fn read_targets(
    src: Source,
    shared: &mut SharedReads,
    prim_json: &document::Primitive,
    prim: &mut Primitive,
    label: &str,
    morph: &mut MorphIndex,
) -> Result<(), ImportError> {
    let Some(targets) = prim_json.targets.as_ref().filter(|t| !t.is_empty()) else { return Ok(()) };
    let total = morph.targets.len() + targets.len();
    if total > MAX_MORPH_TARGETS {
        return Err(ImportError::TooLarge {
            what: format!("morph targets of the character (at {label})"),
            count: total as u64,
            limit: MAX_MORPH_TARGETS as u64,
        });
    }
    let count = prim.file_count;
    let mut rows: Vec<MorphRow> = vec![Vec::new(); prim.positions.len()];
    for (t, target) in targets.iter().enumerate() {
        let mut read = |accessor: Option<usize>, what: &str| {
            let Some(a) = accessor else { return Ok(None) };
            let usage = format!("{what} of {label} morph target {t}");
            let e = shared.floats(src, a, &usage, &[Type::Vec3], MAX_VERTICES)?;
            if e.count() != count {
                return Err(prim_error(
                    label,
                    format!("morph target {t} {what} has {} elements but POSITION has {count}", e.count()),
                ));
            }
            let deltas = to_vec3(&pick_rows(e, prim.rows.as_deref()));
            if let Some(v) = deltas.iter().position(|d| !d.is_finite()) {
                let v = prim.file_vertex(v);
                return Err(prim_error(
                    label,
                    format!("morph target {t} has a non-finite {what} at vertex {v}"),
                ));
            }
            Ok(Some(deltas))
        };
        let positions = read(target.positions, "POSITION")?;
        let normals = read(target.normals, "NORMAL")?;
        for (v, row) in rows.iter_mut().enumerate() {
            let dp = positions.as_ref().map_or(Vec3::ZERO, |d| d[v]);
            let dn = normals.as_ref().map_or(Vec3::ZERO, |d| d[v]);
            if dp != Vec3::ZERO || dn != Vec3::ZERO {
                row.push((t as u16, dp, dn));
                morph.entries += 1;
            }
        }
        if morph.entries > MAX_MORPH_DELTAS {
            return Err(ImportError::TooLarge {
                what: format!("non-zero morph target deltas of the character (at {label})"),
                count: morph.entries as u64,
                limit: MAX_MORPH_DELTAS as u64,
            });
        }
    }
    prim.target_count = targets.len();
    prim.morph = rows;
    Ok(())
}

fn to_vec3(e: &Elements<f32>) -> Vec<Vec3> {
    e.values.chunks_exact(3).map(Vec3::from_slice).collect()
}

/// A triangle list from the corners of a list, strip or fan (§3.7.2.1). Strip and fan triangles
/// with a repeated corner are dropped (strips use them to restart); a list's trailing corners that
/// do not make a whole triangle are dropped too.
fn triangle_list(mode: Mode, corners: &[u32]) -> Vec<u32> {
    let n = corners.len();
    let degenerate = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    match mode {
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| match i % 2 {
                0 => [corners[i], corners[i + 1], corners[i + 2]],
                _ => [corners[i], corners[i + 2], corners[i + 1]],
            })
            .filter(|t| !degenerate(t))
            .flatten()
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .map(|i| [corners[i], corners[i + 1], corners[0]])
            .filter(|t| !degenerate(t))
            .flatten()
            .collect(),
        _ => corners[..n - n % 3].to_vec(),
    }
}

/// Below this sine of a triangle's smallest angle (|cross| < this × longest edge²) a triangle
/// has no area worth the name: its normal is rounding noise, and the simplifier, which never
/// makes such a triangle, cannot move its corners without making or keeping one (its fold check
/// refuses both), so a few of them stopped a whole chain early. They draw nothing; leaving them
/// out changes no pixel. The simplifier's own threshold (`collapse/checks.rs`).
const MIN_SIN_ANGLE: f32 = 1e-6;

/// The triangles of `indices` that have an area (see [`MIN_SIN_ANGLE`]); a triangle with a
/// non-finite corner stays, for the position check to name it.
fn without_arealess_triangles(indices: Vec<u32>, positions: &Elements<f32>) -> Vec<u32> {
    // In f64: squared lengths of coordinates near 1e-20 (a file in odd units) underflow f32.
    let at = |i: u32| Vec3::from_slice(positions.get(i as usize)).as_dvec3();
    let has_area = |t: &[u32]| {
        let [a, b, c] = [at(t[0]), at(t[1]), at(t[2])];
        let longest = (b - a).length_squared().max((c - a).length_squared()).max((c - b).length_squared());
        let cross = (b - a).cross(c - a).length();
        // False for a non-finite corner, which keeps its triangle.
        let no_area = cross <= f64::from(MIN_SIN_ANGLE) * longest;
        !no_area
    };
    if indices.chunks_exact(3).all(has_area) {
        return indices;
    }
    indices.chunks_exact(3).filter(|t| has_area(t)).flatten().copied().collect()
}

/// The four strongest influences of every vertex, in skeleton joint indices; see the module docs.
fn resolve_influences(
    sets: &[(Elements<u32>, Elements<f32>)],
    remap: &[u16],
    label: &str,
    file_vertex: &dyn Fn(usize) -> usize,
) -> Result<Influences, ImportError> {
    let count = sets.first().map_or(0, |(j, _)| j.count());
    let mut joints = Vec::with_capacity(count);
    let mut weights = Vec::with_capacity(count);
    let mut pairs: Vec<(u16, f32)> = Vec::with_capacity(4 * sets.len());
    for v in 0..count {
        pairs.clear();
        for (js, ws) in sets {
            for (&j, &w) in js.get(v).iter().zip(ws.get(v)) {
                if !w.is_finite() || w < 0.0 {
                    return Err(prim_error(label, format!("vertex {} has skin weight {w}", file_vertex(v))));
                }
                if w == 0.0 {
                    continue;
                }
                let Some(&joint) = remap.get(j as usize) else {
                    return Err(prim_error(
                        label,
                        format!(
                            "vertex {} uses joint {j} but its skin has {} joints",
                            file_vertex(v),
                            remap.len()
                        ),
                    ));
                };
                // The same joint listed twice (in two sets, or by a sloppy exporter) adds up.
                match pairs.iter_mut().find(|(pj, _)| *pj == joint) {
                    Some(pair) => pair.1 += w,
                    None => pairs.push((joint, w)),
                }
            }
        }
        // Heaviest first; equal weights by joint index so the result does not depend on file order.
        pairs.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        pairs.truncate(4);
        let total: f32 = pairs.iter().map(|p| p.1).sum();
        if !(total > 0.0 && total.is_finite()) {
            return Err(prim_error(
                label,
                format!("vertex {} has skin weights that are all zero", file_vertex(v)),
            ));
        }
        let mut j4 = [0u16; 4];
        let mut w4 = [0f32; 4];
        for (k, &(j, w)) in pairs.iter().enumerate() {
            j4[k] = j;
            w4[k] = w / total;
        }
        joints.push(j4);
        weights.push(w4);
    }
    Ok(Influences { joints, weights })
}

/// Binds a rigid primitive of `inst` to a joint that follows its node: the vertices move into
/// bind space (model space at rest) and the joint's inverse bind matrix undoes that, so skinning
/// at rest returns them to where the file puts them. `None` when the node's rest transform is
/// singular (a zero scale hides the part; there is no bind space to put it in).
fn bind_rigid(
    prim: &mut Primitive,
    inst: &MeshInstance,
    slots: &[Option<usize>],
    model_from_node: &[Mat4],
    table: &mut JointTable,
    label: &str,
) -> Result<Option<Influences>, ImportError> {
    let slot = slots
        .get(inst.node)
        .copied()
        .flatten()
        .ok_or_else(|| prim_error(label, "belongs to a node outside the skeleton"))?;
    let m = model_from_node[slot];
    let det = m.determinant();
    // Singular relative to its own scale: gltfpack puts a quantized mesh's dequantization on its
    // node, a scale of 1e-4 or less (a determinant of 1e-12 or less) that is no reason to skip it.
    if !crate::skinning::is_invertible(Mat3::from_mat4(m)) {
        return Ok(None);
    }
    let joint = table.add(slot, m.inverse())?;
    for p in &mut prim.positions {
        *p = m.transform_point3(*p);
    }
    // Scaled to determinant ±1: normals are normalized later anyway, and normal deltas then
    // keep their length under uniform scale (`append` rescales them by the normal's length).
    let normal_from_node = Mat3::from_mat4(m).inverse().transpose();
    let normal_from_node = normal_from_node * normal_from_node.determinant().abs().cbrt().recip();
    if let Some(normals) = &mut prim.normals {
        for n in normals.iter_mut() {
            *n = normal_from_node * *n;
        }
    }
    // Deltas are differences of points (and of normals): the linear parts move them.
    for entry in prim.morph.iter_mut().flatten() {
        entry.1 = m.transform_vector3(entry.1);
        entry.2 = normal_from_node * entry.2;
    }
    if det < 0.0 {
        // A mirroring transform turns the winding around (§3.7.2.1): swap two corners back.
        for t in prim.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    let n = prim.positions.len();
    Ok(Some(Influences { joints: vec![[joint, 0, 0, 0]; n], weights: vec![[1.0, 0.0, 0.0, 0.0]; n] }))
}

/// Unit normals for a primitive: the file's, with zero-length ones (and missing ones) replaced by
/// area-weighted face normals.
fn unit_normals(prim: &Primitive) -> Vec<Vec3> {
    let mut computed: Option<Vec<Vec3>> = None;
    let mut compute = || compute_normals(&prim.positions, &prim.indices);
    match &prim.normals {
        None => compute(),
        Some(normals) => normals
            .iter()
            .enumerate()
            .map(|(v, n)| n.try_normalize().unwrap_or_else(|| computed.get_or_insert_with(&mut compute)[v]))
            .collect(),
    }
}

/// Appends a primitive to the merged mesh with its material range.
fn append(
    out: &mut SkinnedMesh,
    prim: Primitive,
    influences: Influences,
    material: Option<usize>,
    first_target: usize,
) -> Result<(), ImportError> {
    let base = out.positions.len();
    let vertices = base + prim.positions.len();
    if vertices > MAX_VERTICES {
        return Err(ImportError::TooLarge {
            what: "vertices of the merged mesh".into(),
            count: vertices as u64,
            limit: MAX_VERTICES as u64,
        });
    }
    let indices = out.indices.len() + prim.indices.len();
    if indices > MAX_INDICES {
        return Err(ImportError::TooLarge {
            what: "indices of the merged mesh".into(),
            count: indices as u64,
            limit: MAX_INDICES as u64,
        });
    }
    let normals = unit_normals(&prim);
    let n = prim.positions.len();
    if !prim.morph.is_empty() || !out.morph.is_empty() {
        while out.morph.row_count() < base {
            out.morph.push_row([]);
        }
        for v in 0..n {
            // The base normal was normalized: scale its deltas alike, so that normalizing the
            // morphed normal gives the file's direction (exact for rigid parts under scale).
            let length = prim.normals.as_ref().map_or(1.0, |ns| ns[v].length());
            let scale = if length > 0.0 && length.is_finite() { 1.0 / length } else { 1.0 };
            let row = prim.morph.get(v).into_iter().flatten();
            out.morph.push_row(row.map(|&(t, dp, dn)| ((first_target + t as usize) as u16, dp, dn * scale)));
        }
    }
    out.normals.extend(normals);
    match (&mut out.uvs, prim.uvs) {
        (Some(uvs), Some(new)) => uvs.extend(new),
        (Some(uvs), None) => uvs.resize(vertices, Vec2::ZERO),
        (None, Some(new)) => out.uvs = Some([vec![Vec2::ZERO; base], new].concat()),
        (None, None) => {}
    }
    match (&mut out.colors, prim.colors) {
        (Some(colors), Some(new)) => colors.extend(new),
        (Some(colors), None) => colors.resize(vertices, Vec4::ONE),
        (None, Some(new)) => out.colors = Some([vec![Vec4::ONE; base], new].concat()),
        (None, None) => {}
    }
    debug_assert_eq!(influences.joints.len(), n);
    out.positions.extend(prim.positions);
    out.joints.extend(influences.joints);
    out.weights.extend(influences.weights);
    let first_index = out.indices.len() as u32;
    out.indices.extend(prim.indices.iter().map(|&i| i + base as u32));
    out.primitives.push(PrimitiveRange { first_index, index_count: prim.indices.len() as u32, material });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3, 4]), vec![0, 1, 2, 1, 3, 2, 2, 3, 4]);
        assert_eq!(triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]), vec![1, 2, 0, 2, 3, 0]);
        assert_eq!(triangle_list(Mode::Triangles, &[0, 1, 2, 3]), vec![0, 1, 2]);
        // A restart: repeated corners make degenerate triangles that are dropped.
        assert_eq!(triangle_list(Mode::TriangleStrip, &[0, 1, 1, 2]), Vec::<u32>::new());
    }

    #[test]
    fn triangles_without_area_are_left_out() {
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.0, 0.0], [0.5, 1e-7, 0.0]];
        let mut values: Vec<f32> = points.iter().flatten().copied().collect();
        values.extend([f32::NAN, 0.0, 0.0]);
        let positions = Elements { values, components: 3 };
        let keep = |t: [u32; 3]| without_arealess_triangles(t.to_vec(), &positions) == t;
        assert!(keep([0, 1, 2]));
        assert!(!keep([0, 3, 1]), "three corners on a line");
        assert!(!keep([0, 1, 4]), "a sliver: its smallest angle is 2e-7 rad");
        assert!(!keep([0, 0, 1]) && !keep([2, 2, 2]), "repeated corners");
        assert!(keep([0, 1, 5]), "a non-finite corner stays for the position check to name it");
        let tiny = Elements { values: positions.values.iter().map(|x| x * 1e-20).collect(), components: 3 };
        assert_eq!(without_arealess_triangles(vec![0, 1, 2], &tiny), [0, 1, 2], "tiny units square in f64");
        let mixed = without_arealess_triangles(vec![0, 3, 1, 0, 1, 2, 1, 1, 2], &positions);
        assert_eq!(mixed, vec![0, 1, 2]);
    }

    #[test]
    fn influences_keep_four_heaviest_sorted_and_renormalized() {
        let joints = Elements { values: vec![0, 1, 2, 3], components: 4 };
        let weights = Elements { values: vec![0.1, 0.4, 0.2, 0.3], components: 4 };
        let joints1 = Elements { values: vec![4, 1, 0, 0], components: 4 };
        let weights1 = Elements { values: vec![0.5, 0.1, 0.0, 0.0], components: 4 };
        let remap = [10, 11, 12, 13, 14];
        let sets = [(joints, weights), (joints1, weights1)];
        let r = resolve_influences(&sets, &remap, "p", &|v| v).unwrap();
        // Joint 1 appears twice (0.4 + 0.1); joint 0 (0.1) is the fifth and is dropped.
        assert_eq!(r.joints, vec![[11, 14, 13, 12]]);
        let total = 0.5 + 0.5 + 0.3 + 0.2;
        assert_eq!(r.weights, vec![[0.5 / total, 0.5 / total, 0.3 / total, 0.2 / total]]);
    }

    #[test]
    fn zero_weight_slots_may_name_any_joint_but_used_ones_must_exist() {
        let sets = [(
            Elements { values: vec![0, 99, 99, 99], components: 4 },
            Elements { values: vec![1.0, 0.0, 0.0, 0.0], components: 4 },
        )];
        assert!(resolve_influences(&sets, &[3], "p", &|v| v).is_ok());
        let sets = [(
            Elements { values: vec![0, 99, 0, 0], components: 4 },
            Elements { values: vec![0.5, 0.5, 0.0, 0.0], components: 4 },
        )];
        let err = resolve_influences(&sets, &[3], "mesh 0 primitive 0", &|v| v).err().unwrap().to_string();
        assert!(err.contains("joint 99") && err.contains("mesh 0 primitive 0"), "{err}");
    }
}
