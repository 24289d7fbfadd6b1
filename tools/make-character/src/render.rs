//! A small CPU rasterizer for looking at the character: orthographic views, z-buffer, Lambert
//! shading with an ambient term, colour = material base colour × vertex colour.
//!
//! An image shows one or more views side by side (usually front, three-quarter, left side), rendered at twice
//! the output resolution and box-filtered down. Views turn the model about +Y; screen x is the
//! turned model's +X, screen y its +Y, and larger z is nearer the viewer. Output is 8-bit sRGB PNG.

use std::path::Path;

use glam::{Quat, Vec3, Vec4};

use crate::validate::Loaded;

/// Size of one view in output pixels.
const VIEW: usize = 400;
/// Supersampling factor per axis (2×2 samples per output pixel).
const SS: usize = 2;
/// What part of the world a view shows.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Model-space point at the centre of each view (before turning; only x and y are used).
    pub center: Vec3,
    /// Visible world height in metres.
    pub height: f32,
}

impl Frame {
    /// The whole character with the floor near the bottom, room for a raised hand at the top.
    pub const FULL: Frame = Frame { center: Vec3::new(0.0, 0.98, 0.0), height: 2.2 };
}

/// Turn angles of the usual three views, in degrees about +Y (0 = front, -90 = the character's
/// left side).
pub const THREE_VIEWS: [f32; 3] = [0.0, -35.0, -90.0];

fn linear_to_srgb(x: f32) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// Renders `positions`/`normals` (skinned or bind) of `loaded` into an RGB image with one view
/// per turn angle in `views` (degrees), side by side.
pub fn render(
    loaded: &Loaded,
    positions: &[Vec3],
    normals: &[Vec3],
    frame: Frame,
    views: &[f32],
) -> (usize, usize, Vec<u8>) {
    let (w, h) = (VIEW * views.len(), VIEW);
    let (sw, sh) = (w * SS, h * SS);
    let background = Vec3::new(0.85, 0.87, 0.9);
    let mut color = vec![background; sw * sh];
    let mut depth = vec![f32::MIN; sw * sh];
    let scale = sh as f32 / frame.height;
    // Light from the upper front-left of each view, plus an ambient term so shadowed sides read.
    let light = Vec3::new(-0.4, 0.6, 0.7).normalize();
    const AMBIENT: f32 = 0.3;

    for (view, &angle) in views.iter().enumerate() {
        let turn = Quat::from_rotation_y(angle.to_radians());
        let x0 = (view * VIEW * SS) as f32 + 0.5 * (VIEW * SS) as f32;
        let project = |p: Vec3| {
            let q = turn * (p - frame.center);
            Vec3::new(x0 + q.x * scale, 0.5 * sh as f32 - q.y * scale, q.z)
        };
        let screen: Vec<Vec3> = positions.iter().map(|&p| project(p)).collect();
        for &(first, count, _, _, base) in &loaded.primitives {
            for t in first..first + count {
                let ids = [0, 1, 2].map(|k| loaded.indices[3 * t + k] as usize);
                let [a, b, c] = ids.map(|i| screen[i]);
                let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
                if area.abs() < 1e-12 {
                    continue;
                }
                let min_x = a.x.min(b.x).min(c.x).floor().max((view * VIEW * SS) as f32) as usize;
                let max_x = a.x.max(b.x).max(c.x).ceil().min(((view + 1) * VIEW * SS - 1) as f32) as usize;
                let min_y = a.y.min(b.y).min(c.y).floor().max(0.0) as usize;
                let max_y = a.y.max(b.y).max(c.y).ceil().min((sh - 1) as f32) as usize;
                for py in min_y..=max_y {
                    for px in min_x..=max_x {
                        let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
                        let w0 = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / area;
                        let w1 = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / area;
                        let w2 = 1.0 - w0 - w1;
                        if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                            continue;
                        }
                        let z = w0 * a.z + w1 * b.z + w2 * c.z;
                        let i = py * sw + px;
                        if z <= depth[i] {
                            continue;
                        }
                        depth[i] = z;
                        let n = turn
                            * (w0 * normals[ids[0]] + w1 * normals[ids[1]] + w2 * normals[ids[2]])
                                .normalize_or_zero();
                        let vc: Vec4 = w0 * loaded.colors[ids[0]]
                            + w1 * loaded.colors[ids[1]]
                            + w2 * loaded.colors[ids[2]];
                        let lambert = n.dot(light).max(0.0);
                        color[i] = base.truncate() * vc.truncate() * (AMBIENT + (1.0 - AMBIENT) * lambert);
                    }
                }
            }
        }
    }

    let mut rgb = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Vec3::ZERO;
            for dy in 0..SS {
                for dx in 0..SS {
                    sum += color[(y * SS + dy) * sw + x * SS + dx];
                }
            }
            let avg = sum / (SS * SS) as f32;
            rgb.extend(avg.to_array().map(linear_to_srgb));
        }
    }
    (w, h, rgb)
}

/// Writes an RGB image as PNG.
pub fn write_png(path: &Path, (w, h, rgb): &(usize, usize, Vec<u8>)) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), *w as u32, *h as u32);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(rgb).map_err(|e| e.to_string())
}
