//! `lowpoly-robot.glb`: a flat-shaded low-poly robot of the kind a game's asset store sells, a
//! different design from [`crate::robot`]'s: stocky (1.5 m), a big head, long gorilla arms with
//! heavy forearms and three-fingered hands with a thumb, short legs, back tanks. Every triangle
//! has its own three vertices and face normal and no two neighbours are coplanar
//! ([`crate::facets`]), so every edge is a normal seam. Every vertex follows one joint (weight 1).
//! 53 joints, two meshes with their own skins (body; head), one primitive per material in each.
//! The head mesh has three morph targets (`Smile`, `Open`, `Blink`; position and normal deltas,
//! copies of a position moving together); clips `Walk` (1 s), `Chatter` (2 s: the three weights,
//! head and an arm wave) and `Idle` (3 s), all LINEAR.

use glam::Vec3;

use crate::facets::{along, ball, sweep, tented_box};
use crate::keys::{joint_index, key_times, track, wave};
use crate::math::{sin_cos, turn};
use crate::robot::{Design, RClip, RJoint, RMesh, RPrimitive};
use crate::shapes::Shape;

const MATERIALS: [(&str, [f32; 4]); 6] = [
    ("Hull", [0.85, 0.83, 0.78, 1.0]),
    ("Frame", [0.18, 0.2, 0.24, 1.0]),
    ("Teal", [0.05, 0.55, 0.55, 1.0]),
    ("Lens", [0.95, 0.8, 0.1, 1.0]),
    ("Rubber", [0.08, 0.08, 0.08, 1.0]),
    ("Screen", [0.1, 0.15, 0.2, 1.0]),
];
const HULL: usize = 0;
const FRAME: usize = 1;
const TEAL: usize = 2;
const LENS: usize = 3;
const RUBBER: usize = 4;
const SCREEN: usize = 5;

/// The skeleton: hips, two spine joints, chest, neck, head, jaw, two eyes, two antennas (11); per
/// arm clavicle, upper arm, forearm, hand, three fingers and a thumb of three bones (16); per leg
/// upper leg, lower leg, ankle, foot, toe (5). 53 in all.
fn skeleton() -> Vec<RJoint> {
    let mut joints: Vec<RJoint> = Vec::new();
    let mut add = |name: String, parent: Option<usize>, head: Vec3| {
        joints.push(RJoint { name, parent, head });
        joints.len() - 1
    };
    let hips = add("Hips".into(), None, Vec3::new(0.0, 0.62, 0.0));
    let spine1 = add("Spine1".into(), Some(hips), Vec3::new(0.0, 0.72, 0.0));
    let spine2 = add("Spine2".into(), Some(spine1), Vec3::new(0.0, 0.84, 0.0));
    let chest = add("Chest".into(), Some(spine2), Vec3::new(0.0, 0.96, 0.0));
    let neck = add("Neck".into(), Some(chest), Vec3::new(0.0, 1.17, 0.03));
    let head = add("Head".into(), Some(neck), Vec3::new(0.0, 1.24, 0.04));
    add("Jaw".into(), Some(head), Vec3::new(0.0, 1.27, 0.1));
    add("EyeL".into(), Some(head), Vec3::new(0.065, 1.38, 0.16));
    add("EyeR".into(), Some(head), Vec3::new(-0.065, 1.38, 0.16));
    add("AntennaL".into(), Some(head), Vec3::new(0.1, 1.48, -0.02));
    add("AntennaR".into(), Some(head), Vec3::new(-0.1, 1.48, -0.02));
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let clavicle = add(format!("Clavicle{side}"), Some(chest), Vec3::new(s * 0.08, 1.13, 0.0));
        let upper = add(format!("UpperArm{side}"), Some(clavicle), Vec3::new(s * 0.3, 1.12, 0.0));
        let fore = add(format!("Forearm{side}"), Some(upper), Vec3::new(s * 0.36, 0.86, 0.02));
        let hand = add(format!("Hand{side}"), Some(fore), Vec3::new(s * 0.41, 0.56, 0.05));
        for f in 0..4 {
            // Three fingers side by side along z under the hand, the thumb on the inside.
            let base = if f < 3 {
                Vec3::new(s * 0.42, 0.47, 0.05 + (f as f32 - 1.0) * 0.035)
            } else {
                Vec3::new(s * 0.37, 0.5, 0.07)
            };
            let mut parent = hand;
            for k in 0..3 {
                let head = base - Vec3::Y * (0.032 * k as f32);
                parent = add(format!("Finger{f}{k}{side}"), Some(parent), head);
            }
        }
    }
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let upper = add(format!("UpperLeg{side}"), Some(hips), Vec3::new(s * 0.12, 0.6, 0.0));
        let lower = add(format!("LowerLeg{side}"), Some(upper), Vec3::new(s * 0.14, 0.36, 0.03));
        let ankle = add(format!("Ankle{side}"), Some(lower), Vec3::new(s * 0.14, 0.11, 0.0));
        let foot = add(format!("Foot{side}"), Some(ankle), Vec3::new(s * 0.14, 0.06, 0.05));
        add(format!("Toe{side}"), Some(foot), Vec3::new(s * 0.14, 0.04, 0.15));
    }
    joints
}

