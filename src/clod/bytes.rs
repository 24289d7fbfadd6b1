//! A built [`Clod`] as bytes, so a Web Worker can build the LOD chain and hand it to the main
//! thread, which imports the same `.glb` itself and decodes the chain against that character.
//!
//! The format is ours (no paper or spec): little-endian, no padding, no compression. Every
//! array is a `u32` element count followed by its elements; vectors are consecutive `f32`s
//! (vec2/vec3/vec4), joints four `u16`s, every id and index a `u32` (`u32::MAX` is "none", as in
//! [`ProgressiveMesh`]). In file order (the order of the build pipeline):
//!
//! 1. header: magic `b"CLOD"`, format version `u32` ([`FORMAT_VERSION`]);
//! 2. pose: tag `u32` (0 bind, 1 clip frame, 2 multi-pose, 3 mid-clip); a clip frame adds the
//!    clip name (`u32` byte count, UTF-8) and the time `f32` in seconds; multi-pose adds
//!    `frames_per_clip` as `u64`;
//! 3. progressive mesh: `input_vertex_count`, `attribute_count`, `base_vertex_count`, stop reason
//!    (0 target reached, 1 max error reached, 2 no valid collapse), all `u32`; then the arrays
//!    `positions` (vec3), `attributes` (f32), `parent`, `born_at`, `survivor_source`,
//!    `vertex_slot`, `indices`, `triangle_source` (u32); `collapses` (40 bytes each: `cost`,
//!    `distance`, `error`, `max_distance` as f32, then `triangles_after`, `vertices_after`,
//!    `first_new_vertex`, `new_vertex_count`, `corner_changes_start`, `corner_changes_end` as
//!    u32); `corner_changes` (12 bytes each: `corner`, `from_slot`, `to_slot`);
//! 4. bind-space data per vertex id: `bind_positions`, `bind_normals` (vec3); `uvs` and `colors`
//!    each a `u32` flag (0 absent, 1 present) then, if present, a vec2 / vec4 array; `joints`
//!    (4 × u16); `weights` (vec4); `singular_back_propagations` (u32);
//! 5. levels: a `u32` count, then per level `collapses` (u32), `requested_triangles` (u64),
//!    `error` (f32) and the arrays `indices`, `vertices`, `ancestors` (u32).
//!
//! Nothing may follow. There is no field of type `f64` in a [`Clod`], so none in the format.
//!
//! Decoding checks everything the cursor, [`crate::render::lod_source::LodSource::from_clod`] and the level
//! accessors rely on (see [`decode`]), and that the bytes belong to the character given: its
//! vertex and triangle counts, its input-vertex data (the first `input_vertex_count` entries of
//! every per-id array are the character's mesh arrays in a built chain) and its triangles.

use glam::{Vec2, Vec3, Vec4};
use thiserror::Error;

use super::{ArticulatedPm, Clod, LodLevel, SimplificationPose};
use crate::character::Character;
use crate::progressive::{CollapseRecord, CornerChange, ProgressiveMesh};
use crate::simplify::StopReason;

/// The first four bytes.
pub const MAGIC: [u8; 4] = *b"CLOD";
/// The layout this module writes and reads; bump it whenever the layout changes.
pub const FORMAT_VERSION: u32 = 1;
const NONE: u32 = u32::MAX;
/// Bytes of one [`CollapseRecord`] and one [`CornerChange`].
const COLLAPSE_BYTES: usize = 40;
const CORNER_CHANGE_BYTES: usize = 12;
/// The smallest level: three counts/scalars and three empty arrays (4 + 8 + 4 + 3 × 4).
const MIN_LEVEL_BYTES: usize = 28;

