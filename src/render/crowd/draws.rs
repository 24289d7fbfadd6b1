//! A crowd frame as the GPU draws it: one record per instance and draw ([`InstanceRaw`], the
//! mirror of `crowd.wgsl`'s instance attributes), grouped so that each view needs one instanced
//! draw per (level, method step) instead of one per instance.
//!
//! Every instance's draws come from [`plan_view`], the function that plans the single
//! character's views, so a crowd instance is drawn exactly as the single character would be with
//! the same transition. Records are ordered opaque first (a blended layer must find every opaque
//! instance's depth), then by the draw's step in its plan (the more opaque layer of a naive
//! cross-fade first), then by level; within a group, in instance order, so a seeded crowd gives
//! the same bytes every time.

use bytemuck::{Pod, Zeroable};

use super::Crowd;
use crate::render::overlay::{draw_tint, Overlay};
use crate::render::plan::{plan_view, DrawCall, Method, PassKind};

/// One instance in one draw (`CrowdInstance` in `crowd.wgsl`, vertex locations 14 and 15).
///
/// Two attributes, not four: the level's vertices take locations 0..=13 (both ends of a geomorph
/// and their morph rows), and WebGL2 guarantees 16. So everything but the placement is packed into
/// one `vec4<u32>` (see [`InstanceRaw::new`]); `crowd.wgsl`'s `crowd_draw` unpacks it exactly as
/// [`InstanceRaw::draw`] does.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct InstanceRaw {
    /// xyz: translation after the turn (world space); w: heading, radians about +Y.
    pub place: [f32; 4],
    /// x: palette row (bits 0..12), dither mode (bits 12..16), opacity as unorm16 (bits 16..32);
    /// y: geomorph `t` (f32 bits); z: dither threshold (f32 bits); w: level tint as unorm8 RGBA
    /// (red in the low byte).
    pub packed: [u32; 4],
}

/// What one record asks of its draw, unpacked ([`InstanceRaw::new`], [`InstanceRaw::draw`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InstanceDraw {
    /// Palette row of the instance's pose (below 4096; [`super::palette::MAX_ROWS`] is 2048).
    pub row: u32,
    /// 0 none, 1 keep below the threshold, 2 the rest.
    pub dither_mode: u32,
    /// Geomorph `t` towards the ancestors one level coarser, kept to the bit: 0 and 1 are exact ends.
    pub t: f32,
    /// 0..=1, to 1/65535.
    pub opacity: f32,
    /// Kept to the bit, like the single view's, so both dither the same pixels.
    pub dither_threshold: f32,
    /// Level overlay: linear RGB and the share of the surface colour it replaces (0: none), to 1/255.
    pub tint: [f32; 4],
}

const ROW_BITS: u32 = 12;
const _: () = assert!(super::palette::MAX_ROWS <= 1 << ROW_BITS);

/// `x` in 0..=1 as an integer of 0..=`max` (NaN gives 0: Rust's float-to-int cast saturates).
fn unorm(x: f32, max: f32) -> u32 {
    (x.clamp(0.0, 1.0) * max).round() as u32
}

impl InstanceRaw {
    /// The record of `draw` for an instance placed at `place`.
    pub fn new(place: [f32; 4], draw: &InstanceDraw) -> Self {
        let ids = draw.row.min((1 << ROW_BITS) - 1) | (draw.dither_mode.min(15) << ROW_BITS);
        let tint = draw.tint.iter().enumerate().fold(0, |acc, (c, &x)| acc | (unorm(x, 255.0) << (8 * c)));
        Self {
            place,
            packed: [
                ids | (unorm(draw.opacity, 65535.0) << 16),
                draw.t.to_bits(),
                draw.dither_threshold.to_bits(),
                tint,
            ],
        }
    }

    /// The draw this record asks for, as the shader reads it.
    pub fn draw(&self) -> InstanceDraw {
        let [ids, t, threshold, tint] = self.packed;
        InstanceDraw {
            row: ids & ((1 << ROW_BITS) - 1),
            dither_mode: (ids >> ROW_BITS) & 15,
            t: f32::from_bits(t),
            opacity: (ids >> 16) as f32 / 65535.0,
            dither_threshold: f32::from_bits(threshold),
            tint: std::array::from_fn(|c| ((tint >> (8 * c)) & 255) as f32 / 255.0),
        }
    }
}

/// Byte offset of each [`InstanceRaw`] field, in order: what the vertex layout reads and
/// `tests/shaders.rs` compares with naga's layout of `CrowdInstance`.
pub const INSTANCE_OFFSETS: [u64; 2] = [0, 16];

/// One instanced draw of a view: `count` records from `first` of the frame's instance array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InstancedDraw {
    pub level: usize,
    pub pass: PassKind,
    /// Geomorph towards the ancestors in this level (always `level + 1`: crowd transitions move
    /// one level at a time).
    pub morph_coarse: Option<usize>,
    pub first: u32,
    pub count: u32,
}

