// The ground plane: a fading grid with the cloth's soft contact shadow.

@group(1) @binding(0) var shadow_map: texture_2d<f32>;
@group(1) @binding(1) var shadow_sampler: sampler;

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_ground(@builtin(vertex_index) index: u32) -> GroundOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let corner = corners[index] * frame.ground.z;
    let world = vec3<f32>(frame.ground_center.x + corner.x, frame.ground.x, frame.ground_center.z + corner.y);
    var out: GroundOut;
    out.clip = frame.clip_from_world * vec4<f32>(world, 1.0);
    out.world = world;
    return out;
}

fn shadow_at(world: vec3<f32>) -> f32 {
    let clip = frame.shadow_clip_from_world * vec4<f32>(world, 1.0);
    let uv = vec2<f32>(clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5);
    // Outside the shadow square there is nothing to blur: skip the taps (software rasterisers feel them).
    let margin = 2.0 * frame.shadow.y;
    if any(uv < vec2<f32>(-margin)) || any(uv > vec2<f32>(1.0 + margin)) {
        return 0.0;
    }
    // A fixed ring of taps around the point: a cheap blur that keeps the shadow soft.
    var taps = array<vec2<f32>, 12>(
        vec2<f32>(1.0, 0.0), vec2<f32>(0.5, 0.866), vec2<f32>(-0.5, 0.866),
        vec2<f32>(-1.0, 0.0), vec2<f32>(-0.5, -0.866), vec2<f32>(0.5, -0.866),
        vec2<f32>(0.35, 0.2), vec2<f32>(0.0, 0.4), vec2<f32>(-0.35, 0.2),
        vec2<f32>(-0.35, -0.2), vec2<f32>(0.0, -0.4), vec2<f32>(0.35, -0.2),
    );
    var sum = textureSampleLevel(shadow_map, shadow_sampler, uv, 0.0).r;
    for (var i = 0; i < 12; i = i + 1) {
        sum = sum + textureSampleLevel(shadow_map, shadow_sampler, uv + taps[i] * frame.shadow.y, 0.0).r;
    }
    return sum / 13.0;
}

@fragment
fn fs_ground(in: GroundOut) -> @location(0) vec4<f32> {
    let radius = length(in.world.xz - frame.ground_center.xz) / frame.ground.z;
    let fade = 1.0 - smoothstep(0.55, 1.0, radius);
    let coord = in.world.xz / frame.ground.y;
    let width = fwidth(coord);
    let distance_to_line = abs(fract(coord - 0.5) - 0.5) / max(width, vec2<f32>(1e-6));
    let line = 1.0 - min(min(distance_to_line.x, distance_to_line.y), 1.0);
    // Lines thinner than a pixel apart turn into grey mush; fade them out instead.
    let density = clamp(1.5 - max(width.x, width.y) * 3.0, 0.0, 1.0);
    let axis_distance = abs(in.world.xz) / max(fwidth(in.world.xz), vec2<f32>(1e-6));
    let on_x_axis = 1.0 - min(axis_distance.y, 1.0);
    let on_z_axis = 1.0 - min(axis_distance.x, 1.0);

    var color = vec3<f32>(0.105, 0.108, 0.115);
    color = mix(color, vec3<f32>(0.2, 0.205, 0.215), line * density * 0.8);
    color = mix(color, vec3<f32>(0.55, 0.24, 0.22), on_x_axis * 0.7);
    color = mix(color, vec3<f32>(0.22, 0.32, 0.55), on_z_axis * 0.7);
    color = color * (1.0 - shadow_at(in.world) * frame.shadow.z);
    return vec4<f32>(mix(frame.background.rgb, color, fade), 1.0);
}

// The shadow pass for compositing: black where the cloth's shadow falls,
// its strength as (premultiplied) alpha, transparent elsewhere.
@fragment
fn fs_ground_shadow(in: GroundOut) -> @location(0) vec4<f32> {
    let radius = length(in.world.xz - frame.ground_center.xz) / frame.ground.z;
    let fade = 1.0 - smoothstep(0.55, 1.0, radius);
    return vec4<f32>(0.0, 0.0, 0.0, shadow_at(in.world) * frame.shadow.z * fade);
}
