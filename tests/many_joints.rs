//! A character with hundreds of joints, as real rigs have (a Mixamo humanoid has 65–67, a game
//! character with face and hair bones several hundred): a tube of `N` segments along +Y, one
//! joint per segment in a parent-first chain, `JOINTS_0` as u16 (indices past 255), every ring
//! of the tube bound rigidly to its segment's joint. One clip turns every joint about +Z by the
//! same angle, so the chain curls and every vertex's skinned position has a closed form.
//! Checked: the import, CPU skinning against that closed form, and the LOD chain built from it.

use clod_viewer::clod::{self, ClodOptions};
use clod_viewer::import::from_gltf;
use glam::{Quat, Vec3};

/// Vertices per ring of the tube.
const RING: usize = 8;
const RADIUS: f32 = 0.2;
/// The clip's angle per joint at its end, radians.
const CURL: f32 = 0.01;

/// The tube's buffer: positions, u16 joints, weights, indices, inverse binds, key times and
/// rotations, in that order; returns the bytes and the byte offset of each part.
fn buffer(joints: usize) -> (Vec<u8>, [usize; 8]) {
    let mut out = Vec::new();
    let f32s = |out: &mut Vec<u8>, xs: &[f32]| xs.iter().for_each(|x| out.extend(x.to_le_bytes()));
    let rings = joints + 1;
    let mut at = [0; 8];
    for k in 0..rings {
        for r in 0..RING {
            let a = std::f32::consts::TAU * r as f32 / RING as f32;
            f32s(&mut out, &[RADIUS * a.cos(), k as f32, RADIUS * a.sin()]);
        }
    }
    at[1] = out.len();
    for k in 0..rings {
        let joint = joint_of_ring(k, joints) as u16;
        for _ in 0..RING {
            for j in [joint, 0, 0, 0] {
                out.extend(j.to_le_bytes());
            }
        }
    }
    at[2] = out.len();
    for _ in 0..rings * RING {
        f32s(&mut out, &[1.0, 0.0, 0.0, 0.0]);
    }
    at[3] = out.len();
    for k in 0..joints {
        for r in 0..RING {
            let (a, b) = ((k * RING + r) as u32, (k * RING + (r + 1) % RING) as u32);
            let (c, d) = (a + RING as u32, b + RING as u32);
            for v in [a, c, b, b, c, d] {
                out.extend(v.to_le_bytes());
            }
        }
    }
    at[4] = out.len();
    for j in 0..joints {
        f32s(&mut out, &glam::Mat4::from_translation(Vec3::new(0.0, -(j as f32), 0.0)).to_cols_array());
    }
    at[5] = out.len();
    f32s(&mut out, &[0.0, 1.0]);
    at[6] = out.len();
    let end = Quat::from_rotation_z(CURL);
    f32s(&mut out, &[0.0, 0.0, 0.0, 1.0, end.x, end.y, end.z, end.w]);
    at[7] = out.len();
    (out, at)
}

/// The joint a ring is bound to: ring k sits at the start of segment k, the last ring at the end
/// of the last segment.
fn joint_of_ring(k: usize, joints: usize) -> usize {
    k.min(joints - 1)
}

