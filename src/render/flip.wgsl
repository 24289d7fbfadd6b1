// LDR-FLIP on the GPU (src/render/flip.rs has the same arithmetic in Rust, tested against NVIDIA's
// reference; src/render/gpu/flip.rs runs this): two fragment passes, so WebGL2 runs it too.
// 1. fs_horizontal, once per picture: 8-bit sRGB to YCxCz, then the horizontal contrast-
//    sensitivity filters ([Y, Cx, Cz1, Cz2] to target 0) and the horizontal feature filters of the
//    lightness (Y + 16) / 116 ([dx, ddx, Gaussian] to target 1), into two rgba32float targets.
// 2. fs_error, once per pair: the vertical filters of both pictures, the colour error (gamut
//    clamp, CIELAB with the Hunt adjustment, HyAB, ^0.7, remapped) and the feature error (edges
//    and points), combined as colour ^ (1 − features) and written as 16 bits in red (high byte)
//    and green (low byte) of an rgba8unorm target.
// Borders are clamped, as in the reference. The kernels come from flip.rs (`FlipKernels::raw`).

struct Kernels {
    // Spatial radius, feature radius, 1 when the pictures hold sRGB-encoded values (a unorm
    // texture) or 0 when reading returns linear values (an sRGB texture), unused.
    radii: vec4<u32>,
    // Per tap from -radius: the Y, Cx, Cz1 and Cz2 Gaussians.
    spatial: array<vec4<f32>, 31>,
    // Per tap: the Gaussian, its first and second derivatives, unused.
    feature: array<vec4<f32>, 31>,
};

@group(0) @binding(0) var<uniform> kernels: Kernels;
@group(0) @binding(1) var picture: texture_2d<f32>;
@group(0) @binding(2) var reference_spatial: texture_2d<f32>;
@group(0) @binding(3) var reference_feature: texture_2d<f32>;
@group(0) @binding(4) var test_spatial: texture_2d<f32>;
@group(0) @binding(5) var test_feature: texture_2d<f32>;

// Vertices 0, 1, 2 at (-1, 1), (3, 1), (-1, -3): one triangle covering the whole target.
@vertex
fn vs_flip(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, 0.0, 1.0);
}

const ILLUMINANT: vec3<f32> = vec3<f32>(0.9504285, 1.0, 1.0889004);

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

fn linear_to_xyz(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        (10135552.0 / 24577794.0) * c.r + (8788810.0 / 24577794.0) * c.g + (4435075.0 / 24577794.0) * c.b,
        (2613072.0 / 12288897.0) * c.r + (8788810.0 / 12288897.0) * c.g + (887015.0 / 12288897.0) * c.b,
        (1425312.0 / 73733382.0) * c.r + (8788810.0 / 73733382.0) * c.g + (70074185.0 / 73733382.0) * c.b,
    );
}

fn xyz_to_linear(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        3.241003275 * c.x - 1.537398934 * c.y - 0.498615861 * c.z,
        -0.969224334 * c.x + 1.875930071 * c.y + 0.041554224 * c.z,
        0.055639423 * c.x - 0.204011202 * c.y + 1.057148933 * c.z,
    );
}

// The picture's texel at `xy` (clamped to its borders) in YCxCz.
fn opponent(xy: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(picture));
    let texel = textureLoad(picture, clamp(xy, vec2<i32>(0), size - 1), 0).rgb;
    let linear = select(texel, srgb_to_linear(texel), kernels.radii.z == 1u);
    let xyz = linear_to_xyz(linear) / ILLUMINANT;
    return vec3<f32>(116.0 * xyz.y - 16.0, 500.0 * (xyz.x - xyz.y), 200.0 * (xyz.y - xyz.z));
}

struct Horizontal {
    @location(0) spatial: vec4<f32>,
    @location(1) feature: vec4<f32>,
};

@fragment
fn fs_horizontal(@builtin(position) position: vec4<f32>) -> Horizontal {
    let xy = vec2<i32>(position.xy);
    let rs = i32(kernels.radii.x);
    let rf = i32(kernels.radii.y);
    var s = vec4<f32>(0.0);
    var f = vec3<f32>(0.0);
    // One loop over both kernels: each texel is converted once.
    for (var i = -max(rs, rf); i <= max(rs, rf); i++) {
        let c = opponent(xy + vec2<i32>(i, 0));
        if abs(i) <= rs {
            let w = kernels.spatial[i + rs];
            s += vec4<f32>(w.x * c.x, w.y * c.y, w.z * c.z, w.w * c.z);
        }
        if abs(i) <= rf {
            let w = kernels.feature[i + rf];
            f += vec3<f32>(w.y, w.z, w.x) * ((c.x + 16.0) / 116.0);
        }
    }
    return Horizontal(s, vec4<f32>(f, 0.0));
}

