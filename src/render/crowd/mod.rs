//! Crowd mode (Larkin 2011, "Level of detail for crowds"): one character instanced hundreds or
//! thousands of times on the ground, each instance choosing its own level by its own screen-space
//! error and running its own transitions, drawn with skinned instancing.
//!
//! Pure and native-testable, like [`super::viewer::ViewerModel`], which owns a [`Crowd`] while the
//! page is in crowd mode. Per frame [`Crowd::advance`] moves the camera along its path, steps every
//! instance's level schedule and returns a [`CrowdFrame`]: one array of per-instance records
//! (mirrors of `crowd.wgsl`'s instance attributes) and, per view, the instanced draws that show the
//! same selections by that view's method (popping, alpha-blending or geomorphing). The views
//! differ only in the method: every instance has one schedule, one pose and one camera.
//!
//! Conventions: world space is the character's model space with each instance turned about +Y and
//! moved on the ground (`world = R_y(heading) · (p − centre) + position`); the camera looks down
//! −Z from above the crowd's front, and dollies forward and back along −Z. Distances are model
//! units; an instance's distance is its centre's from the eye, as the single view's is.
//!
//! Per-instance CPU work per frame is a distance, a frustum test, a level selection, a palette row
//! and one record per draw: the pose comes from the [`PosePalette`], shared by all instances.

pub mod draws;
pub mod palette;
#[cfg(test)]
mod tests;

use glam::camera::rh::{proj::directx, view};
use glam::{Mat4, Vec3, Vec4};

use super::camera::FOVY;
use super::plan::Method;
use super::schedule::{advance_time, select_level, Schedule, Transition, TransitionMode};
use crate::metrics::SplitMix64;
pub use draws::{CrowdFrame, CrowdStats, InstanceDraw, InstanceRaw, InstancedDraw, INSTANCE_OFFSETS};
pub use palette::PosePalette;

/// Most instances a crowd has: 4,096 instances of three views' records are 0.8 MB per frame.
pub const MAX_INSTANCES: usize = 4096;
/// Instances when the page asks for a crowd without a count: a few hundred.
pub const DEFAULT_INSTANCES: usize = 400;

/// Least distance between neighbours' centres, in sphere radii. With the layout's jitter
/// ([`JITTER`]) neighbours stay at least 1.5 radii apart; the animated sphere is much wider than a
/// body (it holds every pose, arms and legs out), so bodies do not touch.
const MIN_SPACING: f32 = 2.2;
/// Random shift of each instance either way along both ground axes, a share of the spacing:
/// rows, but not a parade.
const JITTER: f32 = 0.15;
/// The crowd is this much wider than the view at every depth, so that some instances are always
/// outside the frustum (culled) and the edges of the view are full.
const WEDGE_WIDTH: f32 = 1.25;
/// Nearest row, in framing distances: the front instances nearly fill a view's height.
const NEAR_ROW: f32 = 1.25;
/// The crowd reaches this far past the coarsest level's switch distance, so its back rows show
/// the coarsest level at rest.
const FAR_MARGIN: f32 = 1.3;
/// Share of the crowd's depth the camera dollies forward at the near end of its path: far enough
/// that every row changes level at least once per period.
const DOLLY_SHARE: f32 = 0.35;
/// Heading spread about "facing the camera", radians (±40°): a crowd walking roughly towards the
/// viewer, no two alike.
const HEADING_SPREAD: f32 = 0.7;
/// Walking speed spread (animation playback rate, ±15 %).
const SPEED_SPREAD: f32 = 0.15;

/// One instance: where it stands, how it walks and what it shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Ground position of its centre (world space, `y` the centre's height).
    pub position: Vec3,
    /// Turn about +Y, radians (0 faces +Z, the camera).
    pub heading: f32,
    /// Its animation rate relative to the clock.
    pub speed: f32,
    /// Its clip time at clock 0, seconds.
    pub offset: f32,
    /// Its level selection and the transition it shows (the same in every view).
    pub selected: usize,
    pub transition: Transition,
}

