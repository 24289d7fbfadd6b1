//! Two more test characters of kinds common in the wild, built from [`crate::shapes`]:
//! - `robot.glb`: a flat-shaded low-poly robot, rigid parts parented to joints (every vertex
//!   weight 1 on one joint), 55 joints, three skins (body, hands, face), 27 primitives, and a face
//!   plate with three morph targets (position and normal deltas) whose weights two clips animate;
//! - `parts.glb`: the same skeleton wearing 57 separate smooth-shaded open armour plates (three around each of 19 bones) (one
//!   primitive each, open borders), one skin.
//!
//! Joints carry no rest rotation (local rotation identity, translation to the parent's head), so a
//! clip's rotation of a joint turns its part about the joint's head in model axes. Units: metres,
//! seconds, degrees in the pose functions. Everything goes through [`crate::math`], so the bytes
//! are the same on every platform.

use glam::{Quat, Vec3};

use crate::keys::{joint_index, key_times, track, wave};
use crate::math::{deg, sin_cos, turn};
use crate::shapes::{ball, block, prism, shell, Shape};

/// One joint at rest: name, parent, model-space head.
pub struct RJoint {
    pub name: String,
    pub parent: Option<usize>,
    pub head: Vec3,
}

/// One primitive: a shape bound to joints (skin-local indices), a material, and morph targets
/// (per target: position and normal deltas per vertex).
pub struct RPrimitive {
    pub shape: Shape,
    /// Per vertex, up to four joints (indices in the mesh's skin)…
    pub joints: Vec<[u16; 4]>,
    /// …and their weights, largest first, summing to 1 (`[1, 0, 0, 0]` for a rigid vertex).
    pub weights: Vec<[f32; 4]>,
    pub material: usize,
    pub targets: Vec<(Vec<Vec3>, Vec<Vec3>)>,
}

/// A skinned mesh node.
pub struct RMesh {
    pub name: &'static str,
    /// Joint (node) indices of its skin, in skin order.
    pub skin: Vec<usize>,
    pub primitives: Vec<RPrimitive>,
    /// Default weights of its morph targets (every primitive has as many).
    pub default_weights: Vec<f32>,
}

/// An animation: key times, per joint local rotations, per mesh morph weights (targets × keys).
pub struct RClip {
    pub name: &'static str,
    pub times: Vec<f32>,
    pub rotations: Vec<(usize, Vec<Quat>)>,
    pub weights: Vec<(usize, Vec<f32>)>,
}

pub struct Design {
    /// The scene's name.
    pub scene: &'static str,
    pub joints: Vec<RJoint>,
    pub materials: Vec<(String, [f32; 4])>,
    pub meshes: Vec<RMesh>,
    pub clips: Vec<RClip>,
}

const MATERIALS: [(&str, [f32; 4]); 5] = [
    ("Steel", [0.62, 0.64, 0.68, 1.0]),
    ("Dark", [0.12, 0.13, 0.15, 1.0]),
    ("Orange", [0.95, 0.45, 0.08, 1.0]),
    ("Glass", [0.2, 0.7, 0.95, 1.0]),
    ("Face", [0.85, 0.85, 0.8, 1.0]),
];
const STEEL: usize = 0;
const DARK: usize = 1;
const ORANGE: usize = 2;
const GLASS: usize = 3;
const FACE: usize = 4;

