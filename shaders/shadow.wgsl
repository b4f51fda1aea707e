// The cloth seen from below into a small map: how dark the ground under each
// point gets. The pass blends with max, so the lowest cloth over a spot wins.

struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) height_m: f32,
};

@vertex
fn vs_shadow(@location(0) position: vec3<f32>) -> ShadowOut {
    var out: ShadowOut;
    out.clip = frame.shadow_clip_from_world * vec4<f32>(position, 1.0);
    out.height_m = position.y - frame.ground.x;
    return out;
}

@fragment
fn fs_shadow(in: ShadowOut) -> @location(0) vec4<f32> {
    // Cloth touching the ground darkens it fully; cloth far above still leaves a faint shade.
    let closeness = 1.0 - clamp(in.height_m / frame.shadow.x, 0.0, 1.0);
    let darkness = mix(0.3, 1.0, closeness * closeness);
    return vec4<f32>(darkness, 0.0, 0.0, 1.0);
}
