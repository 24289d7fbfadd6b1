//! Generator-side checks of the four kinds made for the benchmark against meshoptimizer
//! (`hardsurface.glb`, `lowpoly-robot.glb`, `critter.glb`, `fingers.glb`): each file is read back with the `gltf`
//! crate (independently of the project's importer) and checked for what its kind stands for:
//! counts, materials and attributes, how parts are shaded (smooth within a part; or every edge a
//! normal seam), which parts are open or closed, skin weights normalized and sorted, morph targets,
//! and skinning through every clip with a small linear-blend skinner (no vertex strays further
//! than the model's height, and the mean edge length stays within [0.5, 2]× the bind pose's).
//! Each returns a one-paragraph report for the console.

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use clod_viewer::animation::{Clip, Wrap};
use clod_viewer::skeleton::{Node, Skeleton, SkinJoint, Transform};

use crate::validate::{bad_edges, read_channel, weld_by_position, Loaded};

/// One primitive as read back.
struct Prim {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    indices: Vec<u32>,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
    material: Option<usize>,
    has_uv: bool,
    targets: usize,
    /// Its mesh node's skin.
    skin: usize,
}

/// A file as read back: primitives, one skeleton per skin, clips (joint channels only), and how
/// many channels animate morph weights.
struct Read {
    prims: Vec<Prim>,
    joints: usize,
    skins: Vec<Skeleton>,
    clips: Vec<Clip>,
    weight_channels: usize,
    bytes: usize,
}

fn read(bytes: &[u8]) -> Result<Read, String> {
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| format!("not a valid glTF: {e}"))?;
    let blob = gltf.blob.as_deref().ok_or("GLB has no binary chunk")?;
    let buffers = |_: gltf::Buffer| Some(blob);
    let mut prims = Vec::new();
    for node in gltf.nodes().filter(|n| n.mesh().is_some()) {
        let skin = node.skin().ok_or(format!("mesh node {} has no skin", node.index()))?.index();
        for prim in node.mesh().expect("filtered").primitives() {
            let r = prim.reader(buffers);
            prims.push(Prim {
                positions: r.read_positions().ok_or("no POSITION")?.map(Vec3::from).collect(),
                normals: r.read_normals().ok_or("no NORMAL")?.map(Vec3::from).collect(),
                indices: r.read_indices().ok_or("no indices")?.into_u32().collect(),
                joints: r.read_joints(0).ok_or("no JOINTS_0")?.into_u16().collect(),
                weights: r.read_weights(0).ok_or("no WEIGHTS_0")?.into_f32().collect(),
                material: prim.material().index(),
                has_uv: r.read_tex_coords(0).is_some(),
                targets: r.read_morph_targets().count(),
                skin,
            });
        }
    }
    let mut parent = vec![None; gltf.nodes().len()];
    for node in gltf.nodes() {
        for child in node.children() {
            parent[child.index()] = Some(node.index());
        }
    }
    let nodes: Vec<Node> = gltf
        .nodes()
        .map(|node| {
            let (t, r, s) = node.transform().decomposed();
            let rest =
                Transform { translation: Vec3::from(t), rotation: Quat::from_array(r), scale: Vec3::from(s) };
            Node { name: node.name().unwrap_or("").to_string(), parent: parent[node.index()], rest }
        })
        .collect();
    let mut skins = Vec::new();
    for skin in gltf.skins() {
        let ibms = skin.reader(buffers).read_inverse_bind_matrices().ok_or("no inverse bind matrices")?;
        let joints = skin
            .joints()
            .zip(ibms)
            .map(|(j, m)| SkinJoint { node: j.index(), joint_from_bind: Mat4::from_cols_array_2d(&m) })
            .collect();
        skins.push(Skeleton { nodes: nodes.clone(), joints });
    }
    let (mut clips, mut weight_channels) = (Vec::new(), 0);
    for animation in gltf.animations() {
        let mut channels = Vec::new();
        for channel in animation.channels() {
            match read_channel(&channel, buffers)? {
                Some(channel) => channels.push(channel),
                None => weight_channels += 1,
            }
        }
        clips.push(Clip::new(animation.name().unwrap_or(""), channels));
    }
    let joints = gltf.nodes().filter(|n| n.mesh().is_none()).count();
    Ok(Read { prims, joints, skins, clips, weight_channels, bytes: bytes.len() })
}

impl Read {
    fn triangles(&self) -> usize {
        self.prims.iter().map(|p| p.indices.len() / 3).sum()
    }

    fn vertices(&self) -> usize {
        self.prims.iter().map(|p| p.positions.len()).sum()
    }

