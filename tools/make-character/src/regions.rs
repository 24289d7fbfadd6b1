//! Material regions and per-vertex attributes: splits the welded mesh into one primitive per
//! material (skin, hair, shirt, trousers, shoes) with sharp borders, and adds cylindrical UVs with
//! a seam and a baked ambient-occlusion vertex colour.
//!
//! A triangle's region follows from its centroid: the bone of the nearest primitive, refined by
//! height (belt line, sleeves, shoe cuffs, hairline). Each primitive gets its own copy of the
//! vertices it uses, so vertices on a region border are duplicated with identical position,
//! normal and skin data: the border is sharp in colour but the surface does not tear when skinned.
//!
//! UVs are cylindrical around the vertical body axis: `u = atan2(x, z) / 2π + 0.5` (0 and 1 meet
//! on the back, on the plane x = 0, z < 0) and `v = 1 - y / height` (glTF puts v = 0 at the top).
//! A triangle that straddles the seam uses copies of its `u < 0.5` vertices shifted by +1, so the
//! seam is a line of duplicated vertices whose u differs by exactly 1.

use glam::{Vec2, Vec3, Vec4};

use crate::body::{joint, Joint, HEIGHT};
use crate::field::{body_distance, Part};
use crate::math;
use crate::mesher::RawMesh;

/// The material regions, in primitive order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Region {
    Skin,
    Hair,
    Shirt,
    Trousers,
    Shoes,
}

impl Region {
    pub const ALL: [Region; 5] = [Region::Skin, Region::Hair, Region::Shirt, Region::Trousers, Region::Shoes];

    pub fn name(self) -> &'static str {
        match self {
            Region::Skin => "Skin",
            Region::Hair => "Hair",
            Region::Shirt => "Shirt",
            Region::Trousers => "Trousers",
            Region::Shoes => "Shoes",
        }
    }

    /// Linear RGBA base colour of the region's material.
    pub fn base_color(self) -> [f32; 4] {
        match self {
            Region::Skin => [0.80, 0.55, 0.42, 1.0],
            Region::Hair => [0.12, 0.07, 0.04, 1.0],
            Region::Shirt => [0.10, 0.30, 0.70, 1.0],
            Region::Trousers => [0.16, 0.17, 0.20, 1.0],
            Region::Shoes => [0.45, 0.22, 0.08, 1.0],
        }
    }
}

/// One material's share of the mesh, with its own vertex arrays.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub colors: Vec<Vec4>,
    pub joints: Vec<[u16; 4]>,
    pub weights: Vec<[f32; 4]>,
    pub indices: Vec<u32>,
}

/// Height of the trousers' waistband, in metres.
const BELT: f32 = 0.99;
/// Shoes cover the lower leg below this height (the cuff), in metres.
const SHOE_CUFF: f32 = 0.13;
/// Short sleeves end this far along the upper arm (0 = shoulder, 1 = elbow).
const SLEEVE: f32 = 0.55;

/// The region of a point on the surface.
pub fn region_of(parts: &[Part], joints: &[Joint], p: Vec3) -> Region {
    use joint::*;
    let nearest = parts
        .iter()
        .map(|part| (part.shape.distance(p), part.bone))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(HIPS, |(_, bone)| bone);
    match nearest {
        L_FOOT | L_TOES | R_FOOT | R_TOES => Region::Shoes,
        L_LOWER_LEG | R_LOWER_LEG if p.y < SHOE_CUFF => Region::Shoes,
        L_UPPER_LEG | L_LOWER_LEG | R_UPPER_LEG | R_LOWER_LEG => Region::Trousers,
        HIPS | SPINE | CHEST | L_CLAVICLE | R_CLAVICLE => {
            if p.y < BELT {
                Region::Trousers
            } else {
                Region::Shirt
            }
        }
        L_UPPER_ARM | R_UPPER_ARM => {
            let j = &joints[nearest];
            let t = (p - j.head).dot(j.tail - j.head) / (j.tail - j.head).length_squared();
            if t < SLEEVE {
                Region::Shirt
            } else {
                Region::Skin
            }
        }
        HEAD if is_hair(p) => Region::Hair,
        _ => Region::Skin,
    }
}