/// The skeleton: spine and head (9), two arms of shoulder, upper arm, forearm, hand and five
/// three-bone fingers (19 each), two legs of four (55 in all).
fn skeleton() -> Vec<RJoint> {
    let mut joints: Vec<RJoint> = Vec::new();
    let mut add = |name: String, parent: Option<usize>, head: Vec3| {
        joints.push(RJoint { name, parent, head });
        joints.len() - 1
    };
    let hips = add("Hips".into(), None, Vec3::new(0.0, 0.95, 0.0));
    let spine = add("Spine".into(), Some(hips), Vec3::new(0.0, 1.05, 0.0));
    let chest = add("Chest".into(), Some(spine), Vec3::new(0.0, 1.22, 0.0));
    let neck = add("Neck".into(), Some(chest), Vec3::new(0.0, 1.48, 0.0));
    let head = add("Head".into(), Some(neck), Vec3::new(0.0, 1.56, 0.0));
    add("Jaw".into(), Some(head), Vec3::new(0.0, 1.6, 0.04));
    add("EyeL".into(), Some(head), Vec3::new(0.045, 1.71, 0.1));
    add("EyeR".into(), Some(head), Vec3::new(-0.045, 1.71, 0.1));
    add("Antenna".into(), Some(head), Vec3::new(0.0, 1.78, 0.0));
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let shoulder = add(format!("Shoulder{side}"), Some(chest), Vec3::new(s * 0.12, 1.44, 0.0));
        let upper = add(format!("UpperArm{side}"), Some(shoulder), Vec3::new(s * 0.23, 1.44, 0.0));
        let fore = add(format!("Forearm{side}"), Some(upper), Vec3::new(s * 0.23, 1.17, 0.0));
        let hand = add(format!("Hand{side}"), Some(fore), Vec3::new(s * 0.23, 0.93, 0.0));
        for f in 0..5 {
            // Four fingers side by side under the hand, the thumb in front.
            let base = if f < 4 {
                Vec3::new(s * (0.23 + (f as f32 - 1.5) * 0.022), 0.85, 0.0)
            } else {
                Vec3::new(s * 0.2, 0.88, 0.04)
            };
            let mut parent = hand;
            for k in 0..3 {
                let head = base - Vec3::Y * (0.028 * k as f32);
                parent = add(format!("Finger{f}{k}{side}"), Some(parent), head);
            }
        }
    }
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let upper = add(format!("UpperLeg{side}"), Some(hips), Vec3::new(s * 0.1, 0.9, 0.0));
        let lower = add(format!("LowerLeg{side}"), Some(upper), Vec3::new(s * 0.1, 0.5, 0.0));
        let foot = add(format!("Foot{side}"), Some(lower), Vec3::new(s * 0.1, 0.09, 0.0));
        add(format!("Toe{side}"), Some(foot), Vec3::new(s * 0.1, 0.04, 0.1));
    }
    joints
}

/// A rigid primitive on skin-local joint `joint`.
pub fn rigid(shape: Shape, joint: u16, material: usize) -> RPrimitive {
    let joints = vec![[joint, 0, 0, 0]; shape.positions.len()];
    let weights = vec![[1.0, 0.0, 0.0, 0.0]; shape.positions.len()];
    RPrimitive { shape, joints, weights, material, targets: Vec::new() }
}

/// The materials of a fixed table, named.
fn named(table: &[(&str, [f32; 4])]) -> Vec<(String, [f32; 4])> {
    table.iter().map(|&(name, color)| (name.to_string(), color)).collect()
}

/// The face plate (mesh "Face"; its targets, in order: Smile, Blink, Open): a grid of `N × N` facets on the front of the head, closed by a box behind it,
/// and its morph targets "Smile", "Blink" and "Open" (flat-shaded: each target's normal deltas
/// are its facets' new normals minus the old).
fn face_plate(head: u16) -> RPrimitive {
    const N: u32 = 8;
    let (x0, x1, y0, y1, z) = (-0.075, 0.075, 1.59, 1.76, 0.105);
    let grid = |i: u32, j: u32| {
        Vec3::new(x0 + (x1 - x0) * i as f32 / N as f32, y0 + (y1 - y0) * j as f32 / N as f32, z)
    };
    // Displacements of a grid point per target, in metres.
    let targets: [fn(Vec3) -> Vec3; 3] = [
        // Smile: the mouth's corners (lower third, sides) rise and move back.
        |p| {
            let mouth = ((1.65 - p.y) / 0.06).clamp(0.0, 1.0);
            let side = (p.x.abs() / 0.075).powi(2);
            Vec3::new(0.0, 0.012, -0.008) * (mouth * side)
        },
        // Blink: the eye rows (around y = 1.71) close toward their centre line.
        |p| {
            let near = (1.0 - ((p.y - 1.71) / 0.03).abs()).max(0.0);
            Vec3::new(0.0, (1.71 - p.y) * 0.8 * near, -0.004 * near)
        },
        // Open: the lower rows drop and recede (the mouth opens).
        |p| {
            let low = ((1.65 - p.y) / 0.06).clamp(0.0, 1.0);
            Vec3::new(0.0, -0.02 * low, -0.01 * low)
        },
    ];
    let mut shape = Shape::default();
    for j in 0..N {
        for i in 0..N {
            shape.facet(&[grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1)]);
        }
    }
    // A box behind the plate closes it: a back grid and four walls, all cut at the grid's
    // vertices so that the welded plate is watertight (no T-junctions).
    let back = |p: Vec3| Vec3::new(p.x, p.y, z - 0.02);
    let mut rest = Shape::default();
    for j in 0..N {
        for i in 0..N {
            let quad = [grid(i, j), grid(i, j + 1), grid(i + 1, j + 1), grid(i + 1, j)];
            rest.facet(&quad.map(back));
        }
    }
    // The rim, walked counter-clockwise seen from the front: bottom, right, top, left.
    let mut rim: Vec<Vec3> = (0..N).map(|i| grid(i, 0)).collect();
    rim.extend((0..N).map(|j| grid(N, j)));
    rim.extend((0..N).map(|i| grid(N - i, N)));
    rim.extend((0..N).map(|j| grid(0, N - j)));
    for k in 0..rim.len() {
        let (p, q) = (rim[k], rim[(k + 1) % rim.len()]);
        rest.facet(&[p, back(p), back(q), q]);
    }
    shape.append(&rest);
    // Every copy of a front-plane position moves with it: the walls' front edges too, so the
    // plate stretches instead of tearing open, as a file exported from per-vertex shape keys has
    // it (an exporter splits a vertex per facet after the keys are applied, so the copies share
    // their position deltas; only their normal deltas differ).
    let mut morphs = Vec::new();
    for target in targets {
        let moved: Vec<Vec3> =
            shape.positions.iter().map(|&p| if p.z == z { p + target(p) } else { p }).collect();
        let mut normal_deltas = vec![Vec3::ZERO; shape.positions.len()];
        for t in shape.indices.chunks_exact(3) {
            let [p, q, r] = [0, 1, 2].map(|k| moved[t[k] as usize]);
            let n = (q - p).cross(r - p).normalize();
            for &v in t {
                normal_deltas[v as usize] = n - shape.normals[v as usize];
            }
        }
        let deltas = moved.iter().zip(&shape.positions).map(|(m, p)| *m - *p).collect();
        morphs.push((deltas, normal_deltas));
    }
    let mut prim = rigid(shape, head, FACE);
    prim.targets = morphs;
    prim
}