    fn targets(&self) -> usize {
        self.prims.iter().map(|p| p.targets).sum()
    }

    /// Weights non-negative, sorted, summing to 1; joints in range of their skin.
    fn check_weights(&self) -> Result<(), String> {
        for (k, p) in self.prims.iter().enumerate() {
            let joints = self.skins[p.skin].joints.len();
            for (w, j) in p.weights.iter().zip(&p.joints) {
                let sum: f32 = w.iter().sum();
                if (sum - 1.0).abs() > 1e-6 || w.windows(2).any(|q| q[1] > q[0]) || w.iter().any(|&x| x < 0.0)
                {
                    return Err(format!(
                        "primitive {k}: weights {w:?} are not sorted, non-negative and summing to 1"
                    ));
                }
                if j.iter().zip(w).any(|(&j, &w)| w > 0.0 && j as usize >= joints) {
                    return Err(format!("primitive {k}: joint out of range {j:?}"));
                }
            }
        }
        Ok(())
    }

    /// The skin matrices of every skin with clip `clip` at `time` (the bind pose for `None`).
    fn skin_matrices(&self, clip: Option<(usize, f32)>) -> Vec<Vec<Mat4>> {
        let mut pose = self.skins[0].rest_pose();
        if let Some((clip, time)) = clip {
            self.clips[clip].sample_into(time, Wrap::Clamp, &mut pose);
        }
        self.skins.iter().map(|s| s.pose_skin_matrices(&pose)).collect()
    }

    /// Per clip: name, worst displacement from the bind pose and the range of the mean edge
    /// length's ratio to the bind pose's, over 24 frames.
    fn check_skinning(&self) -> Result<Vec<(String, f32, f32, f32)>, String> {
        let all: Vec<Vec3> = self.prims.iter().flat_map(|p| p.positions.iter().copied()).collect();
        let (lo, hi) = all.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let height = hi.y - lo.y;
        let bind_edge = self.mean_edge(&all);
        let mut out = Vec::new();
        for (c, clip) in self.clips.iter().enumerate() {
            let (mut worst, mut ratio_lo, mut ratio_hi) = (0.0f32, f32::MAX, f32::MIN);
            for f in 0..=24 {
                let time = clip.duration() * f as f32 / 24.0;
                let matrices = self.skin_matrices(Some((c, time)));
                let mut posed = Vec::with_capacity(all.len());
                for p in &self.prims {
                    for ((v, j), w) in p.positions.iter().zip(&p.joints).zip(&p.weights) {
                        let m = (0..4).fold(Mat4::ZERO, |m, k| m + matrices[p.skin][j[k] as usize] * w[k]);
                        posed.push(m.transform_point3(*v));
                    }
                }
                for (p, q) in posed.iter().zip(&all) {
                    if !p.is_finite() {
                        return Err(format!("clip {} at {time} s: a non-finite skinned position", clip.name));
                    }
                    worst = worst.max(p.distance(*q));
                }
                let ratio = self.mean_edge(&posed) / bind_edge;
                (ratio_lo, ratio_hi) = (ratio_lo.min(ratio), ratio_hi.max(ratio));
            }
            if worst > height || ratio_lo < 0.5 || ratio_hi > 2.0 {
                return Err(format!(
                    "clip {}: worst displacement {worst} m, edge ratio {ratio_lo}..{ratio_hi}",
                    clip.name
                ));
            }
            out.push((clip.name.clone(), worst, ratio_lo, ratio_hi));
        }
        Ok(out)
    }

    /// The mean edge length of every primitive, `positions` being all their vertices in order.
    fn mean_edge(&self, positions: &[Vec3]) -> f32 {
        let (mut sum, mut count, mut base) = (0.0f64, 0usize, 0usize);
        for p in &self.prims {
            for t in p.indices.chunks_exact(3) {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    sum += f64::from(positions[base + a as usize].distance(positions[base + b as usize]));
                    count += 1;
                }
            }
            base += p.positions.len();
        }
        (sum / count as f64) as f32
    }

    fn clip_text(clips: &[(String, f32, f32, f32)]) -> String {
        let text: Vec<String> = clips
            .iter()
            .map(|(name, worst, lo, hi)| {
                format!("{name} (moves up to {worst:.2} m, edges ×{lo:.3}..{hi:.3})")
            })
            .collect();
        text.join(", ")
    }
}

