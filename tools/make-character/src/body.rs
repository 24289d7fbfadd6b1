//! The character's design: its skeleton at rest and the implicit primitives that make up its body.
//!
//! Units are metres; Y is up, the character faces +Z and stands on y = 0 (glTF conventions), so
//! its left side is +X. The rest pose is an A-pose (arms 42° out from the body) so that arms and
//! torso stay apart and the smooth union does not fuse them. Every primitive belongs to one bone;
//! that ownership drives both the skin weights ([`crate::skin`]) and the material regions
//! ([`crate::regions`]).
//!
//! Joint frames: each joint's local +Y axis points along its bone (from the joint towards its
//! tail), as in most authored rigs, so the rest rotations and inverse bind matrices are not
//! trivial. Rotations are built with [`crate::math`] so the output does not depend on the
//! platform's `sin`/`cos`.

use glam::{Quat, Vec3};

use crate::field::{Part, Shape};
use crate::math;

/// Joint indices, parent-first (a joint's parent always has a smaller index).
pub mod joint {
    pub const HIPS: usize = 0;
    pub const SPINE: usize = 1;
    pub const CHEST: usize = 2;
    pub const NECK: usize = 3;
    pub const HEAD: usize = 4;
    pub const L_CLAVICLE: usize = 5;
    pub const L_UPPER_ARM: usize = 6;
    pub const L_FOREARM: usize = 7;
    pub const L_HAND: usize = 8;
    pub const L_THUMB: usize = 9;
    pub const R_CLAVICLE: usize = 10;
    pub const R_UPPER_ARM: usize = 11;
    pub const R_FOREARM: usize = 12;
    pub const R_HAND: usize = 13;
    pub const R_THUMB: usize = 14;
    pub const L_UPPER_LEG: usize = 15;
    pub const L_LOWER_LEG: usize = 16;
    pub const L_FOOT: usize = 17;
    pub const L_TOES: usize = 18;
    pub const R_UPPER_LEG: usize = 19;
    pub const R_LOWER_LEG: usize = 20;
    pub const R_FOOT: usize = 21;
    pub const R_TOES: usize = 22;
    pub const COUNT: usize = 23;
}

/// One joint at rest, in model space.
#[derive(Clone, Debug)]
pub struct Joint {
    pub name: &'static str,
    pub parent: Option<usize>,
    /// Model-space position of the joint (the bone's head).
    pub head: Vec3,
    /// Model-space end of the bone (the next joint, or the tip for leaves).
    pub tail: Vec3,
    /// `model_from_joint` rotation at rest: local +Y along `tail - head`.
    pub rotation: Quat,
}

/// Total height the design aims at (top of the head), in metres.
pub const HEIGHT: f32 = 1.75;

/// Angle between a hanging arm and the arm at rest, in radians (A-pose).
const ARM_SPREAD: f32 = 42.0 * std::f32::consts::PI / 180.0;

/// Direction of the left arm at rest (the right arm mirrors it in x).
pub fn left_arm_direction() -> Vec3 {
    let (s, c) = math::sin_cos(ARM_SPREAD);
    Vec3::new(s, -c, 0.0)
}

fn mirror(v: Vec3) -> Vec3 {
    Vec3::new(-v.x, v.y, v.z)
}

