//! The shared orbit camera, its dolly, and the projection used by all three views.
//!
//! The camera looks at the character's centre from `distance` model units away, at a fixed
//! elevation, turned `yaw` radians about model +Y (glTF's up). Projection is right-handed with
//! depth in `[0, 1]` (wgpu's clip space). Distances are in the model's units.

use glam::camera::rh::{proj::directx, view};
use glam::{Mat4, Vec3};

/// Vertical field of view, radians: a normal lens (45°), so the pixel error of a level is what a
/// viewer expects from its distance.
pub const FOVY: f32 = std::f32::consts::FRAC_PI_4;

/// Camera elevation above the horizontal, radians: slightly from above, as a character viewer.
pub const PITCH: f32 = 0.15;

/// An orbit camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// What it looks at (model space).
    pub target: Vec3,
    /// Radius of a sphere around `target` that holds the character in every pose.
    pub radius: f32,
    /// Distance from `target` to the eye.
    pub distance: f32,
    /// Turn about +Y, radians; 0 looks along −Z from the +Z side (the glTF front).
    pub yaw: f32,
}

impl OrbitCamera {
    /// Eye position in model space.
    pub fn eye(&self) -> Vec3 {
        let dir = Vec3::new(PITCH.cos() * self.yaw.sin(), PITCH.sin(), PITCH.cos() * self.yaw.cos());
        self.target + dir * self.distance
    }

    /// `clip_from_model` for a view of the given aspect (width / height).
    ///
    /// Near and far hug the character's sphere (depth precision), with the near plane never
    /// closer than 1 % of the distance so a camera inside the sphere still sees something.
    pub fn clip_from_model(&self, aspect: f32) -> Mat4 {
        let near = (self.distance - self.radius).max(self.distance * 0.01).max(1e-4);
        let far = (self.distance + self.radius).max(near * 2.0);
        let view_from_model = view::look_at_mat4(self.eye(), self.target, Vec3::Y);
        // wgpu's clip space is Direct3D's: y up, depth in [0, 1].
        directx::perspective(FOVY, aspect, near, far) * view_from_model
    }
}

/// Framing distance: the character's sphere fills the view's height.
pub fn framing_distance(radius: f32) -> f32 {
    radius / (FOVY * 0.5).sin()
}

/// Distance of a dolly that sweeps from `near` to `far` and back every `period` seconds.
///
/// The sweep is geometric (equal times per doubling of the distance), since level errors grow
/// geometrically, so each level gets a similar share of the sweep; it eases in and out at the ends
/// (cosine). A period that is not positive holds the camera at `near`.
pub fn dolly_distance(near: f32, far: f32, period: f32, time: f64) -> f32 {
    if period <= 0.0 || !(near > 0.0 && far > 0.0) {
        return near;
    }
    let phase = (time / period as f64).rem_euclid(1.0) as f32;
    let s = 0.5 - 0.5 * (std::f32::consts::TAU * phase).cos();
    near * (far / near).powf(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn target_projects_to_the_view_centre() {
        let cam = OrbitCamera { target: Vec3::new(1.0, 2.0, 3.0), radius: 1.0, distance: 5.0, yaw: 0.7 };
        let clip = cam.clip_from_model(1.5) * cam.target.extend(1.0);
        assert!((clip.x / clip.w).abs() < 1e-5 && (clip.y / clip.w).abs() < 1e-5);
        let depth = clip.z / clip.w;
        assert!(depth > 0.0 && depth < 1.0, "depth {depth}");
        assert!((cam.eye().distance(cam.target) - 5.0).abs() < 1e-5);
    }

    #[test]
    fn framed_sphere_touches_the_top_of_the_view() {
        let radius = 2.0;
        let d = framing_distance(radius);
        // The tangent from the eye to the sphere makes half the field of view with the axis.
        assert!(((radius / d).asin() - FOVY / 2.0).abs() < 1e-6);
    }

    #[test]
    fn dolly_sweeps_between_the_ends() {
        assert_eq!(dolly_distance(2.0, 32.0, 10.0, 0.0), 2.0);
        assert!((dolly_distance(2.0, 32.0, 10.0, 5.0) - 32.0).abs() < 1e-4);
        // A quarter period is the geometric middle: sqrt(2 * 32) = 8.
        assert!((dolly_distance(2.0, 32.0, 10.0, 2.5) - 8.0).abs() < 1e-4);
        assert_eq!(dolly_distance(2.0, 32.0, 0.0, 7.0), 2.0);
    }
}