/// A tube from `a` to `b` of `rings` rings whose radius follows `profile(t)` (times `(rx, ry)`),
/// pointed ends standing `tip` beyond them. Every other ring is 6 % thinner (a ribbed limb), so
/// no profile is straight and no two neighbouring triangles lie in one plane.
fn limb(
    a: Vec3,
    b: Vec3,
    radii: (f32, f32),
    sides: u32,
    rings: usize,
    profile: impl Fn(f32) -> f32,
    tip: f32,
) -> Shape {
    let centers = along(a, b, rings - 1);
    let radii: Vec<(f32, f32)> = (0..rings)
        .map(|k| {
            let f = profile(k as f32 / (rings - 1) as f32) * if k % 2 == 1 { 0.94 } else { 1.0 };
            (radii.0 * f, radii.1 * f)
        })
        .collect();
    let up = if (b - a).normalize().y.abs() < 0.9 { Vec3::Y } else { Vec3::Z };
    sweep(&centers, &radii, sides, up, (tip, tip)).0
}

/// Bulges in the middle: 0.8 at the ends, 1 at mid-length.
fn barrel(t: f32) -> f32 {
    0.8 + 0.2 * sin_cos(std::f32::consts::PI * t).0
}

/// Parts of one mesh, merged into one primitive per material.
struct MeshParts {
    /// Per material: the shape and each vertex's joint (skin-local).
    by_material: Vec<(Shape, Vec<u16>)>,
    skin: Vec<usize>,
}

impl MeshParts {
    fn new(skin: Vec<usize>) -> Self {
        MeshParts {
            by_material: (0..MATERIALS.len()).map(|_| (Shape::default(), Vec::new())).collect(),
            skin,
        }
    }

    /// Adds `shape` rigidly bound to joint `joint` (a design index) in `material`.
    fn add(&mut self, shape: Shape, joint: usize, material: usize) {
        let local = self.skin.iter().position(|&j| j == joint).expect("joint in the mesh's skin") as u16;
        let (all, joints) = &mut self.by_material[material];
        joints.extend(std::iter::repeat_n(local, shape.positions.len()));
        all.append(&shape);
    }

    fn primitives(self) -> Vec<RPrimitive> {
        self.by_material
            .into_iter()
            .enumerate()
            .filter(|(_, (shape, _))| !shape.indices.is_empty())
            .map(|(material, (shape, joints))| {
                let weights = vec![[1.0, 0.0, 0.0, 0.0]; joints.len()];
                let joints = joints.into_iter().map(|j| [j, 0, 0, 0]).collect();
                RPrimitive { shape, joints, weights, material, targets: Vec::new() }
            })
            .collect()
    }
}