fn clips(joints: &[RJoint], face_mesh: usize) -> Vec<RClip> {
    let j = |name: &str| joint_index(joints, name);
    let walk_times = key_times(1.2, 24);
    let walk = RClip {
        name: "Walk",
        rotations: vec![
            track(j("UpperLegL"), &|t| turn(Vec3::X, 30.0 * wave(t, 1.2)), &walk_times),
            track(j("UpperLegR"), &|t| turn(Vec3::X, -30.0 * wave(t, 1.2)), &walk_times),
            track(j("LowerLegL"), &|t| turn(Vec3::X, 25.0 * (1.0 + wave(t, 1.2))), &walk_times),
            track(j("LowerLegR"), &|t| turn(Vec3::X, 25.0 * (1.0 - wave(t, 1.2))), &walk_times),
            track(j("UpperArmL"), &|t| turn(Vec3::X, -25.0 * wave(t, 1.2)), &walk_times),
            track(j("UpperArmR"), &|t| turn(Vec3::X, 25.0 * wave(t, 1.2)), &walk_times),
            track(j("Spine"), &|t| turn(Vec3::Y, 8.0 * wave(t, 1.2)), &walk_times),
        ],
        weights: Vec::new(),
        times: walk_times.clone(),
    };
    let talk_times = key_times(2.0, 40);
    let mut weights = Vec::new();
    for &t in &talk_times {
        // Smile, Blink (a quick blink at 1 s), Open (speech rhythm).
        let blink = (1.0 - ((t - 1.0) / 0.1).abs()).max(0.0);
        weights.extend([0.5 + 0.5 * wave(t, 2.0), blink, 0.5 + 0.5 * wave(t, 0.25)]);
    }
    let talk = RClip {
        name: "Talk",
        rotations: vec![
            track(j("Jaw"), &|t| turn(Vec3::X, 6.0 + 6.0 * wave(t, 0.25)), &talk_times),
            track(j("Head"), &|t| turn(Vec3::Y, 15.0 * wave(t, 2.0)), &talk_times),
        ],
        weights: vec![(face_mesh, weights)],
        times: talk_times.clone(),
    };
    let grab_times = key_times(1.5, 30);
    let mut grab_rotations = vec![
        track(
            j("UpperArmR"),
            &|t| turn(Vec3::Z, -60.0 * (0.5 - 0.5 * sin_cos(deg(240.0 * t)).1)),
            &grab_times,
        ),
        track(
            j("ForearmR"),
            &|t| turn(Vec3::X, -50.0 * (0.5 - 0.5 * sin_cos(deg(240.0 * t)).1)),
            &grab_times,
        ),
    ];
    for f in 0..5 {
        for k in 0..3 {
            let curl = move |t: f32| turn(Vec3::X, 35.0 * (0.5 - 0.5 * sin_cos(deg(240.0 * t)).1));
            grab_rotations.push(track(j(&format!("Finger{f}{k}R")), &curl, &grab_times));
        }
    }
    let mut grab_weights = Vec::new();
    for &t in &grab_times {
        grab_weights.extend([0.5 - 0.5 * sin_cos(deg(240.0 * t)).1, 0.0, 0.0]);
    }
    let grab = RClip {
        name: "Grab",
        rotations: grab_rotations,
        weights: vec![(face_mesh, grab_weights)],
        times: grab_times,
    };
    vec![walk, talk, grab]
}

