//! Platform-independent scalar maths for the generator.
//!
//! The asset must come out byte-identical on every machine, but `f32::sin` and friends call the
//! platform's libm, whose last-bit results differ between C libraries. Everything the generator
//! writes therefore goes through the pure-Rust `libm` crate (a port of musl's libm), and through
//! the helpers here that build rotations from it. Square roots are exact in IEEE 754, so glam's
//! `normalize`/`length` are fine.

use glam::{Quat, Vec3};

/// `(sin x, cos x)` from the portable libm.
pub fn sin_cos(x: f32) -> (f32, f32) {
    (libm::sinf(x), libm::cosf(x))
}

/// Degrees to radians.
pub fn deg(x: f32) -> f32 {
    x * (std::f32::consts::PI / 180.0)
}

/// The rotation by `angle` radians about the unit `axis` (right-hand rule).
pub fn axis_angle(axis: Vec3, angle: f32) -> Quat {
    let (s, c) = sin_cos(0.5 * angle);
    let v = axis * s;
    Quat::from_xyzw(v.x, v.y, v.z, c)
}

/// `atan2(y, x)` from the portable libm.
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// Local rotation about model axis `axis` (any length) by `degrees`.
pub fn turn(axis: Vec3, degrees: f32) -> Quat {
    axis_angle(axis.normalize(), deg(degrees))
}
