// The cloth, lit two-sided or toon, and its translucent onion-skin ghosts.

struct Material {
    front_tint: vec4<f32>,
    back_tint: vec4<f32>,
    // x: 1 to multiply by the texture; y: ghost opacity; z: texture repeats across the cloth;
    // w: the toon style's tone bands (2 or 3; 0 when lit).
    params: vec4<f32>,
};

@group(1) @binding(0) var<uniform> material: Material;
@group(1) @binding(1) var cloth_texture: texture_2d<f32>;
@group(1) @binding(2) var cloth_sampler: sampler;

struct ClothOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

@vertex
fn vs_cloth(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32>) -> ClothOut {
    var out: ClothOut;
    out.clip = frame.clip_from_world * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.uv = uv;
    return out;
}

// Diffuse that wraps past the terminator, so folds stay soft instead of going black.
fn wrapped(n: vec3<f32>, l: vec3<f32>, wrap: f32) -> f32 {
    return max((dot(n, l) + wrap) / (1.0 + wrap), 0.0);
}

fn lit(albedo: vec3<f32>, n: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    let key_dir = normalize(vec3<f32>(0.45, 0.8, 0.55));
    let fill_dir = normalize(vec3<f32>(-0.7, 0.25, 0.45));
    let rim_dir = normalize(vec3<f32>(-0.2, 0.5, -0.9));
    let key = vec3<f32>(1.0, 0.95, 0.86) * 0.9 * wrapped(n, key_dir, 0.35);
    let fill = vec3<f32>(0.62, 0.72, 0.95) * 0.38 * wrapped(n, fill_dir, 0.5);
    let sky = mix(vec3<f32>(0.16, 0.14, 0.12), vec3<f32>(0.32, 0.36, 0.42), n.y * 0.5 + 0.5);
    let facing = 1.0 - max(dot(n, view), 0.0);
    let rim = vec3<f32>(1.0, 0.97, 0.92) * 0.45 * pow(facing, 3.0) * wrapped(n, rim_dir, 0.6);
    let half_key = normalize(key_dir + view);
    let sheen = 0.05 * pow(max(dot(n, half_key), 0.0), 24.0);
    return albedo * (key + fill + sky) + rim * (albedo + vec3<f32>(0.25)) + vec3<f32>(sheen);
}

fn albedo_at(uv: vec2<f32>) -> vec3<f32> {
    let texel = textureSample(cloth_texture, cloth_sampler, uv * material.params.z).rgb;
    return mix(vec3<f32>(1.0), texel, material.params.x);
}

@fragment
fn fs_cloth(in: ClothOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let albedo = albedo_at(in.uv);
    let side = select(-1.0, 1.0, front);
    let n = normalize(in.normal) * side;
    let view = normalize(frame.eye_world.xyz - in.world);
    let tint = select(material.back_tint.rgb, material.front_tint.rgb, front);
    return vec4<f32>(lit(albedo * tint, n, view), 1.0);
}

// A step from 0 to 1 where x crosses edge, about one pixel wide: hard, but not jagged.
fn hard_step(edge: f32, x: f32, pixel: f32) -> f32 {
    return clamp((x - edge) / pixel + 0.5, 0.0, 1.0);
}

// The toon style: the key light in flat tone bands (2 or 3, material.params.w),
// the texture and the side's colour kept, no fill, rim or sheen.
@fragment
fn fs_cloth_toon(in: ClothOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let albedo = albedo_at(in.uv);
    let n = normalize(in.normal) * select(-1.0, 1.0, front);
    // The lit style's key light.
    let light = dot(n, normalize(vec3<f32>(0.45, 0.8, 0.55)));
    // Derivatives in uniform control flow, before anything branches.
    let pixel = max(fwidth(light), 1e-4);
    let tint = select(material.back_tint.rgb, material.front_tint.rgb, front);
    let three = material.params.w > 2.5;
    // Lit, half and shadow tones; two bands split at the terminator.
    let lit_from = select(0.15, 0.4, three);
    let to_lit = hard_step(lit_from, light, pixel);
    let to_half = select(0.0, hard_step(-0.15, light, pixel), three);
    let shadow = select(0.45, 0.36, three);
    let tone = mix(mix(shadow, 0.64, to_half), 1.0, to_lit);
    // Shade a little cooler than light, as a painted shadow is.
    let cool = mix(vec3<f32>(0.88, 0.92, 1.06), vec3<f32>(1.0), to_lit);
    return vec4<f32>(albedo * tint * cool * tone * 1.1, 1.0);
}

@fragment
fn fs_ghost(in: ClothOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let n = normalize(in.normal) * select(-1.0, 1.0, front);
    let view = normalize(frame.eye_world.xyz - in.world);
    let shade = 0.55 + 0.45 * abs(dot(n, view));
    return vec4<f32>(material.front_tint.rgb * shade, material.params.y);
}
