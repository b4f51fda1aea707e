//! The uniform blocks shared with the WGSL in `shaders/`, laid out field for
//! field like `Frame` in `frame.wgsl` and `Material` in `cloth.wgsl`.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniform {
    pub clip_from_world: [[f32; 4]; 4],
    pub shadow_clip_from_world: [[f32; 4]; 4],
    pub eye_world: [f32; 4],
    pub viewport_px: [f32; 4],
    pub ground: [f32; 4],
    pub ground_center: [f32; 4],
    pub shadow: [f32; 4],
    pub background: [f32; 4],
    pub wire_color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MaterialUniform {
    pub front_tint: [f32; 4],
    pub back_tint: [f32; 4],
    pub params: [f32; 4],
}

impl MaterialUniform {
    /// One colour on both sides, untextured, at `opacity` (clamped to 0..1):
    /// how ghosts and colliders are drawn.
    pub fn flat([r, g, b]: [f32; 3], opacity: f32) -> MaterialUniform {
        MaterialUniform {
            front_tint: [r, g, b, 1.0],
            back_tint: [r, g, b, 1.0],
            params: [0.0, opacity.clamp(0.0, 1.0), 1.0, 0.0],
        }
    }
}

/// Size of the shadow map's square side, in texels: the shadow is blurred, so a small map is enough.
pub const SHADOW_MAP_PX: u32 = 256;

/// An orthographic view straight up from below the ground, covering the
/// square of half size `half_m` round `center` on the ground: world x maps to
/// clip x, world z to clip −y, and depth is constant (the pass needs none).
pub fn shadow_clip_from_world(center: Vec3, half_m: f32) -> Mat4 {
    let scale = 1.0 / half_m.max(1e-6);
    Mat4::from_cols_array_2d(&[
        [scale, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0],
        [0.0, -scale, 0.0, 0.0],
        [-center.x * scale, center.z * scale, 0.5, 1.0],
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_uniform_matches_the_wgsl_size() {
        // Two mat4x4 and seven vec4 in frame.wgsl.
        assert_eq!(std::mem::size_of::<FrameUniform>(), 2 * 64 + 7 * 16);
        assert_eq!(std::mem::size_of::<MaterialUniform>(), 3 * 16);
    }

    #[test]
    fn the_shadow_view_covers_its_square() {
        let m = shadow_clip_from_world(Vec3::new(1.0, 5.0, -2.0), 2.0);
        let corner = m * Vec3::new(3.0, 7.0, 0.0).extend(1.0);
        assert!((corner.x - 1.0).abs() < 1e-6 && (corner.y + 1.0).abs() < 1e-6 && corner.z == 0.5);
        let centre = m * Vec3::new(1.0, -3.0, -2.0).extend(1.0);
        assert!(centre.x.abs() < 1e-6 && centre.y.abs() < 1e-6);
    }
}