impl Instance {
    /// One frame of its level schedule at `distance` (model units) from the eye.
    fn step(&mut self, params: &CrowdParams, distance: f32, switch: &[f32], dt: f32) {
        let last = switch.len().saturating_sub(1);
        match params.mode {
            TransitionMode::Time { seconds } => {
                self.selected = select_level(self.selected, distance, switch, params.hysteresis).min(last);
                // One level per transition: a geomorph has its ancestors one level coarser in the
                // level's own buffer, and a crowd's camera crosses one switch at a time.
                let shown = self.transition.to;
                let goal = if self.selected > shown {
                    shown + 1
                } else {
                    self.selected.max(shown.saturating_sub(1))
                };
                let mut t = advance_time(self.transition, goal.min(last), seconds, dt.max(0.0));
                (t.from, t.to) = (t.from.min(last), t.to.min(last));
                self.transition = if t.is_running() { t } else { Transition::at(t.to) };
            }
            // Morph zones go from a level to the next one: the single view's schedule.
            TransitionMode::Distance { .. } => {
                let mut schedule = Schedule { selected: self.selected, transition: self.transition };
                schedule.step(params.mode, distance, switch, params.hysteresis, dt);
                (self.selected, self.transition) = (schedule.selected, schedule.transition);
            }
        }
    }
}

/// Everything one crowd frame depends on besides the instances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrowdParams {
    /// Time-driven transitions (of a duration; 0 pops) or morph zones by distance, as in the
    /// single view.
    pub mode: TransitionMode,
    /// Selection hysteresis, a share of each switch distance.
    pub hysteresis: f32,
    /// Whether the camera follows its dolly path (else it stays at the front).
    pub dolly: bool,
    /// Seconds per dolly period (forward and back).
    pub dolly_period: f32,
    /// Level overlay: each instance tinted by the level it shows.
    pub tint_levels: bool,
    /// Every instance at level 0, no transitions: the crowd without LOD, for comparison.
    pub full_detail: bool,
}

/// The crowd (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Crowd {
    pub instances: Vec<Instance>,
    /// The character's animated sphere: its centre (model space) and radius.
    centre: Vec3,
    radius: f32,
    /// Front row and back row distance from the camera's start, model units.
    pub near: f32,
    pub far: f32,
    /// The camera's eye this frame (world space).
    pub eye: Vec3,
    /// `clip_from_world` of every view this frame.
    pub clip_from_world: Mat4,
    /// Height of the ground the instances stand on (world space): the lowest point of the
    /// character's animated bounds; the sphere's bottom until set.
    pub floor: f32,
    seed: u64,
    /// Whether the last frame drew every instance at full detail.
    full_detail: bool,
}

