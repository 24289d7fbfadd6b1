//! Keyframed animation clips and their sampling, after glTF 2.0 §3.11 (animations) and Appendix C
//! (interpolation).
//!
//! A [`Curve`] keeps key times and values in separate arrays and is validated when built, so
//! sampling cannot fail: times are finite and non-decreasing, values finite, rotations unit length.
//! Times are in seconds. Rotations interpolate along the shortest path (slerp for `Linear`,
//! component-wise Hermite then normalization for `CubicSpline`, as the glTF spec prescribes).
//! A [`Clip`] writes its channels over a [`Pose`] that starts at rest, so nodes without a channel
//! keep their rest transform; its morph weight channels (scalar curves, linear interpolation
//! for `Linear` as glTF prescribes) write over the character's default weights the same way.

use glam::{Quat, Vec3, Vec4};
use thiserror::Error;

use crate::skeleton::Pose;

/// How values between two keys are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The earlier key's value holds until the next key.
    Step,
    /// Linear for vectors, spherical-linear for rotations.
    Linear,
    /// Cubic Hermite with per-key in and out tangents.
    CubicSpline,
}

/// Why a curve could not be built.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CurveError {
    #[error("animation curve has no keys")]
    Empty,
    #[error("animation curve key time {0} is not finite")]
    NonFiniteTime(f32),
    #[error("animation curve key times go backwards ({0} after {1})")]
    TimesDecrease(f32, f32),
    #[error("animation curve has {times} key times but {values} values (expected {expected})")]
    CountMismatch { times: usize, values: usize, expected: usize },
    #[error("animation curve has a non-finite value")]
    NonFiniteValue,
    #[error("animation curve has a zero-length rotation")]
    ZeroRotation,
}

/// A value type that curves can interpolate.
pub trait Keyframe: Copy {
    /// Straight interpolation at `s` in `[0, 1]` (slerp for rotations).
    fn interpolate(a: Self, b: Self, s: f32) -> Self;
    /// Cubic Hermite between `p0` and `p1`, with tangents already scaled by the key interval.
    fn hermite(p0: Self, m0: Self, p1: Self, m1: Self, s: f32) -> Self;
    /// Multiplication by a scalar (tangents are per second and scale by the key interval).
    fn scaled(self, k: f32) -> Self;
    /// Whether every component is finite.
    fn is_finite(self) -> bool;
}

fn hermite_basis(s: f32) -> [f32; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2]
}

impl Keyframe for Vec3 {
    fn interpolate(a: Self, b: Self, s: f32) -> Self {
        a.lerp(b, s)
    }
    fn hermite(p0: Self, m0: Self, p1: Self, m1: Self, s: f32) -> Self {
        let [h00, h10, h01, h11] = hermite_basis(s);
        h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1
    }
    fn scaled(self, k: f32) -> Self {
        self * k
    }
    fn is_finite(self) -> bool {
        Vec3::is_finite(self)
    }
}

impl Keyframe for Quat {
    fn interpolate(a: Self, b: Self, s: f32) -> Self {
        // Shortest path: q and -q are the same rotation, so flip b into a's hemisphere.
        let b = if a.dot(b) < 0.0 { -b } else { b };
        a.slerp(b, s).normalize()
    }
    fn hermite(p0: Self, m0: Self, p1: Self, m1: Self, s: f32) -> Self {
        let [h00, h10, h01, h11] = hermite_basis(s);
        let v = h00 * Vec4::from(p0) + h10 * Vec4::from(m0) + h01 * Vec4::from(p1) + h11 * Vec4::from(m1);
        // A spline through unit quaternions leaves the sphere between keys; glTF says normalize.
        v.try_normalize().map(Quat::from_vec4).unwrap_or(p0)
    }
    fn scaled(self, k: f32) -> Self {
        Quat::from_vec4(Vec4::from(self) * k)
    }
    fn is_finite(self) -> bool {
        Quat::is_finite(self)
    }
}

impl Keyframe for f32 {
    fn interpolate(a: Self, b: Self, s: f32) -> Self {
        a + (b - a) * s
    }
    fn hermite(p0: Self, m0: Self, p1: Self, m1: Self, s: f32) -> Self {
        let [h00, h10, h01, h11] = hermite_basis(s);
        h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1
    }
    fn scaled(self, k: f32) -> Self {
        self * k
    }
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
}

/// Key times and values of one animated property; see the module docs for its invariants.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve<T> {
    times: Vec<f32>,
    /// One value per key, or for `CubicSpline` three: in-tangent, value, out-tangent.
    values: Vec<T>,
    interpolation: Interpolation,
}

impl<T: Keyframe> Curve<T> {
    /// Builds a curve, checking the invariants that make [`Self::sample`] infallible.
    ///
    /// # Errors
    /// No keys, non-finite or decreasing times, a value count that does not match the key count
    /// (three values per key for `CubicSpline`), or non-finite values.
    pub fn new(times: Vec<f32>, values: Vec<T>, interpolation: Interpolation) -> Result<Self, CurveError> {
        if times.is_empty() {
            return Err(CurveError::Empty);
        }
        if let Some(&t) = times.iter().find(|t| !t.is_finite()) {
            return Err(CurveError::NonFiniteTime(t));
        }
        if let Some(w) = times.windows(2).find(|w| w[1] < w[0]) {
            return Err(CurveError::TimesDecrease(w[1], w[0]));
        }
        let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        if values.len() != times.len() * per_key {
            return Err(CurveError::CountMismatch {
                times: times.len(),
                values: values.len(),
                expected: times.len() * per_key,
            });
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(CurveError::NonFiniteValue);
        }
        Ok(Self { times, values, interpolation })
    }

