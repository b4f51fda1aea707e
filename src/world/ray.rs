//! Where a ray first meets a collider's surface: what the editor's pointer
//! is over.

use glam::DVec3;

use super::ColliderShape;

/// Sphere-tracing steps along a ray; one grazing a surface may need many and
/// counts as a miss after this many.
const STEPS: usize = 256;

/// A ray this close to the surface (m) has hit it.
const HIT_M: f64 = 1e-5;

/// The distance along the ray from `origin` in `direction` (any length,
/// not zero) to where it first meets `shape`'s surface, if within `max_m`.
/// A ray that starts inside the solid meets nothing (a camera inside a
/// collider sees out of it); so do non-finite inputs.
pub fn ray_hit(shape: &ColliderShape, origin: DVec3, direction: DVec3, max_m: f64) -> Option<f64> {
    let direction = direction.try_normalize()?;
    if !origin.is_finite() || !(max_m > 0.0) {
        return None;
    }
    let mut t = 0.0;
    if shape.distance(origin) <= 0.0 {
        return None;
    }
    for _ in 0..STEPS {
        // The distance is never more than the true one (a mesh far from its
        // box answers the box's), so a step of it never passes the surface.
        let d = shape.distance(origin + direction * t);
        if d < HIT_M {
            return Some(t);
        }
        t += d;
        if !(t <= max_m) {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;

    #[test]
    fn a_ray_meets_a_ball_where_the_geometry_says() {
        let ball = ColliderShape::Sphere { center: DVec3::new(0.0, 1.0, 0.0), radius: 0.5 };
        let t = ray_hit(&ball, DVec3::new(0.0, 1.0, 5.0), DVec3::NEG_Z * 3.0, 100.0).unwrap();
        assert!((t - 4.5).abs() < 1e-4, "{t}");
        // Off to the side it passes; too short it stops before; from inside it sees nothing.
        assert_eq!(ray_hit(&ball, DVec3::new(0.6, 1.0, 5.0), DVec3::NEG_Z, 100.0), None);
        assert_eq!(ray_hit(&ball, DVec3::new(0.0, 1.0, 5.0), DVec3::NEG_Z, 4.0), None);
        assert_eq!(ray_hit(&ball, DVec3::new(0.0, 1.0, 0.0), DVec3::NEG_Z, 100.0), None);
    }

    #[test]
    fn a_ray_meets_a_turned_box_on_its_face() {
        let table = ColliderShape::Box {
            center: DVec3::new(0.0, 0.7, 0.0),
            half: DVec3::new(0.6, 0.02, 0.4),
            world_from_local: DMat3::from_rotation_y(0.3),
        };
        let t = ray_hit(&table, DVec3::new(0.1, 3.0, 0.1), DVec3::NEG_Y, 10.0).unwrap();
        assert!((t - (3.0 - 0.72)).abs() < 1e-4, "{t}");
    }

    #[test]
    fn degenerate_rays_meet_nothing() {
        let ball = ColliderShape::Sphere { center: DVec3::ZERO, radius: 1.0 };
        let from = DVec3::new(0.0, 0.0, 5.0);
        assert_eq!(ray_hit(&ball, from, DVec3::ZERO, 10.0), None);
        assert_eq!(ray_hit(&ball, from, DVec3::NAN, 10.0), None);
        assert_eq!(ray_hit(&ball, DVec3::NAN, DVec3::NEG_Z, 10.0), None);
        assert_eq!(ray_hit(&ball, from, DVec3::NEG_Z, f64::NAN), None);
        assert!(ray_hit(&ball, from, DVec3::NEG_Z, f64::INFINITY).is_some());
    }
}
