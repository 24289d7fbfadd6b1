// Mipmap generation (src/render/gpu/mipmaps.rs): one full-screen triangle per level, drawn into
// level i while sampling level i - 1 through a one-level view. A destination texel's centre is the
// shared corner of the 2×2 source texels it covers, so one bilinear tap is their box average; the
// texture is sRGB, so the average is taken in linear light and encoded again on write.

@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var source_sampler: sampler;

struct VertexOutput {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

// Vertices 0, 1, 2 at uv (0, 0), (2, 0), (0, 2): one triangle covering the whole target.
@vertex
fn vs_mip(@builtin(vertex_index) index: u32) -> VertexOutput {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: VertexOutput;
    out.position = vec4<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, 0.0, 1.0);
    out.uv = uv;
    return out;
}

@fragment
fn fs_mip(in: VertexOutput) -> @location(0) vec4<f32> {
    return textureSampleLevel(source, source_sampler, in.uv, 0.0);
}
