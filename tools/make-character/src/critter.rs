//! `critter.glb`: a low-poly game animal of about 500 triangles, a fox-like quadruped with a long
//! bushy tail and thin legs, flat-shaded as such animals usually are (every triangle its own
//! corners and face normal, [`crate::facets`]), skinned smoothly: along the body, neck and tail
//! every vertex blends the two bones nearest it (by its distance along the spine), along each leg
//! likewise, the ears follow their joints. 26 joints: root, two spine joints, neck, head, two ears,
//! seven tail joints, and upper leg, lower leg and paw of four legs. One mesh, two primitives (fur
//! and the darker legs), no uvs. Clips `Run` (a 0.6 s gallop: legs, spine flex, the tail swinging
//! in a wave) and `Idle` (3 s: tail swish, a look round, an ear twitch, a lifted paw), LINEAR.
//!
//! Units metres, +Z forward (the nose), Y up; joints carry no rest rotation, as in [`crate::robot`].

use glam::Vec3;

use crate::facets::sweep;
use crate::keys::{joint_index, key_times, track, wave};
use crate::math::{sin_cos, turn};
use crate::robot::{Design, RClip, RJoint, RMesh, RPrimitive};
use crate::shapes::Shape;

/// Tail joints.
const TAIL: usize = 7;

/// The tail's joint heads and its tip: arched up, from the rump back.
fn tail_points() -> Vec<Vec3> {
    (0..=TAIL)
        .map(|k| {
            let s = k as f32 / TAIL as f32;
            Vec3::new(0.0, 0.52 + 0.1 * sin_cos(std::f32::consts::PI * s).0, -0.42 - 0.84 * s)
        })
        .collect()
}

/// The legs: name suffix, the joint they hang from, and the x and z of the leg.
const LEGS: [(&str, &str, f32, f32); 4] = [
    ("FL", "Spine2", 0.075, 0.17),
    ("FR", "Spine2", -0.075, 0.17),
    ("BL", "Root", 0.08, -0.33),
    ("BR", "Root", -0.08, -0.33),
];

fn skeleton() -> Vec<RJoint> {
    let mut joints: Vec<RJoint> = Vec::new();
    let mut add = |name: String, parent: Option<usize>, head: Vec3| {
        joints.push(RJoint { name, parent, head });
        joints.len() - 1
    };
    let root = add("Root".into(), None, Vec3::new(0.0, 0.5, -0.3));
    let spine1 = add("Spine1".into(), Some(root), Vec3::new(0.0, 0.51, -0.12));
    let spine2 = add("Spine2".into(), Some(spine1), Vec3::new(0.0, 0.53, 0.1));
    let neck = add("Neck".into(), Some(spine2), Vec3::new(0.0, 0.57, 0.3));
    let head = add("Head".into(), Some(neck), Vec3::new(0.0, 0.72, 0.42));
    add("EarL".into(), Some(head), Vec3::new(0.045, 0.8, 0.43));
    add("EarR".into(), Some(head), Vec3::new(-0.045, 0.8, 0.43));
    let mut parent = root;
    for (k, &p) in tail_points()[..TAIL].iter().enumerate() {
        parent = add(format!("Tail{}", k + 1), Some(parent), p);
    }
    for (suffix, from, x, z) in LEGS {
        let from = if from == "Root" { root } else { spine2 };
        let back = suffix.starts_with('B');
        let upper = add(format!("UpperLeg{suffix}"), Some(from), Vec3::new(x, 0.45, z));
        // Hind legs bend back at the hock, front legs stand straight.
        let lower_z = if back { z - 0.06 } else { z + 0.005 };
        let lower = add(format!("LowerLeg{suffix}"), Some(upper), Vec3::new(x, 0.25, lower_z));
        add(format!("Paw{suffix}"), Some(lower), Vec3::new(x, 0.055, z + 0.01));
    }
    joints
}

