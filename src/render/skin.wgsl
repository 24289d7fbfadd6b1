// Skinned, lit character for the three LOD views (src/render/gpu/pipelines.rs builds its
// pipelines; the Rust mirrors of these structs are in src/render/uniforms.rs and tests/shaders.rs
// checks their sizes match).
//
// Linear-blend skinning on the GPU: `model_from_bind` of every joint is uploaded once per frame,
// as a texture (`joint_matrices`).
// `vs_level` draws one level as it is; `vs_geomorph` also reads each vertex's ancestor in the next
// coarser level (the same attributes, locations 6..11), skins both and interpolates by `draw.morph_t`
// (0 = exactly the fine level, 1 = exactly the coarse one). Both ends are morphed by the frame's
// morph-target weights first (`morphed`), each with its own deltas. The `vs_wire_*` twins and `fs_wire` draw
// the wireframe overlay from line-list index buffers over the same vertices; `vs_bone` and
// `fs_bone` draw the skeleton overlay from a line list of posed joint positions. Lighting is in model space: a hemisphere
// ambient plus one directional light, Lambert diffuse and a little Blinn-Phong. Colours are linear;
// the target is sRGB, or the shader encodes when `camera.encode_srgb` is 1.

// Must equal MAX_MORPH_TARGETS in src/morph.rs: one weight each, 4 KiB of uniforms.
const MAX_MORPH_TARGETS: u32 = 1024u;

