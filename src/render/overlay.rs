//! What is drawn over the cloth: line segments of a fixed pixel width and
//! round markers, in world space. Builders turn the modelling stage (pins,
//! catenary network, triangulation) into them; the renderer only draws.

use glam::{DVec2, Vec3};

use crate::mesh::Mesh;
use crate::shape::approximate::CatenaryNetwork;

/// Linear RGBA colours of the overlays.
pub mod colors {
    pub const PIN: [f32; 4] = [0.85, 0.06, 0.04, 1.0];
    pub const PIN_RING: [f32; 4] = [1.0, 1.0, 1.0, 1.0];
    pub const PIN_HOVERED: [f32; 4] = [1.0, 0.45, 0.1, 1.0];
    pub const PIN_SELECTED: [f32; 4] = [1.0, 0.78, 0.05, 1.0];
    pub const CATENARY: [f32; 4] = [0.95, 0.7, 0.1, 1.0];
    pub const CONFLICTING: [f32; 4] = [0.9, 0.1, 0.5, 0.75];
    pub const CONFLICT_POINT: [f32; 4] = [0.9, 0.1, 0.5, 1.0];
    pub const TRIANGULATION: [f32; 4] = [0.1, 0.65, 0.95, 0.9];
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

    /// The catenary network of the modelling stage (the paper's Fig. 3b–c):
    /// kept catenaries as gold curves, the conflicting ones they beat in
    /// magenta, and a dot at each crossing where a conflict was decided.
    pub fn add_catenary_network(&mut self, network: &CatenaryNetwork) {
        const SAMPLES: usize = 24;
        for (edges, color, width_px) in
            [(&network.conflicting, colors::CONFLICTING, 1.5), (&network.kept, colors::CATENARY, 2.5)]
        {
            for edge in edges.iter() {
                let mut previous = edge.catenary.point_at_arc_fraction(0.0).as_vec3();
                for k in 1..=SAMPLES {
                    let next = edge.catenary.point_at_arc_fraction(k as f64 / SAMPLES as f64).as_vec3();
                    self.segments.push(Segment { a: previous, b: next, width_px, color });
                    previous = next;
                }
            }
        }
        for point in &network.conflict_points {
            let fill = colors::CONFLICT_POINT;
            self.markers.push(Marker { center: point.kept_pos.as_vec3(), radius_px: 3.5, fill, ring: [0.0; 4] });
        }
    }

    /// The triangulation of the pins by the kept catenaries, drawn on the
    /// surface of `mesh`: each edge follows the straight line between its two
    /// pins in material space, mapped through the mesh.
    pub fn add_triangulation(&mut self, mesh: &Mesh, network: &CatenaryNetwork) {
        for edge in &network.kept {
            let (Some(a), Some(b)) = (network.pins.get(edge.a), network.pins.get(edge.b)) else {
                continue;
            };
            let ga = DVec2::new(a.grid.0 as f64, a.grid.1 as f64);
            let gb = DVec2::new(b.grid.0 as f64, b.grid.1 as f64);
            // About two samples per grid cell crossed keeps the line on the surface.
            let samples = ((gb - ga).abs().max_element() * 2.0).ceil().max(1.0) as usize;
            let mut previous = surface_point(mesh, ga);
            for k in 1..=samples {
                let next = surface_point(mesh, ga.lerp(gb, k as f64 / samples as f64));
                self.segments.push(Segment { a: previous, b: next, width_px: 2.0, color: colors::TRIANGULATION });
                previous = next;
            }
        }
    }
}

/// The mesh point at fractional grid coordinates, bilinear in the quad that
/// holds it; coordinates are clamped to the grid, a NaN one reads as 0.
pub fn surface_point(mesh: &Mesh, grid: DVec2) -> Vec3 {
    let grid = DVec2::new(if grid.x.is_nan() { 0.0 } else { grid.x }, if grid.y.is_nan() { 0.0 } else { grid.y });
    let x = grid.x.clamp(0.0, (mesh.cols - 1) as f64);
    let y = grid.y.clamp(0.0, (mesh.rows - 1) as f64);
    let (i0, j0) = ((x.floor() as usize).min(mesh.cols - 2), (y.floor() as usize).min(mesh.rows - 2));
    let (fx, fy) = ((x - i0 as f64) as f32, (y - j0 as f64) as f32);
    let at = |i: usize, j: usize| mesh.positions[j * mesh.cols + i];
    let top = at(i0, j0).lerp(at(i0 + 1, j0), fx);
    let bottom = at(i0, j0 + 1).lerp(at(i0 + 1, j0 + 1), fx);
    top.lerp(bottom, fy)
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
    fn surface_points_interpolate_and_clamp() {
        let mesh = flat(4, 3);
        assert_eq!(surface_point(&mesh, DVec2::new(1.5, 0.5)), Vec3::new(1.5, -0.5, 0.0));
        assert_eq!(surface_point(&mesh, DVec2::new(3.0, 2.0)), Vec3::new(3.0, -2.0, 0.0));
        assert_eq!(surface_point(&mesh, DVec2::new(-5.0, 9.0)), Vec3::new(0.0, -2.0, 0.0));
        assert_eq!(surface_point(&mesh, DVec2::new(f64::NAN, 0.0)).y, 0.0);
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
