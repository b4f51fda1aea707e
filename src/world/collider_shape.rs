//! One collider's solid at one moment: exact signed distances and outward
//! directions for the primitive kinds, and a placed triangle mesh's.

use std::sync::Arc;

use glam::{DMat3, DVec2, DVec3};

use super::far_field::outside_box;
use super::mesh_solid::MeshSolid;
use super::surface_point::SurfacePoint;

/// A collider's solid in world space (metres). Rotations are world_from_local.
#[derive(Clone, Debug, PartialEq)]
pub enum ColliderShape {
    /// Everything below y = `height`.
    Ground {
        height: f64,
    },
    Sphere {
        center: DVec3,
        radius: f64,
    },
    /// The segment a–b swollen by `radius`.
    Capsule {
        a: DVec3,
        b: DVec3,
        radius: f64,
    },
    /// An oriented box with half extents along its own axes.
    Box {
        center: DVec3,
        half: DVec3,
        world_from_local: DMat3,
    },
    /// A cylinder along its own +Y, `half_height` each way from the centre.
    Cylinder {
        center: DVec3,
        radius: f64,
        half_height: f64,
        world_from_local: DMat3,
    },
    /// A triangle mesh, placed: a mesh point m is at
    /// `center + world_from_local · (scale · m)` (`scale` > 0).
    Mesh {
        solid: Arc<MeshSolid>,
        center: DVec3,
        world_from_local: DMat3,
        scale: f64,
    },
}

/// How near the box around a mesh collider a point must be for its
/// distance to be measured to the triangles (m): more than any thickness.
pub const MESH_EXACT_WITHIN_M: f64 = 0.25;

impl ColliderShape {
    /// The rotation X, then Y, then Z (degrees) about the centre, as DESIGN.md states.
    pub fn rotation_from_deg(x_deg: f64, y_deg: f64, z_deg: f64) -> DMat3 {
        DMat3::from_rotation_z(z_deg.to_radians())
            * DMat3::from_rotation_y(y_deg.to_radians())
            * DMat3::from_rotation_x(x_deg.to_radians())
    }

    /// Signed distance from `p` and the outward direction there. A non-finite
    /// `p` reads as far outside (nothing to push). For a mesh, exact within
    /// [`MESH_EXACT_WITHIN_M`] of the box around it; farther, the distance
    /// to that box (never more than the true distance).
    pub fn surface_point(&self, p: DVec3) -> SurfacePoint {
        if !p.is_finite() {
            return SurfacePoint { distance: f64::INFINITY, outward: DVec3::Y };
        }
        match *self {
            ColliderShape::Mesh { ref solid, center, world_from_local, scale } => {
                let local = world_from_local.transpose() * (p - center) / scale;
                // Far from the mesh's box, the distance to the box: a lower bound,
                // which is all a contact test or a sphere trace needs, without
                // searching the triangles.
                let outside = outside_box(solid.bounds(), local);
                let gap = outside.length();
                if gap * scale > MESH_EXACT_WITHIN_M {
                    return SurfacePoint { distance: gap * scale, outward: world_from_local * (outside / gap) };
                }
                let s = solid.surface_point(local);
                SurfacePoint { distance: s.distance * scale, outward: world_from_local * s.outward }
            }
            ColliderShape::Ground { height } => SurfacePoint { distance: p.y - height, outward: DVec3::Y },
            ColliderShape::Sphere { center, radius } => round(p - center, radius),
            ColliderShape::Capsule { a, b, radius } => {
                let ab = b - a;
                let length2 = ab.length_squared();
                let s = if length2 > 0.0 { ((p - a).dot(ab) / length2).clamp(0.0, 1.0) } else { 0.0 };
                round(p - (a + ab * s), radius)
            }
            ColliderShape::Box { center, half, world_from_local } => {
                let local = world_from_local.transpose() * (p - center);
                let (distance, outward) = box_distance(local, half);
                SurfacePoint { distance, outward: world_from_local * outward }
            }
            ColliderShape::Cylinder { center, radius, half_height, world_from_local } => {
                let local = world_from_local.transpose() * (p - center);
                let (distance, outward) = cylinder_distance(local, radius, half_height);
                SurfacePoint { distance, outward: world_from_local * outward }
            }
        }
    }

    /// Signed distance from `p` to the surface (negative inside).
    pub fn distance(&self, p: DVec3) -> f64 {
        self.surface_point(p).distance
    }

