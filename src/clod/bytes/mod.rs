//! A built [`Clod`] as bytes, so a Web Worker can build the LOD chain and hand it to the main
//! thread (and the page can cache it), which imports the same `.glb` itself and decodes the
//! chain against that character.
//!
//! The bytes hold what the build *decided*, nothing it can recompute: the collapse sequence
//! (Hoppe's vertex splits, as slot and corner changes), the positions and attributes the
//! simplifier gave the vertices it created, and the build's choices (pose, weight rule, level
//! requests). Decoding recomputes the rest exactly, with the same code the build ran: the input
//! vertices' `P0` positions and attributes (`PoseInput`), the base triangles, birth
//! steps and slots that follow from the records, back-propagation to bind space and the discrete
//! levels with their ancestor tables (`articulate`). So a chain is about 1.5× its
//! `.glb` (measured in `tests/clod_bytes.rs`), and a decoded chain equals the built one.
//!
//! The format is ours (no paper or spec): little-endian, no padding, no compression. Every
//! array is a `u32` element count followed by its elements; vectors are consecutive `f32`s,
//! every id and index a `u32` (`u32::MAX` is "none", as in [`ProgressiveMesh`]). With `n` input
//! vertices, `m` created vertices and `a` attribute floats per vertex, in file order:
//!
//! 1. header: magic `b"CLOD"`, format version `u32` ([`FORMAT_VERSION`]);
//! 2. the character: `n` and the triangle count (`u32`), and a 64-bit fingerprint of its mesh
//!    (`fingerprint`: FNV-1a over positions, normals, uvs, colours, joints, weights,
//!    triangles and morph deltas), so a chain is never attached to another character;
//! 3. the build's choices: pose tag `u32` (0 bind, 1 clip frame, 2 multi-pose, 3 mid-clip; a
//!    clip frame adds the clip name as `u32` byte count and UTF-8, and the time `f32` in
//!    seconds; multi-pose adds `frames_per_clip` as `u64`); the weight rule `u32` (0 survivor,
//!    1 blend); the levels' requested triangle counts (`u64` array, finest first);
//! 4. the progressive mesh's decisions: `a`, `base_vertex_count` and the stop reason (0 target
//!    reached, 1 max error reached, 2 no valid collapse), all `u32`; the arrays
//!    `triangle_source` (the input triangle of each base triangle), the input vertices' slots
//!    (`n`), the created vertices' survivors (`m`), every vertex's `parent` (`n + m`), the
//!    created vertices' `P0` positions (vec3, `m`) and attributes (`a · m` floats); the
//!    collapses (32 bytes each: `cost`, `distance`, `error`, `max_distance` as f32, then
//!    `triangles_after`, `vertices_after`, `new_vertex_count`, `corner_changes_end` as u32); the
//!    corner changes (8 bytes each: `corner`, `to_slot`; the slot a change starts from is the
//!    corner's slot at that step, found by replaying).
//!
//! Nothing may follow. There is no field of type `f64` in a [`Clod`], so none in the format.
//!
//! Decoding checks everything the cursor, [`crate::render::lod_source::LodSource::from_clod`]
//! and the level accessors rely on (see [`decode`]).

mod io;

use glam::{Vec2, Vec3, Vec4};
use thiserror::Error;

use self::io::{Reader, Writer};
use super::{Clod, SimplificationPose};
use super::{ClodError, PoseInput, WeightRule};
use crate::character::Character;
use crate::morph::MorphDeltas;
use crate::progressive::{CollapseRecord, CornerChange, ProgressiveMesh, StopReason, NONE};