/// Hairline: rises gently towards the forehead (which stays bare) and drops steeply behind the
/// ears down to the nape, as a function of depth z.
fn is_hair(p: Vec3) -> bool {
    let hairline = if p.z > -0.02 { 1.67 + 0.4 * p.z } else { 1.662 + 2.5 * (p.z + 0.02) };
    p.y > hairline
}

/// Fake ambient occlusion from the distance field (Quilez's SDF occlusion): how much the field
/// falls short of the free distance at two steps along the normal. Creases (armpits, crotch,
/// under the chin) darken down to the floor value; open surfaces stay at 1.
fn occlusion(parts: &[Part], p: Vec3, n: Vec3) -> f32 {
    // Steps of 3 and 6 cm: the size of the creases worth darkening.
    const STEP: f32 = 0.03;
    // Darkest value, so occluded skin still shows its material colour.
    const FLOOR: f32 = 0.55;
    let mut shortfall = 0.0;
    for k in 1..=2 {
        let h = STEP * k as f32;
        shortfall += (h - body_distance(parts, p + n * h)).max(0.0) / h;
    }
    (1.0 - 0.5 * shortfall).clamp(FLOOR, 1.0)
}

fn cylindrical_u(p: Vec3) -> f32 {
    math::atan2(p.x, p.z) / std::f32::consts::TAU + 0.5
}

/// Splits `mesh` into one [`Primitive`] per [`Region`] (empty ones included, in `Region::ALL`
/// order) and adds UVs, colours and the given skin data; see the module docs.
pub fn split(
    parts: &[Part],
    joints: &[Joint],
    mesh: &RawMesh,
    skin_joints: &[[u16; 4]],
    skin_weights: &[[f32; 4]],
) -> Vec<Primitive> {
    let n = mesh.positions.len();
    let colors: Vec<Vec4> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .map(|(&p, &nrm)| {
            let ao = occlusion(parts, p, nrm);
            Vec4::new(ao, ao, ao, 1.0)
        })
        .collect();
    let u: Vec<f32> = mesh.positions.iter().map(|&p| cylindrical_u(p)).collect();
    let regions: Vec<Region> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let c = (mesh.positions[t[0] as usize]
                + mesh.positions[t[1] as usize]
                + mesh.positions[t[2] as usize])
                / 3.0;
            region_of(parts, joints, c)
        })
        .collect();

    let mut out = Vec::new();
    for region in Region::ALL {
        let mut prim = Primitive::default();
        // New index of (original vertex, shifted by the seam) in this primitive; u32::MAX = unused.
        let mut remap = vec![u32::MAX; 2 * n];
        for (tri, _) in mesh.indices.chunks_exact(3).zip(&regions).filter(|(_, &r)| r == region) {
            let us = [0, 1, 2].map(|k| u[tri[k] as usize]);
            let straddles = us.iter().cloned().fold(f32::MIN, f32::max)
                - us.iter().cloned().fold(f32::MAX, f32::min)
                > 0.5;
            for &v in tri {
                let v = v as usize;
                let shifted = straddles && u[v] < 0.5;
                let key = 2 * v + shifted as usize;
                if remap[key] == u32::MAX {
                    remap[key] = prim.positions.len() as u32;
                    let p = mesh.positions[v];
                    prim.positions.push(p);
                    prim.normals.push(mesh.normals[v]);
                    prim.uvs.push(Vec2::new(u[v] + shifted as u8 as f32, 1.0 - p.y / HEIGHT));
                    prim.colors.push(colors[v]);
                    prim.joints.push(skin_joints[v]);
                    prim.weights.push(skin_weights[v]);
                }
                prim.indices.push(remap[key]);
            }
        }
        out.push(prim);
    }
    out
}