    /// Whether `p` is `keep` or more outside the surface: the same answer
    /// as `distance(p) >= keep`, cheaper for a mesh far from `p`.
    pub fn keeps_clear(&self, p: DVec3, keep: f64) -> bool {
        let ColliderShape::Mesh { ref solid, center, world_from_local, scale } = *self else {
            return self.distance(p) >= keep;
        };
        if !p.is_finite() {
            return true;
        }
        let local = world_from_local.transpose() * (p - center) / scale;
        let off_box = outside_box(solid.bounds(), local).length() * scale;
        if off_box > MESH_EXACT_WITHIN_M {
            return off_box >= keep;
        }
        solid.keeps_clear(local, keep / scale)
    }

    /// Whether the solid, swollen by `margin`, may reach into the box
    /// `min`..`max`: a cheap test that never misses a contact.
    pub fn may_reach(&self, min: DVec3, max: DVec3, margin: f64) -> bool {
        let (lo, hi) = self.bounds();
        let (lo, hi) = (lo - DVec3::splat(margin), hi + DVec3::splat(margin));
        lo.cmple(max).all() && hi.cmpge(min).all()
    }

    /// An axis-aligned box around the solid (the ground reaches down forever).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match *self {
            ColliderShape::Mesh { ref solid, center, world_from_local, scale } => {
                let (lo, hi) = solid.bounds();
                let middle = center + world_from_local * ((lo + hi) * 0.5 * scale);
                let extent = world_from_local.abs() * ((hi - lo) * 0.5 * scale);
                (middle - extent, middle + extent)
            }
            ColliderShape::Ground { height } => (
                DVec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY),
                DVec3::new(f64::INFINITY, height, f64::INFINITY),
            ),
            ColliderShape::Sphere { center, radius } => (center - DVec3::splat(radius), center + DVec3::splat(radius)),
            ColliderShape::Capsule { a, b, radius } => {
                (a.min(b) - DVec3::splat(radius), a.max(b) + DVec3::splat(radius))
            }
            ColliderShape::Box { center, half, world_from_local } => {
                let extent = world_from_local.abs() * half;
                (center - extent, center + extent)
            }
            ColliderShape::Cylinder { center, radius, half_height, world_from_local } => {
                let extent = world_from_local.abs() * DVec3::new(radius, half_height, radius);
                (center - extent, center + extent)
            }
        }
    }
}

/// A ball of `radius` around the origin, `d` from its centre.
fn round(d: DVec3, radius: f64) -> SurfacePoint {
    let length = d.length();
    let outward = if length > 0.0 { d / length } else { DVec3::Y };
    SurfacePoint { distance: length - radius, outward }
}

/// Signed distance and outward direction of a box of half extents `half` at the origin.
fn box_distance(q: DVec3, half: DVec3) -> (f64, DVec3) {
    let d = q.abs() - half;
    let sign = DVec3::new(sign_of(q.x), sign_of(q.y), sign_of(q.z));
    let outside = d.max(DVec3::ZERO);
    let out_length = outside.length();
    if out_length > 0.0 {
        return (out_length, outside * sign / out_length);
    }
    // Inside (or on the surface): the nearest face; ties go to y, then x.
    let axis = if d.y >= d.x && d.y >= d.z {
        DVec3::Y
    } else if d.x >= d.z {
        DVec3::X
    } else {
        DVec3::Z
    };
    (d.max_element(), axis * sign)
}

/// Signed distance and outward direction of a cylinder along y at the origin.
fn cylinder_distance(q: DVec3, radius: f64, half_height: f64) -> (f64, DVec3) {
    let radial = DVec2::new(q.x, q.z);
    let r = radial.length();
    let across = if r > 0.0 { radial / r } else { DVec2::X };
    let d = DVec2::new(r - radius, q.y.abs() - half_height);
    let up = sign_of(q.y);
    let outside = d.max(DVec2::ZERO);
    let out_length = outside.length();
    if out_length > 0.0 {
        let o = outside / out_length;
        return (out_length, DVec3::new(across.x * o.x, up * o.y, across.y * o.x));
    }
    if d.y >= d.x { (d.y, DVec3::new(0.0, up, 0.0)) } else { (d.x, DVec3::new(across.x, 0.0, across.y)) }
}