/// The first four bytes.
pub const MAGIC: [u8; 4] = *b"CLOD";
/// The layout this module writes and reads; bump it whenever the layout changes. Version 1
/// stored every array of a built chain (about 5× the `.glb`).
pub const FORMAT_VERSION: u32 = 2;
/// The identity of the sources this library was built from (16 hex digits; see `build.rs`).
/// Chains decode with any build of one [`FORMAT_VERSION`], but a build whose simplifier changed
/// makes other levels from the same file: the page keys its chain cache on this tag too, so it
/// never attaches levels the running code did not make.
pub const SOURCE_TAG: &str = env!("CLOD_SOURCE_TAG");
/// Bytes of one collapse record and one corner change.
const COLLAPSE_BYTES: usize = 32;
const CORNER_CHANGE_BYTES: usize = 8;

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
    #[error("the chain was built for another character: the counts agree but the mesh data differs")]
    OtherCharacter,
    #[error("the chain was simplified in clip {name:?}, which this character does not have")]
    UnknownClip { name: String },
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
    let (apm, pm) = (&clod.apm, &clod.apm.pm);
    let n = pm.input_vertex_count;
    let mut w = Writer { out: Vec::new() };
    w.out.extend_from_slice(&MAGIC);
    w.u32(FORMAT_VERSION);

    // The character: a built chain's first `n` entries of every per-id array are its mesh, and
    // its base triangles are the simplifier's input.
    let mut input_indices = vec![0u32; pm.indices.len()];
    for (t, &source) in pm.triangle_source.iter().enumerate() {
        let s = 3 * source as usize;
        input_indices[s..s + 3].copy_from_slice(&pm.indices[3 * t..3 * t + 3]);
    }
    w.len(n);
    w.len(pm.triangle_source.len());
    w.u64(fingerprint(&MeshArrays {
        positions: &apm.bind_positions[..n],
        normals: &apm.bind_normals[..n],
        uvs: apm.uvs.as_deref().map(|uvs| &uvs[..n]),
        colors: apm.colors.as_deref().map(|colors| &colors[..n]),
        joints: &apm.joints[..n],
        weights: &apm.weights[..n],
        indices: &input_indices,
        morph: &apm.morph,
    }));

    // The build's choices.
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
    w.u32(match clod.weights {
        WeightRule::Survivor => 0,
        WeightRule::Blend => 1,
    });
    w.len(clod.levels.len());
    clod.levels.iter().for_each(|level| w.u64(level.requested_triangles as u64));

    // The progressive mesh's decisions.
    w.len(pm.attribute_count);
    w.u32(pm.base_vertex_count);
    w.u32(match pm.stop {
        StopReason::TargetReached => 0,
        StopReason::MaxErrorReached => 1,
        StopReason::NoValidCollapse => 2,
    });
    w.u32s(&pm.triangle_source);
    w.u32s(&pm.vertex_slot[..n]);
    w.u32s(&pm.survivor_source[n..]);
    w.u32s(&pm.parent);
    w.vec3s(&pm.positions[n..]);
    w.f32s(&pm.attributes[n * pm.attribute_count..]);
    w.len(pm.collapses.len());
    for c in &pm.collapses {
        [c.cost, c.distance, c.error, c.max_distance].into_iter().for_each(|x| w.f32(x));
        for x in [c.triangles_after, c.vertices_after, c.new_vertex_count, c.corner_changes_end] {
            w.u32(x);
        }
    }
    w.len(pm.corner_changes.len());
    for c in &pm.corner_changes {
        w.u32(c.corner);
        w.u32(c.to_slot);
    }
    w.out
}

/// The mesh arrays a chain is fingerprinted by, in input order.
struct MeshArrays<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: Option<&'a [Vec2]>,
    colors: Option<&'a [Vec4]>,
    joints: &'a [[u16; 4]],
    weights: &'a [[f32; 4]],
    indices: &'a [u32],
    /// Morph deltas; rows past the vertex count (a chain's created vertices) are not hashed.
    morph: &'a MorphDeltas,
}

