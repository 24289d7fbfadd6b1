//! `fingers.glb`: a humanoid in the joint layout of most rigged characters in the wild (Mixamo's
//! 65 joints: a spine of four, neck, head and its end, and per side a shoulder, arm, forearm,
//! hand, five fingers of three joints and an end each, and a leg of five), smooth-shaded and
//! skinned smoothly: along every limb, finger and the trunk, each vertex blends the two bones
//! nearest it ([`crate::critter::chain_weights`]). Its parts are closed smooth limbs that meet by
//! overlapping (the trunk, neck, arms, palms, 30 finger segments in 10 fingers, legs, feet) plus
//! two eyes, in four primitives (skin, trousers, shoes, eyes), about 24k triangles, no uvs. The
//! fingers are thin (8 to 9.5 mm radius) and bend at every joint, the kind of small part a
//! character's levels lose first. Clips `Walk` (a 1 s stride, fingers relaxed), `Grab` (2 s: both
//! hands close to fists and open) and `Wave` (2 s: the right arm raised, the hand waving), LINEAR.
//!
//! Units metres, +Z forward, Y up; an A-pose at rest; joints carry no rest rotation, as in
//! [`crate::robot`].

use glam::{Quat, Vec3};

use crate::critter::chain_weights;
use crate::keys::{joint_index, key_times, track, wave};
use crate::math::{sin_cos, turn};
use crate::robot::{Design, RClip, RJoint, RMesh, RPrimitive};
use crate::shapes::Shape;
use crate::surfaces::{ellipsoid, frame_about, grid, split, Poles};

/// Angle between a hanging arm and the arm at rest (A-pose), degrees.
const ARM_SPREAD: f32 = 45.0;

/// The fingers, thumb first: name, offset of the knuckle across the palm (+Z is the front), the
/// three phalanges' lengths, and the radius at the knuckle.
const FINGERS: [(&str, f32, [f32; 3], f32); 5] = [
    ("Thumb", 0.03, [0.035, 0.03, 0.025], 0.0095),
    ("Index", 0.024, [0.042, 0.026, 0.021], 0.0088),
    ("Middle", 0.007, [0.046, 0.029, 0.022], 0.0088),
    ("Ring", -0.01, [0.043, 0.027, 0.021], 0.0085),
    ("Pinky", -0.026, [0.034, 0.021, 0.018], 0.008),
];

/// The left arm's direction at rest; the right arm mirrors it in x.
fn arm_direction(side: f32) -> Vec3 {
    let (s, c) = sin_cos(ARM_SPREAD.to_radians());
    Vec3::new(side * s, -c, 0.0)
}

/// Where a finger starts and which way it points, for the hand whose wrist is at `wrist`.
fn finger_line(wrist: Vec3, side: f32, k: usize) -> (Vec3, Vec3) {
    let d = arm_direction(side);
    let across = FINGERS[k].1;
    if k == 0 {
        // The thumb leaves the front edge of the palm near the wrist, pointing forward and down.
        (wrist + 0.03 * d + Vec3::new(0.0, 0.0, across), (d + Vec3::new(0.0, 0.0, 0.9)).normalize())
    } else {
        (
            wrist + 0.095 * d + Vec3::new(0.0, 0.0, across),
            (d + Vec3::new(0.0, 0.0, 0.25 * across / 0.03)).normalize(),
        )
    }
}

