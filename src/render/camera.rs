//! The shared orbit camera, its dolly, and the projection used by all three views.
//!
//! The camera looks at the character's centre (moved by `pan` in the view plane) from `distance`
//! model units away, raised `pitch` radians above the horizontal and turned `yaw` radians about
//! model +Y (glTF's up). Projection is right-handed with depth in `[0, 1]` (wgpu's clip space).
//! Distances are in the model's units.

use glam::camera::rh::{proj::directx, view};
use glam::{Mat4, Vec2, Vec3};

/// Vertical field of view, radians: a normal lens (45°), so the pixel error of a level is what a
/// viewer expects from its distance.
pub const FOVY: f32 = std::f32::consts::FRAC_PI_4;

/// Default camera elevation above the horizontal, radians: slightly from above, as a character
/// viewer.
pub const DEFAULT_PITCH: f32 = 0.15;

/// Largest elevation either way, radians (85°): straight above or below, "up" and the view
/// direction would be parallel and the look-at frame undefined.
pub const MAX_PITCH: f32 = 85.0 * std::f32::consts::PI / 180.0;

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
    /// Elevation above the horizontal, radians; clamped to ±[`MAX_PITCH`] where used.
    pub pitch: f32,
    /// Shift of the point looked at along the view's right and up directions, model units.
    pub pan: Vec2,
    /// Magnification about the point looked at (1: the normal lens): the field of view narrows
    /// so that lengths on screen grow this many times, while the eye stays where it is. The LOD
    /// schedule ignores it, so a magnified view shows the change that happens at the real size.
    pub zoom: f32,
}

impl OrbitCamera {
    /// Unit direction from the point looked at towards the eye.
    fn back(&self) -> Vec3 {
        let pitch = self.pitch.clamp(-MAX_PITCH, MAX_PITCH);
        Vec3::new(pitch.cos() * self.yaw.sin(), pitch.sin(), pitch.cos() * self.yaw.cos())
    }

    /// The point looked at: `target` moved by `pan` in the view plane.
    pub fn look_at(&self) -> Vec3 {
        let back = self.back();
        // |pitch| ≤ 85° keeps `back` away from ±Y, so the cross product is never near zero.
        let right = Vec3::Y.cross(back).normalize();
        let up = back.cross(right);
        self.target + right * self.pan.x + up * self.pan.y
    }

    /// Eye position in model space.
    pub fn eye(&self) -> Vec3 {
        self.look_at() + self.back() * self.distance
    }

    /// `clip_from_model` for a view of the given aspect (width / height).
    ///
    /// Near and far hug the character's sphere (depth precision), with the near plane never
    /// closer than 1 % of the distance so a camera inside the sphere still sees something.
    pub fn clip_from_model(&self, aspect: f32) -> Mat4 {
        let eye = self.eye();
        // Depth range around the sphere at `target` (a pan moves the eye off the sphere's axis).
        let centre = eye.distance(self.target);
        let near = (centre - self.radius).max(self.distance * 0.01).max(1e-4);
        let far = (centre + self.radius).max(near * 2.0);
        let view_from_model = view::look_at_mat4(eye, self.look_at(), Vec3::Y);
        // wgpu's clip space is Direct3D's: y up, depth in [0, 1].
        directx::perspective(magnified_fovy(self.zoom), aspect, near, far) * view_from_model
    }
}

/// The vertical field of view that makes screen lengths `zoom` times larger than [`FOVY`] does
/// (`tan` of the half angle divided by `zoom`); a zoom below 1 or not finite counts as 1.
pub fn magnified_fovy(zoom: f32) -> f32 {
    let zoom = if zoom.is_finite() { zoom.max(1.0) } else { 1.0 };
    2.0 * ((FOVY * 0.5).tan() / zoom).atan()
}

/// Framing distance: the character's sphere fills the view's height.
pub fn framing_distance(radius: f32) -> f32 {
    radius / (FOVY * 0.5).sin()
}

/// Framing distance for a view of `aspect` (width / height): the sphere fills the view's height,
/// or its width when the view is narrower than tall, so it is whole in the view either way.
pub fn framing_distance_for(radius: f32, aspect: f32) -> f32 {
    let half_height = FOVY * 0.5;
    let half_width = (aspect.max(1e-3) * half_height.tan()).atan();
    radius / half_height.min(half_width).sin()
}

