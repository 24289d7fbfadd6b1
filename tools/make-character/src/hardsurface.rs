//! `hardsurface.glb`: a many-part hard-surface robot, the kind of file a mech or armoured
//! character is exported as. Sixty parts on 18 joints, each part its own primitive and material:
//! most are curved open shells with boundary loops (patches of ellipsoids, barrel tubes and tori:
//! chest plates, sleeves, greaves, a visor band, a helmet open at the bottom), twelve are closed
//! (capsules, rounded boxes, joint balls), fifteen have fewer than 300 triangles (bolts, vents,
//! trims). No uvs; smooth normals within a part ([`crate::surfaces`]). Most parts follow one joint
//! rigidly; the abdomen bands, the neck sleeve, the shoulder sleeves, the elbows, knee caps,
//! ankles and hip joints blend two joints across the joint they cover. About 61k triangles at
//! `--detail 1` (`--detail F` scales every part's triangle count by `F`). Clips: `Walk` and
//! `Look` (torso twist, head turn, an arm raised), LINEAR.
//!
//! Joints carry no rest rotation, as in [`crate::robot`]; units metres, +Z forward, Y up.

use glam::Vec3;

use crate::keys::{joint_index, key_times, track, wave};
use crate::math::{sin_cos, turn};
use crate::robot::{Design, RClip, RJoint, RMesh, RPrimitive};
use crate::shapes::Shape;
use crate::surfaces::{capsule, ellipsoid, rounded_box, torus, tube};

/// The 18 joints: hips, spine, chest, head; per side clavicle, upper arm, forearm, hand, upper
/// leg, lower leg, foot.
fn skeleton() -> Vec<RJoint> {
    let mut joints: Vec<RJoint> = Vec::new();
    let mut add = |name: String, parent: Option<usize>, head: Vec3| {
        joints.push(RJoint { name, parent, head });
        joints.len() - 1
    };
    let hips = add("Hips".into(), None, Vec3::new(0.0, 1.0, 0.0));
    let spine = add("Spine".into(), Some(hips), Vec3::new(0.0, 1.14, 0.0));
    let chest = add("Chest".into(), Some(spine), Vec3::new(0.0, 1.32, 0.0));
    add("Head".into(), Some(chest), Vec3::new(0.0, 1.62, 0.0));
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let clavicle = add(format!("Clavicle{side}"), Some(chest), Vec3::new(s * 0.07, 1.55, 0.0));
        let upper = add(format!("UpperArm{side}"), Some(clavicle), Vec3::new(s * 0.26, 1.53, 0.0));
        let fore = add(format!("Forearm{side}"), Some(upper), Vec3::new(s * 0.31, 1.24, 0.0));
        add(format!("Hand{side}"), Some(fore), Vec3::new(s * 0.34, 0.98, 0.02));
    }
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let upper = add(format!("UpperLeg{side}"), Some(hips), Vec3::new(s * 0.12, 0.96, 0.0));
        let lower = add(format!("LowerLeg{side}"), Some(upper), Vec3::new(s * 0.13, 0.54, 0.0));
        add(format!("Foot{side}"), Some(lower), Vec3::new(s * 0.13, 0.1, -0.03));
    }
    joints
}

/// How a part is skinned: rigidly to one joint, to two joints with constant weights, or from the
/// first joint to the second along an axis (`from` to `to` in model space, the blend a smoothstep
/// over that span).
enum Skin {
    Rigid(u16),
    Fixed(u16, u16, f32),
    Along(u16, u16, Vec3, Vec3),
}