impl Crowd {
    /// A crowd of `count` instances (clamped to `1..=`[`MAX_INSTANCES`]) of a character whose
    /// animated sphere is `(centre, radius)`, laid out for views of `aspect` whose levels switch
    /// at `switch` (model units, ascending from 0). `clip_duration` spreads the time offsets
    /// (0: none). The same `seed` gives the same crowd on every platform.
    pub fn new(
        count: usize,
        sphere: (Vec3, f32),
        switch: &[f32],
        aspect: f32,
        clip_duration: f32,
        seed: u64,
    ) -> Self {
        let (centre, radius) = (sphere.0, sphere.1.max(1e-6));
        let count = count.clamp(1, MAX_INSTANCES);
        let framing = super::camera::framing_distance_for(radius, aspect);
        let near = NEAR_ROW * framing;
        let last_switch = switch.iter().copied().filter(|d| d.is_finite()).fold(0.0, f32::max);
        let far_wanted = (FAR_MARGIN * last_switch).max(4.0 * near);
        // Rows `spacing` apart from `near` to `far`, each as wide as the wedge: about
        // `tan · (far² − near²) / spacing²` instances. Solve for the spacing that reaches `far`
        // with `count`, never closer than MIN_SPACING radii.
        let tan = half_width_tan(aspect) * WEDGE_WIDTH;
        let spacing =
            ((tan * (far_wanted * far_wanted - near * near) / count as f32).sqrt()).max(MIN_SPACING * radius);
        let mut rng = SplitMix64(seed);
        let mut instances = Vec::with_capacity(count);
        let mut depth = near;
        while instances.len() < count {
            let width = 2.0 * depth * tan;
            let columns = ((width / spacing).floor() as usize).max(1).min(count - instances.len());
            for c in 0..columns {
                let x = (c as f32 + 0.5 - columns as f32 * 0.5) * spacing + rng.signed() * JITTER * spacing;
                let z = -depth + rng.signed() * JITTER * spacing;
                instances.push(Instance {
                    position: Vec3::new(x, centre.y, z),
                    heading: rng.signed() * HEADING_SPREAD,
                    speed: 1.0 + rng.signed() * SPEED_SPREAD,
                    offset: rng.next_f32() * clip_duration.max(0.0),
                    selected: 0,
                    transition: Transition::at(0),
                });
            }
            depth += spacing;
        }
        let mut crowd = Self {
            instances,
            centre,
            radius,
            near,
            far: depth,
            eye: Vec3::ZERO,
            clip_from_world: Mat4::IDENTITY,
            floor: centre.y - radius,
            seed,
            full_detail: false,
        };
        crowd.place_camera(0.0, aspect);
        crowd.settle(switch);
        crowd
    }

    /// Puts every instance at rest on the level its distance selects: a new crowd, or LOD turned
    /// back on, starts there rather than stepping down from the finest level one transition at a
    /// time.
    fn settle(&mut self, switch: &[f32]) {
        for i in &mut self.instances {
            i.selected = select_level(0, self.eye.distance(i.position), switch, 0.0);
            i.transition = Transition::at(i.selected);
        }
    }

    /// Unit direction the camera looks in (world space).
    pub fn forward(&self) -> Vec3 {
        (self.aim_from(self.eye) - self.eye).normalize_or(Vec3::NEG_Z)
    }

    /// The seed it was laid out with.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// How far forward the camera is along its path at dolly time `time` (model units).
    fn dolly_offset(&self, params: &CrowdParams, time: f64) -> f32 {
        if !params.dolly || params.dolly_period <= 0.0 {
            return 0.0;
        }
        let phase = (time / f64::from(params.dolly_period)).rem_euclid(1.0) as f32;
        // Starts at the front, reaches the forward end at half the period, smooth at both ends.
        DOLLY_SHARE * (self.far - self.near) * 0.5 * (1.0 - (std::f32::consts::TAU * phase).cos())
    }

    /// Puts the camera `forward` model units along its path: above the crowd's front, looking
    /// down −Z and slightly down, so rows recede towards the horizon.
    fn place_camera(&mut self, forward: f32, aspect: f32) {
        let height = 2.0 * self.radius;
        self.eye = Vec3::new(0.0, self.centre.y + height, -forward);
        let aim = self.aim_from(self.eye);
        let view = view::look_at_mat4(self.eye, aim, Vec3::Y);
        // Depth: the nearest instance's sphere may reach past the eye; the far plane holds the back row.
        let near_plane = (0.05 * self.radius).max(1e-4);
        let far_plane = self.far + 4.0 * self.radius + self.eye.y.abs();
        self.clip_from_world = directx::perspective(FOVY, aspect.max(1e-3), near_plane, far_plane) * view;
    }

    /// Where a camera at `eye` looks: at the centres' height, a fifth of the way into the crowd
    /// ahead of it.
    fn aim_from(&self, eye: Vec3) -> Vec3 {
        Vec3::new(0.0, self.centre.y, eye.z - self.near - (self.far - self.near) / 5.0)
    }