/// The flat-shaded robot.
pub fn robot() -> Design {
    let joints = skeleton();
    let j = |name: &str| joint_index(&joints, name);
    let head_of = |name: &str| joints[j(name)].head;
    // Skins: body (everything but hands and fingers, and the face bones), hands, face.
    let is_hand = |name: &str| name.starts_with("Hand") || name.starts_with("Finger");
    let is_face = |name: &str| matches!(name, "Head" | "Jaw" | "EyeL" | "EyeR");
    let body_skin: Vec<usize> = (0..joints.len()).filter(|&i| !is_hand(&joints[i].name)).collect();
    let hand_skin: Vec<usize> = (0..joints.len()).filter(|&i| is_hand(&joints[i].name)).collect();
    let face_skin: Vec<usize> = (0..joints.len()).filter(|&i| is_face(&joints[i].name)).collect();
    let local =
        |skin: &[usize], name: &str| skin.iter().position(|&i| i == j(name)).expect("joint in skin") as u16;

    let mut body = Vec::new();
    let mut part = |shape: Shape, joint: &str, material: usize| {
        body.push(rigid(shape, local(&body_skin, joint), material));
    };
    part(block(Vec3::new(-0.14, 0.86, -0.09), Vec3::new(0.14, 1.0, 0.09), 2), "Hips", DARK);
    part(prism(head_of("Spine"), head_of("Chest"), (0.08, 0.07), 8, 3, 0.0), "Spine", STEEL);
    part(block(Vec3::new(-0.17, 1.22, -0.1), Vec3::new(0.17, 1.47, 0.1), 4), "Chest", ORANGE);
    part(prism(head_of("Neck"), head_of("Head"), (0.035, 0.035), 8, 2, 0.0), "Neck", DARK);
    part(block(Vec3::new(-0.1, 1.56, -0.1), Vec3::new(0.1, 1.78, 0.1), 3), "Head", STEEL);
    let antenna_tip = head_of("Antenna") + Vec3::Y * 0.08;
    let mut antenna = prism(head_of("Antenna"), antenna_tip, (0.008, 0.008), 6, 2, 0.0);
    antenna.append(&ball(antenna_tip, 0.018, 6, 4));
    part(antenna, "Antenna", ORANGE);
    for side in ["L", "R"] {
        let n = |base: &str| format!("{base}{side}");
        let mut shoulder = ball(head_of(&n("Shoulder")), 0.055, 8, 4);
        shoulder.append(&prism(head_of(&n("Shoulder")), head_of(&n("UpperArm")), (0.03, 0.03), 6, 2, 0.0));
        part(shoulder, &n("Shoulder"), ORANGE);
        let mut upper = prism(head_of(&n("UpperArm")), head_of(&n("Forearm")), (0.045, 0.045), 8, 3, 0.0);
        upper.append(&ball(head_of(&n("Forearm")), 0.04, 8, 4));
        part(upper, &n("UpperArm"), STEEL);
        part(
            prism(head_of(&n("Forearm")), head_of(&n("Hand")), (0.04, 0.05), 8, 3, 0.0),
            &n("Forearm"),
            STEEL,
        );
        let mut upper_leg = prism(head_of(&n("UpperLeg")), head_of(&n("LowerLeg")), (0.06, 0.06), 8, 4, 0.0);
        upper_leg.append(&ball(head_of(&n("LowerLeg")), 0.055, 8, 4));
        part(upper_leg, &n("UpperLeg"), STEEL);
        part(
            prism(head_of(&n("LowerLeg")), head_of(&n("Foot")), (0.05, 0.06), 8, 4, 0.0),
            &n("LowerLeg"),
            ORANGE,
        );
        let f = head_of(&n("Foot"));
        part(block(f + Vec3::new(-0.05, -0.09, -0.06), f + Vec3::new(0.05, 0.0, 0.1), 1), &n("Foot"), DARK);
        let t = head_of(&n("Toe"));
        part(block(t + Vec3::new(-0.05, -0.04, 0.0), t + Vec3::new(0.05, 0.0, 0.07), 1), &n("Toe"), DARK);
    }

    let mut hands = Vec::new();
    for side in ["L", "R"] {
        let hand = head_of(&format!("Hand{side}"));
        let palm = block(hand + Vec3::new(-0.05, -0.08, -0.025), hand + Vec3::new(0.05, 0.0, 0.025), 2);
        hands.push(rigid(palm, local(&hand_skin, &format!("Hand{side}")), DARK));
        let mut fingers = rigid(Shape::default(), 0, STEEL);
        for f in 0..5 {
            for k in 0..3 {
                let name = format!("Finger{f}{k}{side}");
                let a = head_of(&name);
                let bone = prism(a, a - Vec3::Y * 0.026, (0.009, 0.009), 6, 2, 0.0);
                let joint = [local(&hand_skin, &name), 0, 0, 0];
                fingers.joints.extend(std::iter::repeat_n(joint, bone.positions.len()));
                fingers.weights.extend(std::iter::repeat_n([1.0, 0.0, 0.0, 0.0], bone.positions.len()));
                fingers.shape.append(&bone);
            }
        }
        hands.push(fingers);
    }

    let mut face = vec![face_plate(local(&face_skin, "Head"))];
    face.push(rigid(
        block(Vec3::new(-0.06, 1.56, 0.06), Vec3::new(0.06, 1.6, 0.11), 1),
        local(&face_skin, "Jaw"),
        DARK,
    ));
    for side in ["L", "R"] {
        let name = format!("Eye{side}");
        face.push(rigid(ball(head_of(&name) + Vec3::Z * 0.01, 0.018, 8, 4), local(&face_skin, &name), GLASS));
    }
    // Every face primitive carries the three targets (the others' deltas are zero).
    for prim in &mut face[1..] {
        let zero = vec![Vec3::ZERO; prim.shape.positions.len()];
        prim.targets = vec![(zero.clone(), zero); 3];
    }

    let meshes = vec![
        RMesh { name: "Body", skin: body_skin, primitives: body, default_weights: Vec::new() },
        RMesh { name: "Hands", skin: hand_skin, primitives: hands, default_weights: Vec::new() },
        RMesh { name: "Face", skin: face_skin, primitives: face, default_weights: vec![0.2, 0.0, 0.0] },
    ];
    let clips = clips(&joints, 2);
    Design { scene: "Robot", joints, materials: named(&MATERIALS), meshes, clips }
}

