//! Sampling of hand-made curves with exact expected values: STEP, LINEAR and CUBICSPLINE at and
//! between keys, shortest-path rotations, clamping outside the keys, and clip looping/clamping.

use clod_viewer::animation::{Channel, ChannelCurve, Clip, Curve, CurveError, Interpolation, Wrap};
use clod_viewer::skeleton::{Pose, Transform};
use glam::{Quat, Vec3};
use std::f32::consts::FRAC_PI_2;

fn v(x: f32) -> Vec3 {
    Vec3::new(x, 0.0, 0.0)
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn step_holds_the_earlier_key() {
    let c = Curve::new(vec![0.0, 1.0, 2.0], vec![v(10.0), v(20.0), v(30.0)], Interpolation::Step).unwrap();
    assert_eq!(c.sample(-1.0), v(10.0));
    assert_eq!(c.sample(0.0), v(10.0));
    assert_eq!(c.sample(0.999), v(10.0));
    assert_eq!(c.sample(1.0), v(20.0));
    assert_eq!(c.sample(1.5), v(20.0));
    assert_eq!(c.sample(2.0), v(30.0));
    assert_eq!(c.sample(9.0), v(30.0));
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn linear_vectors_interpolate_and_clamp() {
    let c = Curve::new(vec![1.0, 3.0], vec![Vec3::ZERO, Vec3::new(4.0, 8.0, -2.0)], Interpolation::Linear)
        .unwrap();
    assert_eq!(c.sample(1.0), Vec3::ZERO);
    assert_eq!(c.sample(1.5), Vec3::new(1.0, 2.0, -0.5));
    assert_eq!(c.sample(2.0), Vec3::new(2.0, 4.0, -1.0));
    assert_eq!(c.sample(3.0), Vec3::new(4.0, 8.0, -2.0));
    assert_eq!(c.sample(0.0), Vec3::ZERO, "before the first key");
    assert_eq!(c.sample(5.0), Vec3::new(4.0, 8.0, -2.0), "after the last key");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn linear_rotations_take_the_shortest_path() {
    // The second key is stored negated: the same 90° about z, but on the far hemisphere. A naive
    // slerp would turn the long way (270°); half-way must be 45° about z.
    let far = -Quat::from_rotation_z(FRAC_PI_2);
    let c = Curve::new(vec![0.0, 1.0], vec![Quat::IDENTITY, far], Interpolation::Linear).unwrap();
    let half = c.sample(0.5);
    let want = Quat::from_rotation_z(FRAC_PI_2 / 2.0);
    assert!(half.dot(want).abs() > 1.0 - 1e-6, "{half:?}");
    assert!((half.length() - 1.0).abs() < 1e-6);
    assert!(c.sample(1.0).dot(far).abs() > 1.0 - 1e-6);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn cubic_spline_uses_tangents_scaled_by_the_key_interval() {
    // Keys at t = 0 and 2 with values 0 and 1; out-tangent 3/s at the first key, in-tangent 0 at
    // the second. At s = 1/2 the Hermite basis is (1/2, 1/8, 1/2, -1/8), the tangents scale by
    // dt = 2: 0/2 + 3·2/8 + 1/2 - 0 = 1.25.
    let values = vec![v(9.0), v(0.0), v(3.0), v(0.0), v(1.0), v(9.0)];
    let c = Curve::new(vec![0.0, 2.0], values, Interpolation::CubicSpline).unwrap();
    assert_eq!(c.sample(0.0), v(0.0));
    assert_eq!(c.sample(1.0), v(1.25));
    assert_eq!(c.sample(2.0), v(1.0));
    assert_eq!(c.sample(3.0), v(1.0), "after the last key: its value, not its tangent");
    assert_eq!(c.sample(-1.0), v(0.0));
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn cubic_spline_rotations_are_normalized() {
    // Zero tangents between identity and 90° about z: the Hermite blend at s = 1/2 is the plain
    // average of the two quaternions, which normalizes to 45° about z.
    let zero = Quat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    let values = vec![zero, Quat::IDENTITY, zero, zero, Quat::from_rotation_z(FRAC_PI_2), zero];
    let c = Curve::new(vec![0.0, 1.0], values, Interpolation::CubicSpline).unwrap();
    let half = c.sample(0.5);
    assert!((half.length() - 1.0).abs() < 1e-6);
    assert!(half.dot(Quat::from_rotation_z(FRAC_PI_2 / 2.0)) > 1.0 - 1e-6, "{half:?}");
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn invalid_curves_are_rejected() {
    assert_eq!(Curve::<Vec3>::new(vec![], vec![], Interpolation::Linear), Err(CurveError::Empty));
    assert_eq!(
        Curve::new(vec![1.0, 0.0], vec![v(0.0), v(1.0)], Interpolation::Linear),
        Err(CurveError::TimesDecrease(0.0, 1.0))
    );
    assert_eq!(
        Curve::new(vec![0.0, 1.0], vec![v(0.0), v(1.0)], Interpolation::CubicSpline),
        Err(CurveError::CountMismatch { times: 2, values: 2, expected: 6 })
    );
    assert_eq!(
        Curve::new(vec![0.0], vec![v(f32::NAN)], Interpolation::Step),
        Err(CurveError::NonFiniteValue)
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn clips_loop_or_clamp() {
    let curve = Curve::new(vec![0.0, 2.0], vec![v(0.0), v(2.0)], Interpolation::Linear).unwrap();
    let clip = Clip::new("slide", vec![Channel { node: 1, curve: ChannelCurve::Translation(curve) }]);
    assert_eq!(clip.duration(), 2.0);
    let x_at = |time: f32, wrap: Wrap| {
        let mut pose = Pose { local: vec![Transform::IDENTITY; 2] };
        clip.sample_into(time, wrap, &mut pose);
        assert_eq!(pose.local[0], Transform::IDENTITY, "node 0 has no channel");
        pose.local[1].translation.x
    };
    assert_eq!(x_at(0.5, Wrap::Loop), 0.5);
    assert_eq!(x_at(3.0, Wrap::Loop), 1.0);
    assert_eq!(x_at(-0.5, Wrap::Loop), 1.5);
    assert_eq!(x_at(3.0, Wrap::Clamp), 2.0);
    assert_eq!(x_at(-0.5, Wrap::Clamp), 0.0);
    assert_eq!(x_at(f32::NAN, Wrap::Loop), 0.0);
}