fn skeleton() -> Vec<RJoint> {
    let mut joints: Vec<RJoint> = Vec::new();
    let mut add = |name: String, parent: Option<usize>, head: Vec3| {
        joints.push(RJoint { name, parent, head });
        joints.len() - 1
    };
    let hips = add("Hips".into(), None, Vec3::new(0.0, 0.95, 0.0));
    let spine = add("Spine".into(), Some(hips), Vec3::new(0.0, 1.05, 0.0));
    let spine1 = add("Spine1".into(), Some(spine), Vec3::new(0.0, 1.17, 0.0));
    let spine2 = add("Spine2".into(), Some(spine1), Vec3::new(0.0, 1.3, 0.0));
    let neck = add("Neck".into(), Some(spine2), Vec3::new(0.0, 1.47, 0.0));
    let head = add("Head".into(), Some(neck), Vec3::new(0.0, 1.57, 0.01));
    add("HeadTop_End".into(), Some(head), Vec3::new(0.0, 1.76, 0.01));
    for (side, name) in [(1.0, "Left"), (-1.0, "Right")] {
        let d = arm_direction(side);
        let shoulder = add(format!("{name}Shoulder"), Some(spine2), Vec3::new(0.04 * side, 1.42, 0.0));
        let arm_at = Vec3::new(0.17 * side, 1.42, 0.0);
        let arm = add(format!("{name}Arm"), Some(shoulder), arm_at);
        let fore = add(format!("{name}ForeArm"), Some(arm), arm_at + 0.28 * d);
        let wrist = arm_at + 0.53 * d;
        let hand = add(format!("{name}Hand"), Some(fore), wrist);
        for (k, &(finger, _, lengths, _)) in FINGERS.iter().enumerate() {
            let (mut at, along) = finger_line(wrist, side, k);
            let mut parent = hand;
            for (segment, length) in lengths.iter().enumerate() {
                parent = add(format!("{name}Hand{finger}{}", segment + 1), Some(parent), at);
                at += *length * along;
            }
            add(format!("{name}Hand{finger}4"), Some(parent), at);
        }
    }
    for (side, name) in [(1.0, "Left"), (-1.0, "Right")] {
        let up = add(format!("{name}UpLeg"), Some(hips), Vec3::new(0.09 * side, 0.92, 0.0));
        let leg = add(format!("{name}Leg"), Some(up), Vec3::new(0.1 * side, 0.5, 0.01));
        let foot = add(format!("{name}Foot"), Some(leg), Vec3::new(0.11 * side, 0.09, -0.02));
        let toe = add(format!("{name}ToeBase"), Some(foot), Vec3::new(0.115 * side, 0.03, 0.11));
        add(format!("{name}Toe_End"), Some(toe), Vec3::new(0.115 * side, 0.03, 0.19));
    }
    joints
}

/// A closed smooth limb from `a` to `b` with hemispherical ends: its radius at `t ∈ [0, 1]` along
/// it is `radius(t)` across the frame's `x` ([`frame_about`]) and `flat` times that across its
/// `z`; about `triangles` triangles.
fn limb(a: Vec3, b: Vec3, radius: impl Fn(f32) -> f32, flat: f32, triangles: f32) -> Shape {
    let (x, y, z) = frame_about(b - a);
    let length = a.distance(b);
    let (ra, rb) = (radius(0.0), radius(1.0));
    let total = ra + length + rb;
    let mean = radius(0.5);
    let (columns, rows) = split(triangles, std::f32::consts::PI * mean * (1.0 + flat) / total);
    grid(columns, rows.max(6), true, Poles::Both, |u, v| {
        // From beyond `b` (v = 0) to beyond `a` (v = 1), so that ∂p/∂u × ∂p/∂v points outward.
        let s = length + rb - v * total;
        let ring = if s < 0.0 {
            (ra * ra - s * s).max(0.0).sqrt()
        } else if s > length {
            (rb * rb - (s - length) * (s - length)).max(0.0).sqrt()
        } else {
            radius(s / length)
        };
        let (sp, cp) = sin_cos(std::f32::consts::TAU * u);
        a + y * s + x * (ring * cp) + z * (flat * ring * sp)
    })
}

/// Shapes with their skin, gathered into one primitive per material.
#[derive(Default)]
struct Skinned {
    shape: Shape,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
}

impl Skinned {
    /// Adds `shape`, each vertex blending the two bones of `chain` (joint, centre) nearest its
    /// distance along `axis` from `origin`.
    fn add(&mut self, shape: Shape, origin: Vec3, axis: Vec3, chain: &[(u16, f32)]) {
        for p in &shape.positions {
            let (j, w) = chain_weights(chain, (*p - origin).dot(axis));
            self.joints.push(j);
            self.weights.push(w);
        }
        self.shape.append(&shape);
    }

    fn primitive(self, material: usize) -> RPrimitive {
        RPrimitive {
            shape: self.shape,
            joints: self.joints,
            weights: self.weights,
            material,
            targets: Vec::new(),
        }
    }
}