/// 64-bit FNV-1a over the little-endian 32-bit words of the mesh's counts and arrays (joints
/// two to a word). Not a cryptographic hash: it tells a chain's own character from another one
/// with the same counts, which is all the decoder needs (a cache is keyed by the file's SHA-256).
fn fingerprint(mesh: &MeshArrays) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut word = |w: u32| {
        for b in w.to_le_bytes() {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    word(mesh.positions.len() as u32);
    word(mesh.indices.len() as u32);
    let floats = mesh.positions.iter().chain(mesh.normals).flat_map(|v| v.to_array());
    let uvs = mesh.uvs.into_iter().flatten().flat_map(|v| v.to_array());
    let colors = mesh.colors.into_iter().flatten().flat_map(|v| v.to_array());
    let weights = mesh.weights.iter().flatten().copied();
    floats.chain(uvs).chain(colors).chain(weights).for_each(|x| word(x.to_bits()));
    word(u32::from(mesh.uvs.is_some()) | u32::from(mesh.colors.is_some()) << 1);
    for j in mesh.joints {
        word(u32::from(j[0]) | u32::from(j[1]) << 16);
        word(u32::from(j[2]) | u32::from(j[3]) << 16);
    }
    mesh.indices.iter().for_each(|&i| word(i));
    for v in 0..mesh.positions.len() {
        for (target, position, normal) in mesh.morph.of(v) {
            word(v as u32);
            word(target.into());
            position.to_array().into_iter().chain(normal.to_array()).for_each(|x| word(x.to_bits()));
        }
    }
    hash
}

/// Decodes a chain [`encode`] wrote for `character` (the same `.glb` imported again: import is
/// deterministic). The result equals the built chain and is usable exactly like it:
/// [`ProgressiveMesh::cursor`] with any triangle or collapse count,
/// [`crate::render::lod_source::LodSource::from_clod`] and
/// [`crate::render::lod_source::LodSource::from_cursor`], and the `level_*` accessors of [`Clod`].
///
/// Never panics, and allocates at most a small multiple of `bytes.len()` plus the character's
/// own size (every length prefix is checked against the bytes left before anything is
/// allocated). Checked:
/// - the character: vertex and triangle counts, the mesh fingerprint, the attribute channels
///   and the pose's clip;
/// - every array length against its vertex, corner or level count, and every id, index, slot,
///   parent, survivor and corner against the array it indexes;
/// - the collapse forest: parents are created vertices with larger ids (so ancestor walks end),
///   survivors have smaller ids, each step creates the next ids and its corner changes follow
///   the previous step's;
/// - a replay of every collapse as [`crate::progressive::PmCursor`] does it: each new vertex
///   replaces its survivor, triangle and slot counts never grow, and every live corner points at
///   a live slot at every level;
/// - created positions are finite; level requests are positive, decreasing and give distinct
///   levels.
///
/// Not checked, because nothing relies on them: collapse costs and errors, and attribute values.
///
/// # Errors
/// [`ClodBytesError`] naming the first problem found.
pub fn decode(bytes: &[u8], character: &Character) -> Result<Clod> {
    let mut r = Reader::new(bytes);
    let magic = r.take(4, "magic")?;
    if magic != MAGIC {
        return Err(ClodBytesError::BadMagic { found: [magic[0], magic[1], magic[2], magic[3]] });
    }
    let version = r.u32("version")?;
    if version != FORMAT_VERSION {
        return Err(ClodBytesError::UnsupportedVersion { found: version, supported: FORMAT_VERSION });
    }
    let fingerprint = read_character(&mut r, character)?;
    let pose = read_pose(&mut r)?;
    let weights = match r.u32("weight rule")? {
        0 => WeightRule::Survivor,
        1 => WeightRule::Blend,
        tag => return Err(ClodBytesError::UnknownTag { field: "weight rule", tag }),
    };
    let level_triangles = read_level_requests(&mut r)?;
    let input = PoseInput::new(character, &pose).map_err(|e| match e {
        ClodError::UnknownClip { name, .. } => ClodBytesError::UnknownClip { name },
        _ => ClodBytesError::NonFinite { field: "pose time", index: 0 },
    })?;
    if fingerprint != character_fingerprint(character, &input) {
        return Err(ClodBytesError::OtherCharacter);
    }
    let mut pm = read_pm(&mut r, character, &input)?;
    if r.remaining() > 0 {
        return Err(ClodBytesError::TrailingBytes { count: r.remaining() });
    }
    pm.restore_from_slots().map_err(|e| inconsistent(e.field, e.index, e.reason))?;
    let clod = super::articulate(character, pm, &input, weights, &level_triangles, pose);
    if clod.levels.len() != level_triangles.len() {
        let reason = "two requests give the same level";
        return Err(inconsistent("level requests", clod.levels.len(), reason));
    }
    Ok(clod)
}

/// Vertex and triangle counts against the character, then the chain's fingerprint (compared in
/// [`decode`] once the simplifier's input is known). Runs first, so the arrays sized by the vertex
/// count below are bounded by the character, not by a number in the bytes.
fn read_character(r: &mut Reader, character: &Character) -> Result<u64> {
    let mesh = &character.mesh;
    let mismatch = |what, bytes: u32, character: usize| ClodBytesError::CharacterMismatch {
        what,
        bytes: bytes.into(),
        character: character as u64,
    };
    let vertices = r.u32("vertex count")?;
    if vertices as usize != mesh.vertex_count() {
        return Err(mismatch("vertices", vertices, mesh.vertex_count()));
    }
    let triangles = r.u32("triangle count")?;
    if triangles as usize != mesh.triangle_count() {
        return Err(mismatch("triangles", triangles, mesh.triangle_count()));
    }
    r.u64("fingerprint")
}

/// The fingerprint [`encode`] writes for a chain of `character`: its mesh, with the triangles the
/// simplifier saw (flat-shaded vertices welded).
fn character_fingerprint(character: &Character, input: &PoseInput) -> u64 {
    let mesh = &character.mesh;
    fingerprint(&MeshArrays {
        positions: &mesh.positions,
        normals: &mesh.normals,
        uvs: mesh.uvs.as_deref(),
        colors: mesh.colors.as_deref(),
        joints: &mesh.joints,
        weights: &mesh.weights,
        indices: &input.indices,
        morph: &mesh.morph,
    })
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

/// The levels' requested triangle counts: at least one, positive and decreasing, as
/// [`super::build`] accepts them.
fn read_level_requests(r: &mut Reader) -> Result<Vec<usize>> {
    let n = r.count("level requests", 8)?;
    let mut requests: Vec<usize> = Vec::with_capacity(n);
    for i in 0..n {
        // usize is 32 bits on wasm32; a larger request means "every triangle" all the same.
        let triangles = usize::try_from(r.u64("level requests")?).unwrap_or(usize::MAX);
        if triangles == 0 || requests.last().is_some_and(|&last| triangles >= last) {
            return Err(inconsistent("level requests", i, "requests are positive and decreasing"));
        }
        requests.push(triangles);
    }
    if requests.is_empty() {
        return Err(ClodBytesError::LengthMismatch { field: "level requests", found: 0, expected: 1 });
    }
    Ok(requests)
}

/// Reads section 4 and rebuilds the full [`ProgressiveMesh`] from it and the character, checking
/// every id before it is used as an index. Corner changes get their `from_slot` in [`replay`].
fn read_pm(r: &mut Reader, character: &Character, input: &PoseInput) -> Result<ProgressiveMesh> {
    let mesh = &character.mesh;
    let (n, triangles) = (mesh.vertex_count(), mesh.triangle_count());
    let stride = r.u32("attribute count")? as usize;
    if stride != input.layout.weights.len() {
        let (bytes, ours) = (stride as u64, input.layout.weights.len() as u64);
        return Err(ClodBytesError::CharacterMismatch { what: "attribute channels", bytes, character: ours });
    }
    let base_vertex_count = r.u32("base vertex count")?;
    if base_vertex_count as usize > n {
        let (value, bound) = (base_vertex_count.into(), n as u64 + 1);
        return Err(ClodBytesError::OutOfRange { field: "base_vertex_count", index: 0, value, bound });
    }
    let stop = match r.u32("stop reason")? {
        0 => StopReason::TargetReached,
        1 => StopReason::MaxErrorReached,
        2 => StopReason::NoValidCollapse,
        tag => return Err(ClodBytesError::UnknownTag { field: "stop reason", tag }),
    };

    // Base triangles: the simplifier's input (the character's, flat vertices welded), in the
    // order triangle_source gives.
    let triangle_source = r.u32s("triangle_source")?;
    expect_len("triangle_source", triangle_source.len(), triangles)?;
    expect_permutation("triangle_source", &triangle_source, "an input triangle appears twice")?;
    let indices: Vec<u32> = triangle_source
        .iter()
        .flat_map(|&s| input.indices[3 * s as usize..3 * s as usize + 3].iter().copied())
        .collect();

    let mut vertex_slot = r.u32s("vertex_slot")?;
    expect_len("vertex_slot", vertex_slot.len(), n)?;
    expect_permutation("vertex_slot", &vertex_slot, "two input vertices share a slot")?;
    let survivors = r.u32s("survivor_source")?;
    let total = n + survivors.len();
    let mut survivor_source = vec![NONE; n];
    for (i, &s) in survivors.iter().enumerate() {
        if s as usize >= n + i {
            // clod_materials and the slots below walk survivors down to an input vertex.
            let reason = "created vertices inherit from a smaller id";
            return Err(inconsistent("survivor_source", n + i, reason));
        }
        survivor_source.push(s);
        vertex_slot.push(vertex_slot[s as usize]);
    }
    let parent = r.u32s("parent")?;
    expect_len("parent", parent.len(), total)?;
    let created = r.vec3s("positions")?;
    expect_len("positions", created.len(), survivors.len())?;
    if let Some(index) = created.iter().position(|p| !p.is_finite()) {
        return Err(ClodBytesError::NonFinite { field: "positions", index: n + index });
    }
    let created_attributes = r.f32s("attributes")?;
    expect_len("attributes", created_attributes.len(), survivors.len().saturating_mul(stride))?;

    let count = r.count("collapses", COLLAPSE_BYTES)?;
    let mut collapses = Vec::with_capacity(count);
    let mut born_at = vec![0u32; n];
    let (mut next_change, mut next_vertex) = (0u32, n);
    for s in 0..count {
        let f = |r: &mut Reader| r.f32("collapses");
        let (cost, distance, error, max_distance) = (f(r)?, f(r)?, f(r)?, f(r)?);
        let u = |r: &mut Reader| r.u32("collapses");
        let (triangles_after, vertices_after, new_vertex_count, corner_changes_end) =
            (u(r)?, u(r)?, u(r)?, u(r)?);
        if new_vertex_count as usize > total - next_vertex {
            return Err(inconsistent("collapses", s, "more created vertices than survivors"));
        }
        if corner_changes_end < next_change {
            return Err(inconsistent("collapses", s, "corner changes must continue the previous step's"));
        }
        born_at.resize(next_vertex + new_vertex_count as usize, s as u32 + 1);
        collapses.push(CollapseRecord {
            cost,
            distance,
            error,
            max_distance,
            triangles_after,
            vertices_after,
            first_new_vertex: next_vertex as u32,
            new_vertex_count,
            corner_changes_start: next_change,
            corner_changes_end,
        });
        (next_vertex, next_change) = (next_vertex + new_vertex_count as usize, corner_changes_end);
    }
    if next_vertex != total {
        return Err(inconsistent("collapses", count, "some created vertices have no step"));
    }
    let count = r.count("corner_changes", CORNER_CHANGE_BYTES)?;
    if next_change as usize != count {
        return Err(inconsistent("collapses", collapses.len(), "some corner changes have no step"));
    }
    let mut corner_changes = Vec::with_capacity(count);
    for i in 0..count {
        let (corner, to_slot) = (r.u32("corner_changes")?, r.u32("corner_changes")?);
        if corner as usize >= indices.len() || to_slot as usize >= n {
            let (field, value, bound) = match corner as usize >= indices.len() {
                true => ("corner_changes (corner)", corner, indices.len()),
                false => ("corner_changes (slot)", to_slot, n),
            };
            return Err(ClodBytesError::OutOfRange {
                field,
                index: i,
                value: value.into(),
                bound: bound as u64,
            });
        }
        corner_changes.push(CornerChange { corner, from_slot: NONE, to_slot });
    }

    let mut positions = input.positions.clone();
    positions.extend(created);
    let mut attributes = input.attributes.clone();
    attributes.extend(created_attributes);
    Ok(ProgressiveMesh {
        positions,
        attributes,
        attribute_count: stride,
        input_vertex_count: n,
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

fn expect_len(field: &'static str, found: usize, expected: usize) -> Result<()> {
    if found != expected {
        return Err(ClodBytesError::LengthMismatch { field, found: found as u64, expected: expected as u64 });
    }
    Ok(())
}

/// `values` is a permutation of `0..values.len()`.
fn expect_permutation(field: &'static str, values: &[u32], repeated: &'static str) -> Result<()> {
    let bound = values.len();
    let mut seen = vec![false; bound];
    for (index, &v) in values.iter().enumerate() {
        if v as usize >= bound {
            return Err(ClodBytesError::OutOfRange { field, index, value: v.into(), bound: bound as u64 });
        }
        if std::mem::replace(&mut seen[v as usize], true) {
            return Err(inconsistent(field, index, repeated));
        }
    }
    Ok(())
}

fn inconsistent(field: &'static str, index: usize, reason: &'static str) -> ClodBytesError {
    ClodBytesError::Inconsistent { field, index, reason }
}
