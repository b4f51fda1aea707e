// Per-frame values shared by every Drape pipeline (bind group 0). The Rust
// side is `render::uniforms::FrameUniform`; keep the two in the same order.
struct Frame {
    clip_from_world: mat4x4<f32>,
    // Orthographic view from below: world x/z to the shadow map's clip x/y.
    shadow_clip_from_world: mat4x4<f32>,
    eye_world: vec4<f32>,
    // x, y: target size in pixels; z, w: their reciprocals.
    viewport_px: vec4<f32>,
    // x: ground height (m); y: grid spacing (m); z: ground half size (m); w: 1 if the ground is drawn.
    ground: vec4<f32>,
    // xz: centre of the ground patch (m).
    ground_center: vec4<f32>,
    // x: height (m) at which the contact shadow has faded to its floor; y: blur radius (uv); z: strength.
    shadow: vec4<f32>,
    // Linear RGB clear colour, which the ground fades into.
    background: vec4<f32>,
    wire_color: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

// Moves a point a little towards the eye so lines drawn on the cloth win the depth test.
fn pulled_towards_eye(world: vec3<f32>, fraction: f32) -> vec3<f32> {
    let to_eye = frame.eye_world.xyz - world;
    return world + to_eye * fraction;
}
