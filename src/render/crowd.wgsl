// Crowd: skinned instancing (Larkin 2011). Appended to skin.wgsl (uniforms.rs concatenates them),
// so it shares its bindings, vertex layouts, `shade` and the sRGB/dither helpers; the Rust side is
// src/render/gpu/crowd.rs and the records come from src/render/crowd/.
//
// Every instance reads its pose from the palette (rows of `model_from_bind` matrices, four texels
// per column-major matrix, `textureLoad` on both WebGPU and WebGL2), skins its vertex in model
// space exactly as `vs_level`/`vs_geomorph` do, then turns it about +Y by its heading and moves it
// into place: `world = R_y(place.w) · skinned + place.xyz`. `camera.clip_from_model` holds
// `clip_from_world` and `camera.eye_model` the eye in world space. Opacity, dither mode and
// threshold, geomorph `t` and the level tint are per instance and reach the fragment flat.

@group(3) @binding(0) var palette: texture_2d<f32>;

// Mirrors `InstanceRaw` in src/render/crowd/draws.rs (tests/shaders.rs compares the layouts).
struct CrowdInstance {
    // xyz: translation after the turn; w: heading, radians.
    @location(12) place: vec4<f32>,
    // x: palette row; y: dither mode.
    @location(13) ids: vec4<u32>,
    // x: geomorph t; y: opacity; z: dither threshold.
    @location(14) params: vec4<f32>,
    @location(15) tint: vec4<f32>,
};

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

// Joint `joint`'s matrix in palette row `row`; indices past the palette read its last texel
// (defence in depth: the records and the importer keep them in range).
fn palette_matrix(row: u32, joint: u32) -> mat4x4<f32> {
    let size = textureDimensions(palette);
    let x = i32(min(joint, size.x / 4u - 1u) * 4u);
    let y = i32(min(row, size.y - 1u));
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

fn crowd_finish(position: vec3<f32>, normal: vec3<f32>, uv: vec2<f32>, color: vec4<f32>, i: CrowdInstance) -> CrowdVaryings {
    var out: CrowdVaryings;
    let world = turned(position, i.place.w) + i.place.xyz;
    out.clip = camera.clip_from_model * vec4<f32>(world, 1.0);
    out.position = world;
    out.normal = turned(normal, i.place.w);
    out.uv = uv;
    out.color = color;
    out.params = i.params;
    out.tint = i.tint;
    out.dither_mode = i.ids.y;
    return out;
}

@vertex
fn vs_crowd_level(v: LevelVertex, i: CrowdInstance) -> CrowdVaryings {
    let m = palette_blend(i.ids.x, v.joints, v.weights);
    let p = (m * vec4<f32>(v.position, 1.0)).xyz;
    let n = (m * vec4<f32>(v.normal, 0.0)).xyz;
    return crowd_finish(p, n, v.uv, v.color, i);
}

@vertex
fn vs_crowd_geomorph(v: LevelVertex, a: AncestorVertex, i: CrowdInstance) -> CrowdVaryings {
    let fine = palette_blend(i.ids.x, v.joints, v.weights);
    let coarse = palette_blend(i.ids.x, a.joints, a.weights);
    let t = i.params.x;
    let p = mix((fine * vec4<f32>(v.position, 1.0)).xyz, (coarse * vec4<f32>(a.position, 1.0)).xyz, t);
    let n = mix((fine * vec4<f32>(v.normal, 0.0)).xyz, (coarse * vec4<f32>(a.normal, 0.0)).xyz, t);
    return crowd_finish(p, n, mix(v.uv, a.uv, t), mix(v.color, a.color, t), i);
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
