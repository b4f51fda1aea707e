//! The one place where Drape's axes become Blender's.
//!
//! Drape is Y-up (gravity along −Y); Blender is Z-up. Blender's frame is
//! Drape's rotated +90° about X: Blender (x, y, z) = Drape (x, −z, y), a
//! proper rotation, so triangles keep their winding and normals turn with it.

use glam::{DVec3, Vec3};

/// The axes positions are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axes {
    /// Drape's own: Y up, metres.
    YUp,
    /// Blender's: Z up, metres.
    ZUp,
}

/// A Drape point in Blender's axes.
pub fn z_up_from_y_up(p: Vec3) -> Vec3 {
    Vec3::new(p.x, -p.z, p.y)
}

/// A Blender point in Drape's axes (the inverse of [`z_up_from_y_up`]).
pub fn y_up_from_z_up(p: Vec3) -> Vec3 {
    Vec3::new(p.x, p.z, -p.y)
}

/// [`z_up_from_y_up`] in double precision (pins).
pub fn z_up_from_y_up_f64(p: DVec3) -> DVec3 {
    DVec3::new(p.x, -p.z, p.y)
}

/// A Blender point in Drape's axes, in double precision (pin targets).
pub fn y_up_from_z_up_f64(p: DVec3) -> DVec3 {
    DVec3::new(p.x, p.z, -p.y)
}

/// Flattens `positions` into x, y, z triples in `axes`, replacing `out`'s contents.
pub fn write_flat(positions: &[Vec3], axes: Axes, out: &mut Vec<f32>) {
    out.clear();
    out.reserve(positions.len() * 3);
    match axes {
        Axes::YUp => out.extend(positions.iter().flat_map(|p| p.to_array())),
        Axes::ZUp => out.extend(positions.iter().flat_map(|&p| z_up_from_y_up(p).to_array())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drape_up_is_blender_up_and_drape_front_is_blender_back() {
        // Drape's +Y (up) is Blender's +Z; Drape's +Z (towards the viewer) is Blender's −Y.
        assert_eq!(z_up_from_y_up(Vec3::Y), Vec3::Z);
        assert_eq!(z_up_from_y_up(Vec3::Z), -Vec3::Y);
        assert_eq!(z_up_from_y_up(Vec3::X), Vec3::X);
    }

    #[test]
    fn the_conversion_is_a_rotation_and_round_trips() {
        let (a, b) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(-0.5, 0.25, 4.0));
        let (ra, rb) = (z_up_from_y_up(a), z_up_from_y_up(b));
        // Lengths, angles and handedness are kept.
        assert_eq!(ra.length(), a.length());
        assert_eq!(ra.dot(rb), a.dot(b));
        assert_eq!(ra.cross(rb), z_up_from_y_up(a.cross(b)));
        assert_eq!(y_up_from_z_up(ra), a);
        assert_eq!(y_up_from_z_up_f64(ra.as_dvec3()), a.as_dvec3());
        assert_eq!(z_up_from_y_up_f64(a.as_dvec3()), ra.as_dvec3());
    }

    #[test]
    fn flat_triples_follow_vertex_order() {
        let mut out = vec![9.0];
        write_flat(&[Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)], Axes::ZUp, &mut out);
        assert_eq!(out, [1.0, -3.0, 2.0, 4.0, -6.0, 5.0]);
        write_flat(&[Vec3::new(1.0, 2.0, 3.0)], Axes::YUp, &mut out);
        assert_eq!(out, [1.0, 2.0, 3.0]);
    }
}
