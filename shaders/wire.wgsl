// The cloth's grid edges as thin lines over the surface.

@vertex
fn vs_wire(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return frame.clip_from_world * vec4<f32>(pulled_towards_eye(position, 0.002), 1.0);
}

@fragment
fn fs_wire() -> @location(0) vec4<f32> {
    return frame.wire_color;
}