/// The character.
pub fn fingers() -> Design {
    let joints = skeleton();
    let j = |name: &str| joint_index(&joints, name) as u16;
    let at = |name: &str| joints[j(name) as usize].head;
    let mid = |a: &str, b: &str| 0.5 * (at(a).y + at(b).y);
    let (mut skin, mut trousers, mut shoes, mut eyes) =
        (Skinned::default(), Skinned::default(), Skinned::default(), Skinned::default());

    // The trunk: hips to shoulders, its depth (the frame's x is +Z) narrower at the waist, its
    // width 1.45 times that.
    let trunk = |t: f32| 0.1 - 0.015 * sin_cos(std::f32::consts::PI * t.min(0.7) / 0.7).0 + 0.015 * t;
    let chain = [
        (j("Hips"), mid("Hips", "Spine")),
        (j("Spine"), mid("Spine", "Spine1")),
        (j("Spine1"), mid("Spine1", "Spine2")),
        (j("Spine2"), mid("Spine2", "Neck")),
        (j("Neck"), at("Neck").y + 0.03),
    ];
    let (bottom, top) = (Vec3::new(0.0, 0.86, 0.0), Vec3::new(0.0, 1.38, 0.0));
    skin.add(limb(bottom, top, trunk, 1.45, 3200.0), Vec3::ZERO, Vec3::Y, &chain);
    let chain = [(j("Spine2"), 1.4), (j("Neck"), mid("Neck", "Head")), (j("Head"), at("Head").y + 0.04)];
    skin.add(
        limb(Vec3::new(0.0, 1.38, 0.0), Vec3::new(0.0, 1.6, 0.01), |_| 0.05, 1.0, 500.0),
        Vec3::ZERO,
        Vec3::Y,
        &chain,
    );
    let head = ellipsoid(
        Vec3::new(0.0, 1.665, 0.015),
        Vec3::Y,
        Vec3::new(0.1, 0.11, 0.09),
        (0.0, 1.0),
        (0.0, 1.0),
        2000.0,
    );
    skin.add(head, Vec3::ZERO, Vec3::Y, &[(j("Head"), 0.0)]);
    for side in [0.09f32, -0.09] {
        let eye = ellipsoid(
            Vec3::new(0.4 * side, 1.68, 0.095),
            Vec3::Z,
            Vec3::splat(0.014),
            (0.0, 1.0),
            (0.0, 1.0),
            120.0,
        );
        eyes.add(eye, Vec3::ZERO, Vec3::Y, &[(j("Head"), 0.0)]);
    }

    for (side, name) in [(1.0f32, "Left"), (-1.0, "Right")] {
        let n = |part: &str| format!("{name}{part}");
        let d = arm_direction(side);
        let (arm, fore, hand) = (at(&n("Arm")), at(&n("ForeArm")), at(&n("Hand")));
        let shoulder = at(&n("Shoulder"));
        // Along the arm, measured from the shoulder joint.
        let chain = [
            (j(&n("Shoulder")), (arm - shoulder).dot(d) * 0.5),
            (j(&n("Arm")), (arm.lerp(fore, 0.5) - shoulder).dot(d)),
            (j(&n("ForeArm")), (fore.lerp(hand, 0.5) - shoulder).dot(d)),
            (j(&n("Hand")), (hand - shoulder).dot(d) + 0.02),
        ];
        let start = Vec3::new(0.12 * side, 1.42, 0.0);
        let arm_radius = |t: f32| 0.048 - 0.02 * t;
        skin.add(limb(start, hand, arm_radius, 1.0, 2400.0), shoulder, d, &chain);
        // The palm: wide across Z, thin across the arm's plane.
        let chain = [(j(&n("ForeArm")), -0.02), (j(&n("Hand")), 0.05)];
        let palm = limb(hand + 0.01 * d, hand + 0.085 * d, |_| 0.038, 0.4, 700.0);
        skin.add(palm, hand, d, &chain);
        for (k, &(finger, _, lengths, radius)) in FINGERS.iter().enumerate() {
            let (base, along) = finger_line(hand, side, k);
            let f = |segment: usize| j(&n(&format!("Hand{finger}{segment}")));
            let total: f32 = lengths.iter().sum();
            let (l1, l2) = (lengths[0], lengths[0] + lengths[1]);
            let chain = [
                (j(&n("Hand")), -0.012),
                (f(1), 0.5 * l1),
                (f(2), 0.5 * (l1 + l2)),
                (f(3), 0.5 * (l2 + total)),
            ];
            let shape = limb(base, base + total * along, |t| radius * (1.0 - 0.2 * t), 0.9, 330.0);
            skin.add(shape, base, along, &chain);
        }
    }

    for (side, name) in [(1.0f32, "Left"), (-1.0, "Right")] {
        let n = |part: &str| format!("{name}{part}");
        let (up, foot) = (at(&n("UpLeg")), at(&n("Foot")));
        let chain = [
            (j("Hips"), up.y + 0.04),
            (j(&n("UpLeg")), mid(&n("UpLeg"), &n("Leg"))),
            (j(&n("Leg")), mid(&n("Leg"), &n("Foot"))),
            (j(&n("Foot")), foot.y - 0.02),
        ];
        let leg_radius = |t: f32| 0.075 - 0.035 * t;
        let top = Vec3::new(0.085 * side, 0.97, 0.0);
        let shape = limb(top, Vec3::new(foot.x, foot.y + 0.03, foot.z), leg_radius, 1.0, 3600.0);
        // Down the leg by height: a vertex's distance along −Y from the origin is −y.
        let chain = chain.map(|(joint, y)| (joint, -y));
        trousers.add(shape, Vec3::ZERO, -Vec3::Y, &chain);
        let (toe, tip) = (at(&n("ToeBase")), at(&n("Toe_End")));
        let chain = [(j(&n("Foot")), 0.0), (j(&n("ToeBase")), (toe.z + tip.z) * 0.5)];
        let heel = Vec3::new(foot.x, 0.05, foot.z - 0.05);
        let shape = limb(heel, Vec3::new(tip.x, 0.04, tip.z), |t| 0.045 - 0.012 * t, 0.75, 900.0);
        shoes.add(shape, Vec3::ZERO, Vec3::Z, &chain);
    }

    let primitives = vec![skin.primitive(0), trousers.primitive(1), shoes.primitive(2), eyes.primitive(3)];
    let meshes = vec![RMesh {
        name: "Body",
        skin: (0..joints.len()).collect(),
        primitives,
        default_weights: Vec::new(),
    }];
    let materials = vec![
        ("Skin".to_string(), [0.87, 0.66, 0.52, 1.0]),
        ("Trousers".to_string(), [0.18, 0.22, 0.35, 1.0]),
        ("Shoes".to_string(), [0.12, 0.1, 0.09, 1.0]),
        ("Eyes".to_string(), [0.1, 0.2, 0.35, 1.0]),
    ];
    let clips = clips(&joints);
    Design { scene: "Fingers", joints, materials, meshes, clips }
}

