//! LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild, "FLIP: A
//! Difference Evaluator for Alternating Images", HPG 2020): a per-pixel perceptual difference
//! between a reference and a test picture, 0 (the same to a viewer flipping between them) to 1,
//! for pictures seen at a given number of pixels per degree of visual angle (ppd).
//!
//! The arithmetic is that of NVIDIA's reference implementation (`FLIP.h`, the separable filters
//! of its version 1.2 and later, checked against `flip-evaluator` 1.7 on the fixtures in
//! `tests/fixtures/flip/`): both pictures go from 8-bit sRGB to the opponent space YCxCz;
//! - **colour**: each channel is low-passed by the contrast sensitivity of the eye (Gaussians
//!   whose widths scale with the ppd; the blue–yellow channel a sum of two, separated as in the
//!   reference's `separatedConvolutions.pdf`), clamped to the sRGB gamut, taken to CIELAB with
//!   the Hunt adjustment (chroma × L/100), compared by the HyAB distance, raised to `qc = 0.7` and
//!   remapped so that `pc = 0.4` of the largest distance (green to blue) maps to `pt = 0.95`;
//! - **features**: edges and points of the lightness `(Y + 16) / 116`, found with the first and
//!   second derivatives of a Gaussian (σ = 0.5 · 0.082 · ppd), their magnitudes compared;
//! - the error is `colour ^ (1 − features)`.
//!
//! Images are clamped at their borders, as in the reference. This module is the pure version
//! (native-tested against the reference's numbers); `flip.wgsl` does the same on the GPU in two
//! fragment passes (per picture: the horizontal filters; per pair: the vertical filters and the
//! error), with the kernels this module makes ([`FlipKernels`]) in a uniform buffer.

use bytemuck::{Pod, Zeroable};

/// Pixels per degree of FLIP's standard viewer: 0.7 m from a 0.7 m wide, 3840-pixel screen.
pub const DEFAULT_PPD: f32 = 0.7 * (3840.0 / 0.7) * (std::f32::consts::PI / 180.0);

/// The FLIP shader: `vs_flip`, `fs_horizontal` (per picture) and `fs_error` (per pair).
pub const FLIP_WGSL: &str = include_str!(concat!(env!("OUT_DIR"), "/flip.wgsl"));

/// Taps the GPU kernels hold at most per side (`2 * MAX_RADIUS + 1` in all): a spatial radius of
/// 15 is 111 ppd, a feature radius of 15 is 122 ppd.
pub const MAX_RADIUS: usize = 15;

const QC: f32 = 0.7;
const PC: f32 = 0.4;
const PT: f32 = 0.95;
const GW: f32 = 0.082;
const QF: f32 = 0.5;
/// The contrast-sensitivity Gaussians `a · √(π/b) · exp(−π² x² / b)` of the Y, Cx and Cz channels
/// (`a1, b1, a2, b2`; only Cz uses the second).
const A1: [f32; 3] = [1.0, 1.0, 34.1];
const B1: [f32; 3] = [0.0047, 0.0053, 0.04];
const A2: [f32; 3] = [0.0, 0.0, 13.5];
const B2: [f32; 3] = [1.0e-5, 1.0e-5, 0.025];
const ILLUMINANT: [f32; 3] = [0.950_428_5, 1.0, 1.088_900_4];

/// The 1-D kernels of both pipelines for one ppd, normalized as the reference does.
#[derive(Clone, Debug, PartialEq)]
pub struct FlipKernels {
    pub ppd: f32,
    pub spatial_radius: usize,
    /// Per tap from `-radius` to `radius`: Y, Cx, and the two Cz Gaussians.
    pub spatial: Vec<[f32; 4]>,
    pub feature_radius: usize,
    /// Per tap: the Gaussian, its first and its second derivative.
    pub feature: Vec<[f32; 3]>,
}