impl Skin {
    /// Joints and weights of a vertex at `p`, largest weight first.
    fn at(&self, p: Vec3) -> ([u16; 4], [f32; 4]) {
        let (a, b, w) = match *self {
            Skin::Rigid(j) => return ([j, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            Skin::Fixed(a, b, w) => (a, b, w),
            Skin::Along(a, b, from, to) => {
                let d = to - from;
                let t = ((p - from).dot(d) / d.length_squared()).clamp(0.0, 1.0);
                (a, b, t * t * (3.0 - 2.0 * t))
            }
        };
        // `w` is the second joint's weight; rounded to 1/1024 so that the pair sums to 1 exactly.
        let w = (w * 1024.0).round() / 1024.0;
        match w {
            w if w <= 0.0 => ([a, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            w if w >= 1.0 => ([b, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            w if w > 0.5 => ([b, a, 0, 0], [w, 1.0 - w, 0.0, 0.0]),
            w => ([a, b, 0, 0], [1.0 - w, w, 0.0, 0.0]),
        }
    }
}

/// A base colour for part `k`: steel greys, gunmetal, an accent orange and a few glass blues,
/// each a little lighter or darker so that no two materials are equal.
fn colour(k: usize, kind: usize) -> [f32; 4] {
    const BASES: [[f32; 3]; 4] =
        [[0.62, 0.64, 0.68], [0.16, 0.17, 0.2], [0.95, 0.45, 0.08], [0.2, 0.7, 0.95]];
    let shade = 0.9 + 0.2 * ((k * 7) % 11) as f32 / 10.0;
    let [r, g, b] = BASES[kind].map(|c| (c * shade).min(1.0));
    [r, g, b, 1.0]
}

const STEEL: usize = 0;
const GUNMETAL: usize = 1;
const ACCENT: usize = 2;
const GLASS: usize = 3;

/// The parts as they are added: a name, a shape, its skinning and its colour kind.
struct Parts {
    detail: f32,
    primitives: Vec<RPrimitive>,
    materials: Vec<(String, [f32; 4])>,
}

impl Parts {
    /// Triangles for a part asked `n` at detail 1 (at least 8).
    fn n(&self, n: f32) -> f32 {
        (n * self.detail).max(8.0)
    }

    fn add(&mut self, name: &str, shape: Shape, skin: Skin, kind: usize) {
        let (joints, weights) = shape.positions.iter().map(|&p| skin.at(p)).unzip();
        let material = self.materials.len();
        self.materials.push((name.to_string(), colour(material, kind)));
        self.primitives.push(RPrimitive { shape, joints, weights, material, targets: Vec::new() });
    }
}

/// The robot; `detail` scales every part's triangle count.
pub fn hardsurface(detail: f64) -> Design {
    let joints = skeleton();
    let j = |name: &str| joint_index(&joints, name) as u16;
    let head = |name: &str| joints[j(name) as usize].head;
    let mut parts = Parts { detail: detail as f32, primitives: Vec::new(), materials: Vec::new() };
    let p = &mut parts;
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    let full = (0.0, 1.0);
    // About an axis along ±Y (the frame of `surfaces::frame_about`), turn 0 is the front (+Z) and
    // the first radius the depth (along Z), the last the width (along X).

    // Torso: layered chest plates, three abdomen bands, a belt, a skirt, a backpack.
    let chest = Vec3::new(0.0, 1.4, 0.0);
    let n = p.n(2700.0);
    p.add(
        "ChestFront",
        ellipsoid(chest, y, Vec3::new(0.15, 0.17, 0.2), (-0.2, 0.2), (0.18, 0.78), n),
        Skin::Rigid(j("Chest")),
        STEEL,
    );
    let n = p.n(2400.0);
    p.add(
        "ChestBack",
        ellipsoid(chest, y, Vec3::new(0.145, 0.165, 0.195), (0.3, 0.7), (0.15, 0.8), n),
        Skin::Rigid(j("Chest")),
        STEEL,
    );
    let n = p.n(1000.0);
    p.add(
        "ChestSideL",
        ellipsoid(chest, y, Vec3::new(0.14, 0.16, 0.19), (0.65, 0.85), (0.25, 0.75), n),
        Skin::Rigid(j("Chest")),
        GUNMETAL,
    );
    p.add(
        "ChestSideR",
        ellipsoid(chest, y, Vec3::new(0.14, 0.16, 0.19), (0.15, 0.35), (0.25, 0.75), n),
        Skin::Rigid(j("Chest")),
        GUNMETAL,
    );
    let n = p.n(1400.0);
    p.add(
        "Collar",
        torus(Vec3::new(0.0, 1.55, 0.0), y, (0.11, 0.035), (-0.37, 0.37), (0.0, 0.6), n),
        Skin::Rigid(j("Chest")),
        ACCENT,
    );
    let (hips, spine, chest_joint) = (head("Hips"), head("Spine"), head("Chest"));
    let n = p.n(950.0);
    p.add(
        "AbdomenLow",
        tube(Vec3::new(0.0, 1.02, 0.0), Vec3::new(0.0, 1.1, 0.0), (0.13, 0.16), full, 0.04, 0.95, n),
        Skin::Along(j("Hips"), j("Spine"), hips, spine),
        GUNMETAL,
    );
    p.add(
        "AbdomenMid",
        tube(Vec3::new(0.0, 1.08, 0.0), Vec3::new(0.0, 1.18, 0.0), (0.12, 0.15), full, 0.04, 0.95, n),
        Skin::Rigid(j("Spine")),
        GUNMETAL,
    );
    p.add(
        "AbdomenHigh",
        tube(Vec3::new(0.0, 1.15, 0.0), Vec3::new(0.0, 1.26, 0.0), (0.125, 0.155), full, 0.04, 1.05, n),
        Skin::Along(j("Spine"), j("Chest"), spine, chest_joint),
        GUNMETAL,
    );
    let n = p.n(1700.0);
    p.add(
        "Belt",
        torus(Vec3::new(0.0, 0.98, 0.0), y, (0.15, 0.05), full, (-0.25, 0.25), n),
        Skin::Rigid(j("Hips")),
        ACCENT,
    );
    let n = p.n(950.0);
    p.add(
        "SkirtFront",
        tube(Vec3::new(0.0, 0.8, 0.0), Vec3::new(0.0, 0.97, 0.0), (0.15, 0.19), (-0.13, 0.13), 0.05, 0.85, n),
        Skin::Rigid(j("Hips")),
        STEEL,
    );
    p.add(
        "SkirtBack",
        tube(Vec3::new(0.0, 0.8, 0.0), Vec3::new(0.0, 0.97, 0.0), (0.15, 0.19), (0.37, 0.63), 0.05, 0.85, n),
        Skin::Rigid(j("Hips")),
        STEEL,
    );
    let pack = Vec3::new(0.0, 1.38, -0.2);
    p.add(
        "Backpack",
        rounded_box(pack, y, Vec3::new(0.07, 0.16, 0.14), 0.3, p.n(900.0)),
        Skin::Rigid(j("Chest")),
        GUNMETAL,
    );
    let n = p.n(200.0);
    p.add(
        "BackpackVent",
        tube(
            pack + Vec3::new(-0.07, 0.17, 0.0),
            pack + Vec3::new(0.07, 0.17, 0.0),
            (0.03, 0.03),
            (0.0, 0.5),
            0.0,
            1.0,
            n,
        ),
        Skin::Rigid(j("Chest")),
        ACCENT,
    );
    let n = p.n(240.0);
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let (a, b) = (Vec3::new(s * 0.08, 1.3, -0.27), Vec3::new(s * 0.08, 1.18, -0.29));
        p.add(
            &format!("Exhaust{side}"),
            tube(a, b, (0.025, 0.025), full, 0.0, 1.2, n),
            Skin::Rigid(j("Chest")),
            GUNMETAL,
        );
    }

    // Head: a helmet open at the bottom, a visor band, a face plate, ear cups, a crest, an
    // antenna and a neck sleeve.
    let skull = Vec3::new(0.0, 1.74, 0.0);
    p.add(
        "Helmet",
        ellipsoid(skull, y, Vec3::new(0.14, 0.14, 0.13), full, (0.0, 0.62), p.n(3600.0)),
        Skin::Rigid(j("Head")),
        STEEL,
    );
    let n = p.n(1500.0);
    p.add(
        "Visor",
        tube(
            Vec3::new(0.0, 1.69, 0.0),
            Vec3::new(0.0, 1.77, 0.0),
            (0.148, 0.138),
            (-0.18, 0.18),
            0.03,
            1.0,
            n,
        ),
        Skin::Rigid(j("Head")),
        GLASS,
    );
    let n = p.n(1200.0);
    p.add(
        "Faceplate",
        ellipsoid(Vec3::new(0.0, 1.67, 0.02), y, Vec3::new(0.13, 0.09, 0.11), (-0.15, 0.15), (0.45, 0.9), n),
        Skin::Rigid(j("Head")),
        GUNMETAL,
    );
    let n = p.n(480.0);
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let ear = ellipsoid(
            Vec3::new(s * 0.128, 1.72, 0.0),
            x * s,
            Vec3::new(0.05, 0.03, 0.05),
            full,
            (0.0, 0.5),
            n,
        );
        p.add(&format!("Ear{side}"), ear, Skin::Rigid(j("Head")), ACCENT);
    }
    let n = p.n(140.0);
    p.add(
        "Antenna",
        capsule(Vec3::new(0.09, 1.8, -0.04), Vec3::new(0.11, 1.98, -0.06), 0.008, n),
        Skin::Rigid(j("Head")),
        ACCENT,
    );
    let n = p.n(700.0);
    p.add(
        "Crest",
        torus(skull, x, (0.145, 0.015), (0.1, 0.45), (-0.3, 0.3), n),
        Skin::Rigid(j("Head")),
        ACCENT,
    );
    let n = p.n(800.0);
    let (neck_a, neck_b) = (Vec3::new(0.0, 1.52, 0.0), Vec3::new(0.0, 1.66, 0.0));
    p.add(
        "NeckSleeve",
        tube(neck_a, neck_b, (0.06, 0.055), full, 0.08, 1.0, n),
        Skin::Along(j("Chest"), j("Head"), neck_a, neck_b),
        GUNMETAL,
    );

    // Arms.
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let name = |base: &str| format!("{base}{side}");
        let (shoulder, elbow, wrist) = (head(&name("UpperArm")), head(&name("Forearm")), head(&name("Hand")));
        let (clavicle, upper, fore, hand) =
            (j(&name("Clavicle")), j(&name("UpperArm")), j(&name("Forearm")), j(&name("Hand")));
        let pad = Vec3::new(s * 0.25, 1.55, 0.0);
        p.add(
            &name("Pauldron"),
            ellipsoid(pad, y, Vec3::new(0.12, 0.1, 0.12), full, (0.0, 0.45), p.n(2500.0)),
            Skin::Rigid(clavicle),
            STEEL,
        );
        // The trim runs around the pauldron's rim but for a gap on the neck's side.
        let gap = if s > 0.0 { (0.35, 1.15) } else { (-0.15, 0.65) };
        let n = p.n(280.0);
        p.add(
            &name("PauldronTrim"),
            torus(pad - y * 0.045, y, (0.113, 0.012), gap, (0.0, 0.5), n),
            Skin::Rigid(clavicle),
            ACCENT,
        );
        let (a, b) = (shoulder.lerp(elbow, 0.08), shoulder.lerp(elbow, 0.85));
        let n = p.n(1450.0);
        p.add(
            &name("UpperArmSleeve"),
            tube(a, b, (0.065, 0.06), full, 0.06, 0.9, n),
            Skin::Along(clavicle, upper, shoulder, shoulder.lerp(elbow, 0.3)),
            GUNMETAL,
        );
        p.add(
            &name("Elbow"),
            ellipsoid(elbow, elbow - shoulder, Vec3::splat(0.055), full, (0.0, 1.0), p.n(600.0)),
            Skin::Fixed(upper, fore, 0.5),
            GUNMETAL,
        );
        // The vambrace covers three quarters of the forearm, its outside; a strip closes the inside.
        let (a, b) = (elbow.lerp(wrist, 0.12), elbow.lerp(wrist, 0.95));
        let outside = if s > 0.0 { (-0.125, 0.625) } else { (0.375, 1.125) };
        let n = p.n(1750.0);
        p.add(
            &name("Vambrace"),
            tube(a, b, (0.062, 0.056), outside, 0.08, 0.85, n),
            Skin::Rigid(fore),
            STEEL,
        );
        let inside = (outside.1, outside.0 + 1.0);
        let n = p.n(260.0);
        p.add(
            &name("ForearmInner"),
            tube(a, b, (0.055, 0.05), inside, 0.05, 0.85, n),
            Skin::Rigid(fore),
            GUNMETAL,
        );
        let tip = wrist + (wrist - elbow).normalize() * 0.15;
        let n = p.n(700.0);
        p.add(
            &name("Hand"),
            rounded_box(wrist.lerp(tip, 0.5), tip - wrist, Vec3::new(0.045, 0.075, 0.03), 0.35, n),
            Skin::Rigid(hand),
            GUNMETAL,
        );
        let knuckles = wrist.lerp(tip, 0.72) + z * 0.01;
        let n = p.n(120.0);
        p.add(
            &name("Knuckles"),
            tube(knuckles - x * 0.04, knuckles + x * 0.04, (0.045, 0.045), (-0.2, 0.2), 0.0, 1.0, n),
            Skin::Rigid(hand),
            ACCENT,
        );
    }

    // Legs.
    for (side, s) in [("L", 1.0), ("R", -1.0)] {
        let name = |base: &str| format!("{base}{side}");
        let (hip, knee, ankle) = (head(&name("UpperLeg")), head(&name("LowerLeg")), head(&name("Foot")));
        let (upper, lower, foot) = (j(&name("UpperLeg")), j(&name("LowerLeg")), j(&name("Foot")));
        // Plates front and back: about a bone pointing down, turn 0 is the front (+Z).
        let (a, b) = (hip.lerp(knee, 0.1), hip.lerp(knee, 0.9));
        let n = p.n(2200.0);
        p.add(
            &name("ThighFront"),
            tube(a, b, (0.088, 0.092), (-0.23, 0.23), 0.08, 0.85, n),
            Skin::Rigid(upper),
            STEEL,
        );
        let n = p.n(1450.0);
        p.add(
            &name("ThighBack"),
            tube(a, b, (0.084, 0.088), (0.27, 0.73), 0.06, 0.85, n),
            Skin::Rigid(upper),
            GUNMETAL,
        );
        let n = p.n(600.0);
        p.add(
            &name("KneeCap"),
            ellipsoid(knee + z * 0.07, z, Vec3::new(0.06, 0.035, 0.07), full, (0.0, 0.42), n),
            Skin::Fixed(lower, upper, 0.3),
            ACCENT,
        );
        let (a, b) = (knee.lerp(ankle, 0.08), knee.lerp(ankle, 0.88));
        let n = p.n(2200.0);
        p.add(
            &name("Greave"),
            tube(a, b, (0.072, 0.078), (-0.22, 0.22), 0.1, 0.8, n),
            Skin::Rigid(lower),
            STEEL,
        );
        let n = p.n(1350.0);
        p.add(
            &name("Calf"),
            tube(a, b, (0.07, 0.074), (0.28, 0.72), 0.14, 0.75, n),
            Skin::Rigid(lower),
            GUNMETAL,
        );
        let n = p.n(280.0);
        p.add(
            &name("Ankle"),
            capsule(ankle - x * 0.045, ankle + x * 0.045, 0.038, n),
            Skin::Fixed(lower, foot, 0.5),
            GUNMETAL,
        );
        let n = p.n(1550.0);
        let shell = ellipsoid(
            ankle + Vec3::new(0.0, -0.03, 0.07),
            y,
            Vec3::new(0.13, 0.06, 0.07),
            full,
            (0.0, 0.55),
            n,
        );
        p.add(&name("FootShell"), shell, Skin::Rigid(foot), STEEL);
        let n = p.n(500.0);
        p.add(
            &name("Sole"),
            rounded_box(Vec3::new(s * 0.13, 0.025, 0.05), y, Vec3::new(0.14, 0.025, 0.075), 0.3, n),
            Skin::Rigid(foot),
            GUNMETAL,
        );
        let n = p.n(220.0);
        p.add(
            &name("ToeCap"),
            ellipsoid(
                Vec3::new(s * 0.13, 0.045, 0.17),
                z,
                Vec3::new(0.05, 0.025, 0.035),
                full,
                (0.0, 0.45),
                n,
            ),
            Skin::Rigid(foot),
            ACCENT,
        );
        let (a, b) = (Vec3::new(s * 0.05, 0.98, 0.0), hip + Vec3::new(s * 0.03, -0.04, 0.0));
        let n = p.n(600.0);
        p.add(&name("HipJoint"), capsule(a, b, 0.05, n), Skin::Along(j("Hips"), upper, a, b), GUNMETAL);
    }
    let n = p.n(100.0);
    p.add(
        "Emblem",
        ellipsoid(Vec3::new(0.0, 1.46, 0.14), z, Vec3::new(0.035, 0.012, 0.035), full, (0.0, 0.3), n),
        Skin::Rigid(j("Chest")),
        ACCENT,
    );

    let Parts { primitives, materials, .. } = parts;
    let skin = (0..joints.len()).collect();
    let meshes = vec![RMesh { name: "Armour", skin, primitives, default_weights: Vec::new() }];
    let clips = clips(&joints);
    Design { scene: "HardSurface", joints, materials, meshes, clips }
}

fn clips(joints: &[RJoint]) -> Vec<RClip> {
    let j = |name: &str| joint_index(joints, name);
    let walk_times = key_times(1.2, 24);
    let walk = RClip {
        name: "Walk",
        rotations: vec![
            track(j("UpperLegL"), &|t| turn(Vec3::X, -28.0 * wave(t, 1.2)), &walk_times),
            track(j("UpperLegR"), &|t| turn(Vec3::X, 28.0 * wave(t, 1.2)), &walk_times),
            track(
                j("LowerLegL"),
                &|t| turn(Vec3::X, 30.0 * (1.0 - wave(t, 1.2)).max(0.0) * 0.6),
                &walk_times,
            ),
            track(
                j("LowerLegR"),
                &|t| turn(Vec3::X, 30.0 * (1.0 + wave(t, 1.2)).max(0.0) * 0.6),
                &walk_times,
            ),
            track(j("FootL"), &|t| turn(Vec3::X, 10.0 * wave(t + 0.3, 1.2)), &walk_times),
            track(j("FootR"), &|t| turn(Vec3::X, -10.0 * wave(t + 0.3, 1.2)), &walk_times),
            track(j("UpperArmL"), &|t| turn(Vec3::X, 22.0 * wave(t, 1.2)), &walk_times),
            track(j("UpperArmR"), &|t| turn(Vec3::X, -22.0 * wave(t, 1.2)), &walk_times),
            track(j("ForearmL"), &|t| turn(Vec3::X, -20.0 - 10.0 * wave(t, 1.2)), &walk_times),
            track(j("ForearmR"), &|t| turn(Vec3::X, -20.0 + 10.0 * wave(t, 1.2)), &walk_times),
            track(j("Spine"), &|t| turn(Vec3::Y, 7.0 * wave(t, 1.2)), &walk_times),
            track(j("Chest"), &|t| turn(Vec3::Y, -5.0 * wave(t, 1.2)), &walk_times),
            track(j("Head"), &|t| turn(Vec3::X, 3.0 * wave(t, 0.6)), &walk_times),
        ],
        weights: Vec::new(),
        times: walk_times.clone(),
    };
    let look_times: Vec<f32> = (0..=40).map(|k| 2.0 * k as f32 / 40.0).collect();
    // 0 → 1 → 0 over the clip.
    let rise = |t: f32| 0.5 - 0.5 * sin_cos(std::f32::consts::TAU * t / 2.0).1;
    let look = RClip {
        name: "Look",
        rotations: vec![
            track(j("Spine"), &|t| turn(Vec3::Y, 25.0 * rise(t)), &look_times),
            track(j("Chest"), &|t| turn(Vec3::Y, 15.0 * rise(t)), &look_times),
            track(j("Head"), &|t| turn(Vec3::Y, 40.0 * wave(t, 2.0)), &look_times),
            track(j("ClavicleR"), &|t| turn(Vec3::Z, -12.0 * rise(t)), &look_times),
            track(j("UpperArmR"), &|t| turn(Vec3::new(-0.3, 0.0, -1.0), 80.0 * rise(t)), &look_times),
            track(j("ForearmR"), &|t| turn(Vec3::X, -70.0 * rise(t)), &look_times),
            track(j("HandR"), &|t| turn(Vec3::Y, 30.0 * wave(t, 0.5) * rise(t)), &look_times),
            track(j("UpperLegL"), &|t| turn(Vec3::X, -10.0 * rise(t)), &look_times),
            track(j("LowerLegL"), &|t| turn(Vec3::X, 20.0 * rise(t)), &look_times),
        ],
        weights: Vec::new(),
        times: look_times,
    };
    vec![walk, look]
}