    /// Key times in seconds.
    pub fn times(&self) -> &[f32] {
        &self.times
    }

    /// The interpolation mode.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// Time of the last key.
    pub fn end_time(&self) -> f32 {
        *self.times.last().expect("curves are never empty")
    }

    /// The value at key `k` (the middle one of a cubic triplet).
    fn key_value(&self, k: usize) -> T {
        match self.interpolation {
            Interpolation::CubicSpline => self.values[3 * k + 1],
            _ => self.values[k],
        }
    }

    /// The value at `time`, held constant before the first key and after the last.
    pub fn sample(&self, time: f32) -> T {
        let last = self.times.len() - 1;
        // Index of the first key strictly after `time`.
        let next = self.times.partition_point(|&k| k <= time);
        if next == 0 {
            return self.key_value(0);
        }
        if next > last {
            return self.key_value(last);
        }
        let prev = next - 1;
        let (t0, t1) = (self.times[prev], self.times[next]);
        let dt = t1 - t0;
        // Coincident keys (a jump): the later key applies from its time on.
        let s = if dt > 0.0 { ((time - t0) / dt).clamp(0.0, 1.0) } else { 1.0 };
        match self.interpolation {
            Interpolation::Step => self.values[prev],
            Interpolation::Linear => T::interpolate(self.values[prev], self.values[next], s),
            Interpolation::CubicSpline => {
                let p0 = self.values[3 * prev + 1];
                let m0 = self.values[3 * prev + 2].scaled(dt);
                let p1 = self.values[3 * next + 1];
                let m1 = self.values[3 * next].scaled(dt);
                T::hermite(p0, m0, p1, m1, s)
            }
        }
    }
}

/// Which node property a channel animates, with its curve.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelCurve {
    Translation(Curve<Vec3>),
    Rotation(Curve<Quat>),
    Scale(Curve<Vec3>),
    /// One morph weight (glTF's `weights` path, weight index `k` of the node's mesh), driving
    /// these global targets of [`crate::Character::morph_targets`] (one per primitive).
    MorphWeight {
        targets: Vec<u32>,
        curve: Curve<f32>,
    },
}

impl ChannelCurve {
    fn end_time(&self) -> f32 {
        match self {
            Self::Translation(c) | Self::Scale(c) => c.end_time(),
            Self::Rotation(c) => c.end_time(),
            Self::MorphWeight { curve, .. } => curve.end_time(),
        }
    }
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// Index into [`crate::Skeleton::nodes`].
    pub node: usize,
    pub curve: ChannelCurve,
}

/// What happens to times outside `[0, duration]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Time wraps around modulo the duration (walk cycles).
    Loop,
    /// Time is held at the first or last key.
    Clamp,
}

/// A named animation: channels over the nodes of one skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    pub name: String,
    channels: Vec<Channel>,
    duration: f32,
}

impl Clip {
    /// A clip from its channels; its duration is the latest key time of any channel (0 if none).
    ///
    /// Channel node indices are not checked here: [`Self::sample_into`] skips channels outside
    /// the pose, and the importer only makes channels for nodes it kept.
    pub fn new(name: impl Into<String>, channels: Vec<Channel>) -> Self {
        let duration = channels.iter().map(|c| c.curve.end_time()).fold(0.0f32, f32::max);
        Self { name: name.into(), channels, duration }
    }

    /// Length in seconds (the latest key time; clips are taken to start at 0).
    pub fn duration(&self) -> f32 {
        self.duration
    }

    /// The channels, in file order.
    pub fn channels(&self) -> &[Channel] {
        &self.channels
    }

    /// Maps a playback time to a time within the clip: modulo the duration for [`Wrap::Loop`],
    /// clamped to `[0, duration]` for [`Wrap::Clamp`]. Non-finite times map to 0.
    pub fn local_time(&self, time: f32, wrap: Wrap) -> f32 {
        if !time.is_finite() || self.duration <= 0.0 {
            return 0.0;
        }
        match wrap {
            Wrap::Loop => time.rem_euclid(self.duration),
            Wrap::Clamp => time.clamp(0.0, self.duration),
        }
    }

    /// Writes the clip's values at `time` over `pose` (nodes without channels keep their values).
    pub fn sample_into(&self, time: f32, wrap: Wrap, pose: &mut Pose) {
        let t = self.local_time(time, wrap);
        for channel in &self.channels {
            let Some(local) = pose.local.get_mut(channel.node) else { continue };
            match &channel.curve {
                ChannelCurve::Translation(c) => local.translation = c.sample(t),
                ChannelCurve::Rotation(c) => local.rotation = c.sample(t),
                ChannelCurve::Scale(c) => local.scale = c.sample(t),
                ChannelCurve::MorphWeight { .. } => {}
            }
        }
    }

    /// Writes the clip's morph weights at `time` over `weights` (indexed by global target;
    /// targets without a channel keep their values, targets past `weights` are skipped).
    pub fn sample_morph_weights(&self, time: f32, wrap: Wrap, weights: &mut [f32]) {
        let t = self.local_time(time, wrap);
        for channel in &self.channels {
            if let ChannelCurve::MorphWeight { targets, curve } = &channel.curve {
                let w = curve.sample(t);
                for &target in targets {
                    if let Some(slot) = weights.get_mut(target as usize) {
                        *slot = w;
                    }
                }
            }
        }
    }

    /// Whether the clip animates any morph weight.
    pub fn has_morph_weights(&self) -> bool {
        self.channels.iter().any(|c| matches!(c.curve, ChannelCurve::MorphWeight { .. }))
    }
}
