//! A drag of pins in the viewport: which pins, from where, and an axis it may be locked to.

use glam::Vec3;

/// A world axis a dragged pin is locked to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisLock {
    X,
    Y,
    Z,
}

impl AxisLock {
    pub fn vector(self) -> Vec3 {
        match self {
            AxisLock::X => Vec3::X,
            AxisLock::Y => Vec3::Y,
            AxisLock::Z => Vec3::Z,
        }
    }
}

/// A pin being dragged: its grid point and its position when the drag began.
pub type MovingPin = ((u32, u32), (f64, f64, f64));

/// A drag of one or more pins, from where they were when it began.
pub struct PinDrag {
    /// The pin under the mouse and its start position.
    pub grabbed: (u32, u32),
    pub anchor: Vec3,
    /// Every moving pin with its start position.
    pub pins: Vec<MovingPin>,
    pub lock: Option<AxisLock>,
    /// Key index the pins belong to.
    pub key: usize,
    /// Started on a gizmo arrow (drawn highlighted while it lasts).
    pub by_gizmo: bool,
}