fn clips(joints: &[RJoint]) -> Vec<RClip> {
    let j = |name: &str| joint_index(joints, name);
    // Fingers curl towards the palm, which faces the thigh in the A-pose: about −Z on the left
    // hand, +Z on the right; the thumb folds across the palm about the arm's direction.
    let curl = |side: f32, finger: usize, degrees: f32| {
        if finger == 0 {
            turn(arm_direction(side), side * 0.6 * degrees)
        } else {
            turn(Vec3::Z, -side * degrees)
        }
    };
    let hand_tracks = |tracks: &mut Vec<(usize, Vec<Quat>)>,
                       side: f32,
                       name: &str,
                       ts: &[f32],
                       angle: &dyn Fn(f32, usize) -> f32| {
        for (k, &(finger, ..)) in FINGERS.iter().enumerate() {
            for segment in 1..=3 {
                let joint = j(&format!("{name}Hand{finger}{segment}"));
                // The middle and outer joints bend a little less than the knuckle.
                let share = [1.0, 0.9, 0.7][segment - 1];
                tracks.push(track(joint, &|t| curl(side, k, share * angle(t, k)), ts));
            }
        }
    };

    const STRIDE: f32 = 1.0;
    let walk_times = key_times(STRIDE, 24);
    let mut walk = Vec::new();
    for (side, name, phase) in [(1.0f32, "Left", 0.0f32), (-1.0, "Right", 0.5)] {
        let swing = move |t: f32| wave(t + phase * STRIDE, STRIDE);
        walk.push(track(j(&format!("{name}UpLeg")), &|t| turn(Vec3::X, -28.0 * swing(t)), &walk_times));
        walk.push(track(
            j(&format!("{name}Leg")),
            &|t| turn(Vec3::X, 40.0 * wave(t + (phase + 0.3) * STRIDE, STRIDE).max(0.0)),
            &walk_times,
        ));
        walk.push(track(j(&format!("{name}Foot")), &|t| turn(Vec3::X, 12.0 * swing(t)), &walk_times));
        // Arms swing against their legs, elbows a little bent.
        walk.push(track(j(&format!("{name}Arm")), &|t| turn(Vec3::X, 20.0 * swing(t)), &walk_times));
        walk.push(track(
            j(&format!("{name}ForeArm")),
            &|t| turn(Vec3::X, -15.0 - 10.0 * swing(t).max(0.0)),
            &walk_times,
        ));
        hand_tracks(&mut walk, side, name, &walk_times, &|t, k| {
            12.0 + 6.0 * wave(t + 0.1 * k as f32, STRIDE)
        });
    }
    walk.push(track(j("Spine"), &|t| turn(Vec3::Y, 5.0 * wave(t, STRIDE)), &walk_times));
    walk.push(track(j("Spine2"), &|t| turn(Vec3::Y, -7.0 * wave(t, STRIDE)), &walk_times));
    walk.push(track(j("Head"), &|t| turn(Vec3::Y, 3.0 * wave(t, STRIDE)), &walk_times));
    let walk = RClip { name: "Walk", rotations: walk, weights: Vec::new(), times: walk_times };

    // Both hands reach forward and close to fists, then open again.
    let grab_times = key_times(2.0, 32);
    let closed = |t: f32| 0.5 - 0.5 * sin_cos(std::f32::consts::TAU * t / 2.0).1;
    let mut grab = Vec::new();
    for (side, name) in [(1.0f32, "Left"), (-1.0, "Right")] {
        grab.push(track(j(&format!("{name}Arm")), &|t| turn(Vec3::X, -50.0 * closed(t)), &grab_times));
        grab.push(track(j(&format!("{name}ForeArm")), &|t| turn(Vec3::X, -30.0 * closed(t)), &grab_times));
        grab.push(track(j(&format!("{name}Hand")), &|t| turn(Vec3::Z * side, 15.0 * closed(t)), &grab_times));
        // The fingers close one after another, index first.
        hand_tracks(&mut grab, side, name, &grab_times, &|t, k| {
            85.0 * closed((t - 0.04 * k as f32).max(0.0))
        });
    }
    let grab = RClip { name: "Grab", rotations: grab, weights: Vec::new(), times: grab_times };

    // The right arm raised, the forearm and hand waving, the fingers stretched and bending back
    // by turns; the left hand half closed.
    let wave_times = key_times(2.0, 32);
    let mut waving = vec![
        track(j("RightArm"), &|_| turn(Vec3::Z, -100.0), &wave_times),
        track(j("RightForeArm"), &|t| turn(Vec3::Z, 25.0 + 20.0 * wave(t, 0.5)), &wave_times),
        track(j("RightHand"), &|t| turn(Vec3::Z, 15.0 * wave(t + 0.1, 0.5)), &wave_times),
        track(j("Head"), &|t| turn(Vec3::Y, -10.0 - 5.0 * wave(t, 2.0)), &wave_times),
    ];
    hand_tracks(&mut waving, -1.0, "Right", &wave_times, &|t, k| {
        -8.0 + 3.0 * (k as f32 - 2.0) * wave(t, 2.0)
    });
    hand_tracks(&mut waving, 1.0, "Left", &wave_times, &|t, _| 20.0 + 10.0 * wave(t, 2.0));
    let waving = RClip { name: "Wave", rotations: waving, weights: Vec::new(), times: wave_times };
    vec![walk, grab, waving]
}
