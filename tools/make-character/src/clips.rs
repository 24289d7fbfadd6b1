//! The character's animation clips: "Walk" (a looping in-place cycle, CUBICSPLINE), "Wave" (right
//! arm raises and waves, LINEAR) and "Crouch" (knees and hips bend and return, LINEAR).
//!
//! Each clip is an analytic pose function of time, sampled at evenly spaced keys starting at 0.
//! A pose gives, per animated joint, a rotation about the joint expressed in model-space axes at
//! rest (so "about +X" means the same for every bone); it becomes the node's local rotation
//! `rest_local * joint_from_model * q * model_from_joint`. Cubic tangents are central differences
//! of the same function, so the spline reproduces the motion closely. Angles are in degrees in
//! the pose functions, times in seconds, translations in metres.

use glam::{Quat, Vec3, Vec4};

use crate::body::{joint, left_arm_direction, Joint};
use crate::math::{axis_angle, deg, sin_cos};

/// glTF sampler interpolation of a clip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Linear,
    CubicSpline,
}

/// One animated property of one node, already in the node's local terms.
#[derive(Clone, Debug)]
pub enum Track {
    /// Local rotations as `[x, y, z, w]`; for cubic clips, `(in, value, out)` triplets per key.
    Rotation { node: usize, values: Vec<Vec4> },
    /// Local translations; for cubic clips, `(in, value, out)` triplets per key.
    Translation { node: usize, values: Vec<Vec3> },
}

/// A sampled clip, ready to write.
#[derive(Clone, Debug)]
pub struct Clip {
    pub name: &'static str,
    pub interpolation: Interpolation,
    pub times: Vec<f32>,
    pub tracks: Vec<Track>,
}

/// What a pose function returns: model-axis rotations for some joints and an offset of the hips.
struct PoseDelta {
    rotations: Vec<(usize, Quat)>,
    hips_offset: Vec3,
}

/// Step for the central differences that give cubic tangents, in seconds: small against the
/// motion's time scale (tenths of a second), large against f32 noise in the quaternions.
const TANGENT_STEP: f32 = 1e-3;

/// Rotation about a model-space axis by `degrees`.
fn rot(axis: Vec3, degrees: f32) -> Quat {
    axis_angle(axis.normalize(), deg(degrees))
}

