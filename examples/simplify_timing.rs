//! Release-mode timing of a full progressive-mesh build on a seeded ~50k-triangle noisy torus
//! with normals and uv (two seam loops). Run: `cargo run --release --example simplify_timing
//! --no-default-features`.

use clod_viewer::simplify::{simplify, CollapseMode, SimplifyInput, SimplifyOptions};
use glam::Vec3;
use std::time::Instant;

fn main() {
    let (nu, nv) = (200u32, 125u32);
    let mut state = 0x1234_5678_u64;
    let mut noise = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5
    };
    let bumps: Vec<f32> = (0..nu * nv).map(|_| 0.004 * noise()).collect();
    let mut positions = Vec::new();
    let mut attributes = Vec::new();
    for j in 0..=nv {
        for i in 0..=nu {
            let (iu, jv) = (i % nu, j % nv);
            let theta = std::f32::consts::TAU * iu as f32 / nu as f32;
            let phi = std::f32::consts::TAU * jv as f32 / nv as f32;
            let r = 0.35 + bumps[(jv * nu + iu) as usize];
            let ring = 1.0 + r * phi.cos();
            positions.push(Vec3::new(ring * theta.cos(), ring * theta.sin(), r * phi.sin()));
            let n = Vec3::new(phi.cos() * theta.cos(), phi.cos() * theta.sin(), phi.sin());
            attributes.extend_from_slice(&[n.x, n.y, n.z, i as f32 / nu as f32, j as f32 / nv as f32]);
        }
    }
    let mut indices = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let a = j * (nu + 1) + i;
            indices.extend_from_slice(&[a, a + 1, a + nu + 2, a, a + nu + 2, a + nu + 1]);
        }
    }
    let weights = [0.05, 0.05, 0.05, 1.0, 1.0];
    let input = SimplifyInput {
        positions: &positions,
        attributes: &attributes,
        attribute_weights: &weights,
        indices: &indices,
        triangle_materials: &[],
        vertex_quadrics: None,
    };
    for (name, attribute_weights, mode) in [
        ("full, 5 attributes", &weights[..], CollapseMode::Full),
        ("full, geometry only", &[][..], CollapseMode::Full),
        ("half-edge, 5 attributes", &weights[..], CollapseMode::HalfEdge),
    ] {
        let input = SimplifyInput {
            attributes: if attribute_weights.is_empty() { &[] } else { &attributes },
            attribute_weights,
            ..input
        };
        let options = SimplifyOptions {
            mode,
            normal_channel: (!attribute_weights.is_empty()).then_some(0),
            ..SimplifyOptions::default()
        };
        let mut best = f64::INFINITY;
        let mut result = None;
        for _ in 0..5 {
            let start = Instant::now();
            let pm = simplify(&input, &options).expect("valid input");
            best = best.min(start.elapsed().as_secs_f64());
            result = Some(pm);
        }
        let pm = result.expect("ran");
        let k = pm.collapse_count();
        println!(
            "{name}: {} triangles -> {} in {} collapses, best of 5: {:.1} ms",
            indices.len() / 3,
            pm.triangle_count_after(k),
            k,
            best * 1e3
        );
    }
}