fn tube_gltf(joints: usize) -> Vec<u8> {
    use base64::Engine;
    let (bin, at) = buffer(joints);
    let rings = joints + 1;
    let vertices = rings * RING;
    let nodes: Vec<String> = (0..joints)
        .map(|j| {
            let children =
                if j + 1 < joints { format!(r#", "children": [{}]"#, j + 1) } else { String::new() };
            let translation = if j == 0 { "[0, 0, 0]" } else { "[0, 1, 0]" };
            format!(r#"{{"name": "joint{j}", "translation": {translation}{children}}}"#)
        })
        .collect();
    let channels: Vec<String> = (0..joints)
        .map(|j| format!(r#"{{"sampler": {j}, "target": {{"node": {j}, "path": "rotation"}}}}"#))
        .collect();
    let samplers: Vec<String> = (0..joints).map(|_| r#"{"input": 5, "output": 6}"#.to_string()).collect();
    let view = |k: usize| {
        format!(r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#, at[k], at[k + 1] - at[k])
    };
    let json = format!(
        r#"{{
      "asset": {{"version": "2.0"}},
      "scene": 0,
      "scenes": [{{"nodes": [0, {tube}]}}],
      "nodes": [{nodes}, {{"name": "tube", "mesh": 0, "skin": 0}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}}, "indices": 3}}]}}],
      "skins": [{{"joints": [{joint_list}], "inverseBindMatrices": 4}}],
      "animations": [{{"name": "Curl", "channels": [{channels}], "samplers": [{samplers}]}}],
      "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{uri}"}}],
      "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {pos_len}}}, {v1}, {v2}, {v3}, {v4}, {v5}, {v6}],
      "accessors": [
        {{"bufferView": 0, "componentType": 5126, "count": {vertices}, "type": "VEC3",
          "min": [-{RADIUS}, 0, -{RADIUS}], "max": [{RADIUS}, {joints}, {RADIUS}]}},
        {{"bufferView": 1, "componentType": 5123, "count": {vertices}, "type": "VEC4"}},
        {{"bufferView": 2, "componentType": 5126, "count": {vertices}, "type": "VEC4"}},
        {{"bufferView": 3, "componentType": 5125, "count": {index_count}, "type": "SCALAR"}},
        {{"bufferView": 4, "componentType": 5126, "count": {joints}, "type": "MAT4"}},
        {{"bufferView": 5, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]}},
        {{"bufferView": 6, "componentType": 5126, "count": 2, "type": "VEC4"}}
      ]
    }}"#,
        tube = joints,
        nodes = nodes.join(", "),
        joint_list = (0..joints).map(|j| j.to_string()).collect::<Vec<_>>().join(", "),
        channels = channels.join(", "),
        samplers = samplers.join(", "),
        len = bin.len(),
        uri = base64::engine::general_purpose::STANDARD.encode(&bin),
        pos_len = at[1],
        v1 = view(1),
        v2 = view(2),
        v3 = view(3),
        v4 = view(4),
        v5 = view(5),
        v6 = view(6),
        index_count = 6 * RING * joints,
    );
    json.into_bytes()
}

/// Where the clip puts bind-pose point `p` of ring `k` when every joint has turned by `angle`:
/// joint j has turned by (j + 1) · `angle` in the world (every ancestor's turn adds up), and sits at the end of the
/// chain of unit bones before it.
fn curled(p: Vec3, k: usize, joints: usize, angle: f32) -> Vec3 {
    let j = joint_of_ring(k, joints);
    let origin: Vec3 = (1..=j).map(|i| Quat::from_rotation_z(i as f32 * angle) * Vec3::Y).sum();
    origin + Quat::from_rotation_z((j + 1) as f32 * angle) * (p - Vec3::new(0.0, j as f32, 0.0))
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn hundreds_of_joints_import_skin_and_simplify() {
    // 70: a humanoid's count; 300: past u8 indices and past what a WebGL2 uniform block of joint
    // matrices holds (256; the renderer reads a texture, tests/browser/page.test.mjs draws 1,100).
    for joints in [70, 300] {
        let character = from_gltf(&tube_gltf(joints), &mut |_| None).expect("the tube imports");
        assert_eq!(character.skeleton.joints.len(), joints);
        assert!(character.warnings.is_empty(), "{:?}", character.warnings);
        let clip = character.clip("Curl").expect("the clip imports");
        let bind = &character.mesh.positions;
        let rest = character.clip_skinned_positions(clip, 0.0);
        // Halfway: the rotation keys' slerp is exactly half the angle (the clip loops, so its
        // end would be its start).
        let end = character.clip_skinned_positions(clip, 0.5);
        let mut worst = 0.0f32;
        for (v, (p, (r, e))) in bind.iter().zip(rest.iter().zip(&end)).enumerate() {
            assert!((*r - *p).length() < 1e-4, "{joints} joints: vertex {v} moved at t = 0");
            // Ring k lies at height k (the file has no normals, so its corners come flat-shaded,
            // one per triangle corner, in drawing order rather than ring order).
            worst = worst.max((*e - curled(*p, p.y.round() as usize, joints, CURL / 2.0)).length());
        }
        // f32 through a chain of `joints` matrices: the error grows with the chain's length.
        assert!(worst < 1e-5 * joints as f32, "{joints} joints: {worst} from the closed form");
        // The tip has swung far from the bind pose: the clip reached the last joint.
        assert!((end[end.len() - 1] - bind[bind.len() - 1]).x.abs() > 1.0);

        let built =
            clod::build(&character, &ClodOptions::default(), &mut |_| {}).expect("the tube simplifies");
        assert!(built.levels.len() >= 3, "{joints} joints: {} levels", built.levels.len());
        let skin = character.skin_matrices(&character.pose_at(clip, 0.5));
        for (i, level) in built.levels.iter().enumerate() {
            let positions = built.level_skinned_positions(i, &skin);
            assert_eq!(positions.len(), level.vertices.len());
            assert!(positions.iter().all(|p| p.is_finite()), "{joints} joints: level {i} not finite");
        }
    }
}
