// Screen-space overlays: wide line segments (catenaries, triangulation) and
// round markers (pins), each an instance expanded to a quad in the vertex shader.

struct OverlayOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
    // Segments: (distance across the line in px, half width in px). Markers: offset from the centre in px.
    @location(1) local_px: vec2<f32>,
    @location(2) ring: vec4<f32>,
    @location(3) radius_px: f32,
};

fn to_pixels(clip: vec4<f32>) -> vec2<f32> {
    return clip.xy / clip.w * frame.viewport_px.xy * 0.5;
}

// Moves a clip-space point behind the eye onto the near side, so a segment that
// crosses the eye plane still draws its visible part.
fn in_front(clip: vec4<f32>, other: vec4<f32>) -> vec4<f32> {
    let near_w = 1e-4;
    if clip.w >= near_w {
        return clip;
    }
    let t = (near_w - clip.w) / (other.w - clip.w);
    return mix(clip, other, t);
}

@vertex
fn vs_segment(
    @builtin(vertex_index) index: u32,
    @location(0) a: vec3<f32>,
    @location(1) width_px: f32,
    @location(2) b: vec3<f32>,
    @location(3) color: vec4<f32>,
) -> OverlayOut {
    var ends = array<f32, 6>(0.0, 1.0, 1.0, 0.0, 1.0, 0.0);
    var sides = array<f32, 6>(-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
    let raw_a = frame.clip_from_world * vec4<f32>(pulled_towards_eye(a, 0.004), 1.0);
    let raw_b = frame.clip_from_world * vec4<f32>(pulled_towards_eye(b, 0.004), 1.0);
    var out: OverlayOut;
    out.color = color;
    out.ring = vec4<f32>(0.0);
    out.radius_px = 0.0;
    if raw_a.w <= 0.0 && raw_b.w <= 0.0 {
        out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
        out.local_px = vec2<f32>(0.0);
        return out;
    }
    let clip_a = in_front(raw_a, raw_b);
    let clip_b = in_front(raw_b, raw_a);
    let delta = to_pixels(clip_b) - to_pixels(clip_a);
    let length_px = length(delta);
    let along = select(vec2<f32>(1.0, 0.0), delta / length_px, length_px > 1e-6);
    let across = vec2<f32>(-along.y, along.x);
    let end = ends[index];
    let side = sides[index];
    let half_px = width_px * 0.5 + 1.0;
    // Extend past each end by half a width: round-ish joins between consecutive segments.
    let offset_px = across * side * half_px + along * (end * 2.0 - 1.0) * half_px;
    let base = mix(clip_a, clip_b, end);
    out.clip = base + vec4<f32>(offset_px * 2.0 * frame.viewport_px.zw * base.w, 0.0, 0.0);
    out.local_px = vec2<f32>(side * half_px, width_px * 0.5);
    return out;
}

@fragment
fn fs_segment(in: OverlayOut) -> @location(0) vec4<f32> {
    let coverage = clamp(in.local_px.y + 0.5 - abs(in.local_px.x), 0.0, 1.0);
    return vec4<f32>(in.color.rgb, in.color.a * coverage);
}

@vertex
fn vs_marker(
    @builtin(vertex_index) index: u32,
    @location(0) center: vec3<f32>,
    @location(1) radius_px: f32,
    @location(2) fill: vec4<f32>,
    @location(3) ring: vec4<f32>,
) -> OverlayOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    // Well in front of the surface the pin sits on, so its own cloth never cuts the dot.
    let clip = frame.clip_from_world * vec4<f32>(pulled_towards_eye(center, 0.02), 1.0);
    var out: OverlayOut;
    out.color = fill;
    out.ring = ring;
    out.radius_px = radius_px;
    if clip.w <= 0.0 {
        out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
        out.local_px = vec2<f32>(0.0);
        return out;
    }
    let extent_px = corners[index] * (radius_px + 1.5);
    out.clip = clip + vec4<f32>(extent_px * 2.0 * frame.viewport_px.zw * clip.w, 0.0, 0.0);
    out.local_px = extent_px;
    return out;
}

fn marker_color(in: OverlayOut) -> vec4<f32> {
    let r = length(in.local_px);
    let coverage = clamp(in.radius_px + 0.5 - r, 0.0, 1.0);
    let ring_width_px = min(2.0, in.radius_px * 0.4);
    let in_ring = clamp(r - (in.radius_px - ring_width_px) + 0.5, 0.0, 1.0);
    let color = mix(in.color, in.ring, in_ring * in.ring.a);
    return vec4<f32>(color.rgb, color.a * coverage);
}

@fragment
fn fs_marker(in: OverlayOut) -> @location(0) vec4<f32> {
    return marker_color(in);
}

// Markers hidden behind the cloth: drawn faint, so a pin never vanishes but reads as behind.
@fragment
fn fs_marker_hidden(in: OverlayOut) -> @location(0) vec4<f32> {
    let color = marker_color(in);
    return vec4<f32>(color.rgb, color.a * 0.3);
}
