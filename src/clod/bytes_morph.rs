//! Section 6 of the chain bytes ([`super`]): the morph deltas of every vertex id
//! ([`crate::clod::ArticulatedPm::morph`]). Kept apart from the other sections so that the
//! format's other fields can change without touching it.
//!
//! Layout: a `u32` flag (0: no morph deltas, nothing follows; 1: present), then the arrays
//! `offsets` (u32, one per vertex id plus one), `targets` (u32, each below the character's
//! target count), `positions` and `normals` (vec3), as in [`crate::morph::MorphDeltas`].
//!
//! Checked on decoding: lengths (offsets cover every vertex id, start at 0, never decrease and
//! end at the entry count), targets in range and increasing within a row, deltas finite, and
//! the input vertices' rows equal to the character's (the chain was built for it).

use glam::Vec3;

use super::{expect_below, expect_finite, expect_len, inconsistent, ClodBytesError, Reader, Result, Writer};
use crate::character::Character;
use crate::morph::MorphDeltas;

pub(super) fn write(w: &mut Writer, morph: &MorphDeltas) {
    w.u32(u32::from(!morph.is_empty()));
    if morph.is_empty() {
        return;
    }
    w.u32s(&morph.offsets);
    let targets: Vec<u32> = morph.targets.iter().map(|&t| u32::from(t)).collect();
    w.u32s(&targets);
    w.vectors(morph.positions.iter().map(|p| p.to_array()), morph.positions.len());
    w.vectors(morph.normals.iter().map(|n| n.to_array()), morph.normals.len());
}

/// Reads the section; [`check`] validates it once the vertex count is known.
pub(super) fn read(r: &mut Reader) -> Result<MorphDeltas> {
    if !r.flag("morph flag")? {
        return Ok(MorphDeltas::default());
    }
    let offsets = r.u32s("morph offsets")?;
    let targets = r.u32s("morph targets")?;
    let positions = r.vectors::<3>("morph positions")?;
    let normals = r.vectors::<3>("morph normals")?;
    expect_finite("morph positions", positions.iter().copied())?;
    expect_finite("morph normals", normals.iter().copied())?;
    // Targets are u16 in memory; the character check below bounds them further.
    expect_below("morph targets", &targets, usize::from(u16::MAX) + 1)?;
    Ok(MorphDeltas {
        offsets,
        targets: targets.into_iter().map(|t| t as u16).collect(),
        positions: positions.into_iter().map(Vec3::from_array).collect(),
        normals: normals.into_iter().map(Vec3::from_array).collect(),
    })
}

/// The section against the chain's vertex ids and the character.
pub(super) fn check(morph: &MorphDeltas, vertex_total: usize, character: &Character) -> Result<()> {
    let mesh = &character.mesh.morph;
    if morph.is_empty() != mesh.is_empty() {
        return Err(ClodBytesError::CharacterMismatch {
            what: "vertices with morph deltas (0: none)",
            bytes: morph.entry_count() as u64,
            character: mesh.entry_count() as u64,
        });
    }
    if morph.is_empty() {
        return Ok(());
    }
    expect_len("morph offsets", morph.offsets.len(), vertex_total + 1)?;
    let entries = morph.targets.len();
    expect_len("morph positions", morph.positions.len(), entries)?;
    expect_len("morph normals", morph.normals.len(), entries)?;
    if morph.offsets[0] != 0 {
        return Err(inconsistent("morph offsets", 0, "the first row does not start at 0"));
    }
    if let Some(v) = morph.offsets.windows(2).position(|w| w[1] < w[0]) {
        return Err(inconsistent("morph offsets", v + 1, "rows go backwards"));
    }
    expect_len("morph targets", entries, morph.offsets[vertex_total] as usize)?;
    let targets: Vec<u32> = morph.targets.iter().map(|&t| u32::from(t)).collect();
    expect_below("morph targets", &targets, character.morph_targets.len())?;
    for v in 0..vertex_total {
        let row = &morph.targets[morph.offsets[v] as usize..morph.offsets[v + 1] as usize];
        if let Some(k) = row.windows(2).position(|w| w[1] <= w[0]) {
            return Err(inconsistent("morph targets", morph.offsets[v] as usize + k + 1, "not increasing"));
        }
    }
    let n = character.mesh.vertex_count();
    for v in 0..n {
        if !morph.of(v).eq(mesh.of(v)) {
            return Err(ClodBytesError::CharacterDataMismatch { what: "morph deltas of vertex", index: v });
        }
    }
    Ok(())
}
