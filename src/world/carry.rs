//! Where a point held still relative to a moving solid goes: the solid's
//! move from one moment to another, as a rigid motion.

use glam::{DQuat, DVec3};

use super::ColliderShape;

/// `p` carried with the solid from its place `from` to its place `to` (the
/// same collider at two moments), as if glued to it: translated and turned
/// as its centre and axes are (a capsule by its ends' midpoint and
/// direction; a change of size is not followed). `None` where the two are
/// not one solid rigidly moved: different kinds, or meshes of different
/// solids (a skinned body's poses).
pub fn carried_with(from: &ColliderShape, to: &ColliderShape, p: DVec3) -> Option<DVec3> {
    use ColliderShape as S;
    match (from, to) {
        (S::Ground { height: h0 }, S::Ground { height: h1 }) => Some(p + DVec3::Y * (h1 - h0)),
        (S::Sphere { center: c0, .. }, S::Sphere { center: c1, .. }) => Some(p + (*c1 - *c0)),
        (S::Capsule { a: a0, b: b0, .. }, S::Capsule { a: a1, b: b1, .. }) => {
            let (m0, m1) = ((*a0 + *b0) * 0.5, (*a1 + *b1) * 0.5);
            let (d0, d1) = ((*b0 - *a0).normalize_or_zero(), (*b1 - *a1).normalize_or_zero());
            let turn =
                if d0 == DVec3::ZERO || d1 == DVec3::ZERO { DQuat::IDENTITY } else { DQuat::from_rotation_arc(d0, d1) };
            Some(m1 + turn * (p - m0))
        }
        (S::Box { center: c0, world_from_local: r0, .. }, S::Box { center: c1, world_from_local: r1, .. })
        | (
            S::Cylinder { center: c0, world_from_local: r0, .. },
            S::Cylinder { center: c1, world_from_local: r1, .. },
        ) => Some(*c1 + *r1 * (r0.transpose() * (p - *c0))),
        (
            S::Mesh { solid: s0, center: c0, world_from_local: r0, scale: k0 },
            S::Mesh { solid: s1, center: c1, world_from_local: r1, scale: k1 },
        ) if std::sync::Arc::ptr_eq(s0, s1) => Some(*c1 + *r1 * (r0.transpose() * (p - *c0)) * (k1 / k0)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;

    /// A point carried keeps its distance and outward direction relative to
    /// the solid: carried back, it is where it started.
    #[test]
    fn a_carried_point_keeps_its_place_on_the_solid() {
        let turn = ColliderShape::rotation_from_deg(10.0, 30.0, -20.0);
        let pairs = [
            (
                ColliderShape::Capsule { a: DVec3::new(0.0, 0.3, -0.4), b: DVec3::new(0.0, 1.1, -0.4), radius: 0.08 },
                ColliderShape::Capsule { a: DVec3::new(0.2, 0.3, 0.3), b: DVec3::new(0.0, 1.0, 0.3), radius: 0.08 },
            ),
            (
                ColliderShape::Box { center: DVec3::ZERO, half: DVec3::splat(0.2), world_from_local: DMat3::IDENTITY },
                ColliderShape::Box { center: DVec3::X, half: DVec3::splat(0.2), world_from_local: turn },
            ),
            (
                ColliderShape::Sphere { center: DVec3::ZERO, radius: 0.3 },
                ColliderShape::Sphere { center: DVec3::new(0.0, 0.1, 0.5), radius: 0.3 },
            ),
        ];
        let p = DVec3::new(0.05, 0.6, -0.25);
        for (from, to) in pairs {
            let Some(q) = carried_with(&from, &to, p) else { panic!("{from:?} moves rigidly") };
            let (before, after) = (from.surface_point(p), to.surface_point(q));
            assert!((before.distance - after.distance).abs() < 1e-12, "{from:?}: {before:?} {after:?}");
            let Some(back) = carried_with(&to, &from, q) else { panic!("and back") };
            assert!(back.distance(p) < 1e-12, "{from:?}: back at {back}");
        }
        let ball = ColliderShape::Sphere { center: DVec3::ZERO, radius: 0.3 };
        assert_eq!(carried_with(&ball, &ColliderShape::Ground { height: 0.0 }, p), None);
    }
}
