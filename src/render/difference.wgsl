// The difference overlay (src/render/gpu/difference.rs): over each view, a heat map of where its
// picture differs from the full-detail reference drawn at the same pose and camera, read from the
// live meter's pictures of the same frame (src/render/gpu/meter.rs; 256 px tall, so the map is
// at the meter's resolution, nearest texel). Magenta where the two cover the view differently
// (alpha: the covered share of the pixel), amber where both cover it and the colour differs;
// pixels that match are left untouched.

@group(0) @binding(0) var reference: texture_2d<f32>;
@group(0) @binding(1) var shown: texture_2d<f32>;
@group(0) @binding(2) var<uniform> area: Area;

struct Area {
    // The view's top-left corner and size in the target's pixels.
    origin: vec2<f32>,
    size: vec2<f32>,
};

// Vertices 0, 1, 2 at (-1, 1), (3, 1), (-1, -3): one triangle covering the whole viewport.
@vertex
fn vs_difference(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, 0.0, 1.0);
}

// A colour change this large (sum over RGB, linear 0..3) shows at full strength: a tenth of the
// range, so shading changes a viewer can see stand out without saturating every edge.
const FULL_SHADING: f32 = 0.3;

@fragment
fn fs_difference(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let dims = vec2<f32>(textureDimensions(reference));
    let uv = (position.xy - area.origin) / max(area.size, vec2<f32>(1.0));
    let texel = vec2<i32>(clamp(floor(uv * dims), vec2<f32>(0.0), dims - 1.0));
    let r = textureLoad(reference, texel, 0);
    let v = textureLoad(shown, texel, 0);
    let outline = abs(r.a - v.a);
    let both = r.a > 0.999 && v.a > 0.999;
    let shading = select(0.0, clamp(dot(abs(r.rgb - v.rgb), vec3<f32>(1.0)) / FULL_SHADING, 0.0, 1.0), both);
    let strength = max(outline, shading);
    if strength < 0.02 {
        discard;
    }
    let rgb = (outline * vec3<f32>(1.0, 0.1, 0.9) + shading * vec3<f32>(1.0, 0.65, 0.0)) / (outline + shading);
    return vec4<f32>(rgb, 0.35 + 0.6 * strength);
}
