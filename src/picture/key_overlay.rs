//! The overlays of a key's modelling stage (the paper's Fig. 3b–c): its pins,
//! its catenary network with the conflicts decided on it, and the
//! triangulation of its pins drawn on the cloth, as the plain segments and
//! markers [`crate::render`] draws. The editor and `drape render` build them here.

use glam::{DVec2, Vec3};

use crate::animate::Evaluator;
use crate::mesh::Mesh;
use crate::render::overlay::{Marker, Overlay, PinState, Segment};
use crate::scene::Scene;
use crate::shape::approximate::CatenaryNetwork;

/// Linear RGBA colours of the modelling stage's overlays.
pub mod colors {
    pub const CATENARY: [f32; 4] = [0.95, 0.7, 0.1, 1.0];
    pub const CONFLICTING: [f32; 4] = [0.9, 0.1, 0.5, 0.75];
    pub const CONFLICT_POINT: [f32; 4] = [0.9, 0.1, 0.5, 1.0];
    pub const TRIANGULATION: [f32; 4] = [0.1, 0.65, 0.95, 0.9];
}

/// Which overlays a scene picture shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneOverlays {
    pub wireframe: bool,
    /// Red dots on the pins of the key in effect.
    pub pins: bool,
    /// The catenary network (with conflicts) of the key in effect.
    pub catenaries: bool,
    /// The key's triangulation of its pins, drawn on the surface.
    pub triangulation: bool,
    /// Leaves the scene's colliders out of the picture (`--no-colliders`);
    /// they are drawn by default.
    pub hide_colliders: bool,
    /// Leaves the scene's referenced glTF files out (`--no-references`).
    pub hide_references: bool,
    /// Looks through the framing camera even when the scene has a shot
    /// camera (`--camera view`).
    pub view_camera: bool,
    /// The cloth alone over transparency (`--alpha`): no ground, background,
    /// colliders or references; straight (not premultiplied) alpha, as PNG stores it.
    pub alpha: bool,
    /// The cloth's shadow on the ground alone (`--pass shadow`): black with
    /// straight alpha over transparency, for laying on a drawn floor.
    pub shadow_pass: bool,
    /// Draws in the toon style with the scene's `cloth.toon` settings
    /// (`--style toon`) instead of lit.
    pub toon: bool,
}

/// The overlays `show` asks for, for the key in effect at `frame`, drawn on
/// `mesh`, each pin as `pin_state` says (the wireframe is a render option,
/// not an overlay). Segments come triangulation first, then the network;
/// markers the network's conflict points first, then the pins.
pub fn key_overlay(
    evaluator: &mut Evaluator,
    scene: &Scene,
    frame: f64,
    mesh: &Mesh,
    show: SceneOverlays,
    pin_state: impl Fn((u32, u32)) -> PinState,
) -> Overlay {
    let mut overlay = Overlay::default();
    let key = scene.key_in_effect(frame);
    if show.catenaries || show.triangulation {
        let shape = evaluator.key_shape(scene, key);
        if show.triangulation {
            add_triangulation(&mut overlay, mesh, &shape.rest.network);
        }
        if show.catenaries {
            add_catenary_network(&mut overlay, &shape.rest.network);
        }
    }
    if show.pins {
        let pins = key.pins.iter().map(|p| ((p.grid.0 as usize, p.grid.1 as usize), pin_state(p.grid)));
        overlay.add_pins(mesh, pins);
    }
    overlay
}

/// The catenary network: kept catenaries as gold curves, the conflicting
/// ones they beat in magenta, and a dot at each crossing where a conflict
/// was decided.
pub fn add_catenary_network(overlay: &mut Overlay, network: &CatenaryNetwork) {
    const SAMPLES: usize = 24;
    for (edges, color, width_px) in
        [(&network.conflicting, colors::CONFLICTING, 1.5), (&network.kept, colors::CATENARY, 2.5)]
    {
        for edge in edges.iter() {
            let mut previous = edge.catenary.point_at_arc_fraction(0.0).as_vec3();
            for k in 1..=SAMPLES {
                let next = edge.catenary.point_at_arc_fraction(k as f64 / SAMPLES as f64).as_vec3();
                overlay.segments.push(Segment { a: previous, b: next, width_px, color });
                previous = next;
            }
        }
    }
    for point in &network.conflict_points {
        let fill = colors::CONFLICT_POINT;
        overlay.markers.push(Marker { center: point.kept_pos.as_vec3(), radius_px: 3.5, fill, ring: [0.0; 4] });
    }
}

/// The triangulation of the pins by the kept catenaries, drawn on the
/// surface of `mesh`: each edge follows the straight line between its two
/// pins in material space, mapped through the mesh.
pub fn add_triangulation(overlay: &mut Overlay, mesh: &Mesh, network: &CatenaryNetwork) {
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
            overlay.segments.push(Segment { a: previous, b: next, width_px: 2.0, color: colors::TRIANGULATION });
            previous = next;
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

    #[test]
    fn surface_points_interpolate_and_clamp() {
        let positions: Vec<DVec3> =
            (0..3).flat_map(|j| (0..4).map(move |i| DVec3::new(i as f64, -(j as f64), 0.0))).collect();
        let mesh = Mesh::from_grid(4, 3, &positions);
        assert_eq!(surface_point(&mesh, DVec2::new(1.5, 0.5)), Vec3::new(1.5, -0.5, 0.0));
        assert_eq!(surface_point(&mesh, DVec2::new(3.0, 2.0)), Vec3::new(3.0, -2.0, 0.0));
        assert_eq!(surface_point(&mesh, DVec2::new(-5.0, 9.0)), Vec3::new(0.0, -2.0, 0.0));
        assert_eq!(surface_point(&mesh, DVec2::new(f64::NAN, 0.0)).y, 0.0);
    }
}
