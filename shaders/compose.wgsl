// Copies the viewport's finished picture into the window's render pass: one
// triangle covering the viewport rectangle, sampled 1:1. The picture is
// premultiplied: opaque it replaces what is there, transparent (over a plate)
// it lets what egui painted behind show.

@group(0) @binding(0) var picture: texture_2d<f32>;
@group(0) @binding(1) var picture_sampler: sampler;

struct ComposeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_compose(@builtin(vertex_index) index: u32) -> ComposeOut {
    // (0,0), (2,0), (0,2) in uv: one triangle that covers the unit square.
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: ComposeOut;
    out.clip = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}

// For an sRGB target: the hardware encodes what we return.
@fragment
fn fs_compose(in: ComposeOut) -> @location(0) vec4<f32> {
    return textureSampleLevel(picture, picture_sampler, in.uv, 0.0);
}

fn srgb_from_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

// For a linear target holding sRGB bytes (egui's usual surface): encode here,
// the straight colour, premultiplied again after, as egui blends its own.
@fragment
fn fs_compose_encoded(in: ComposeOut) -> @location(0) vec4<f32> {
    let c = textureSampleLevel(picture, picture_sampler, in.uv, 0.0);
    if c.a <= 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(srgb_from_linear(c.rgb / c.a) * c.a, c.a);
}
