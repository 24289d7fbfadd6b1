//! What the generated kinds key their clips with: a joint looked up by name, evenly spaced key
//! times, a sine of a period, and a rotation track sampled from a pose function. Times are in
//! seconds; the sine goes through [`crate::math`], so the keys are the same bytes on every
//! platform.

use glam::Quat;

use crate::math::sin_cos;
use crate::robot::RJoint;

/// The index of the joint named `name` in `joints`.
///
/// # Panics
/// If no joint has that name: a generator's own typo, found the first time it runs.
pub fn joint_index(joints: &[RJoint], name: &str) -> usize {
    joints.iter().position(|j| j.name == name).unwrap_or_else(|| panic!("no joint {name}"))
}

/// `count + 1` key times spread evenly over `duration` seconds, both ends included.
pub fn key_times(duration: f32, count: usize) -> Vec<f32> {
    (0..=count).map(|k| duration * k as f32 / count as f32).collect()
}

/// `sin(2π t / period)`: a wave of `period` seconds, 0 at `t = 0` and rising.
pub fn wave(t: f32, period: f32) -> f32 {
    sin_cos(std::f32::consts::TAU * t / period).0
}

/// A rotation track of `joint`: `pose` sampled at `times`.
pub fn track(joint: usize, pose: &dyn Fn(f32) -> Quat, times: &[f32]) -> (usize, Vec<Quat>) {
    (joint, times.iter().map(|&t| pose(t)).collect())
}