/// The skeleton at rest, parent-first, [`joint::COUNT`] joints.
pub fn skeleton() -> Vec<Joint> {
    use joint::*;
    let d = left_arm_direction();
    // Left-side landmarks; the right side mirrors them.
    let shoulder = Vec3::new(0.18, 1.42, -0.015);
    let elbow = shoulder + 0.29 * d;
    let wrist = elbow + 0.255 * d;
    let fingertip = wrist + 0.19 * d;
    // The thumb leaves the front (+Z) edge of the palm and points forward and down.
    let thumb_base = wrist + 0.035 * d + Vec3::new(-0.004, 0.0, 0.022);
    let thumb_tip = thumb_base + 0.065 * (d + Vec3::new(0.0, 0.0, 1.1)).normalize();
    let hip = Vec3::new(0.095, 0.92, 0.0);
    let knee = Vec3::new(0.105, 0.50, 0.012);
    let ankle = Vec3::new(0.11, 0.085, -0.02);
    let ball = Vec3::new(0.115, 0.03, 0.115);
    let toe_tip = Vec3::new(0.115, 0.03, 0.19);

    let mut joints: Vec<(&'static str, Option<usize>, Vec3, Vec3)> = vec![
        ("Hips", None, Vec3::new(0.0, 0.95, 0.0), Vec3::new(0.0, 1.07, -0.005)),
        ("Spine", Some(HIPS), Vec3::new(0.0, 1.07, -0.005), Vec3::new(0.0, 1.25, -0.01)),
        ("Chest", Some(SPINE), Vec3::new(0.0, 1.25, -0.01), Vec3::new(0.0, 1.45, -0.015)),
        ("Neck", Some(CHEST), Vec3::new(0.0, 1.45, -0.015), Vec3::new(0.0, 1.56, 0.0)),
        ("Head", Some(NECK), Vec3::new(0.0, 1.56, 0.0), Vec3::new(0.0, HEIGHT, 0.0)),
    ];
    for side in 0..2 {
        let m = |v: Vec3| if side == 0 { v } else { mirror(v) };
        let names = if side == 0 {
            ["LeftShoulder", "LeftUpperArm", "LeftForearm", "LeftHand", "LeftThumb"]
        } else {
            ["RightShoulder", "RightUpperArm", "RightForearm", "RightHand", "RightThumb"]
        };
        let base = joints.len();
        let clavicle = Vec3::new(0.03, 1.43, -0.01);
        joints.push((names[0], Some(CHEST), m(clavicle), m(shoulder)));
        joints.push((names[1], Some(base), m(shoulder), m(elbow)));
        joints.push((names[2], Some(base + 1), m(elbow), m(wrist)));
        joints.push((names[3], Some(base + 2), m(wrist), m(fingertip)));
        joints.push((names[4], Some(base + 3), m(thumb_base), m(thumb_tip)));
    }
    for side in 0..2 {
        let m = |v: Vec3| if side == 0 { v } else { mirror(v) };
        let names = if side == 0 {
            ["LeftUpperLeg", "LeftLowerLeg", "LeftFoot", "LeftToes"]
        } else {
            ["RightUpperLeg", "RightLowerLeg", "RightFoot", "RightToes"]
        };
        let base = joints.len();
        joints.push((names[0], Some(HIPS), m(hip), m(knee)));
        joints.push((names[1], Some(base), m(knee), m(ankle)));
        joints.push((names[2], Some(base + 1), m(ankle), m(ball)));
        joints.push((names[3], Some(base + 2), m(ball), m(toe_tip)));
    }
    debug_assert_eq!(joints.len(), COUNT);
    joints
        .into_iter()
        .map(|(name, parent, head, tail)| {
            let rotation = Quat::from_rotation_arc(Vec3::Y, (tail - head).normalize());
            Joint { name, parent, head, tail, rotation }
        })
        .collect()
}