/// The many-part character: the robot's skeleton wearing 57 open smooth-shaded plates.
pub fn parts(detail: f64) -> Design {
    // `detail` times the quads per plate: columns and rows each × √detail (8 × 4 at detail 1).
    let scale = detail.sqrt();
    let (columns, rows) = ((8.0 * scale).round() as u32, (4.0 * scale).round().max(1.0) as u32);
    let joints = skeleton();
    let skin: Vec<usize> = (0..joints.len()).collect();
    let mut primitives = Vec::new();
    // Every non-finger bone (a joint to its first child, at least 5 cm) gets three plates around
    // it, each a bit less than a third of a turn: gaps between them, open borders.
    for (i, joint) in joints.iter().enumerate() {
        if joint.name.starts_with("Finger") {
            continue;
        }
        let Some(child) = joints.iter().position(|c| c.parent == Some(i)) else { continue };
        let (a, b) = (joint.head, joints[child].head);
        if a.distance(b) < 0.05 {
            continue;
        }
        let radius = (0.02 + 0.12 * a.distance(b)).min(0.09);
        for (k, (from, to)) in [(0.02, 0.31), (0.35, 0.64), (0.68, 0.97)].into_iter().enumerate() {
            let plate = shell(a, b, (radius, radius * 0.9), (from, to), columns, rows);
            let material = [STEEL, ORANGE, DARK][(i + k) % 3];
            primitives.push(rigid(plate, i as u16, material));
        }
    }
    let meshes = vec![RMesh { name: "Armour", skin, primitives, default_weights: Vec::new() }];
    let mut clips = clips(&joints, usize::MAX);
    for clip in &mut clips {
        clip.weights.clear();
    }
    Design { scene: "Robot", joints, materials: named(&MATERIALS), meshes, clips }
}