/// +1 or −1; 0 counts as +1 so a point on a mirror plane has one answer.
fn sign_of(v: f64) -> f64 {
    if v < 0.0 { -1.0 } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn sphere_and_capsule_distances_are_exact() {
        let ball = ColliderShape::Sphere { center: DVec3::new(0.0, 1.0, 0.0), radius: 0.5 };
        let s = ball.surface_point(DVec3::new(0.0, 3.0, 0.0));
        assert!(close(s.distance, 1.5) && s.outward == DVec3::Y);
        assert!(close(ball.distance(DVec3::new(0.3, 1.0, 0.0)), -0.2));
        let arm = ColliderShape::Capsule { a: DVec3::ZERO, b: DVec3::new(2.0, 0.0, 0.0), radius: 0.1 };
        assert!(close(arm.distance(DVec3::new(1.0, 0.5, 0.0)), 0.4));
        assert!(close(arm.distance(DVec3::new(3.0, 0.0, 0.0)), 0.9), "past the end it is a ball");
        let dot = ColliderShape::Capsule { a: DVec3::ONE, b: DVec3::ONE, radius: 0.1 };
        assert!(close(dot.distance(DVec3::new(1.0, 2.0, 1.0)), 0.9), "a = b is a sphere");
    }

    #[test]
    fn a_box_measures_faces_edges_and_inside() {
        let table = ColliderShape::Box {
            center: DVec3::new(0.0, 0.72, 0.0),
            half: DVec3::new(0.6, 0.02, 0.4),
            world_from_local: DMat3::IDENTITY,
        };
        let above = table.surface_point(DVec3::new(0.1, 1.0, 0.1));
        assert!(close(above.distance, 0.26) && above.outward == DVec3::Y);
        let edge = table.surface_point(DVec3::new(0.9, 0.74 + 0.4, 0.0));
        assert!(close(edge.distance, 0.5));
        assert!((edge.outward - DVec3::new(0.6, 0.8, 0.0)).length() < 1e-12);
        let inside = table.surface_point(DVec3::new(0.0, 0.73, 0.0));
        assert!(close(inside.distance, -0.01) && inside.outward == DVec3::Y);
        let below = table.surface_point(DVec3::new(0.0, 0.705, 0.0));
        assert!(below.outward == -DVec3::Y);
    }

    #[test]
    fn a_turned_box_turns_its_distances() {
        let r = ColliderShape::rotation_from_deg(0.0, 0.0, 90.0);
        let post = ColliderShape::Box { center: DVec3::ZERO, half: DVec3::new(1.0, 0.1, 0.1), world_from_local: r };
        // Its long axis now runs along y.
        assert!(close(post.distance(DVec3::new(0.0, 0.95, 0.0)), -0.05));
        assert!(close(post.distance(DVec3::new(0.5, 0.0, 0.0)), 0.4));
        let (lo, hi) = post.bounds();
        assert!((hi - DVec3::new(0.1, 1.0, 0.1)).length() < 1e-12 && (lo + hi).length() < 1e-12);
    }

    #[test]
    fn a_cylinder_measures_its_side_caps_and_rim() {
        let round_table = ColliderShape::Cylinder {
            center: DVec3::ZERO,
            radius: 0.6,
            half_height: 0.02,
            world_from_local: DMat3::IDENTITY,
        };
        assert!(close(round_table.distance(DVec3::new(0.0, 0.5, 0.3)), 0.48));
        let side = round_table.surface_point(DVec3::new(0.0, 0.0, 1.0));
        assert!(close(side.distance, 0.4) && (side.outward - DVec3::Z).length() < 1e-12);
        assert!(close(round_table.distance(DVec3::new(0.9, 0.42, 0.0)), 0.5), "the rim: a 3-4-5 triangle");
        assert!(close(round_table.distance(DVec3::new(0.0, 0.01, 0.0)), -0.01));
    }

    #[test]
    fn non_finite_points_are_far_outside() {
        let ball = ColliderShape::Sphere { center: DVec3::ZERO, radius: 1.0 };
        assert_eq!(ball.distance(DVec3::new(f64::NAN, 0.0, 0.0)), f64::INFINITY);
        assert!(ColliderShape::Ground { height: 0.0 }.may_reach(DVec3::splat(-1.0), DVec3::ZERO, 0.0));
        assert!(!ColliderShape::Ground { height: 0.0 }.may_reach(DVec3::splat(1.0), DVec3::splat(2.0), 0.5));
    }
}