/// Weights of two joints by a coordinate `s` between the "centres" of a chain of bones, `chain`
/// being `(joint, centre)` in increasing order of centre: inside a bone's centre and the next's
/// the two blend linearly, outside the first or last the end bone has it all. The blend is
/// rounded to 1/1024 so that the two weights sum to 1 exactly; the larger comes first.
pub fn chain_weights(chain: &[(u16, f32)], s: f32) -> ([u16; 4], [f32; 4]) {
    let rigid = |j: u16| ([j, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]);
    if s <= chain[0].1 {
        return rigid(chain[0].0);
    }
    for pair in chain.windows(2) {
        let ((a, sa), (b, sb)) = (pair[0], pair[1]);
        if s <= sb {
            let w = (((s - sa) / (sb - sa)) * 1024.0).round() / 1024.0;
            return match w {
                w if w <= 0.0 => rigid(a),
                w if w >= 1.0 => rigid(b),
                w if w > 0.5 => ([b, a, 0, 0], [w, 1.0 - w, 0.0, 0.0]),
                w => ([a, b, 0, 0], [1.0 - w, w, 0.0, 0.0]),
            };
        }
    }
    rigid(chain[chain.len() - 1].0)
}

/// The animal.
pub fn critter() -> Design {
    let joints = skeleton();
    let j = |name: &str| joint_index(&joints, name) as u16;
    let at = |name: &str| joints[j(name) as usize].head;
    let tail = tail_points();

    // The body: one tube from the tail's tip to the nose, its rings (centre, across, up).
    let mut rings: Vec<(Vec3, f32, f32)> = Vec::new();
    for k in (1..=TAIL).rev() {
        // A brush: thickest two thirds of the way out.
        let s = k as f32 / TAIL as f32;
        let r = 0.03 + 0.035 * sin_cos(std::f32::consts::PI * (0.2 + 0.7 * s)).0 - 0.02 * s * s;
        rings.push((tail[k], r, r));
    }
    rings.push((tail[0], 0.045, 0.05));
    for (c, across, up) in [
        (Vec3::new(0.0, 0.5, -0.34), 0.1, 0.11),
        (Vec3::new(0.0, 0.5, -0.24), 0.115, 0.13),
        (Vec3::new(0.0, 0.5, -0.06), 0.115, 0.135),
        (Vec3::new(0.0, 0.52, 0.11), 0.105, 0.145),
        (Vec3::new(0.0, 0.55, 0.22), 0.09, 0.12),
        (Vec3::new(0.0, 0.61, 0.32), 0.065, 0.075),
        (Vec3::new(0.0, 0.68, 0.39), 0.065, 0.07),
        (Vec3::new(0.0, 0.73, 0.44), 0.08, 0.075),
        (Vec3::new(0.0, 0.735, 0.51), 0.065, 0.06),
        (Vec3::new(0.0, 0.71, 0.59), 0.03, 0.03),
    ] {
        rings.push((c, across, up));
    }
    let centers: Vec<Vec3> = rings.iter().map(|r| r.0).collect();
    // Every other ring 6 % thinner: the profile is never straight, so no two neighbouring
    // triangles lie in one plane (every edge stays a normal seam).
    let radii: Vec<(f32, f32)> = rings
        .iter()
        .enumerate()
        .map(|(k, r)| if k % 2 == 0 { (r.1, r.2) } else { (0.94 * r.1, 0.94 * r.2) })
        .collect();
    let (mut fur, _) = sweep(&centers, &radii, 8, Vec3::Y, (0.06, 0.05));
    // Bones along the body by z, tail tip first: each bone's centre is the middle of its span.
    let nose = centers[centers.len() - 1].z + 0.05;
    let mut chain: Vec<(u16, f32)> = Vec::new();
    for k in (1..=TAIL).rev() {
        chain.push((j(&format!("Tail{k}")), 0.5 * (tail[k - 1].z + tail[k].z)));
    }
    chain.push((j("Root"), 0.5 * (tail[0].z + at("Spine1").z)));
    chain.push((j("Spine1"), 0.5 * (at("Spine1").z + at("Spine2").z)));
    chain.push((j("Spine2"), 0.5 * (at("Spine2").z + at("Neck").z)));
    chain.push((j("Neck"), 0.5 * (at("Neck").z + at("Head").z)));
    chain.push((j("Head"), 0.5 * (at("Head").z + nose)));
    let (mut fur_joints, mut fur_weights): (Vec<[u16; 4]>, Vec<[f32; 4]>) =
        fur.positions.iter().map(|p| chain_weights(&chain, p.z)).unzip();
    // Ears: low three-sided pyramids on the head.
    for side in ["L", "R"] {
        let ear = at(&format!("Ear{side}"));
        let (shape, _) = sweep(
            &[ear - Vec3::Y * 0.03, ear + Vec3::Y * 0.01],
            &[(0.03, 0.018), (0.02, 0.012)],
            3,
            Vec3::Z,
            (0.005, 0.05),
        );
        let joint = j(&format!("Ear{side}"));
        fur_joints.extend(std::iter::repeat_n([joint, 0, 0, 0], shape.positions.len()));
        fur_weights.extend(std::iter::repeat_n([1.0, 0.0, 0.0, 0.0], shape.positions.len()));
        fur.append(&shape);
    }

    let mut legs = Shape::default();
    let (mut leg_joints, mut leg_weights) = (Vec::new(), Vec::new());
    for (suffix, from, x, z) in LEGS {
        let (upper, lower, paw) =
            (at(&format!("UpperLeg{suffix}")), at(&format!("LowerLeg{suffix}")), at(&format!("Paw{suffix}")));
        let thigh = if suffix.starts_with('B') { 0.05 } else { 0.04 };
        let centers = [
            Vec3::new(x, upper.y + 0.06, z),
            upper.lerp(lower, 0.5),
            lower,
            paw,
            Vec3::new(x, 0.02, paw.z + 0.04),
        ];
        let radii =
            [(thigh, thigh * 1.2), (thigh * 0.7, thigh * 0.9), (0.02, 0.022), (0.016, 0.016), (0.024, 0.02)];
        let (shape, _) = sweep(&centers, &radii, 5, Vec3::Z, (0.01, 0.02));
        // Down the leg by height: the body it hangs from, the upper leg, the lower leg, the paw.
        let leg_chain = [
            (j(&format!("Paw{suffix}")), paw.y - 0.02),
            (j(&format!("LowerLeg{suffix}")), 0.5 * (lower.y + paw.y)),
            (j(&format!("UpperLeg{suffix}")), 0.5 * (upper.y + lower.y)),
            (j(from), upper.y + 0.06),
        ];
        let (js, ws): (Vec<_>, Vec<_>) =
            shape.positions.iter().map(|p| chain_weights(&leg_chain, p.y)).unzip();
        leg_joints.extend(js);
        leg_weights.extend(ws);
        legs.append(&shape);
    }

    let primitives = vec![
        RPrimitive { shape: fur, joints: fur_joints, weights: fur_weights, material: 0, targets: Vec::new() },
        RPrimitive {
            shape: legs,
            joints: leg_joints,
            weights: leg_weights,
            material: 1,
            targets: Vec::new(),
        },
    ];
    let skin = (0..joints.len()).collect();
    let meshes = vec![RMesh { name: "Critter", skin, primitives, default_weights: Vec::new() }];
    let materials =
        vec![("Fur".to_string(), [0.85, 0.42, 0.12, 1.0]), ("Socks".to_string(), [0.15, 0.1, 0.08, 1.0])];
    let clips = clips(&joints);
    Design { scene: "Critter", joints, materials, meshes, clips }
}