/// `0 → 1` with zero slope at both ends (for easing in and out).
fn smoothstep(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Up over `[t0, t1]`, hold, down over `[t2, t3]`.
fn envelope(t: f32, [t0, t1, t2, t3]: [f32; 4]) -> f32 {
    smoothstep((t - t0) / (t1 - t0)) * (1.0 - smoothstep((t - t2) / (t3 - t2)))
}

/// The elbow's hinge axis for an arm with rest direction `d`: positive angles bring the forearm
/// forward (towards +Z), because `(d × Z) × d = Z` for a horizontal-plane-free `d ⟂ Z`.
fn elbow_axis(d: Vec3) -> Vec3 {
    d.cross(Vec3::Z).normalize()
}

const WALK_PERIOD: f32 = 1.2;

fn walk(t: f32) -> PoseDelta {
    use joint::*;
    let phase = std::f32::consts::TAU * t / WALK_PERIOD;
    let (s, c) = sin_cos(phase);
    let (_, c2) = sin_cos(2.0 * phase);
    // Knee flexion peaks mid-swing (phase 0 for the left leg, π for the right).
    let knee = |cos: f32| 5.0 + 55.0 * ((1.0 + cos) / 2.0).powi(3);
    let (knee_l, knee_r) = (knee(c), knee(-c));
    let (hip_l, hip_r) = (-22.0 * s, 22.0 * s);
    let dl = left_arm_direction();
    let dr = Vec3::new(-dl.x, dl.y, dl.z);
    PoseDelta {
        rotations: vec![
            (HIPS, rot(Vec3::Y, -6.0 * s)),
            (CHEST, rot(Vec3::Y, 10.0 * s)),
            (HEAD, rot(Vec3::Y, -4.0 * s)),
            (L_UPPER_LEG, rot(Vec3::X, hip_l)),
            (R_UPPER_LEG, rot(Vec3::X, hip_r)),
            (L_LOWER_LEG, rot(Vec3::X, knee_l)),
            (R_LOWER_LEG, rot(Vec3::X, knee_r)),
            // The ankle lifts the toes while the knee is bent, to clear the floor.
            (L_FOOT, rot(Vec3::X, -0.6 * knee_l - 0.3 * hip_l)),
            (R_FOOT, rot(Vec3::X, -0.6 * knee_r - 0.3 * hip_r)),
            // Arms swing against the legs.
            (L_UPPER_ARM, rot(Vec3::X, 16.0 * s)),
            (R_UPPER_ARM, rot(Vec3::X, -16.0 * s)),
            (L_FOREARM, rot(elbow_axis(dl), 18.0 + 12.0 * (1.0 - s))),
            (R_FOREARM, rot(elbow_axis(dr), 18.0 + 12.0 * (1.0 + s))),
        ],
        // The hips drop when the legs are spread (twice per cycle).
        hips_offset: Vec3::new(0.0, -0.02 * (1.0 - c2) / 2.0, 0.0),
    }
}

const WAVE_DURATION: f32 = 3.0;

fn wave(t: f32) -> PoseDelta {
    use joint::*;
    let raise = envelope(t, [0.0, 0.6, 2.4, 3.0]);
    // Three waves between 0.6 s and 2.4 s.
    let (w, _) = sin_cos(std::f32::consts::TAU * (t - 0.6) / 0.6);
    let w = w * envelope(t, [0.4, 0.7, 2.3, 2.6]);
    let dr = {
        let d = left_arm_direction();
        Vec3::new(-d.x, d.y, d.z)
    };
    // Twist the upper arm a quarter turn about itself so the elbow hinges in the frontal plane,
    // then lift it sideways to just above horizontal.
    let upper = rot(Vec3::Z, -70.0 * raise) * rot(dr, 90.0 * raise);
    PoseDelta {
        rotations: vec![
            (SPINE, rot(Vec3::Z, 3.0 * raise)),
            (HEAD, rot(Vec3::Z, -6.0 * raise) * rot(Vec3::Y, -12.0 * raise)),
            (R_CLAVICLE, rot(Vec3::Z, -8.0 * raise)),
            (R_UPPER_ARM, upper),
            (R_FOREARM, rot(elbow_axis(dr), 95.0 * raise + 28.0 * w)),
            (R_HAND, rot(elbow_axis(dr), 12.0 * w)),
        ],
        hips_offset: Vec3::ZERO,
    }
}

const CROUCH_DURATION: f32 = 2.4;

fn crouch(t: f32, leg_length: f32) -> PoseDelta {
    use joint::*;
    let s = envelope(t, [0.0, 0.9, 1.5, 2.4]);
    let alpha = 62.0 * s;
    // Thigh forward by α, shin back by α (knee 2α), foot back to level: with thigh and shin of
    // equal length the hips stay above the ankles and drop by L(1 - cos α), feet stay planted.
    let (_, cos_alpha) = sin_cos(deg(alpha));
    let dl = left_arm_direction();
    let dr = Vec3::new(-dl.x, dl.y, dl.z);
    PoseDelta {
        rotations: vec![
            (SPINE, rot(Vec3::X, 22.0 * s)),
            (CHEST, rot(Vec3::X, 10.0 * s)),
            (NECK, rot(Vec3::X, -14.0 * s)),
            (HEAD, rot(Vec3::X, -10.0 * s)),
            (L_UPPER_LEG, rot(Vec3::X, -alpha)),
            (R_UPPER_LEG, rot(Vec3::X, -alpha)),
            (L_LOWER_LEG, rot(Vec3::X, 2.0 * alpha)),
            (R_LOWER_LEG, rot(Vec3::X, 2.0 * alpha)),
            (L_FOOT, rot(Vec3::X, -alpha)),
            (R_FOOT, rot(Vec3::X, -alpha)),
            // Arms reach forward for balance.
            (L_UPPER_ARM, rot(Vec3::X, -45.0 * s)),
            (R_UPPER_ARM, rot(Vec3::X, -45.0 * s)),
            (L_FOREARM, rot(elbow_axis(dl), 25.0 * s)),
            (R_FOREARM, rot(elbow_axis(dr), 25.0 * s)),
        ],
        hips_offset: Vec3::new(0.0, -leg_length * (1.0 - cos_alpha), 0.0),
    }
}

/// The rest local rotation and translation of every joint (parent-relative), as written to the
/// glTF nodes.
pub fn rest_locals(joints: &[Joint]) -> Vec<(Vec3, Quat)> {
    joints
        .iter()
        .map(|j| match j.parent {
            Some(p) => {
                let parent = &joints[p];
                let parent_inv = parent.rotation.inverse();
                (parent_inv * (j.head - parent.head), (parent_inv * j.rotation).normalize())
            }
            None => (j.head, j.rotation),
        })
        .collect()
}

/// Samples a pose function into local tracks at `keys + 1` evenly spaced times over `duration`.
fn sample_clip(
    name: &'static str,
    joints: &[Joint],
    duration: f32,
    keys: usize,
    interpolation: Interpolation,
    pose: &dyn Fn(f32) -> PoseDelta,
) -> Clip {
    let rest = rest_locals(joints);
    let times: Vec<f32> = (0..=keys).map(|k| duration * k as f32 / keys as f32).collect();
    let animated: Vec<usize> = pose(0.0).rotations.iter().map(|r| r.0).collect();
    let local_rotation = |t: f32, slot: usize| {
        let (node, q) = pose(t).rotations[slot];
        let j = &joints[node];
        // rest_local * (joint_from_model * q * model_from_joint), see the module docs.
        let delta = j.rotation.inverse() * q * j.rotation;
        Vec4::from((rest[node].1 * delta).normalize())
    };
    let hips = |t: f32| Vec4::from((rest[joint::HIPS].0 + pose(t).hips_offset, 0.0));

    let mut tracks = Vec::new();
    for (slot, &node) in animated.iter().enumerate() {
        let values = keyframes(&times, interpolation, |t| local_rotation(t, slot), true);
        tracks.push(Track::Rotation { node, values });
    }
    let moves_hips = times.iter().any(|&t| pose(t).hips_offset != Vec3::ZERO);
    if moves_hips {
        let values =
            keyframes(&times, interpolation, hips, false).into_iter().map(|v| v.truncate()).collect();
        tracks.push(Track::Translation { node: joint::HIPS, values });
    }
    Clip { name, interpolation, times, tracks }
}

/// Key values of `f` at `times` (with cubic tangents when asked). For quaternions, each key is
/// flipped into the previous key's hemisphere so component-wise interpolation takes the short way.
fn keyframes(
    times: &[f32],
    interpolation: Interpolation,
    f: impl Fn(f32) -> Vec4,
    is_quat: bool,
) -> Vec<Vec4> {
    let mut out = Vec::new();
    let mut previous: Option<Vec4> = None;
    for &t in times {
        let mut v = f(t);
        let sign = if is_quat && previous.is_some_and(|p| p.dot(v) < 0.0) { -1.0 } else { 1.0 };
        v *= sign;
        previous = Some(v);
        match interpolation {
            Interpolation::Linear => out.push(v),
            Interpolation::CubicSpline => {
                let align = |w: Vec4| if is_quat && w.dot(v) < 0.0 { -w } else { w };
                let ahead = align(f(t + TANGENT_STEP));
                let behind = align(f(t - TANGENT_STEP));
                let tangent = (ahead - behind) / (2.0 * TANGENT_STEP);
                out.extend([tangent, v, tangent]);
            }
        }
    }
    out
}

/// All clips of the character.
pub fn clips(joints: &[Joint]) -> Vec<Clip> {
    use joint::*;
    let leg_length = joints[L_UPPER_LEG].head.distance(joints[L_LOWER_LEG].head)
        + joints[L_LOWER_LEG].head.distance(joints[L_FOOT].head);
    vec![
        // 12 keys per cycle (every 0.1 s): the spline's tangents carry the motion between them.
        sample_clip("Walk", joints, WALK_PERIOD, 12, Interpolation::CubicSpline, &walk),
        // Linear keys every 0.05 s: the waving forearm turns ~10° between keys.
        sample_clip("Wave", joints, WAVE_DURATION, 60, Interpolation::Linear, &wave),
        sample_clip("Crouch", joints, CROUCH_DURATION, 24, Interpolation::Linear, &|t| crouch(t, leg_length)),
    ]
}