/// Whether every triangle has its own three vertices, each with the triangle's face normal.
fn faceted(p: &Prim) -> bool {
    let mut used = vec![false; p.positions.len()];
    p.indices.chunks_exact(3).all(|t| {
        let [a, b, c] = [0, 1, 2].map(|k| p.positions[t[k] as usize]);
        let face = (b - a).cross(c - a).normalize();
        t.iter().all(|&v| {
            !std::mem::replace(&mut used[v as usize], true) && p.normals[v as usize].dot(face) > 0.9999
        })
    })
}

/// Edges (welded by position) whose two triangles have the same face normal: no normal seam.
fn flat_edges(p: &Prim) -> usize {
    let (welded, _) = weld_by_position(&p.positions, &p.indices);
    let mut edges: Vec<([u32; 2], usize)> = Vec::new();
    for (k, t) in welded.chunks_exact(3).enumerate() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            edges.push(([a.min(b), a.max(b)], k));
        }
    }
    edges.sort_unstable();
    let normal = |k: usize| {
        let [a, b, c] = [0, 1, 2].map(|i| p.positions[p.indices[3 * k + i] as usize]);
        (b - a).cross(c - a).normalize()
    };
    edges.windows(2).filter(|w| w[0].0 == w[1].0 && normal(w[0].1).dot(normal(w[1].1)) > 1.0 - 1e-6).count()
}