impl FlipKernels {
    pub fn new(ppd: f32) -> Self {
        let pi = std::f32::consts::PI;
        let max_b = B1.iter().chain(&B2).fold(0.0f32, |m, &b| m.max(b));
        let spatial_radius = (3.0 * (max_b / (2.0 * pi * pi)).sqrt() * ppd).ceil() as usize;
        let gaussian = |x2: f32, a: f32, b: f32| a * (pi / b).sqrt() * (-pi * pi * x2 / b).exp();
        let gaussian_sqrt =
            |x2: f32, a: f32, b: f32| (a * (pi / b).sqrt()).sqrt() * (-pi * pi * x2 / b).exp();
        let mut spatial: Vec<[f32; 4]> = (0..2 * spatial_radius + 1)
            .map(|i| {
                let x = (i as f32 - spatial_radius as f32) / ppd;
                let x2 = x * x;
                [
                    gaussian(x2, A1[0], B1[0]),
                    gaussian(x2, A1[1], B1[1]),
                    gaussian_sqrt(x2, A1[2], B1[2]),
                    gaussian_sqrt(x2, A2[2], B2[2]),
                ]
            })
            .collect();
        let sum = |c: usize, k: &[[f32; 4]]| k.iter().map(|w| w[c]).sum::<f32>();
        let (sy, sx) = (sum(0, &spatial), sum(1, &spatial));
        let sz = (sum(2, &spatial).powi(2) + sum(3, &spatial).powi(2)).sqrt();
        for w in &mut spatial {
            *w = [w[0] / sy, w[1] / sx, w[2] / sz, w[3] / sz];
        }
        let sd = 0.5 * GW * ppd;
        let feature_radius = (3.0 * sd).ceil() as usize;
        let mut feature: Vec<[f32; 3]> = (0..2 * feature_radius + 1)
            .map(|i| {
                let x = i as f32 - feature_radius as f32;
                let g = (-(x * x) / (2.0 * sd * sd)).exp();
                [g, -x * g, (x * x / (sd * sd) - 1.0) * g]
            })
            .collect();
        let g_sum: f32 = feature.iter().map(|w| w[0]).sum();
        let signed = |c: usize, positive: bool| -> f32 {
            feature.iter().map(|w| w[c]).filter(|&v| (v > 0.0) == positive).map(f32::abs).sum()
        };
        let (dp, dn, ddp, ddn) = (signed(1, true), signed(1, false), signed(2, true), signed(2, false));
        for w in &mut feature {
            *w = [
                w[0] / g_sum,
                w[1] / if w[1] > 0.0 { dp } else { dn },
                w[2] / if w[2] > 0.0 { ddp } else { ddn },
            ];
        }
        Self { ppd, spatial_radius, spatial, feature_radius, feature }
    }

    /// The kernels as the shader's uniform, when they fit ([`MAX_RADIUS`]).
    pub fn raw(&self) -> Option<FlipKernelsRaw> {
        if self.spatial_radius > MAX_RADIUS || self.feature_radius > MAX_RADIUS {
            return None;
        }
        let mut raw = FlipKernelsRaw::zeroed();
        raw.radii = [self.spatial_radius as u32, self.feature_radius as u32, 0, 0];
        for (slot, w) in raw.spatial.iter_mut().zip(&self.spatial) {
            *slot = *w;
        }
        for (slot, w) in raw.feature.iter_mut().zip(&self.feature) {
            *slot = [w[0], w[1], w[2], 0.0];
        }
        Some(raw)
    }
}

/// `Kernels` in `flip.wgsl`: the radii, then the taps from `-radius` on (the rest zero).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FlipKernelsRaw {
    /// Spatial radius, feature radius, whether the pictures hold sRGB-encoded values that the
    /// shader must decode (1) or linear ones (0, an sRGB texture), and 0.
    pub radii: [u32; 4],
    pub spatial: [[f32; 4]; 2 * MAX_RADIUS + 1],
    pub feature: [[f32; 4]; 2 * MAX_RADIUS + 1],
}

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_xyz([r, g, b]: [f32; 3]) -> [f32; 3] {
    [
        (10_135_552.0 / 24_577_794.0) * r
            + (8_788_810.0 / 24_577_794.0) * g
            + (4_435_075.0 / 24_577_794.0) * b,
        (2_613_072.0 / 12_288_897.0) * r + (8_788_810.0 / 12_288_897.0) * g + (887_015.0 / 12_288_897.0) * b,
        (1_425_312.0 / 73_733_382.0) * r
            + (8_788_810.0 / 73_733_382.0) * g
            + (70_074_185.0 / 73_733_382.0) * b,
    ]
}

fn xyz_to_linear([x, y, z]: [f32; 3]) -> [f32; 3] {
    [
        3.241_003_3 * x - 1.537_398_9 * y - 0.498_615_86 * z,
        -0.969_224_3 * x + 1.875_930_1 * y + 0.041_554_224 * z,
        0.055_639_423 * x - 0.204_011_2 * y + 1.057_148_9 * z,
    ]
}