/// What the crowd shows this frame, for `state().crowd`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CrowdStats {
    pub instances: usize,
    /// Instances inside the frustum (drawn in every view).
    pub drawn: usize,
    /// Drawn instances by the level they show or are going to (sums to `drawn`).
    pub per_level: Vec<usize>,
    /// Drawn instances in a transition.
    pub transitions: usize,
    /// Triangles each view draws (a cross-fade draws both levels).
    pub triangles: Vec<usize>,
    /// Triangles one view would draw with every drawn instance at full detail.
    pub triangles_full: usize,
}

/// A crowd frame: records, each view's draws, and the full-detail reference's (the live meter).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CrowdFrame {
    pub instances: Vec<InstanceRaw>,
    pub views: Vec<Vec<InstancedDraw>>,
    pub reference: Vec<InstancedDraw>,
    pub stats: CrowdStats,
    /// The ground's two triangles ([`Crowd::ground`]).
    pub ground: [[f32; 4]; 6],
}

/// Group order of a draw (see the module docs).
type GroupKey = (bool, usize, usize, Option<usize>, u8, u32);

fn group_key(step: usize, d: &DrawCall) -> GroupKey {
    let pass = match d.pass {
        PassKind::Opaque => 0,
        PassKind::BlendNaive => 1,
        PassKind::BlendOver => 2,
    };
    (d.pass != PassKind::Opaque, step, d.level, d.morph.map(|m| m.coarse), pass, d.dither_mode)
}

/// Builds the frame of the `visible` instances (indices into `crowd.instances`) with their
/// palette `rows`, one view per method.
pub(super) fn build(
    crowd: &Crowd,
    visible: &[usize],
    rows: &[u32],
    methods: &[Method],
    tint_levels: bool,
    level_triangles: &[usize],
) -> CrowdFrame {
    let overlay = if tint_levels { Overlay::Levels } else { Overlay::None };
    let triangles_of = |level: usize| level_triangles.get(level).copied().unwrap_or(0);
    let mut frame = CrowdFrame::default();
    let mut stats = CrowdStats {
        instances: crowd.instances.len(),
        drawn: visible.len(),
        per_level: vec![0; level_triangles.len().max(1)],
        triangles_full: visible.len() * triangles_of(0),
        ..CrowdStats::default()
    };
    for &k in visible {
        let t = crowd.instances[k].transition;
        let slot = t.to.min(stats.per_level.len() - 1);
        stats.per_level[slot] += 1;
        stats.transitions += usize::from(t.is_running());
    }
    let mut records: Vec<(GroupKey, InstanceRaw)> = Vec::new();
    for &method in methods {
        records.clear();
        let mut triangles = 0;
        for (&k, &row) in visible.iter().zip(rows) {
            let instance = &crowd.instances[k];
            let place = crowd.placement(instance).to_array();
            for (step, d) in plan_view(method, &instance.transition).draws.iter().enumerate() {
                triangles += triangles_of(d.level);
                let raw = InstanceRaw::new(
                    place,
                    &InstanceDraw {
                        row,
                        dither_mode: d.dither_mode,
                        t: d.morph.map_or(0.0, |m| m.t),
                        opacity: d.opacity,
                        dither_threshold: d.dither_threshold,
                        tint: draw_tint(overlay, d.level, d.morph),
                    },
                );
                records.push((group_key(step, d), raw));
            }
        }
        // Stable: instance order inside a group.
        records.sort_by_key(|(key, _)| *key);
        let draws = groups(&records, frame.instances.len() as u32);
        frame.instances.extend(records.iter().map(|(_, raw)| *raw));
        frame.views.push(draws);
        stats.triangles.push(triangles);
    }
    // The reference: every drawn instance at full detail, as a popping view at rest on level 0.
    let first = frame.instances.len() as u32;
    frame.instances.extend(visible.iter().zip(rows).map(|(&k, &row)| {
        let draw =
            InstanceDraw { row, opacity: 1.0, tint: draw_tint(overlay, 0, None), ..InstanceDraw::default() };
        InstanceRaw::new(crowd.placement(&crowd.instances[k]).to_array(), &draw)
    }));
    if !visible.is_empty() {
        frame.reference = vec![InstancedDraw {
            level: 0,
            pass: PassKind::Opaque,
            morph_coarse: None,
            first,
            count: visible.len() as u32,
        }];
    }
    frame.stats = stats;
    frame.ground = crowd.ground();
    frame
}

/// The runs of equal keys in sorted `records` as draws, their records starting at `base`.
fn groups(records: &[(GroupKey, InstanceRaw)], base: u32) -> Vec<InstancedDraw> {
    let mut draws: Vec<InstancedDraw> = Vec::new();
    for (i, (key, _)) in records.iter().enumerate() {
        let same = i > 0 && records[i - 1].0 == *key;
        match draws.last_mut() {
            Some(last) if same => last.count += 1,
            _ => {
                let (_, _, level, morph_coarse, pass, _) = *key;
                let pass = match pass {
                    0 => PassKind::Opaque,
                    1 => PassKind::BlendNaive,
                    _ => PassKind::BlendOver,
                };
                draws.push(InstancedDraw { level, pass, morph_coarse, first: base + i as u32, count: 1 });
            }
        }
    }
    draws
}