/// The distances an automatic dolly sweeps between, from the levels' switch distances (`switch[k]`:
/// where level `k` takes over, ascending, the same units as `framing`).
///
/// It starts at the framing distance, so the first frame shows the whole character (nearer, its
/// head and feet leave the view); it ends past the coarsest switch (30 % beyond, so the last level
/// is seen settled), at least twice `near` and at most 100 framing distances (beyond, the
/// character is a few pixels tall). No switches: framed to twice that.
pub fn dolly_range(framing: f32, switch: &[f32]) -> (f32, f32) {
    let near = framing;
    let last = switch.last().copied().filter(|d| d.is_finite()).unwrap_or(0.0);
    let far = (1.3 * last).clamp(2.0 * near, 100.0 * framing);
    (near, far)
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
    fn dolly_range_spans_the_switches_within_sensible_distances() {
        // Switches from a tenth to three framing distances: from framed to 3.9 framed.
        let (near, far) = dolly_range(2.0, &[0.0, 0.2, 1.0, 6.0]);
        assert!(near == 2.0 && (far - 7.8).abs() < 1e-5, "{near} {far}");
        // A last switch close to near: far is still twice near.
        assert_eq!(dolly_range(1.0, &[0.0, 1.0, 1.2]), (1.0, 2.0));
        // Far switches are capped at 100 framed; no switches at all give framed to twice that.
        assert_eq!(dolly_range(1.0, &[0.0, 5.0, 500.0]), (1.0, 100.0));
        assert_eq!(dolly_range(1.0, &[]), (1.0, 2.0));
        assert_eq!(dolly_range(1.0, &[0.0, f32::INFINITY]), (1.0, 2.0));
    }

    #[test]
    fn target_projects_to_the_view_centre() {
        let cam = OrbitCamera {
            target: Vec3::new(1.0, 2.0, 3.0),
            radius: 1.0,
            distance: 5.0,
            yaw: 0.7,
            pitch: DEFAULT_PITCH,
            pan: Vec2::ZERO,
            zoom: 1.0,
        };
        let clip = cam.clip_from_model(1.5) * cam.target.extend(1.0);
        assert!((clip.x / clip.w).abs() < 1e-5 && (clip.y / clip.w).abs() < 1e-5);
        let depth = clip.z / clip.w;
        assert!(depth > 0.0 && depth < 1.0, "depth {depth}");
        assert!((cam.eye().distance(cam.target) - 5.0).abs() < 1e-5);
    }

    #[test]
    fn pitch_raises_the_eye_and_is_clamped() {
        let flat = OrbitCamera {
            target: Vec3::ZERO,
            radius: 1.0,
            distance: 2.0,
            yaw: 0.0,
            pitch: 0.0,
            pan: Vec2::ZERO,
            zoom: 1.0,
        };
        assert!((flat.eye() - Vec3::new(0.0, 0.0, 2.0)).length() < 1e-6);
        let above = OrbitCamera { pitch: std::f32::consts::FRAC_PI_6, ..flat };
        assert!((above.eye().y - 1.0).abs() < 1e-6, "sin 30° × 2 = 1: {}", above.eye());
        let over = OrbitCamera { pitch: 3.0, ..flat };
        assert!((over.eye().y - 2.0 * MAX_PITCH.sin()).abs() < 1e-6);
        assert!(over.clip_from_model(1.0).is_finite());
    }

    #[test]
    fn pan_moves_the_view_in_its_own_plane() {
        // Looking along −Z from +Z: right is +X and up is +Y.
        let cam = OrbitCamera {
            target: Vec3::ZERO,
            radius: 1.0,
            distance: 4.0,
            yaw: 0.0,
            pitch: 0.0,
            pan: Vec2::new(0.5, -0.25),
            zoom: 1.0,
        };
        assert!((cam.look_at() - Vec3::new(0.5, -0.25, 0.0)).length() < 1e-6);
        assert!((cam.eye() - Vec3::new(0.5, -0.25, 4.0)).length() < 1e-6);
        // The panned point projects to the view centre; the target to its left and above.
        let clip_from_model = cam.clip_from_model(1.0);
        let centre = clip_from_model * cam.look_at().extend(1.0);
        assert!((centre.x / centre.w).abs() < 1e-6 && (centre.y / centre.w).abs() < 1e-6);
        let target = clip_from_model * Vec3::ZERO.extend(1.0);
        assert!(target.x / target.w < 0.0 && target.y / target.w > 0.0);
    }

    #[test]
    fn framed_sphere_touches_the_top_of_the_view() {
        let radius = 2.0;
        let d = framing_distance(radius);
        // The tangent from the eye to the sphere makes half the field of view with the axis.
        assert!(((radius / d).asin() - FOVY / 2.0).abs() < 1e-6);
    }

    #[test]
    fn magnifying_scales_screen_lengths_about_the_point_looked_at() {
        let cam = OrbitCamera {
            target: Vec3::ZERO,
            radius: 1.0,
            distance: 4.0,
            yaw: 0.0,
            pitch: 0.0,
            pan: Vec2::ZERO,
            zoom: 1.0,
        };
        let ndc = |c: &OrbitCamera, p: Vec3| {
            let clip = c.clip_from_model(1.0) * p.extend(1.0);
            Vec2::new(clip.x, clip.y) / clip.w
        };
        let point = Vec3::new(0.1, 0.2, 0.0);
        let four = OrbitCamera { zoom: 4.0, ..cam };
        assert!((ndc(&four, point) - 4.0 * ndc(&cam, point)).length() < 1e-5);
        assert!(ndc(&four, Vec3::ZERO).length() < 1e-6, "the point looked at stays in the centre");
        assert_eq!(magnified_fovy(0.5), FOVY);
        assert_eq!(magnified_fovy(f32::NAN), FOVY);
    }

    #[test]
    fn a_narrow_view_frames_by_its_width() {
        let wide = framing_distance_for(1.0, 2.0);
        assert!((wide - framing_distance(1.0)).abs() < 1e-6, "wide views frame by their height");
        let narrow = framing_distance_for(1.0, 0.5);
        // The tangent from the eye makes half the horizontal field of view with the axis.
        let half_width = (0.5 * (FOVY * 0.5).tan()).atan();
        assert!(((1.0 / narrow).asin() - half_width).abs() < 1e-5 && narrow > wide);
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
