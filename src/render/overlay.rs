//! What is drawn over the cloth: line segments of a fixed pixel width and
//! round markers, in world space, and pins as markers on mesh points. The
//! renderer only draws them; what a scene's overlays show is decided above
//! it (`crate::picture`, the editor).

use glam::Vec3;

use crate::mesh::Mesh;

/// Linear RGBA colours of the pin markers.
pub mod colors {
    pub const PIN: [f32; 4] = [0.85, 0.06, 0.04, 1.0];
    pub const PIN_RING: [f32; 4] = [1.0, 1.0, 1.0, 1.0];
    pub const PIN_HOVERED: [f32; 4] = [1.0, 0.45, 0.1, 1.0];
    pub const PIN_SELECTED: [f32; 4] = [1.0, 0.78, 0.05, 1.0];
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub a: Vec3,
    pub b: Vec3,
    pub width_px: f32,
    pub color: [f32; 4],
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    pub center: Vec3,
    pub radius_px: f32,
    pub fill: [f32; 4],
    /// Outline colour; alpha 0 for none.
    pub ring: [f32; 4],
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlay {
    pub segments: Vec<Segment>,
    pub markers: Vec<Marker>,
}

/// How a pin is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinState {
    Normal,
    Hovered,
    Selected,
}

/// Pin radius on screen.
pub const PIN_RADIUS_PX: f32 = 6.0;

impl Overlay {
    pub fn clear(&mut self) {
        self.segments.clear();
        self.markers.clear();
    }

    /// A dot on each pinned grid point `(i, j)` of `mesh`, drawn where the mesh
    /// puts it; points outside the grid are skipped.
    pub fn add_pins(&mut self, mesh: &Mesh, pins: impl IntoIterator<Item = ((usize, usize), PinState)>) {
        for ((i, j), state) in pins {
            if i >= mesh.cols || j >= mesh.rows {
                continue;
            }
            let (fill, radius_px) = match state {
                PinState::Normal => (colors::PIN, PIN_RADIUS_PX),
                PinState::Hovered => (colors::PIN_HOVERED, PIN_RADIUS_PX + 1.5),
                PinState::Selected => (colors::PIN_SELECTED, PIN_RADIUS_PX + 1.5),
            };
            let center = mesh.positions[j * mesh.cols + i];
            self.markers.push(Marker { center, radius_px, fill, ring: colors::PIN_RING });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn flat(cols: usize, rows: usize) -> Mesh {
        let positions: Vec<DVec3> =
            (0..rows).flat_map(|j| (0..cols).map(move |i| DVec3::new(i as f64, -(j as f64), 0.0))).collect();
        Mesh::from_grid(cols, rows, &positions)
    }

    #[test]
    fn pins_outside_the_grid_are_skipped() {
        let mesh = flat(3, 3);
        let mut overlay = Overlay::default();
        overlay.add_pins(&mesh, [((2, 2), PinState::Selected), ((3, 0), PinState::Normal)]);
        assert_eq!(overlay.markers.len(), 1);
        assert_eq!(overlay.markers[0].center, Vec3::new(2.0, -2.0, 0.0));
        assert_eq!(overlay.markers[0].fill, colors::PIN_SELECTED);
    }
}
