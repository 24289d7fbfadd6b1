// Crowd: skinned instancing (Larkin 2011). Appended to skin.wgsl (uniforms.rs concatenates them),
// so it shares its bindings, vertex layouts, `shade` and the sRGB/dither helpers; the Rust side is
// src/render/gpu/crowd.rs and the records come from src/render/crowd/.
//
// Every instance reads its pose from the palette (rows of `model_from_bind` matrices, four texels
// per column-major matrix, `textureLoad` on both WebGPU and WebGL2) and its morph weights from the
// same row of `palette_weights`, morphs and skins its vertex in model space exactly as
// `vs_level`/`vs_geomorph` do, then turns it about +Y by its heading and moves it
// into place: `world = R_y(place.w) · skinned + place.xyz`. `camera.clip_from_model` holds
// `clip_from_world` and `camera.eye_model` the eye in world space. Opacity, dither mode and
// threshold, geomorph `t` and the level tint are per instance and reach the fragment flat.

@group(3) @binding(0) var palette: texture_2d<f32>;
// Each palette row's morph-target weights, four per texel (src/render/crowd/palette.rs
// `weight_texels`): zeros when morphs are off.
@group(3) @binding(1) var palette_weights: texture_2d<f32>;

// Mirrors `InstanceRaw` in src/render/crowd/draws.rs (tests/shaders.rs compares the layouts).
// Two locations: the level's vertices and their morph rows take 0..13.
struct CrowdInstance {
    // xyz: translation after the turn; w: heading, radians.
    @location(14) place: vec4<f32>,
    // x: palette row (bits 0..12), dither mode (12..16), opacity unorm16 (16..32); y: geomorph t
    // (f32 bits); z: dither threshold (f32 bits); w: level tint, unorm8 RGBA, red in the low byte.
    @location(15) packed: vec4<u32>,
};

// `InstanceDraw` in draws.rs: the record unpacked as `InstanceRaw::draw` unpacks it.
struct CrowdDraw {
    row: u32,
    dither_mode: u32,
    // x: geomorph t; y: opacity; z: dither threshold.
    params: vec4<f32>,
    tint: vec4<f32>,
};

fn crowd_draw(i: CrowdInstance) -> CrowdDraw {
    let ids = i.packed.x;
    let tint = i.packed.w;
    var out: CrowdDraw;
    out.row = ids & 0xfffu;
    out.dither_mode = (ids >> 12u) & 15u;
    out.params = vec4<f32>(bitcast<f32>(i.packed.y), f32(ids >> 16u) / 65535.0, bitcast<f32>(i.packed.z), 0.0);
    out.tint = vec4<f32>(
        f32(tint & 255u), f32((tint >> 8u) & 255u), f32((tint >> 16u) & 255u), f32(tint >> 24u)
    ) / 255.0;
    return out;
}

struct CrowdVaryings {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
    @location(4) @interpolate(flat) params: vec4<f32>,
    @location(5) @interpolate(flat) tint: vec4<f32>,
    @location(6) @interpolate(flat) dither_mode: u32,
};

// Joint `joint`'s matrix in palette row `row`: each pose takes the palette's height over the
// number of poses (the weights texture's height) in texture rows of `width / 4` joints
// (src/render/crowd/palette.rs). Indices past the palette read its last slot (defence in depth:
// the records and the importer keep them in range).
fn palette_matrix(row: u32, joint: u32) -> mat4x4<f32> {
    let size = textureDimensions(palette);
    let poses = max(textureDimensions(palette_weights).y, 1u);
    let per_row = size.x / 4u;
    let rows_per_pose = max(size.y / poses, 1u);
    let k = min(joint, per_row * rows_per_pose - 1u);
    let x = i32((k % per_row) * 4u);
    let y = i32(min(row, poses - 1u) * rows_per_pose + k / per_row);
    return mat4x4<f32>(
        textureLoad(palette, vec2<i32>(x, y), 0),
        textureLoad(palette, vec2<i32>(x + 1, y), 0),
        textureLoad(palette, vec2<i32>(x + 2, y), 0),
        textureLoad(palette, vec2<i32>(x + 3, y), 0),
    );
}

fn palette_blend(row: u32, j: vec4<u32>, w: vec4<f32>) -> mat4x4<f32> {
    return palette_matrix(row, j.x) * w.x + palette_matrix(row, j.y) * w.y
        + palette_matrix(row, j.z) * w.z + palette_matrix(row, j.w) * w.w;
}

