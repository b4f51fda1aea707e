//! A collider dragged in the viewport: which one, from where, at which
//! frame, and an axis it may be locked to. The viewport's handling of it is
//! in the viewport's `collider_input`.

use glam::Vec3;

use super::pin_drag::AxisLock;
use crate::scene::Collider;

/// A collider being dragged, from where it was when the drag began.
pub struct ColliderDrag {
    pub index: usize,
    /// The world point under the mouse when the drag began.
    pub anchor: Vec3,
    pub start: Collider,
    /// The frame its positions are written at.
    pub frame: i32,
    pub lock: Option<AxisLock>,
    pub by_gizmo: bool,
}