/// Border loops of a primitive welded by position: connected runs of edges used by one triangle.
fn border_loops(p: &Prim) -> usize {
    let (welded, _) = weld_by_position(&p.positions, &p.indices);
    let mut edges: Vec<[u32; 2]> = welded
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    let border: Vec<[u32; 2]> = edges
        .iter()
        .enumerate()
        .filter(|&(i, e)| edges.get(i + 1) != Some(e) && (i == 0 || edges[i - 1] != *e))
        .map(|(_, e)| *e)
        .collect();
    // Union-find over the border's vertices; each component is a loop.
    let mut parent: Vec<u32> = (0..p.positions.len() as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for [a, b] in &border {
        let (ra, rb) = (root(&mut parent, *a), root(&mut parent, *b));
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
    let mut roots: Vec<u32> = border.iter().map(|e| root(&mut parent, e[0])).collect();
    roots.sort_unstable();
    roots.dedup();
    roots.len()
}

/// Six times the signed volume of a closed primitive (positive when its triangles face out).
fn volume(p: &Prim) -> f32 {
    p.indices
        .chunks_exact(3)
        .map(|t| p.positions[t[0] as usize].dot(p.positions[t[1] as usize].cross(p.positions[t[2] as usize])))
        .sum()
}

/// The hard-surface robot at `detail` (see `--detail`).
///
/// # Errors
/// A message naming the first check that failed.
pub fn check_hardsurface(bytes: &[u8], detail: f64) -> Result<String, String> {
    let r = read(bytes)?;
    r.check_weights()?;
    let (prims, triangles) = (r.prims.len(), r.triangles());
    let (lo, hi) = ((50_000.0 * detail) as usize, (75_000.0 * detail) as usize);
    if !(55..=65).contains(&prims)
        || r.joints != 18
        || r.skins.len() != 1
        || r.clips.len() < 2
        || (detail == 1.0 && !(lo..=hi).contains(&triangles))
    {
        return Err(format!(
            "hardsurface: {prims} primitives, {} joints, {} skins, {} clips, {triangles} triangles; \
             expected 55–65, 18, 1, ≥ 2, {lo}–{hi}",
            r.joints,
            r.skins.len(),
            r.clips.len()
        ));
    }
    let mut materials: Vec<Option<usize>> = r.prims.iter().map(|p| p.material).collect();
    materials.sort_unstable();
    materials.dedup();
    if materials.len() != prims || materials.contains(&None) {
        return Err(format!(
            "hardsurface: {} materials over {prims} primitives; expected one each",
            materials.len()
        ));
    }
    let (mut closed, mut small, mut blended) = (0, 0, 0);
    for (k, p) in r.prims.iter().enumerate() {
        if p.has_uv {
            return Err(format!("hardsurface: primitive {k} has uvs"));
        }
        // Smooth within a part: vertices are shared (no two at one position).
        let (_, distinct) = weld_by_position(&p.positions, &p.indices);
        if distinct != p.positions.len() {
            return Err(format!(
                "hardsurface: primitive {k} has {} vertices at {distinct} positions",
                p.positions.len()
            ));
        }
        let loops = border_loops(p);
        if loops == 0 {
            if !bad_edges(&p.indices).is_empty() || volume(p) <= 0.0 {
                return Err(format!("hardsurface: closed primitive {k} is not a closed surface facing out"));
            }
            closed += 1;
        }
        small += usize::from(p.indices.len() / 3 < 300);
        blended += usize::from(p.weights.iter().any(|w| w[1] > 0.0));
    }
    // About a fifth closed, a quarter under 300 triangles (at the default detail), some blended.
    if !(10..=14).contains(&closed) || (detail == 1.0 && !(12..=18).contains(&small)) || blended < 6 {
        return Err(format!(
            "hardsurface: {closed} closed parts, {small} under 300 triangles, {blended} blended across a \
             joint; expected 10–14, 12–18, ≥ 6"
        ));
    }
    let clips = r.check_skinning()?;
    Ok(format!(
        "{} bytes: {prims} primitives and materials, {} vertices, {triangles} triangles, {} joints, \
         {closed} closed parts, {} open (with border loops), {small} under 300 triangles, {blended} \
         blended across a joint, no uvs; clips {}",
        r.bytes,
        r.vertices(),
        r.joints,
        prims - closed,
        Read::clip_text(&clips)
    ))
}

/// Checks shared by the two flat-shaded kinds: every triangle its own corners with its face
/// normal, every edge a normal seam, every primitive closed once welded by position.
fn check_faceted(r: &Read, what: &str) -> Result<(), String> {
    for (k, p) in r.prims.iter().enumerate() {
        if !faceted(p) {
            return Err(format!(
                "{what}: primitive {k} is not faceted (a triangle shares a corner or lacks its face normal)"
            ));
        }
        let flat = flat_edges(p);
        if flat > 0 {
            return Err(format!(
                "{what}: primitive {k} has {flat} edges between coplanar triangles (not a normal seam)"
            ));
        }
        let (welded, _) = weld_by_position(&p.positions, &p.indices);
        let bad = bad_edges(&welded).len();
        if bad > 0 {
            return Err(format!("{what}: primitive {k} is not closed ({bad} bad edges)"));
        }
    }
    Ok(())
}

/// The flat-shaded low-poly robot.
///
/// # Errors
/// A message naming the first check that failed.
pub fn check_lowpoly_robot(bytes: &[u8]) -> Result<String, String> {
    let r = read(bytes)?;
    r.check_weights()?;
    check_faceted(&r, "lowpoly-robot")?;
    let triangles = r.triangles();
    let rigid = r.prims.iter().all(|p| p.weights.iter().all(|w| *w == [1.0, 0.0, 0.0, 0.0]));
    if !(2_800..=3_600).contains(&triangles)
        || !(40..=60).contains(&r.joints)
        || r.targets() == 0
        || r.weight_channels == 0
        || !rigid
    {
        return Err(format!(
            "lowpoly-robot: {triangles} triangles, {} joints, {} morph targets, {} weight channels, \
             rigid {rigid}; \
             expected 2,800–3,600, 40–60, some, some, rigid",
            r.joints,
            r.targets(),
            r.weight_channels
        ));
    }
    let clips = r.check_skinning()?;
    Ok(format!(
        "{} bytes: {} primitives, {} vertices, {triangles} triangles (each its own corners, every edge \
         a normal seam), {} skins, \
         {} joints, {} morph targets over all primitives, {} weight channels; clips {}",
        r.bytes,
        r.prims.len(),
        r.vertices(),
        r.skins.len(),
        r.joints,
        r.targets(),
        r.weight_channels,
        Read::clip_text(&clips)
    ))
}

/// The low-poly animal: faceted, 400–650 triangles, 20–30 joints, blended skinning, a tail of
/// at least five joints and under 300 KB.
///
/// # Errors
/// A message naming the first check that failed.
pub fn check_critter(bytes: &[u8]) -> Result<String, String> {
    let r = read(bytes)?;
    r.check_weights()?;
    check_faceted(&r, "critter")?;
    let triangles = r.triangles();
    let tail = r.skins[0].joints.iter().filter(|j| r.skins[0].nodes[j.node].name.starts_with("Tail")).count();
    let blended = r.prims.iter().flat_map(|p| &p.weights).filter(|w| w[1] > 0.0).count();
    if !(400..=650).contains(&triangles)
        || !(20..=30).contains(&r.joints)
        || tail < 5
        || blended == 0
        || r.bytes >= 300_000
        || r.clips.len() < 2
    {
        return Err(format!(
            "critter: {triangles} triangles, {} joints, {tail} tail joints, {blended} blended vertices, \
             {} bytes, {} clips; \
             expected 400–650, 20–30, ≥ 5, some, < 300,000, ≥ 2",
            r.joints,
            r.bytes,
            r.clips.len()
        ));
    }
    let clips = r.check_skinning()?;
    Ok(format!(
        "{} bytes: {} primitives, {} vertices, {triangles} triangles (each its own corners, every edge \
         a normal seam), \
         {} joints ({tail} in the tail), {blended} vertices blending two joints; clips {}",
        r.bytes,
        r.prims.len(),
        r.vertices(),
        r.joints,
        Read::clip_text(&clips)
    ))
}

/// `fingers.glb`: 65 joints with 40 in the fingers, about 24k smooth-shaded triangles in four
/// primitives, closed parts, weights blending two joints, three clips that keep the mesh whole.
///
/// # Errors
/// A message naming what is off.
pub fn check_fingers(bytes: &[u8]) -> Result<String, String> {
    let r = read(bytes)?;
    r.check_weights()?;
    let triangles = r.triangles();
    let names = &r.skins[0].nodes;
    let finger_joints = r.skins[0].joints.iter().filter(|j| {
        let name = &names[j.node].name;
        ["Thumb", "Index", "Middle", "Ring", "Pinky"].iter().any(|f| name.contains(f))
    });
    let finger_joints = finger_joints.count();
    let blended = r.prims.iter().flat_map(|p| &p.weights).filter(|w| w[1] > 0.0).count();
    let open = r.prims.iter().map(border_loops).sum::<usize>();
    let faceted_parts = r.prims.iter().filter(|p| faceted(p)).count();
    if !(20_000..=28_000).contains(&triangles)
        || r.joints != 65
        || finger_joints != 40
        || r.prims.len() != 4
        || blended == 0
        || open != 0
        || faceted_parts != 0
        || r.clips.len() != 3
    {
        return Err(format!(
            "fingers: {triangles} triangles, {} joints ({finger_joints} in the fingers), {} primitives, \
             {blended} blended vertices, {open} border loops, {faceted_parts} faceted primitives, {} clips; \
             expected 20,000–28,000, 65 (40), 4, some, none, none, 3",
            r.joints,
            r.prims.len(),
            r.clips.len()
        ));
    }
    let clips = r.check_skinning()?;
    Ok(format!(
        "{} bytes: {} primitives, {} vertices, {triangles} smooth-shaded triangles, {} joints \
         ({finger_joints} in the fingers), {blended} vertices blending two joints; clips {}",
        r.bytes,
        r.prims.len(),
        r.vertices(),
        r.joints,
        Read::clip_text(&clips)
    ))
}

/// A design's file posed by clip `clip` (its index) at `time`, or in the bind pose, as a [`Loaded`]
/// for [`crate::render`]: skinned positions and normals, white vertex colours, every primitive with
/// its material's colour, and `names` the clips' names.
///
/// # Errors
/// What [`read`] rejects.
pub fn posed(bytes: &[u8], clip: Option<(usize, f32)>) -> Result<(Loaded, Vec<String>), String> {
    let r = read(bytes)?;
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| e.to_string())?;
    let colours: Vec<Vec4> =
        gltf.materials().map(|m| Vec4::from(m.pbr_metallic_roughness().base_color_factor())).collect();
    let matrices = r.skin_matrices(clip);
    let mut loaded = Loaded {
        positions: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
        colors: Vec::new(),
        joints: Vec::new(),
        weights: Vec::new(),
        indices: Vec::new(),
        primitives: Vec::new(),
        skeleton: Skeleton::default(),
        clips: Vec::new(),
    };
    for p in &r.prims {
        let base = loaded.positions.len() as u32;
        let first = loaded.indices.len() / 3;
        for (((v, n), j), w) in p.positions.iter().zip(&p.normals).zip(&p.joints).zip(&p.weights) {
            let m = (0..4).fold(Mat4::ZERO, |m, k| m + matrices[p.skin][j[k] as usize] * w[k]);
            loaded.positions.push(m.transform_point3(*v));
            loaded.normals.push((Mat3::from_mat4(m) * *n).normalize_or(*n));
            loaded.colors.push(Vec4::ONE);
        }
        loaded.indices.extend(p.indices.iter().map(|i| i + base));
        let colour = p.material.map_or(Vec4::ONE, |m| colours[m]);
        loaded.primitives.push((first, p.indices.len() / 3, p.positions.len(), String::new(), colour));
    }
    Ok((loaded, r.clips.iter().map(|c| c.name.clone()).collect()))
}

/// The length in seconds of clip `clip` (its index) of a design's file.
///
/// # Errors
/// What [`read`] rejects, or no such clip.
pub fn clip_duration(bytes: &[u8], clip: usize) -> Result<f32, String> {
    read(bytes)?.clips.get(clip).map(Clip::duration).ok_or(format!("no clip {clip}"))
}
