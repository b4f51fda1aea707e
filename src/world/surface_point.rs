//! Where a point stands against a solid: what every collider's distance query answers.

use glam::DVec3;

/// Where a point stands against a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Signed distance to the surface: negative inside (m).
    pub distance: f64,
    /// Unit direction in which the distance grows fastest (outwards); a
    /// fixed choice (+Y, or the nearest face) where it is not unique.
    pub outward: DVec3,
}