/// The robot.
pub fn lowpoly_robot() -> Design {
    let joints = skeleton();
    let j = |name: &str| joint_index(&joints, name);
    let at = |name: &str| joints[j(name)].head;
    let is_head = |name: &str| matches!(name, "Head" | "Jaw" | "EyeL" | "EyeR" | "AntennaL" | "AntennaR");
    let body_skin: Vec<usize> = (0..joints.len()).filter(|&i| !is_head(&joints[i].name)).collect();
    let head_skin: Vec<usize> = (0..joints.len()).filter(|&i| is_head(&joints[i].name)).collect();
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    let upright = (x, y, z);

    let mut body = MeshParts::new(body_skin);
    body.add(limb(at("Hips") - y * 0.08, at("Spine1"), (0.16, 0.12), 12, 4, barrel, 0.03), j("Hips"), FRAME);
    body.add(limb(at("Spine1"), at("Spine2"), (0.12, 0.1), 8, 3, |_| 1.0, 0.02), j("Spine1"), RUBBER);
    body.add(limb(at("Spine2"), at("Chest"), (0.17, 0.13), 10, 3, barrel, 0.02), j("Spine2"), TEAL);
    body.add(
        limb(
            at("Chest"),
            at("Neck") - y * 0.02,
            (0.24, 0.17),
            14,
            6,
            |t| 0.85 + 0.25 * sin_cos(3.0 * t).0,
            0.04,
        ),
        j("Chest"),
        HULL,
    );
    for s in [1.0, -1.0] {
        let tank = at("Chest") + Vec3::new(s * 0.09, 0.09, -0.17);
        body.add(limb(tank - y * 0.1, tank + y * 0.1, (0.06, 0.06), 8, 4, barrel, 0.03), j("Chest"), FRAME);
    }
    body.add(
        tented_box(at("Chest") + Vec3::new(0.0, 0.1, 0.19), upright, Vec3::new(0.1, 0.06, 0.02), 0.5),
        j("Chest"),
        TEAL,
    );
    body.add(
        limb(at("Neck") - y * 0.03, at("Head") + y * 0.02, (0.05, 0.05), 8, 2, |_| 1.0, 0.01),
        j("Neck"),
        RUBBER,
    );
    for side in ["L", "R"] {
        let n = |base: &str| format!("{base}{side}");
        let (shoulder, elbow, wrist) = (at(&n("UpperArm")), at(&n("Forearm")), at(&n("Hand")));
        body.add(ball(shoulder + y * 0.02, y, Vec3::new(0.1, 0.08, 0.1), 12, 6), j(&n("Clavicle")), TEAL);
        body.add(limb(shoulder, elbow, (0.055, 0.055), 10, 4, barrel, 0.02), j(&n("UpperArm")), FRAME);
        body.add(ball(elbow, elbow - shoulder, Vec3::splat(0.055), 8, 4), j(&n("Forearm")), RUBBER);
        // The heavy forearm swells towards the wrist.
        let swell = |t: f32| 0.75 + 0.35 * t - 0.15 * t * t;
        body.add(limb(elbow, wrist, (0.085, 0.08), 12, 5, swell, 0.03), j(&n("Forearm")), HULL);
        let hand = wrist.lerp(wrist - y * 0.09, 0.5);
        body.add(tented_box(hand, upright, Vec3::new(0.03, 0.045, 0.06), 0.3), j(&n("Hand")), FRAME);
        for f in 0..4 {
            for k in 0..3 {
                let name = format!("Finger{f}{k}{side}");
                let a = at(&name);
                let finger = limb(a, a - y * 0.03, (0.012, 0.012), 5, 2, |_| 1.0, 0.006);
                body.add(finger, j(&name), if k == 2 { TEAL } else { RUBBER });
            }
        }
    }
    for side in ["L", "R"] {
        let n = |base: &str| format!("{base}{side}");
        let (hip, knee, ankle) = (at(&n("UpperLeg")), at(&n("LowerLeg")), at(&n("Ankle")));
        body.add(limb(hip, knee, (0.075, 0.07), 10, 4, barrel, 0.02), j(&n("UpperLeg")), FRAME);
        body.add(ball(knee, knee - hip, Vec3::new(0.06, 0.05, 0.06), 8, 4), j(&n("LowerLeg")), TEAL);
        let pad = (x, (knee - hip).normalize(), x.cross((knee - hip).normalize()));
        body.add(
            tented_box(knee + z * 0.06, pad, Vec3::new(0.045, 0.05, 0.015), 0.4),
            j(&n("LowerLeg")),
            HULL,
        );
        body.add(limb(knee, ankle, (0.07, 0.075), 8, 5, |t| 1.0 - 0.3 * t, 0.02), j(&n("LowerLeg")), HULL);
        body.add(ball(ankle, y, Vec3::splat(0.04), 6, 3), j(&n("Ankle")), RUBBER);
        let foot = at(&n("Foot"));
        body.add(
            tented_box(foot + Vec3::new(0.0, -0.02, 0.01), upright, Vec3::new(0.06, 0.035, 0.08), 0.25),
            j(&n("Foot")),
            FRAME,
        );
        let toe = at(&n("Toe"));
        body.add(
            tented_box(toe + Vec3::new(0.0, -0.01, 0.0), upright, Vec3::new(0.055, 0.025, 0.035), 0.3),
            j(&n("Toe")),
            HULL,
        );
    }

    let mut head = MeshParts::new(head_skin);
    let skull = at("Head") + Vec3::new(0.0, 0.13, 0.0);
    // A wide faceted dome, 14 sides, its front the screen the morph targets move.
    head.add(ball(skull, y, Vec3::new(0.17, 0.15, 0.16), 16, 9), j("Head"), SCREEN);
    let jaw = at("Jaw") + z * 0.05;
    head.add(limb(jaw - x * 0.09, jaw + x * 0.09, (0.04, 0.05), 8, 3, barrel, 0.02), j("Jaw"), FRAME);
    for side in ["L", "R"] {
        let eye = at(&format!("Eye{side}"));
        head.add(ball(eye + z * 0.01, z, Vec3::new(0.035, 0.02, 0.03), 8, 4), j(&format!("Eye{side}")), LENS);
        let base = at(&format!("Antenna{side}"));
        let tip = base + Vec3::new(base.x * 0.4, 0.12, -0.03);
        head.add(
            limb(base, tip, (0.01, 0.01), 5, 3, |t| 1.0 - 0.4 * t, 0.005),
            j(&format!("Antenna{side}")),
            FRAME,
        );
        head.add(ball(tip, y, Vec3::splat(0.022), 6, 3), j(&format!("Antenna{side}")), LENS);
    }
    let (body_skin, head_skin) = (body.skin.clone(), head.skin.clone());
    let mut head_primitives = head.primitives();
    add_face_targets(&mut head_primitives, skull);

    let meshes = vec![
        RMesh { name: "Body", skin: body_skin, primitives: body.primitives(), default_weights: Vec::new() },
        RMesh {
            name: "Head",
            skin: head_skin,
            primitives: head_primitives,
            default_weights: vec![0.0, 0.0, 0.0],
        },
    ];
    let materials = MATERIALS.iter().map(|&(name, c)| (name.to_string(), c)).collect();
    let clips = clips(&joints, 1);
    Design { scene: "LowPolyRobot", joints, materials, meshes, clips }
}