fn clips(joints: &[RJoint]) -> Vec<RClip> {
    let j = |name: &str| joint_index(joints, name);

    // The gallop: hind legs together (a little apart), then the front legs half a stride later.
    const STRIDE: f32 = 0.6;
    let run_times = key_times(STRIDE, 24);
    let mut run = Vec::new();
    for (suffix, phase) in [("BL", 0.0), ("BR", 0.06), ("FL", 0.5), ("FR", 0.56)] {
        let back = suffix.starts_with('B');
        let reach = if back { 35.0 } else { 40.0 };
        let swing = move |t: f32| turn(Vec3::X, -reach * wave(t + phase * STRIDE, STRIDE));
        // The lower leg folds while the leg swings forward.
        let fold = move |t: f32| {
            let lift = wave(t + (phase + 0.25) * STRIDE, STRIDE).max(0.0);
            turn(Vec3::X, if back { -50.0 * lift } else { 60.0 * lift })
        };
        let paw = move |t: f32| turn(Vec3::X, 30.0 * wave(t + (phase + 0.1) * STRIDE, STRIDE));
        run.push(track(j(&format!("UpperLeg{suffix}")), &swing, &run_times));
        run.push(track(j(&format!("LowerLeg{suffix}")), &fold, &run_times));
        run.push(track(j(&format!("Paw{suffix}")), &paw, &run_times));
    }
    run.push(track(j("Root"), &|t| turn(Vec3::X, 6.0 * wave(t, STRIDE)), &run_times));
    run.push(track(j("Spine1"), &|t| turn(Vec3::X, -8.0 * wave(t + 0.1, STRIDE)), &run_times));
    run.push(track(j("Spine2"), &|t| turn(Vec3::X, 6.0 * wave(t + 0.2, STRIDE)), &run_times));
    run.push(track(j("Neck"), &|t| turn(Vec3::X, -8.0 * wave(t + 0.3, STRIDE)), &run_times));
    run.push(track(j("Head"), &|t| turn(Vec3::X, 6.0 * wave(t + 0.3, STRIDE)), &run_times));
    for side in ["L", "R"] {
        run.push(track(
            j(&format!("Ear{side}")),
            &|t| turn(Vec3::X, -20.0 - 5.0 * wave(t, STRIDE)),
            &run_times,
        ));
    }
    for k in 1..=TAIL {
        // A wave down the tail: each joint a little later, the side swing growing to the tip.
        let lag = 0.07 * k as f32;
        let side = 6.0 + 2.0 * k as f32;
        let f = move |t: f32| {
            turn(Vec3::Y, side * wave(t - lag * STRIDE, STRIDE))
                * turn(Vec3::X, 7.0 * wave(t - lag * STRIDE + 0.15, STRIDE))
        };
        run.push(track(j(&format!("Tail{k}")), &f, &run_times));
    }
    let run = RClip { name: "Run", rotations: run, weights: Vec::new(), times: run_times };

    let idle_times = key_times(3.0, 36);
    let rise = |t: f32| 0.5 - 0.5 * sin_cos(std::f32::consts::TAU * t / 3.0).1;
    let mut idle = vec![
        track(j("Spine1"), &|t| turn(Vec3::X, 2.0 * wave(t, 1.5)), &idle_times),
        track(
            j("Neck"),
            &|t| turn(Vec3::Y, 30.0 * wave(t, 3.0)) * turn(Vec3::X, -10.0 * rise(t)),
            &idle_times,
        ),
        track(j("Head"), &|t| turn(Vec3::Z, 12.0 * wave(t, 3.0)), &idle_times),
        track(j("EarL"), &|t| turn(Vec3::X, -25.0 * (1.0 - ((t - 1.0) / 0.15).abs()).max(0.0)), &idle_times),
        track(j("EarR"), &|t| turn(Vec3::Z, -10.0 * wave(t, 3.0)), &idle_times),
        track(j("UpperLegFL"), &|t| turn(Vec3::X, -25.0 * rise(t)), &idle_times),
        track(j("LowerLegFL"), &|t| turn(Vec3::X, 70.0 * rise(t)), &idle_times),
        track(j("PawFL"), &|t| turn(Vec3::X, 40.0 * rise(t)), &idle_times),
    ];
    for k in 1..=TAIL {
        let lag = 0.1 * k as f32;
        let f = move |t: f32| turn(Vec3::Y, (5.0 + 2.5 * k as f32) * wave(t - lag, 1.5));
        idle.push(track(j(&format!("Tail{k}")), &f, &idle_times));
    }
    let idle = RClip { name: "Idle", rotations: idle, weights: Vec::new(), times: idle_times };
    vec![run, idle]
}