/// The body's implicit primitives in union order: the torso first (soft blends), then the head,
/// arms and legs.
pub fn parts(joints: &[Joint]) -> Vec<Part> {
    use joint::*;
    let capsule = |a: Vec3, b: Vec3, ra: f32, rb: f32| Shape::Capsule { a, b, ra, rb };
    let ellipsoid = |center: Vec3, radii: Vec3| Shape::Ellipsoid { center, rotation: Quat::IDENTITY, radii };
    let part = |shape: Shape, bone: usize, blend: f32| Part { shape, bone, blend };
    // Torso pieces overlap a lot; a wide blend (6 cm) turns them into one smooth trunk.
    const TORSO_BLEND: f32 = 0.06;
    // Limbs join the trunk with a tighter crease (3 cm) so armpits and the crotch stay readable.
    const LIMB_BLEND: f32 = 0.03;
    // Small features (nose, ears, thumb) need a small blend or they melt away.
    const DETAIL_BLEND: f32 = 0.012;

    let mut parts = vec![
        part(ellipsoid(Vec3::new(0.0, 0.945, -0.005), Vec3::new(0.165, 0.12, 0.11)), HIPS, TORSO_BLEND),
        part(ellipsoid(Vec3::new(0.0, 0.87, -0.035), Vec3::new(0.13, 0.08, 0.07)), HIPS, TORSO_BLEND),
        part(ellipsoid(Vec3::new(0.0, 1.11, 0.0), Vec3::new(0.148, 0.16, 0.095)), SPINE, TORSO_BLEND),
        part(ellipsoid(Vec3::new(0.0, 1.30, 0.0), Vec3::new(0.16, 0.16, 0.105)), CHEST, TORSO_BLEND),
        part(ellipsoid(Vec3::new(0.0, 1.28, 0.03), Vec3::new(0.14, 0.08, 0.075)), CHEST, TORSO_BLEND),
    ];
    for (clavicle, upper, fore, hand, thumb) in [
        (L_CLAVICLE, L_UPPER_ARM, L_FOREARM, L_HAND, L_THUMB),
        (R_CLAVICLE, R_UPPER_ARM, R_FOREARM, R_HAND, R_THUMB),
    ] {
        let c = &joints[clavicle];
        parts.push(part(capsule(c.head, c.tail, 0.06, 0.052), clavicle, TORSO_BLEND));
        let u = &joints[upper];
        parts.push(part(capsule(u.head, u.tail, 0.05, 0.041), upper, LIMB_BLEND));
        let f = &joints[fore];
        parts.push(part(capsule(f.head, f.tail, 0.04, 0.029), fore, LIMB_BLEND));
        // A mitten: palm and fingers as flat rounded boxes in the hand frame (local x = thickness,
        // local y = along the bone, local z = width, which lies along the body's Z). Their edge
        // radius stays above the mesher's cell so the rims polygonize cleanly.
        let h = &joints[hand];
        let along = (h.tail - h.head).normalize();
        let frame = hand_frame(along, h.head.x.signum());
        parts.push(part(
            Shape::RoundedBox {
                center: h.head + 0.055 * along,
                rotation: frame,
                half: Vec3::new(0.0, 0.042, 0.027),
                radius: 0.015,
            },
            hand,
            LIMB_BLEND,
        ));
        parts.push(part(
            Shape::RoundedBox {
                center: h.head + 0.137 * along,
                rotation: frame,
                half: Vec3::new(0.0, 0.04, 0.025),
                radius: 0.011,
            },
            hand,
            DETAIL_BLEND,
        ));
        let t = &joints[thumb];
        parts.push(part(capsule(t.head, t.tail, 0.015, 0.012), thumb, DETAIL_BLEND));
    }
    for (upper, lower, foot, toes) in
        [(L_UPPER_LEG, L_LOWER_LEG, L_FOOT, L_TOES), (R_UPPER_LEG, R_LOWER_LEG, R_FOOT, R_TOES)]
    {
        let u = &joints[upper];
        parts.push(part(capsule(u.head, u.tail, 0.078, 0.052), upper, LIMB_BLEND));
        let l = &joints[lower];
        parts.push(part(capsule(l.head, l.tail, 0.05, 0.035), lower, LIMB_BLEND));
        // Calf muscle: behind and below the knee.
        let calf = l.head.lerp(l.tail, 0.3) + Vec3::new(0.0, 0.0, -0.018);
        parts.push(part(ellipsoid(calf, Vec3::new(0.048, 0.12, 0.048)), lower, LIMB_BLEND));
        // A shoe: a rounded box from the heel to the ball (foot bone) and a flatter one for the
        // toes; the floor cut flattens the sole.
        let x = joints[foot].head.x;
        let shoe = |center: Vec3, half: Vec3, radius: f32| Shape::RoundedBox {
            center,
            rotation: Quat::IDENTITY,
            half,
            radius,
        };
        parts.push(part(
            shoe(Vec3::new(x, 0.045, 0.022), Vec3::new(0.016, 0.018, 0.058), 0.032),
            foot,
            LIMB_BLEND,
        ));
        parts.push(part(
            shoe(Vec3::new(x, 0.03, 0.148), Vec3::new(0.014, 0.002, 0.028), 0.03),
            toes,
            LIMB_BLEND,
        ));
    }
    parts.extend([
        part(
            capsule(joints[NECK].head - Vec3::new(0.0, 0.03, 0.0), joints[NECK].tail, 0.053, 0.049),
            NECK,
            LIMB_BLEND,
        ),
        part(ellipsoid(Vec3::new(0.0, 1.643, 0.005), Vec3::new(0.089, 0.107, 0.104)), HEAD, LIMB_BLEND),
        part(ellipsoid(Vec3::new(0.0, 1.578, 0.03), Vec3::new(0.066, 0.056, 0.07)), HEAD, LIMB_BLEND),
        part(ellipsoid(Vec3::new(0.0, 1.628, 0.104), Vec3::new(0.014, 0.026, 0.02)), HEAD, DETAIL_BLEND),
        part(ellipsoid(Vec3::new(0.086, 1.635, 0.0), Vec3::new(0.014, 0.03, 0.02)), HEAD, DETAIL_BLEND),
        part(ellipsoid(Vec3::new(-0.086, 1.635, 0.0), Vec3::new(0.014, 0.03, 0.02)), HEAD, DETAIL_BLEND),
    ]);
    parts
}

/// The hand's frame: local y along the bone, local z along the body's +Z (palm width), local x
/// the palm's normal, pointing away from the body for both hands.
fn hand_frame(along: Vec3, side: f32) -> Quat {
    let z = Vec3::Z;
    let x = along.cross(z).normalize() * -side;
    let x = if x.dot(Vec3::new(side, 0.0, 0.0)) < 0.0 { -x } else { x };
    let z = x.cross(along);
    Quat::from_mat3(&glam::Mat3::from_cols(x, along, z)).normalize()
}