struct Camera {
    clip_from_model: mat4x4<f32>,
    eye_model: vec4<f32>,
    // xyz: unit direction towards the light, model space; w: its intensity.
    light_dir: vec4<f32>,
    sky_color: vec4<f32>,
    ground_color: vec4<f32>,
    // xyz: model-space up for the hemisphere light.
    up: vec4<f32>,
    encode_srgb: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

// Morph target weights of this frame's pose, four per vec4 (std140 pads a scalar array).
struct MorphWeights {
    weights: array<vec4<f32>, 256>,
};

struct Material {
    base_color_factor: vec4<f32>,
    // Fragments with alpha below this are discarded (glTF MASK); 0 for other modes.
    alpha_cutoff: f32,
    double_sided: u32,
    _pad0: u32,
    _pad1: u32,
};

struct Draw {
    morph_t: f32,
    // Alpha written by the fragment shader (1 for opaque draws).
    opacity: f32,
    // 0: no dither; 1: keep pixels whose Bayer threshold is below `dither_threshold`; 2: keep the
    // others. Modes 1 and 2 with the same threshold cover every pixel exactly once.
    dither_mode: u32,
    _pad0: u32,
    dither_threshold: f32,
    _pad1: f32,
    // Top-left of the view in framebuffer pixels, so every view dithers with the same pattern.
    viewport_origin: vec2<f32>,
    // Level overlay: linear RGB and how much of the surface colour it replaces (0: none).
    tint: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;
// `model_from_bind` of every skin joint, four texels per column-major matrix, `width / 4` joints to
// a row (src/render/joint_texture.rs): a texture, so any joint count draws on WebGL2 too.
@group(0) @binding(1) var joint_matrices: texture_2d<f32>;
@group(0) @binding(2) var<uniform> morph_weights: MorphWeights;
// Every morph delta by vertex id, two texels per entry: (Δp, target) and (Δn, 0), rows of
// `textureDimensions(morph_deltas).x` texels (src/render/lod_source.rs `morph_texels`).
@group(0) @binding(3) var morph_deltas: texture_2d<f32>;
@group(1) @binding(0) var<uniform> material: Material;
@group(1) @binding(1) var base_color_texture: texture_2d<f32>;
@group(1) @binding(2) var base_color_sampler: sampler;
@group(2) @binding(0) var<uniform> draw: Draw;

struct LevelVertex {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
    @location(4) joints: vec4<u32>,
    @location(5) weights: vec4<f32>,
};

// A vertex's morph deltas: (first entry, entry count) in `morph_deltas`, for the drawn vertex
// and its ancestor (VertexRaw::morph of each half of GeomorphVertexRaw).
struct MorphRows {
    @location(12) fine: vec2<u32>,
    @location(13) coarse: vec2<u32>,
};

// The drawn vertex's row alone (levels drawn as they are).
struct MorphRow {
    @location(12) fine: vec2<u32>,
};

// The ancestor's attributes, in `LevelVertex`'s order, at locations 6..11.
struct AncestorVertex {
    @location(6) position: vec3<f32>, @location(7) normal: vec3<f32>,
    @location(8) uv: vec2<f32>, @location(9) color: vec4<f32>,
    @location(10) joints: vec4<u32>, @location(11) weights: vec4<f32>,
};

struct Varyings {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
};

// Joint `joint`'s `model_from_bind`. Out-of-range joints (the importer rejects them; defence in
// depth) read the texture's last slot rather than past it.
fn joint_matrix(joint: u32) -> mat4x4<f32> {
    let size = textureDimensions(joint_matrices);
    let per_row = size.x / 4u;
    let k = min(joint, per_row * size.y - 1u);
    let x = i32((k % per_row) * 4u);
    let y = i32(k / per_row);
    return mat4x4<f32>(
        textureLoad(joint_matrices, vec2<i32>(x, y), 0),
        textureLoad(joint_matrices, vec2<i32>(x + 1, y), 0),
        textureLoad(joint_matrices, vec2<i32>(x + 2, y), 0),
        textureLoad(joint_matrices, vec2<i32>(x + 3, y), 0),
    );
}

fn blend_matrix(j: vec4<u32>, w: vec4<f32>) -> mat4x4<f32> {
    return joint_matrix(j.x) * w.x + joint_matrix(j.y) * w.y + joint_matrix(j.z) * w.z + joint_matrix(j.w) * w.w;
}

fn finish(position: vec3<f32>, normal: vec3<f32>, uv: vec2<f32>, color: vec4<f32>) -> Varyings {
    var out: Varyings;
    out.clip = camera.clip_from_model * vec4<f32>(position, 1.0);
    out.position = position;
    out.normal = normal;
    out.uv = uv;
    out.color = color;
    return out;
}

struct Morphed {
    position: vec3<f32>,
    normal: vec3<f32>,
};

fn morph_texel(i: u32) -> vec4<f32> {
    let width = textureDimensions(morph_deltas).x;
    return textureLoad(morph_deltas, vec2<i32>(i32(i % width), i32(i / width)), 0);
}

// One morph entry: a target's position and normal deltas for one vertex.
struct MorphEntry {
    dp: vec3<f32>,
    dn: vec3<f32>,
    target_index: u32,
};

// Entry `k` of a vertex's `row` (k < row.y).
fn morph_entry(row: vec2<u32>, k: u32) -> MorphEntry {
    let e = row.x + k;
    let dp = morph_texel(2u * e);
    let dn = morph_texel(2u * e + 1u);
    return MorphEntry(dp.xyz, dn.xyz, min(u32(dp.w), MAX_MORPH_TARGETS - 1u));
}

// glTF morphing (§3.7.2.2), before skinning: p + Σ w_t Δp_t and n + Σ w_t Δn_t over the vertex's
// entries, with the frame's weights. A vertex has at most one entry per target, hence the loop's
// bound. (`crowd_morphed` in crowd.wgsl is the same sum with each instance's weights.)
fn morphed(position: vec3<f32>, normal: vec3<f32>, row: vec2<u32>) -> Morphed {
    var out = Morphed(position, normal);
    for (var k = 0u; k < min(row.y, MAX_MORPH_TARGETS); k++) {
        let m = morph_entry(row, k);
        let w = morph_weights.weights[m.target_index / 4u][m.target_index % 4u];
        out.position += w * m.dp;
        out.normal += w * m.dn;
    }
    return out;
}

fn level_varyings(v: LevelVertex, row: vec2<u32>) -> Varyings {
    let b = morphed(v.position, v.normal, row);
    let m = blend_matrix(v.joints, v.weights);
    let p = (m * vec4<f32>(b.position, 1.0)).xyz;
    // No non-uniform scale in skins we accept, so the upper 3x3 transforms normals too.
    let n = (m * vec4<f32>(b.normal, 0.0)).xyz;
    return finish(p, n, v.uv, v.color);
}

fn geomorph_varyings(v: LevelVertex, a: AncestorVertex, rows: MorphRows) -> Varyings {
    let fb = morphed(v.position, v.normal, rows.fine);
    let cb = morphed(a.position, a.normal, rows.coarse);
    let fine = blend_matrix(v.joints, v.weights);
    let coarse = blend_matrix(a.joints, a.weights);
    let t = draw.morph_t;
    // mix(a, b, t) = a * (1 - t) + b * t: exactly a at t = 0 and exactly b at t = 1.
    let p = mix((fine * vec4<f32>(fb.position, 1.0)).xyz, (coarse * vec4<f32>(cb.position, 1.0)).xyz, t);
    let n = mix((fine * vec4<f32>(fb.normal, 0.0)).xyz, (coarse * vec4<f32>(cb.normal, 0.0)).xyz, t);
    return finish(p, n, mix(v.uv, a.uv, t), mix(v.color, a.color, t));
}

// Wireframe lines lie on their own triangles: pulled this fraction of w towards the eye (about
// 1e-4 of the depth range hugging the character), they win the depth test against them.
// Depth bias would be the usual tool, but WebGPU allows it on triangles only.
const WIRE_DEPTH_PULL: f32 = 0.0002;

fn pulled(v: Varyings) -> Varyings {
    var out = v;
    out.clip.z = max(v.clip.z - WIRE_DEPTH_PULL * v.clip.w, 0.0);
    return out;
}

@vertex
fn vs_level(v: LevelVertex, row: MorphRow) -> Varyings {
    return level_varyings(v, row.fine);
}

@vertex
fn vs_geomorph(v: LevelVertex, a: AncestorVertex, rows: MorphRows) -> Varyings {
    return geomorph_varyings(v, a, rows);
}

@vertex
fn vs_wire_level(v: LevelVertex, row: MorphRow) -> Varyings {
    return pulled(level_varyings(v, row.fine));
}

@vertex
fn vs_wire_geomorph(v: LevelVertex, a: AncestorVertex, rows: MorphRows) -> Varyings {
    return pulled(geomorph_varyings(v, a, rows));
}

// 4x4 Bayer matrix, thresholds (k + 0.5) / 16 so no pixel sits exactly on 0 or 1.
fn bayer_threshold(pixel: vec2<u32>) -> f32 {
    var m = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    let k = m[(pixel.y % 4u) * 4u + pixel.x % 4u];
    return (f32(k) + 0.5) / 16.0;
}

// Whether a screen-door mask (`mode` and `threshold` as in `Draw`) drops the fragment at
// framebuffer position `xy`.
fn dithered_out(xy: vec2<f32>, mode: u32, threshold: f32) -> bool {
    if (mode == 0u) {
        return false;
    }
    let pixel = vec2<u32>(max(xy - draw.viewport_origin, vec2<f32>(0.0)));
    let below = bayer_threshold(pixel) < threshold;
    return below != (mode == 1u);
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

@fragment
fn fs_main(in: Varyings, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return shade(in, front, draw.opacity, draw.dither_mode, draw.dither_threshold, draw.tint);
}

// The lit surface colour of a fragment with the draw's opacity, screen-door mask and level tint
// (from the `Draw` uniform for one character, from the instance record in a crowd).
fn shade(in: Varyings, front: bool, opacity: f32, dither_mode: u32, dither_threshold: f32, tint: vec4<f32>) -> vec4<f32> {
    // Sample first: texture sampling needs uniform control flow, before any discard.
    let texel = textureSample(base_color_texture, base_color_sampler, in.uv);
    let base = material.base_color_factor * texel * in.color;
    if (base.a < material.alpha_cutoff) {
        discard;
    }
    if (dithered_out(in.clip.xy, dither_mode, dither_threshold)) {
        discard;
    }
    var n = normalize(in.normal);
    if (!front && material.double_sided == 1u) {
        n = -n;
    }
    let l = camera.light_dir.xyz;
    let up = camera.up.xyz;
    let ambient = mix(camera.ground_color.rgb, camera.sky_color.rgb, 0.5 + 0.5 * dot(n, up));
    let n_dot_l = max(dot(n, l), 0.0);
    let view = normalize(camera.eye_model.xyz - in.position);
    let h = normalize(l + view);
    // A little Blinn-Phong: exponent 32 and strength 0.12 keep skin and cloth from looking plastic.
    let specular = select(0.0, 0.12 * pow(max(dot(n, h), 0.0), 32.0), n_dot_l > 0.0);
    // The level overlay's tint replaces part of the surface colour (strength 0 without it).
    let albedo = mix(base.rgb, tint.rgb, tint.w);
    var rgb = albedo * (ambient + n_dot_l * camera.light_dir.w) + vec3<f32>(specular * camera.light_dir.w);
    if (camera.encode_srgb == 1u) {
        rgb = srgb_encode(clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0)));
    }
    return vec4<f32>(rgb, opacity);
}

// Wireframe lines: near-black, half covering the shading, faded with their draw.
@fragment
fn fs_wire(in: Varyings) -> @location(0) vec4<f32> {
    if (dithered_out(in.clip.xy, draw.dither_mode, draw.dither_threshold)) {
        discard;
    }
    var rgb = vec3<f32>(0.01, 0.012, 0.02);
    if (camera.encode_srgb == 1u) {
        rgb = srgb_encode(rgb);
    }
    return vec4<f32>(rgb, 0.6 * draw.opacity);
}

// Skeleton overlay: one line per bone, endpoints already posed in model space (the CPU computes
// them from the same pose as the joint matrices), drawn with depth test off so bones show through.
@vertex
fn vs_bone(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return camera.clip_from_model * vec4<f32>(position, 1.0);
}

// Bones: opaque yellow-orange (linear), bright against the grey background and on skin or cloth.
@fragment
fn fs_bone() -> @location(0) vec4<f32> {
    var rgb = vec3<f32>(1.0, 0.55, 0.02);
    if (camera.encode_srgb == 1u) {
        rgb = srgb_encode(rgb);
    }
    return vec4<f32>(rgb, 1.0);
}