// `v` turned about +Y by `heading` radians (glam's `Mat4::from_rotation_y`).
fn turned(v: vec3<f32>, heading: f32) -> vec3<f32> {
    let c = cos(heading);
    let s = sin(heading);
    return vec3<f32>(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
}

// Target `t`'s weight in palette row `row` (weights past the texture's width read 0).
fn palette_weight(row: u32, t: u32) -> f32 {
    let size = textureDimensions(palette_weights);
    if (t / 4u >= size.x) {
        return 0.0;
    }
    let texel = textureLoad(palette_weights, vec2<i32>(i32(t / 4u), i32(min(row, size.y - 1u))), 0);
    return texel[t % 4u];
}

// `morphed` with the weights of the instance's palette row.
fn crowd_morphed(position: vec3<f32>, normal: vec3<f32>, entries: vec2<u32>, row: u32) -> Morphed {
    var out = Morphed(position, normal);
    for (var k = 0u; k < min(entries.y, MAX_MORPH_TARGETS); k++) {
        let m = morph_entry(entries, k);
        let w = palette_weight(row, m.target_index);
        out.position += w * m.dp;
        out.normal += w * m.dn;
    }
    return out;
}

fn crowd_finish(position: vec3<f32>, normal: vec3<f32>, uv: vec2<f32>, color: vec4<f32>, i: CrowdInstance, d: CrowdDraw) -> CrowdVaryings {
    var out: CrowdVaryings;
    let world = turned(position, i.place.w) + i.place.xyz;
    out.clip = camera.clip_from_model * vec4<f32>(world, 1.0);
    out.position = world;
    out.normal = turned(normal, i.place.w);
    out.uv = uv;
    out.color = color;
    out.params = d.params;
    out.tint = d.tint;
    out.dither_mode = d.dither_mode;
    return out;
}

@vertex
fn vs_crowd_level(v: LevelVertex, morph: MorphRow, i: CrowdInstance) -> CrowdVaryings {
    let d = crowd_draw(i);
    let b = crowd_morphed(v.position, v.normal, morph.fine, d.row);
    let m = palette_blend(d.row, v.joints, v.weights);
    let p = (m * vec4<f32>(b.position, 1.0)).xyz;
    let n = (m * vec4<f32>(b.normal, 0.0)).xyz;
    return crowd_finish(p, n, v.uv, v.color, i, d);
}

@vertex
fn vs_crowd_geomorph(v: LevelVertex, a: AncestorVertex, morph: MorphRows, i: CrowdInstance) -> CrowdVaryings {
    let d = crowd_draw(i);
    let fb = crowd_morphed(v.position, v.normal, morph.fine, d.row);
    let cb = crowd_morphed(a.position, a.normal, morph.coarse, d.row);
    let fine = palette_blend(d.row, v.joints, v.weights);
    let coarse = palette_blend(d.row, a.joints, a.weights);
    let t = d.params.x;
    let p = mix((fine * vec4<f32>(fb.position, 1.0)).xyz, (coarse * vec4<f32>(cb.position, 1.0)).xyz, t);
    let n = mix((fine * vec4<f32>(fb.normal, 0.0)).xyz, (coarse * vec4<f32>(cb.normal, 0.0)).xyz, t);
    return crowd_finish(p, n, mix(v.uv, a.uv, t), mix(v.color, a.color, t), i, d);
}

@fragment
fn fs_crowd(in: CrowdVaryings, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var v: Varyings;
    v.clip = in.clip;
    v.position = in.position;
    v.normal = in.normal;
    v.uv = in.uv;
    v.color = in.color;
    return shade(v, front, in.params.y, in.dither_mode, in.params.z, in.tint);
}

// The ground: two triangles at the floor's height (`Crowd::ground`, world space), `w` the grid's
// cell size. A dark ground with faint grid lines, antialiased by their screen-space width and
// faded out where a cell gets smaller than a few pixels, so far rows stand on a plain.
struct GroundVaryings {
    @builtin(position) clip: vec4<f32>,
    @location(0) ground: vec2<f32>,
};

@vertex
fn vs_ground(@location(0) corner: vec4<f32>) -> GroundVaryings {
    var out: GroundVaryings;
    out.clip = camera.clip_from_model * vec4<f32>(corner.xyz, 1.0);
    out.ground = corner.xz / corner.w;
    return out;
}

@fragment
fn fs_ground(in: GroundVaryings) -> @location(0) vec4<f32> {
    let width = fwidth(in.ground);
    // Distance to the nearest grid line in cells, over its screen-space width: 1 px wide lines.
    let line = abs(fract(in.ground - 0.5) - 0.5) / max(width, vec2<f32>(1e-6));
    let on_line = 1.0 - min(min(line.x, line.y), 1.0);
    let fade = 1.0 - smoothstep(0.05, 0.3, max(width.x, width.y));
    var rgb = mix(vec3<f32>(0.16, 0.17, 0.18), vec3<f32>(0.11, 0.12, 0.13), on_line * fade);
    if (camera.encode_srgb == 1u) {
        rgb = srgb_encode(rgb);
    }
    // The pipeline writes colour only: alpha stays the clear value, so the live meter's
    // coverage (alpha) sees the characters, not the ground.
    return vec4<f32>(rgb, 1.0);
}