fn xyz_to_lab(xyz: vec3<f32>) -> vec3<f32> {
    let delta = 6.0 / 29.0;
    let v = xyz / ILLUMINANT;
    let f = select(v / (3.0 * delta * delta) + 4.0 / 29.0, pow(v, vec3<f32>(1.0 / 3.0)), v > vec3<f32>(delta * delta * delta));
    return vec3<f32>(116.0 * f.y - 16.0, 500.0 * (f.x - f.y), 200.0 * (f.y - f.z));
}

fn hunt_lab(linear: vec3<f32>) -> vec3<f32> {
    let lab = xyz_to_lab(linear_to_xyz(linear));
    return vec3<f32>(lab.x, 0.01 * lab.x * lab.y, 0.01 * lab.x * lab.z);
}

fn hyab(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return abs(a.x - b.x) + length(a.yz - b.yz);
}

// x^y for x ≥ 0 that is 0 at x = 0 (pow through exp2(y log2 x) is undefined there).
fn power(x: f32, y: f32) -> f32 {
    return select(pow(x, y), 0.0, x <= 0.0);
}

// A low-passed YCxCz colour, clamped to the sRGB gamut, in Hunt-adjusted CIELAB.
fn gamut(c: vec3<f32>) -> vec3<f32> {
    let y = (c.x + 16.0) / 116.0;
    let xyz = vec3<f32>(y + c.y / 500.0, y, y - c.z / 200.0) * ILLUMINANT;
    return hunt_lab(clamp(xyz_to_linear(xyz), vec3<f32>(0.0), vec3<f32>(1.0)));
}

fn colour_error(reference: vec3<f32>, test: vec3<f32>) -> f32 {
    let cmax = power(hyab(hunt_lab(vec3<f32>(0.0, 1.0, 0.0)), hunt_lab(vec3<f32>(0.0, 0.0, 1.0))), 0.7);
    let pccmax = 0.4 * cmax;
    let d = power(hyab(gamut(reference), gamut(test)), 0.7);
    return select(0.95 + (d - pccmax) / (cmax - pccmax) * 0.05, d * 0.95 / pccmax, d < pccmax);
}

// [dx, dy, ddx, ddy] of both pictures to the feature error.
fn feature_error(reference: vec4<f32>, test: vec4<f32>) -> f32 {
    let edges = abs(length(reference.xy) - length(test.xy));
    let points = abs(length(reference.zw) - length(test.zw));
    return power(0.70710678 * max(edges, points), 0.5);
}

@fragment
fn fs_error(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let xy = vec2<i32>(position.xy);
    let last = i32(textureDimensions(reference_spatial).y) - 1;
    let rs = i32(kernels.radii.x);
    var sr = vec4<f32>(0.0);
    var st = vec4<f32>(0.0);
    for (var i = -rs; i <= rs; i++) {
        let at = vec2<i32>(xy.x, clamp(xy.y + i, 0, last));
        let w = kernels.spatial[i + rs];
        sr += w * textureLoad(reference_spatial, at, 0);
        st += w * textureLoad(test_spatial, at, 0);
    }
    let rf = i32(kernels.radii.y);
    var fr = vec4<f32>(0.0);
    var ft = vec4<f32>(0.0);
    for (var i = -rf; i <= rf; i++) {
        let at = vec2<i32>(xy.x, clamp(xy.y + i, 0, last));
        let w = kernels.feature[i + rf];
        let r = textureLoad(reference_feature, at, 0);
        let t = textureLoad(test_feature, at, 0);
        fr += vec4<f32>(w.x * r.x, w.y * r.z, w.x * r.y, w.z * r.z);
        ft += vec4<f32>(w.x * t.x, w.y * t.z, w.x * t.y, w.z * t.z);
    }
    let colour = colour_error(vec3<f32>(sr.xy, sr.z + sr.w), vec3<f32>(st.xy, st.z + st.w));
    let error = clamp(power(colour, 1.0 - feature_error(fr, ft)), 0.0, 1.0);
    let bits = u32(round(error * 65535.0));
    return vec4<f32>(f32(bits >> 8u) / 255.0, f32(bits & 255u) / 255.0, 0.0, 1.0);
}