/// 8-bit sRGB to YCxCz (Y in 0..100).
pub fn ycxcz(rgb: [u8; 3]) -> [f32; 3] {
    let linear = rgb.map(|c| srgb_to_linear(f32::from(c) / 255.0));
    let [x, y, z] = linear_to_xyz(linear);
    let (x, y, z) = (x / ILLUMINANT[0], y / ILLUMINANT[1], z / ILLUMINANT[2]);
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

fn ycxcz_to_xyz([yy, cx, cz]: [f32; 3]) -> [f32; 3] {
    let y = (yy + 16.0) / 116.0;
    [(y + cx / 500.0) * ILLUMINANT[0], y * ILLUMINANT[1], (y - cz / 200.0) * ILLUMINANT[2]]
}

fn xyz_to_lab(xyz: [f32; 3]) -> [f32; 3] {
    let delta: f32 = 6.0 / 29.0;
    let f = |v: f32| {
        if v > delta * delta * delta {
            v.powf(1.0 / 3.0)
        } else {
            v / (3.0 * delta * delta) + 4.0 / 29.0
        }
    };
    let [x, y, z] = [f(xyz[0] / ILLUMINANT[0]), f(xyz[1] / ILLUMINANT[1]), f(xyz[2] / ILLUMINANT[2])];
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

/// CIELAB with the Hunt adjustment (chroma × L / 100) of a linear RGB colour.
fn hunt_lab(linear: [f32; 3]) -> [f32; 3] {
    let [l, a, b] = xyz_to_lab(linear_to_xyz(linear));
    [l, 0.01 * l * a, 0.01 * l * b]
}

fn hyab(a: [f32; 3], b: [f32; 3]) -> f32 {
    (a[0] - b[0]).abs() + ((a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The colour error of two low-passed YCxCz colours, 0..1.
pub fn colour_error(reference: [f32; 3], test: [f32; 3]) -> f32 {
    let gamut = |c: [f32; 3]| hunt_lab(xyz_to_linear(ycxcz_to_xyz(c)).map(|v| v.clamp(0.0, 1.0)));
    let cmax = hyab(hunt_lab([0.0, 1.0, 0.0]), hunt_lab([0.0, 0.0, 1.0])).powf(QC);
    let pccmax = PC * cmax;
    let d = hyab(gamut(reference), gamut(test)).powf(QC);
    if d < pccmax {
        d * PT / pccmax
    } else {
        PT + (d - pccmax) / (cmax - pccmax) * (1.0 - PT)
    }
}

/// The feature error of two pictures' `[dx, dy, ddx, ddy]` responses, 0..1.
pub fn feature_error(reference: [f32; 4], test: [f32; 4]) -> f32 {
    let edge = |f: [f32; 4]| (f[0] * f[0] + f[1] * f[1]).sqrt();
    let point = |f: [f32; 4]| (f[2] * f[2] + f[3] * f[3]).sqrt();
    let d = (edge(reference) - edge(test)).abs().max((point(reference) - point(test)).abs());
    (std::f32::consts::FRAC_1_SQRT_2 * d).powf(QF)
}

/// The per-picture filters: per pixel, the spatially filtered YCxCz and the feature responses
/// `[dx, dy, ddx, ddy]` of the normalized lightness.
fn filtered(rgba: &[u8], width: usize, height: usize, k: &FlipKernels) -> Vec<([f32; 3], [f32; 4])> {
    let opponent: Vec<[f32; 3]> = rgba.chunks_exact(4).map(|p| ycxcz([p[0], p[1], p[2]])).collect();
    let at = |x: isize, y: usize, w: usize| y * w + x.clamp(0, w as isize - 1) as usize;
    // Horizontal: [Y, Cx, Cz1, Cz2] and [dx, ddx, g] of the lightness.
    let mut spatial_h = vec![[0.0f32; 4]; width * height];
    let mut feature_h = vec![[0.0f32; 3]; width * height];
    for y in 0..height {
        for x in 0..width {
            let mut s = [0.0f32; 4];
            for (i, w) in k.spatial.iter().enumerate() {
                let c = opponent[at(x as isize + i as isize - k.spatial_radius as isize, y, width)];
                s = [s[0] + w[0] * c[0], s[1] + w[1] * c[1], s[2] + w[2] * c[2], s[3] + w[3] * c[2]];
            }
            let mut f = [0.0f32; 3];
            for (i, w) in k.feature.iter().enumerate() {
                let c = opponent[at(x as isize + i as isize - k.feature_radius as isize, y, width)];
                let l = (c[0] + 16.0) / 116.0;
                f = [f[0] + w[1] * l, f[1] + w[2] * l, f[2] + w[0] * l];
            }
            spatial_h[y * width + x] = s;
            feature_h[y * width + x] = f;
        }
    }
    let row = |y: isize| y.clamp(0, height as isize - 1) as usize;
    let mut out = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let mut s = [0.0f32; 4];
            for (i, w) in k.spatial.iter().enumerate() {
                let c = spatial_h[row(y as isize + i as isize - k.spatial_radius as isize) * width + x];
                s = [s[0] + w[0] * c[0], s[1] + w[1] * c[1], s[2] + w[2] * c[2], s[3] + w[3] * c[3]];
            }
            let mut f = [0.0f32; 4];
            for (i, w) in k.feature.iter().enumerate() {
                let c = feature_h[row(y as isize + i as isize - k.feature_radius as isize) * width + x];
                f = [f[0] + w[0] * c[0], f[1] + w[1] * c[2], f[2] + w[0] * c[1], f[3] + w[2] * c[2]];
            }
            out.push(([s[0], s[1], s[2] + s[3]], f));
        }
    }
    out
}

/// The LDR-FLIP error map of two RGBA8 sRGB pictures of `width` × `height` (alpha ignored), seen
/// at `ppd` pixels per degree: one value in 0..1 per pixel, rows top first.
///
/// # Panics
/// If the pictures are not both `4 * width * height` bytes.
pub fn flip_map(reference: &[u8], test: &[u8], width: usize, height: usize, ppd: f32) -> Vec<f32> {
    assert!(reference.len() == 4 * width * height && test.len() == reference.len(), "two RGBA8 pictures");
    let kernels = FlipKernels::new(ppd);
    let (r, t) = (filtered(reference, width, height, &kernels), filtered(test, width, height, &kernels));
    r.iter()
        .zip(&t)
        .map(|((rc, rf), (tc, tf))| colour_error(*rc, *tc).powf(1.0 - feature_error(*rf, *tf)))
        .collect()
}

/// The mean of an error map and its 99th percentile (linear between the nearest ranks, as
/// numpy's default).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlipStats {
    pub mean: f32,
    pub p99: f32,
}

impl FlipStats {
    pub fn of(map: &[f32]) -> Self {
        if map.is_empty() {
            return Self::default();
        }
        let mean = (map.iter().map(|&e| f64::from(e)).sum::<f64>() / map.len() as f64) as f32;
        let mut sorted = map.to_vec();
        sorted.sort_by(f32::total_cmp);
        let rank = 0.99 * (sorted.len() - 1) as f32;
        let lo = rank.floor() as usize;
        let hi = (lo + 1).min(sorted.len() - 1);
        let p99 = sorted[lo] + (rank - lo as f32) * (sorted[hi] - sorted[lo]);
        Self { mean, p99 }
    }
}

/// An error the shader wrote as 16 bits in two 8-bit channels (`high`, `low`), back to 0..1.
pub fn unpack_error(high: u8, low: u8) -> f32 {
    f32::from(u16::from(high) << 8 | u16::from(low)) / 65535.0
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn kernels_are_normalized_as_the_reference_does() {
        let k = FlipKernels::new(DEFAULT_PPD);
        assert_eq!((k.spatial_radius, k.feature_radius), (10, 9), "at 67 ppd");
        let sum = |c: usize| k.spatial.iter().map(|w| w[c]).sum::<f32>();
        assert!((sum(0) - 1.0).abs() < 1e-5 && (sum(1) - 1.0).abs() < 1e-5);
        // The two Cz Gaussians together: their 2-D sum is 1.
        assert!((sum(2).powi(2) + sum(3).powi(2) - 1.0).abs() < 1e-5);
        let f = |c: usize, positive: bool| {
            k.feature.iter().map(|w| w[c]).filter(|&v| (v > 0.0) == positive).sum::<f32>()
        };
        assert!((f(0, true) - 1.0).abs() < 1e-5);
        for c in [1, 2] {
            assert!((f(c, true) - 1.0).abs() < 1e-5 && (f(c, false) + 1.0).abs() < 1e-5, "{c}");
        }
        assert!(k.raw().is_some() && FlipKernels::new(200.0).raw().is_none());
    }

    #[test]
    fn equal_pictures_do_not_differ_and_black_against_white_is_large() {
        let grey: Vec<u8> = (0..16 * 16).flat_map(|i| [(i % 200) as u8, 90, 40, 255]).collect();
        assert!(flip_map(&grey, &grey, 16, 16, 30.0).iter().all(|&e| e == 0.0));
        let (black, white) = (vec![0u8; 4 * 64], vec![255u8; 4 * 64]);
        let stats = FlipStats::of(&flip_map(&black, &white, 8, 8, 30.0));
        assert!(stats.mean > 0.9 && stats.mean <= 1.0, "{stats:?}");
    }

    #[test]
    fn the_percentile_interpolates_between_ranks_and_errors_unpack() {
        let map: Vec<f32> = (0..=100).map(|i| i as f32 / 100.0).collect();
        let s = FlipStats::of(&map);
        assert!((s.mean - 0.5).abs() < 1e-6 && (s.p99 - 0.99).abs() < 1e-6, "{s:?}");
        let s = FlipStats::of(&[0.0, 1.0]);
        assert!((s.p99 - 0.99).abs() < 1e-6);
        assert_eq!((unpack_error(255, 255), unpack_error(0, 0)), (1.0, 0.0));
        assert!((unpack_error(128, 0) - 32768.0 / 65535.0).abs() < 1e-7);
    }
}