    /// Advances every instance by `dt` seconds (transitions) with the dolly at `dolly_time`, and
    /// returns what the views draw. `switch` are the levels' switch distances (model units),
    /// `level_triangles` each level's triangle count, `methods` the views' methods (only the first
    /// `views` are drawn), `anim_time` the animation clock (seconds).
    #[allow(clippy::too_many_arguments)]
    pub fn advance(
        &mut self,
        params: &CrowdParams,
        dt: f32,
        dolly_time: f64,
        anim_time: f64,
        aspect: f32,
        switch: &[f32],
        level_triangles: &[usize],
        palette: &PosePalette,
        methods: &[Method],
    ) -> CrowdFrame {
        let forward = self.dolly_offset(params, dolly_time);
        self.place_camera(forward, aspect);
        let planes = frustum_planes(&self.clip_from_world);
        if self.full_detail && !params.full_detail {
            self.settle(switch);
        }
        self.full_detail = params.full_detail;
        let mut visible = Vec::with_capacity(self.instances.len());
        for (index, i) in self.instances.iter_mut().enumerate() {
            let distance = self.eye.distance(i.position);
            if params.full_detail {
                (i.selected, i.transition) = (0, Transition::at(0));
            } else {
                i.step(params, distance, switch, dt);
            }
            if sphere_visible(&planes, i.position, self.radius) {
                visible.push(index);
            }
        }
        let rows: Vec<u32> = visible
            .iter()
            .map(|&k| {
                let i = &self.instances[k];
                palette.row_at(anim_time * f64::from(i.speed) + f64::from(i.offset))
            })
            .collect();
        draws::build(self, &visible, &rows, methods, params.tint_levels, level_triangles)
    }

    /// The ground under the crowd as two triangles, `(x, y, z, grid cell)` per corner (world
    /// space): from just behind the camera's start to past the back row, twice the wedge's width
    /// at the back, a grid of one spacing-sized cell per instance slot.
    pub fn ground(&self) -> [[f32; 4]; 6] {
        let back = -(self.far + 4.0 * self.radius);
        let front = 4.0 * self.radius;
        let half = self.far * 2.0;
        let cell = MIN_SPACING * self.radius;
        let corner = |x: f32, z: f32| [x, self.floor, z, cell];
        let (a, b, c, d) =
            (corner(-half, front), corner(half, front), corner(half, back), corner(-half, back));
        [a, b, c, a, c, d]
    }

    /// The record placing instance `i` in world space: `world = R_y(heading)(p − centre) + position`
    /// as a translation after the turn.
    fn placement(&self, i: &Instance) -> Vec4 {
        let (s, c) = i.heading.sin_cos();
        let turned = Vec3::new(
            c * self.centre.x + s * self.centre.z,
            self.centre.y,
            -s * self.centre.x + c * self.centre.z,
        );
        (i.position - turned).extend(i.heading)
    }
}

/// `tan` of half the horizontal field of view of a view of `aspect`.
fn half_width_tan(aspect: f32) -> f32 {
    aspect.max(1e-3) * (FOVY * 0.5).tan()
}

/// The six planes of a `clip_from_world` matrix with depth in `[0, 1]` (Gribb & Hartmann), each
/// `(n, d)` with `n · p + d ≥ 0` inside; not normalised.
pub fn frustum_planes(m: &Mat4) -> [Vec4; 6] {
    let r = |i: usize| m.row(i);
    [r(3) + r(0), r(3) - r(0), r(3) + r(1), r(3) - r(1), r(2), r(3) - r(2)]
}

/// Whether a sphere is at least partly inside the frustum.
pub fn sphere_visible(planes: &[Vec4; 6], centre: Vec3, radius: f32) -> bool {
    planes.iter().all(|p| {
        let n = p.truncate();
        p.dot(centre.extend(1.0)) >= -radius * n.length()
    })
}