/// Why bytes could not be decoded into a [`Clod`] for a character.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ClodBytesError {
    #[error("not a CLOD chain: the bytes start with {found:?}, expected \"CLOD\"")]
    BadMagic { found: [u8; 4] },
    #[error("CLOD format version {found} is not supported; this build reads version {supported}")]
    UnsupportedVersion { found: u32, supported: u32 },
    #[error("truncated at {field}: it needs {needed} bytes, {remaining} are left")]
    Truncated { field: &'static str, needed: u64, remaining: usize },
    #[error("{count} unexpected bytes after the last field")]
    TrailingBytes { count: usize },
    #[error("unknown {field} tag {tag}")]
    UnknownTag { field: &'static str, tag: u32 },
    #[error("the simplification pose's clip name is not UTF-8")]
    BadClipName,
    #[error("the chain was built for a character with {bytes} {what}; this character has {character}")]
    CharacterMismatch { what: &'static str, bytes: u64, character: u64 },
    #[error("{what} {index} differs from this character's: the chain was built for another character")]
    CharacterDataMismatch { what: &'static str, index: usize },
    #[error("the chain was simplified in clip {name:?}, which this character does not have")]
    UnknownClip { name: String },
    #[error("vertex {vertex} uses joint {joint} but the character has {joint_count} joints")]
    JointOutOfRange { vertex: usize, joint: u16, joint_count: usize },
    #[error("{field} has {found} entries, expected {expected}")]
    LengthMismatch { field: &'static str, found: u64, expected: u64 },
    #[error("{field}[{index}] = {value} is out of range (must be below {bound})")]
    OutOfRange { field: &'static str, index: usize, value: u64, bound: u64 },
    #[error("{field}[{index}] is not finite")]
    NonFinite { field: &'static str, index: usize },
    #[error("{field}[{index}]: {reason}")]
    Inconsistent { field: &'static str, index: usize, reason: &'static str },
}

type Result<T> = std::result::Result<T, ClodBytesError>;

/// Encodes a chain in the layout of the module docs.
///
/// # Panics
/// If an array has more than `u32::MAX` elements (impossible for vertex ids, which are `u32`;
/// the attribute array would need over four billion floats).
pub fn encode(clod: &Clod) -> Vec<u8> {
    let pm = &clod.apm.pm;
    let apm = &clod.apm;
    let mut w = Writer { out: Vec::new() };
    w.out.extend_from_slice(&MAGIC);
    w.u32(FORMAT_VERSION);

    match &clod.pose {
        SimplificationPose::Bind => w.u32(0),
        SimplificationPose::ClipFrame { clip, time } => {
            w.u32(1);
            w.len(clip.len());
            w.out.extend_from_slice(clip.as_bytes());
            w.f32(*time);
        }
        SimplificationPose::MultiPose { frames_per_clip } => {
            w.u32(2);
            w.u64(*frames_per_clip as u64);
        }
        SimplificationPose::MidClip => w.u32(3),
    }

    w.len(pm.input_vertex_count);
    w.len(pm.attribute_count);
    w.u32(pm.base_vertex_count);
    w.u32(match pm.stop {
        StopReason::TargetReached => 0,
        StopReason::MaxErrorReached => 1,
        StopReason::NoValidCollapse => 2,
    });
    w.vectors(pm.positions.iter().map(|p| p.to_array()), pm.positions.len());
    w.f32s(&pm.attributes);
    for ids in
        [&pm.parent, &pm.born_at, &pm.survivor_source, &pm.vertex_slot, &pm.indices, &pm.triangle_source]
    {
        w.u32s(ids);
    }
    w.len(pm.collapses.len());
    for c in &pm.collapses {
        for x in [c.cost, c.distance, c.error, c.max_distance] {
            w.f32(x);
        }
        for x in [
            c.triangles_after,
            c.vertices_after,
            c.first_new_vertex,
            c.new_vertex_count,
            c.corner_changes_start,
            c.corner_changes_end,
        ] {
            w.u32(x);
        }
    }
    w.len(pm.corner_changes.len());
    for c in &pm.corner_changes {
        for x in [c.corner, c.from_slot, c.to_slot] {
            w.u32(x);
        }
    }

    w.vectors(apm.bind_positions.iter().map(|p| p.to_array()), apm.bind_positions.len());
    w.vectors(apm.bind_normals.iter().map(|n| n.to_array()), apm.bind_normals.len());
    w.u32(u32::from(apm.uvs.is_some()));
    if let Some(uvs) = &apm.uvs {
        w.vectors(uvs.iter().map(|t| t.to_array()), uvs.len());
    }
    w.u32(u32::from(apm.colors.is_some()));
    if let Some(colors) = &apm.colors {
        w.vectors(colors.iter().map(|c| c.to_array()), colors.len());
    }
    w.len(apm.joints.len());
    for j in apm.joints.iter().flatten() {
        w.out.extend_from_slice(&j.to_le_bytes());
    }
    w.vectors(apm.weights.iter().copied(), apm.weights.len());
    w.len(apm.singular_back_propagations);

    w.len(clod.levels.len());
    for level in &clod.levels {
        w.len(level.collapses);
        w.u64(level.requested_triangles as u64);
        w.f32(level.error);
        w.u32s(&level.indices);
        w.u32s(&level.vertices);
        w.u32s(&level.ancestors);
    }
    w.out
}

struct Writer {
    out: Vec<u8>,
}

impl Writer {
    fn u32(&mut self, x: u32) {
        self.out.extend_from_slice(&x.to_le_bytes());
    }

    fn u64(&mut self, x: u64) {
        self.out.extend_from_slice(&x.to_le_bytes());
    }

    fn f32(&mut self, x: f32) {
        self.out.extend_from_slice(&x.to_le_bytes());
    }

    /// A count or `usize` field, as `u32`.
    fn len(&mut self, n: usize) {
        self.u32(u32::try_from(n).expect("CLOD arrays and counts fit in u32"));
    }

    fn u32s(&mut self, xs: &[u32]) {
        self.len(xs.len());
        xs.iter().for_each(|&x| self.u32(x));
    }

    fn f32s(&mut self, xs: &[f32]) {
        self.len(xs.len());
        xs.iter().for_each(|&x| self.f32(x));
    }

    fn vectors<const N: usize>(&mut self, xs: impl Iterator<Item = [f32; N]>, count: usize) {
        self.len(count);
        xs.flatten().for_each(|x| self.f32(x));
    }
}

/// Decodes a chain [`encode`] wrote for `character` (the same `.glb` imported again: import is
/// deterministic). The result is usable exactly like a built chain: [`ProgressiveMesh::cursor`]
/// with any triangle or collapse count, [`crate::render::lod_source::LodSource::from_clod`] and
/// [`crate::render::lod_source::LodSource::from_cursor`], and the `level_*` accessors of [`Clod`].
///
/// Never panics, and allocates at most a small multiple of `bytes.len()` (every length prefix is
/// checked against the bytes left before anything is allocated). Checked, after parsing:
/// - the character: vertex count, triangles (the base triangles are the character's, permuted
///   by `triangle_source`), the input vertices' bind data, uv/colour presence, joint indices of
///   every non-zero weight, and the pose's clip;
/// - every array length against its vertex, corner or level count, and every id, index, slot,
///   parent, survivor, corner and ancestor against the array it indexes;
/// - the collapse forest: parents are created vertices with larger ids (so ancestor walks end),
///   survivors have smaller ids and share their slot, each step creates the next ids and its
///   corner changes follow the previous step's;
/// - a replay of every collapse as [`crate::progressive::PmCursor`] does it: each corner change
///   starts from the corner's current slot and each new vertex replaces its survivor (so undoing
///   restores exactly), triangle and slot counts never grow, and every live corner points at a
///   live slot at every level;
/// - positions (simplification pose and bind space) are finite.
///
/// Not checked, because nothing relies on them: collapse costs and errors, attribute and normal
/// values, and whether a level's vertices are the active ancestors of its collapse count (a
/// tampered level still renders as a valid, different mesh).
///
/// # Errors
/// [`ClodBytesError`] naming the first problem found.
pub fn decode(bytes: &[u8], character: &Character) -> Result<Clod> {
    let mut r = Reader { bytes, at: 0 };
    let magic = r.take(4, "magic")?;
    if magic != MAGIC {
        return Err(ClodBytesError::BadMagic { found: [magic[0], magic[1], magic[2], magic[3]] });
    }
    let version = r.u32("version")?;
    if version != FORMAT_VERSION {
        return Err(ClodBytesError::UnsupportedVersion { found: version, supported: FORMAT_VERSION });
    }
    let pose = read_pose(&mut r)?;
    let pm = read_pm(&mut r)?;
    let apm = read_apm(&mut r, pm)?;
    let levels = read_levels(&mut r)?;
    if r.remaining() > 0 {
        return Err(ClodBytesError::TrailingBytes { count: r.remaining() });
    }
    let mut clod = Clod { apm, levels, pose, flat: Vec::new() };
    check_character(&clod, character)?;
    check_forest(&clod.apm.pm)?;
    check_replay(&clod.apm.pm)?;
    check_levels(&clod)?;
    // Derived from the character, as the build does; not stored.
    let weld = super::shading::ShadingWeld::of_character(character);
    clod.flat = super::shading::flat_ids(&weld, &clod.apm.pm);
    Ok(clod)
}

fn read_pose(r: &mut Reader) -> Result<SimplificationPose> {
    Ok(match r.u32("pose tag")? {
        0 => SimplificationPose::Bind,
        1 => {
            let n = r.count("pose clip name", 1)?;
            let name = r.take(n, "pose clip name")?;
            let clip = String::from_utf8(name.to_vec()).map_err(|_| ClodBytesError::BadClipName)?;
            SimplificationPose::ClipFrame { clip, time: r.f32("pose time")? }
        }
        2 => {
            let frames = r.u64("pose frames per clip")?;
            // usize is 32 bits on wasm32: a count it cannot hold was not written there.
            let frames_per_clip = usize::try_from(frames).map_err(|_| ClodBytesError::OutOfRange {
                field: "pose frames per clip",
                index: 0,
                value: frames,
                bound: usize::MAX as u64,
            })?;
            SimplificationPose::MultiPose { frames_per_clip }
        }
        3 => SimplificationPose::MidClip,
        tag => return Err(ClodBytesError::UnknownTag { field: "pose", tag }),
    })
}

fn read_pm(r: &mut Reader) -> Result<ProgressiveMesh> {
    let input_vertex_count = r.u32("input vertex count")? as usize;
    let attribute_count = r.u32("attribute count")? as usize;
    let base_vertex_count = r.u32("base vertex count")?;
    let stop = match r.u32("stop reason")? {
        0 => StopReason::TargetReached,
        1 => StopReason::MaxErrorReached,
        2 => StopReason::NoValidCollapse,
        tag => return Err(ClodBytesError::UnknownTag { field: "stop reason", tag }),
    };
    let positions: Vec<Vec3> = r.vectors::<3>("positions")?.into_iter().map(Vec3::from_array).collect();
    let attributes = r.f32s("attributes")?;
    let parent = r.u32s("parent")?;
    let born_at = r.u32s("born_at")?;
    let survivor_source = r.u32s("survivor_source")?;
    let vertex_slot = r.u32s("vertex_slot")?;
    let indices = r.u32s("indices")?;
    let triangle_source = r.u32s("triangle_source")?;
    let n = r.count("collapses", COLLAPSE_BYTES)?;
    let mut collapses = Vec::with_capacity(n);
    for _ in 0..n {
        let f = |r: &mut Reader| r.f32("collapses");
        let (cost, distance, error, max_distance) = (f(r)?, f(r)?, f(r)?, f(r)?);
        let u = |r: &mut Reader| r.u32("collapses");
        collapses.push(CollapseRecord {
            cost,
            distance,
            error,
            max_distance,
            triangles_after: u(r)?,
            vertices_after: u(r)?,
            first_new_vertex: u(r)?,
            new_vertex_count: u(r)?,
            corner_changes_start: u(r)?,
            corner_changes_end: u(r)?,
        });
    }
    let n = r.count("corner_changes", CORNER_CHANGE_BYTES)?;
    let mut corner_changes = Vec::with_capacity(n);
    for _ in 0..n {
        let u = |r: &mut Reader| r.u32("corner_changes");
        corner_changes.push(CornerChange { corner: u(r)?, from_slot: u(r)?, to_slot: u(r)? });
    }
    Ok(ProgressiveMesh {
        positions,
        attributes,
        attribute_count,
        input_vertex_count,
        parent,
        born_at,
        survivor_source,
        vertex_slot,
        indices,
        triangle_source,
        collapses,
        stop,
        base_vertex_count,
        corner_changes,
    })
}

fn read_apm(r: &mut Reader, pm: ProgressiveMesh) -> Result<ArticulatedPm> {
    let vec3s = |r: &mut Reader, field| -> Result<Vec<Vec3>> {
        Ok(r.vectors::<3>(field)?.into_iter().map(Vec3::from_array).collect())
    };
    let bind_positions = vec3s(r, "bind_positions")?;
    let bind_normals = vec3s(r, "bind_normals")?;
    let uvs = match r.flag("uvs flag")? {
        true => Some(r.vectors::<2>("uvs")?.into_iter().map(Vec2::from_array).collect()),
        false => None,
    };
    let colors = match r.flag("colors flag")? {
        true => Some(r.vectors::<4>("colors")?.into_iter().map(Vec4::from_array).collect()),
        false => None,
    };
    let n = r.count("joints", 8)?;
    let raw = r.take(8 * n, "joints")?;
    let joints = raw
        .chunks_exact(8)
        .map(|c| std::array::from_fn(|k| u16::from_le_bytes([c[2 * k], c[2 * k + 1]])))
        .collect();
    let weights = r.vectors::<4>("weights")?;
    let singular_back_propagations = r.u32("singular_back_propagations")? as usize;
    Ok(ArticulatedPm {
        pm,
        bind_positions,
        bind_normals,
        uvs,
        colors,
        joints,
        weights,
        singular_back_propagations,
    })
}

fn read_levels(r: &mut Reader) -> Result<Vec<LodLevel>> {
    let n = r.count("levels", MIN_LEVEL_BYTES)?;
    let mut levels = Vec::with_capacity(n);
    for _ in 0..n {
        let collapses = r.u32("level collapses")? as usize;
        let requested = r.u64("level requested triangles")?;
        // usize is 32 bits on wasm32; a larger request means "every triangle" all the same.
        let requested_triangles = usize::try_from(requested).unwrap_or(usize::MAX);
        let error = r.f32("level error")?;
        levels.push(LodLevel {
            collapses,
            requested_triangles,
            error,
            indices: r.u32s("level indices")?,
            vertices: r.u32s("level vertices")?,
            ancestors: r.u32s("level ancestors")?,
        });
    }
    Ok(levels)
}

/// A cursor over the input bytes; every read checks the bytes left first.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn take(&mut self, n: usize, field: &'static str) -> Result<&'a [u8]> {
        if n > self.remaining() {
            return Err(ClodBytesError::Truncated { field, needed: n as u64, remaining: self.remaining() });
        }
        let out = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(out)
    }

    fn u32(&mut self, field: &'static str) -> Result<u32> {
        let b = self.take(4, field)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, field: &'static str) -> Result<u64> {
        let (lo, hi) = (self.u32(field)?, self.u32(field)?);
        Ok(u64::from(lo) | u64::from(hi) << 32)
    }

    fn f32(&mut self, field: &'static str) -> Result<f32> {
        Ok(f32::from_bits(self.u32(field)?))
    }

    fn flag(&mut self, field: &'static str) -> Result<bool> {
        match self.u32(field)? {
            0 => Ok(false),
            1 => Ok(true),
            tag => Err(ClodBytesError::UnknownTag { field, tag }),
        }
    }

    /// An element count, checked against the bytes left (each element needs at least
    /// `element_bytes`), so a lying prefix cannot make the decoder allocate.
    fn count(&mut self, field: &'static str, element_bytes: usize) -> Result<usize> {
        let n = self.u32(field)? as usize;
        let needed = n as u64 * element_bytes as u64;
        if needed > self.remaining() as u64 {
            return Err(ClodBytesError::Truncated { field, needed, remaining: self.remaining() });
        }
        Ok(n)
    }

    fn u32s(&mut self, field: &'static str) -> Result<Vec<u32>> {
        let n = self.count(field, 4)?;
        let raw = self.take(4 * n, field)?;
        Ok(raw.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
    }

    fn f32s(&mut self, field: &'static str) -> Result<Vec<f32>> {
        Ok(self.u32s(field)?.into_iter().map(f32::from_bits).collect())
    }

    fn vectors<const N: usize>(&mut self, field: &'static str) -> Result<Vec<[f32; N]>> {
        let n = self.count(field, 4 * N)?;
        let raw = self.take(4 * N * n, field)?;
        Ok(raw
            .chunks_exact(4 * N)
            .map(|c| {
                std::array::from_fn(|k| {
                    f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
                })
            })
            .collect())
    }
}

fn expect_len(field: &'static str, found: usize, expected: usize) -> Result<()> {
    if found != expected {
        return Err(ClodBytesError::LengthMismatch { field, found: found as u64, expected: expected as u64 });
    }
    Ok(())
}

/// The first `value` of `values` that is not below `bound`.
fn expect_below(field: &'static str, values: &[u32], bound: usize) -> Result<()> {
    match values.iter().position(|&v| v as usize >= bound) {
        Some(index) => {
            Err(ClodBytesError::OutOfRange { field, index, value: values[index].into(), bound: bound as u64 })
        }
        None => Ok(()),
    }
}

fn expect_finite<const N: usize>(field: &'static str, values: impl Iterator<Item = [f32; N]>) -> Result<()> {
    for (index, v) in values.enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(ClodBytesError::NonFinite { field, index });
        }
    }
    Ok(())
}

fn first_difference<T: PartialEq>(a: &[T], b: &[T]) -> Option<usize> {
    a.iter().zip(b).position(|(x, y)| x != y)
}

fn inconsistent(field: &'static str, index: usize, reason: &'static str) -> ClodBytesError {
    ClodBytesError::Inconsistent { field, index, reason }
}

/// Counts, lengths and input data against the character; runs first, so the arrays sized by
/// the vertex count below are bounded by the character, not by a number in the bytes.
fn check_character(clod: &Clod, character: &Character) -> Result<()> {
    let (pm, apm, mesh) = (&clod.apm.pm, &clod.apm, &character.mesh);
    let n = pm.input_vertex_count;
    let mismatch = |what, bytes: usize, character: usize| ClodBytesError::CharacterMismatch {
        what,
        bytes: bytes as u64,
        character: character as u64,
    };
    if n != mesh.vertex_count() {
        return Err(mismatch("vertices", n, mesh.vertex_count()));
    }
    if pm.indices.len() != mesh.indices.len() {
        return Err(mismatch("triangle corners", pm.indices.len(), mesh.indices.len()));
    }
    if apm.uvs.is_some() != mesh.uvs.is_some() {
        return Err(mismatch("uv sets", usize::from(apm.uvs.is_some()), usize::from(mesh.uvs.is_some())));
    }
    if apm.colors.is_some() != mesh.colors.is_some() {
        let (bytes, ours) = (usize::from(apm.colors.is_some()), usize::from(mesh.colors.is_some()));
        return Err(mismatch("colour sets", bytes, ours));
    }
    if let SimplificationPose::ClipFrame { clip, .. } = &clod.pose {
        if character.clip(clip).is_none() {
            return Err(ClodBytesError::UnknownClip { name: clip.clone() });
        }
    }

    let total = pm.positions.len();
    if total < n {
        return Err(inconsistent("positions", total, "fewer positions than input vertices"));
    }
    // Saturating: no array read from the bytes can be usize::MAX long, so an overflow mismatches.
    let attributes = total.saturating_mul(pm.attribute_count);
    expect_len("attributes", pm.attributes.len(), attributes)?;
    for (field, len) in [
        ("parent", pm.parent.len()),
        ("born_at", pm.born_at.len()),
        ("survivor_source", pm.survivor_source.len()),
        ("vertex_slot", pm.vertex_slot.len()),
        ("bind_positions", apm.bind_positions.len()),
        ("bind_normals", apm.bind_normals.len()),
        ("uvs", apm.uvs.as_ref().map_or(total, Vec::len)),
        ("colors", apm.colors.as_ref().map_or(total, Vec::len)),
        ("joints", apm.joints.len()),
        ("weights", apm.weights.len()),
    ] {
        expect_len(field, len, total)?;
    }
    expect_len("triangle_source", 3 * pm.triangle_source.len(), pm.indices.len())?;
    expect_finite("positions", pm.positions.iter().map(|p| p.to_array()))?;
    expect_finite("bind_positions", apm.bind_positions.iter().map(|p| p.to_array()))?;

    // A built chain starts every per-id array with the character's own mesh arrays.
    let differs = |what, index: Option<usize>| match index {
        Some(index) => Err(ClodBytesError::CharacterDataMismatch { what, index }),
        None => Ok(()),
    };
    differs("bind position of vertex", first_difference(&apm.bind_positions[..n], &mesh.positions))?;
    differs("bind normal of vertex", first_difference(&apm.bind_normals[..n], &mesh.normals))?;
    if let (Some(ours), Some(theirs)) = (&apm.uvs, &mesh.uvs) {
        differs("uv of vertex", first_difference(&ours[..n], theirs))?;
    }
    if let (Some(ours), Some(theirs)) = (&apm.colors, &mesh.colors) {
        differs("colour of vertex", first_difference(&ours[..n], theirs))?;
    }
    differs("joints of vertex", first_difference(&apm.joints[..n], &mesh.joints))?;
    differs("skin weights of vertex", first_difference(&apm.weights[..n], &mesh.weights))?;

    let joint_count = character.skeleton.joints.len();
    for (vertex, (joints, weights)) in apm.joints.iter().zip(&apm.weights).enumerate() {
        // blend_matrix skips zero weights, and the importer pads unused slots with joint 0.
        if let Some(k) = (0..4).find(|&k| weights[k] != 0.0 && joints[k] as usize >= joint_count) {
            return Err(ClodBytesError::JointOutOfRange { vertex, joint: joints[k], joint_count });
        }
    }

    // The base triangles are the character's (its flat vertices welded, as the build does), in
    // the order triangle_source gives.
    let weld = super::shading::ShadingWeld::of_character(character);
    let welded = weld.weld_indices(&mesh.indices);
    let triangles = pm.triangle_source.len();
    expect_below("triangle_source", &pm.triangle_source, triangles)?;
    let mut seen = vec![false; triangles];
    for (t, &source) in pm.triangle_source.iter().enumerate() {
        if std::mem::replace(&mut seen[source as usize], true) {
            return Err(inconsistent("triangle_source", t, "an input triangle appears twice"));
        }
        let s = 3 * source as usize;
        if pm.indices[3 * t..3 * t + 3] != welded[s..s + 3] {
            return Err(ClodBytesError::CharacterDataMismatch { what: "triangle", index: source as usize });
        }
    }
    Ok(())
}

/// The collapse forest and the step records: ids, slots and ranges.
fn check_forest(pm: &ProgressiveMesh) -> Result<()> {
    let n = pm.input_vertex_count;
    let total = pm.vertex_total();
    for v in 0..total {
        let p = pm.parent[v];
        if p != NONE && (p as usize >= total || (p as usize) < n.max(v + 1)) {
            // Ancestor walks stop because ids grow towards the roots; parents are created ids.
            return Err(inconsistent("parent", v, "a parent must be a created vertex with a larger id"));
        }
        let s = pm.survivor_source[v];
        let created = v >= n;
        if created != (s != NONE) || (created && s as usize >= v) {
            // clod_materials walks survivors down to an input vertex.
            return Err(inconsistent(
                "survivor_source",
                v,
                "created vertices inherit from a smaller id; input vertices from none",
            ));
        }
        if !created && pm.born_at[v] != 0 {
            return Err(inconsistent("born_at", v, "input vertices are born at step 0"));
        }
    }
    expect_below("vertex_slot", &pm.vertex_slot, n)?;
    let mut slot_taken = vec![false; n];
    for v in 0..n {
        if std::mem::replace(&mut slot_taken[pm.vertex_slot[v] as usize], true) {
            return Err(inconsistent("vertex_slot", v, "two input vertices share a slot"));
        }
    }
    for x in n..total {
        if pm.vertex_slot[x] != pm.vertex_slot[pm.survivor_source[x] as usize] {
            return Err(inconsistent("vertex_slot", x, "a created vertex takes its survivor's slot"));
        }
    }
    expect_below("indices", &pm.indices, n)?;
    if pm.base_vertex_count as usize > n {
        let (value, bound) = (pm.base_vertex_count.into(), n as u64);
        return Err(ClodBytesError::OutOfRange { field: "base_vertex_count", index: 0, value, bound });
    }

    let changes = &pm.corner_changes;
    let corners = changes.iter().map(|c| c.corner).collect::<Vec<_>>();
    expect_below("corner_changes (corner)", &corners, pm.indices.len())?;
    for (i, c) in changes.iter().enumerate() {
        if c.from_slot as usize >= n || c.to_slot as usize >= n {
            let value = c.from_slot.max(c.to_slot).into();
            return Err(ClodBytesError::OutOfRange {
                field: "corner_changes (slot)",
                index: i,
                value,
                bound: n as u64,
            });
        }
    }

    // Steps create consecutive ids and own consecutive corner-change ranges.
    let (mut next_vertex, mut next_change) = (n as u64, 0u32);
    let (mut triangles, mut vertices) = (pm.indices.len() as u64 / 3, u64::from(pm.base_vertex_count));
    for (s, c) in pm.collapses.iter().enumerate() {
        let end = u64::from(c.first_new_vertex) + u64::from(c.new_vertex_count);
        if u64::from(c.first_new_vertex) != next_vertex || end > total as u64 {
            return Err(inconsistent("collapses", s, "new vertices must continue the previous step's ids"));
        }
        if (c.first_new_vertex..end as u32).any(|x| pm.born_at[x as usize] as usize != s + 1) {
            return Err(inconsistent("born_at", s, "a vertex's birth step is not the step creating it"));
        }
        if c.corner_changes_start != next_change
            || c.corner_changes_end < c.corner_changes_start
            || c.corner_changes_end as usize > changes.len()
        {
            return Err(inconsistent("collapses", s, "corner changes must continue the previous step's"));
        }
        if u64::from(c.triangles_after) > triangles || u64::from(c.vertices_after) > vertices {
            return Err(inconsistent("collapses", s, "triangle and slot counts never grow"));
        }
        (next_vertex, next_change) = (end, c.corner_changes_end);
        (triangles, vertices) = (c.triangles_after.into(), c.vertices_after.into());
    }
    if next_vertex != total as u64 {
        return Err(inconsistent("collapses", pm.collapses.len(), "some created vertices have no step"));
    }
    if next_change as usize != changes.len() {
        return Err(inconsistent("collapses", pm.collapses.len(), "some corner changes have no step"));
    }
    Ok(())
}

/// Replays every collapse as `PmCursor::set_collapses` does, checking that each write replaces
/// what undoing it restores and that the live corners only use live slots at every level.
/// Linear in corners, slots and changes: the live-slot bound only shrinks, so a per-slot count
/// of live corners and a running count of those past the bound suffice.
fn check_replay(pm: &ProgressiveMesh) -> Result<()> {
    let n = pm.input_vertex_count;
    let mut corner_slots: Vec<u32> = pm.indices.iter().map(|&v| pm.vertex_slot[v as usize]).collect();
    let mut slot_vertex = vec![0u32; n];
    for v in 0..n {
        slot_vertex[pm.vertex_slot[v] as usize] = v as u32;
    }
    let mut live_corners = pm.indices.len();
    let mut live_slots = pm.base_vertex_count as usize;
    let mut corners_at = vec![0u32; n];
    corner_slots.iter().for_each(|&s| corners_at[s as usize] += 1);
    let mut past_bound: u64 = corners_at[live_slots..].iter().map(|&c| u64::from(c)).sum();
    if past_bound > 0 {
        return Err(inconsistent("base_vertex_count", 0, "a triangle uses a slot past the live ones"));
    }
    for (s, record) in pm.collapses.iter().enumerate() {
        let range = record.corner_changes_start as usize..record.corner_changes_end as usize;
        for (i, change) in pm.corner_changes[range.clone()].iter().enumerate() {
            let corner = change.corner as usize;
            if corner_slots[corner] != change.from_slot {
                return Err(inconsistent(
                    "corner_changes",
                    range.start + i,
                    "from_slot is not the corner's slot",
                ));
            }
            corner_slots[corner] = change.to_slot;
            if corner < live_corners {
                let (from, to) = (change.from_slot as usize, change.to_slot as usize);
                corners_at[from] -= 1;
                corners_at[to] += 1;
                past_bound = past_bound - u64::from(from >= live_slots) + u64::from(to >= live_slots);
            }
        }
        for x in record.first_new_vertex..record.first_new_vertex + record.new_vertex_count {
            let slot = pm.vertex_slot[x as usize] as usize;
            if slot_vertex[slot] != pm.survivor_source[x as usize] {
                return Err(inconsistent("survivor_source", x as usize, "the survivor is not in its slot"));
            }
            slot_vertex[slot] = x;
        }
        let triangles_after = record.triangles_after as usize;
        for &slot in &corner_slots[3 * triangles_after..live_corners] {
            corners_at[slot as usize] -= 1;
            past_bound -= u64::from(slot as usize >= live_slots);
        }
        live_corners = 3 * triangles_after;
        let vertices_after = record.vertices_after as usize;
        past_bound += corners_at[vertices_after..live_slots].iter().map(|&c| u64::from(c)).sum::<u64>();
        live_slots = vertices_after;
        if past_bound > 0 {
            return Err(inconsistent("collapses", s, "a live triangle uses a slot past the live ones"));
        }
    }
    Ok(())
}

/// Levels: collapse counts, sizes and every index against the array it indexes.
fn check_levels(clod: &Clod) -> Result<()> {
    let pm = &clod.apm.pm;
    if clod.levels.is_empty() {
        return Err(ClodBytesError::LengthMismatch { field: "levels", found: 0, expected: 1 });
    }
    // A request the progressive mesh cannot reach gets `collapse_count() + 1` from
    // `collapses_for_triangle_count` (every use clamps it), so that is a count a build can store.
    let most = pm.collapse_count() + 1;
    for (i, pair) in clod.levels.windows(2).enumerate() {
        if pair[1].collapses <= pair[0].collapses {
            return Err(inconsistent(
                "level collapses",
                i + 1,
                "each level has more collapses than the last",
            ));
        }
    }
    for (i, level) in clod.levels.iter().enumerate() {
        if level.collapses > most {
            let (value, bound) = (level.collapses as u64, most as u64 + 1);
            return Err(ClodBytesError::OutOfRange { field: "level collapses", index: i, value, bound });
        }
        expect_len("level indices", level.indices.len(), 3 * pm.triangle_count_after(level.collapses))?;
        expect_below("level indices", &level.indices, level.vertices.len())?;
        expect_below("level vertices", &level.vertices, pm.vertex_total())?;
        match clod.levels.get(i + 1) {
            Some(coarser) => {
                expect_len("level ancestors", level.ancestors.len(), level.vertices.len())?;
                expect_below("level ancestors", &level.ancestors, coarser.vertices.len())?;
            }
            None => expect_len("level ancestors", level.ancestors.len(), 0)?,
        }
    }
    Ok(())
}