/// The head's three targets, on every primitive of the head mesh: `Smile` (the screen's lower
/// corners rise and recede), `Open` (its lower front drops and recedes, the mouth opening) and
/// `Blink` (the lenses flatten to a slit). A position's copies all move by its delta; each
/// triangle's normal deltas are its new face normal minus its old.
fn add_face_targets(primitives: &mut [RPrimitive], skull: Vec3) {
    // Displacement of a point per target (in metres), from its offset to the skull's centre.
    let smile = |p: Vec3, screen: bool| {
        let d = p - skull;
        let front = (d.z / 0.16).max(0.0);
        let low = ((-d.y) / 0.12).clamp(0.0, 1.0);
        let side = (d.x.abs() / 0.12).min(1.0);
        if screen {
            Vec3::new(0.0, 0.02, -0.01) * (front * low * side)
        } else {
            Vec3::ZERO
        }
    };
    let open = |p: Vec3, screen: bool| {
        let d = p - skull;
        let front = (d.z / 0.16).max(0.0);
        let low = ((-d.y - 0.02) / 0.1).clamp(0.0, 1.0);
        if screen {
            Vec3::new(0.0, -0.025, -0.015) * (front * front * low)
        } else {
            Vec3::ZERO
        }
    };
    for prim in primitives.iter_mut() {
        let screen = prim.material == SCREEN;
        let lens = prim.material == LENS;
        // A lens flattens towards its own centre line: the mean height of its copies' ball.
        let blink =
            |p: Vec3| if lens && p.z > 0.1 { Vec3::new(0.0, (1.38 - p.y) * 0.8, -0.005) } else { Vec3::ZERO };
        let moves: [&dyn Fn(Vec3) -> Vec3; 3] = [&|p| smile(p, screen), &|p| open(p, screen), &blink];
        for target in moves {
            let moved: Vec<Vec3> = prim.shape.positions.iter().map(|&p| p + target(p)).collect();
            let mut normals = vec![Vec3::ZERO; moved.len()];
            for t in prim.shape.indices.chunks_exact(3) {
                let [a, b, c] = [0, 1, 2].map(|k| moved[t[k] as usize]);
                let n = (b - a).cross(c - a).normalize();
                for &v in t {
                    normals[v as usize] = n - prim.shape.normals[v as usize];
                }
            }
            let deltas = moved.iter().zip(&prim.shape.positions).map(|(m, p)| *m - *p).collect();
            prim.targets.push((deltas, normals));
        }
    }
}

