//! A drag of pins in the viewport: which pins, from where, and an axis it may be locked to.

use eframe::egui;
use glam::{DVec3, Vec3};

use crate::scene::Pin;

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

/// This frame's keys during a drag (of pins or a collider): X / Y / Z lock
/// `lock` to that axis, or free it when it is locked there already. Returns
/// whether Esc was pressed (put it back).
pub fn drag_keys(ui: &egui::Ui, lock: &mut Option<AxisLock>) -> bool {
    let (x, y, z, escape) = ui.input(|i| {
        use egui::Key;
        (i.key_pressed(Key::X), i.key_pressed(Key::Y), i.key_pressed(Key::Z), i.key_pressed(Key::Escape))
    });
    for (pressed, axis) in [(x, AxisLock::X), (y, AxisLock::Y), (z, AxisLock::Z)] {
        if pressed {
            *lock = if *lock == Some(axis) { None } else { Some(axis) };
        }
    }
    escape
}

/// A pin being dragged, as its key held it when the drag began.
#[derive(Clone, Debug)]
pub struct MovingPin {
    /// The pin then (its attachment too): Esc puts it back.
    pub start: Pin,
    /// Where it was then at its key's frame (m): on its attachment, if attached.
    pub from: DVec3,
}

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