fn clips(joints: &[RJoint], head_mesh: usize) -> Vec<RClip> {
    let j = |name: &str| joint_index(joints, name);

    let walk_times = key_times(1.0, 20);
    let mut walk = vec![
        track(j("UpperLegL"), &|t| turn(Vec3::X, -32.0 * wave(t, 1.0)), &walk_times),
        track(j("UpperLegR"), &|t| turn(Vec3::X, 32.0 * wave(t, 1.0)), &walk_times),
        track(j("LowerLegL"), &|t| turn(Vec3::X, 40.0 * (-wave(t + 0.15, 1.0)).max(0.0)), &walk_times),
        track(j("LowerLegR"), &|t| turn(Vec3::X, 40.0 * wave(t + 0.15, 1.0).max(0.0)), &walk_times),
        track(j("FootL"), &|t| turn(Vec3::X, 12.0 * wave(t + 0.25, 1.0)), &walk_times),
        track(j("FootR"), &|t| turn(Vec3::X, -12.0 * wave(t + 0.25, 1.0)), &walk_times),
        track(j("UpperArmL"), &|t| turn(Vec3::X, 30.0 * wave(t, 1.0)), &walk_times),
        track(j("UpperArmR"), &|t| turn(Vec3::X, -30.0 * wave(t, 1.0)), &walk_times),
        track(j("ForearmL"), &|t| turn(Vec3::X, -25.0 - 15.0 * wave(t, 1.0)), &walk_times),
        track(j("ForearmR"), &|t| turn(Vec3::X, -25.0 + 15.0 * wave(t, 1.0)), &walk_times),
        track(j("Spine2"), &|t| turn(Vec3::Y, 10.0 * wave(t, 1.0)), &walk_times),
        track(j("Chest"), &|t| turn(Vec3::Z, 4.0 * wave(t, 1.0)), &walk_times),
        track(j("Head"), &|t| turn(Vec3::X, 5.0 * wave(t, 0.5)), &walk_times),
        track(j("AntennaL"), &|t| turn(Vec3::Z, 15.0 * wave(t + 0.1, 0.5)), &walk_times),
        track(j("AntennaR"), &|t| turn(Vec3::Z, -15.0 * wave(t + 0.1, 0.5)), &walk_times),
    ];
    for side in ["L", "R"] {
        for f in 0..4 {
            let curl = move |t: f32| turn(Vec3::X, -15.0 - 10.0 * wave(t, 1.0));
            walk.push(track(j(&format!("Finger{f}0{side}")), &curl, &walk_times));
        }
    }
    let walk = RClip { name: "Walk", rotations: walk, weights: Vec::new(), times: walk_times };

    let chatter_times = key_times(2.0, 40);
    // 0 → 1 → 0 over the clip.
    let rise = |t: f32| 0.5 - 0.5 * sin_cos(std::f32::consts::TAU * t / 2.0).1;
    let mut weights = Vec::new();
    for &t in &chatter_times {
        let blink = (1.0 - ((t - 1.2) / 0.12).abs()).max(0.0);
        weights.extend([rise(t), (0.5 + 0.5 * wave(t, 0.3)) * rise(t), blink]);
    }
    let mut chatter = vec![
        track(j("Jaw"), &|t| turn(Vec3::X, 8.0 * (0.5 + 0.5 * wave(t, 0.3))), &chatter_times),
        track(j("Head"), &|t| turn(Vec3::new(0.2, 1.0, 0.0), 25.0 * wave(t, 2.0)), &chatter_times),
        track(j("Neck"), &|t| turn(Vec3::Z, 8.0 * rise(t)), &chatter_times),
        track(j("ClavicleR"), &|t| turn(Vec3::Z, -15.0 * rise(t)), &chatter_times),
        track(j("UpperArmR"), &|t| turn(Vec3::Z, -110.0 * rise(t)), &chatter_times),
        track(j("ForearmR"), &|t| turn(Vec3::Z, -30.0 * rise(t) * (1.0 + wave(t, 0.5))), &chatter_times),
        track(j("HandR"), &|t| turn(Vec3::Y, 30.0 * wave(t, 0.5) * rise(t)), &chatter_times),
        track(j("EyeL"), &|t| turn(Vec3::Y, 15.0 * wave(t, 1.0)), &chatter_times),
        track(j("EyeR"), &|t| turn(Vec3::Y, 15.0 * wave(t, 1.0)), &chatter_times),
    ];
    for f in 0..4 {
        for k in 0..3 {
            let spread =
                move |t: f32| turn(Vec3::X, -30.0 * rise(t) * (0.5 + 0.5 * wave(t + 0.1 * k as f32, 0.5)));
            chatter.push(track(j(&format!("Finger{f}{k}R")), &spread, &chatter_times));
        }
    }
    let chatter = RClip {
        name: "Chatter",
        rotations: chatter,
        weights: vec![(head_mesh, weights)],
        times: chatter_times,
    };

    let idle_times = key_times(3.0, 30);
    let idle = RClip {
        name: "Idle",
        rotations: vec![
            track(j("Spine1"), &|t| turn(Vec3::X, 3.0 * wave(t, 3.0)), &idle_times),
            track(j("Head"), &|t| turn(Vec3::Y, 20.0 * wave(t, 3.0)), &idle_times),
            track(j("UpperArmL"), &|t| turn(Vec3::Z, 5.0 * wave(t, 1.5)), &idle_times),
            track(j("UpperArmR"), &|t| turn(Vec3::Z, -5.0 * wave(t, 1.5)), &idle_times),
            track(j("AntennaL"), &|t| turn(Vec3::X, 10.0 * wave(t, 0.75)), &idle_times),
            track(j("AntennaR"), &|t| turn(Vec3::X, -10.0 * wave(t, 0.75)), &idle_times),
        ],
        weights: Vec::new(),
        times: idle_times,
    };
    vec![walk, chatter, idle]
}
