//! A collider's shape as a few lines: what the editor draws round the
//! selected one.

use glam::{DMat3, DVec3};

use super::ColliderShape;

/// Segments per circle.
const CIRCLE_SEGMENTS: usize = 32;

impl ColliderShape {
    /// Line segments that draw the solid's shape: a box's twelve edges, a
    /// ball's three great circles, a cylinder's rims and four sides, a
    /// capsule's end circles and four sides, a mesh's turned bounding box.
    /// The ground, without an edge, has none.
    pub fn outline(&self) -> Vec<[DVec3; 2]> {
        let mut lines = Vec::new();
        match *self {
            ColliderShape::Ground { .. } => {}
            ColliderShape::Box { center, half, world_from_local } => {
                box_edges(&mut lines, center, half, world_from_local);
            }
            ColliderShape::Mesh { ref solid, center, world_from_local, scale } => {
                let (lo, hi) = solid.bounds();
                let middle = center + world_from_local * ((lo + hi) * 0.5 * scale);
                box_edges(&mut lines, middle, (hi - lo) * 0.5 * scale, world_from_local);
            }
            ColliderShape::Sphere { center, radius } => {
                for (u, v) in [(DVec3::X, DVec3::Y), (DVec3::Y, DVec3::Z), (DVec3::Z, DVec3::X)] {
                    circle(&mut lines, center, u * radius, v * radius);
                }
            }
            ColliderShape::Cylinder { center, radius, half_height, world_from_local } => {
                let (u, v, up) = (world_from_local.x_axis, world_from_local.z_axis, world_from_local.y_axis);
                sides(&mut lines, center - up * half_height, center + up * half_height, u * radius, v * radius);
            }
            ColliderShape::Capsule { a, b, radius } => {
                let axis = (b - a).try_normalize().unwrap_or(DVec3::Y);
                let u = axis.any_orthonormal_vector();
                let v = axis.cross(u);
                sides(&mut lines, a, b, u * radius, v * radius);
            }
        }
        lines
    }
}

/// Two circles (spanned by `u` and `v`) round `a` and `b`, joined by four lines.
fn sides(lines: &mut Vec<[DVec3; 2]>, a: DVec3, b: DVec3, u: DVec3, v: DVec3) {
    circle(lines, a, u, v);
    circle(lines, b, u, v);
    for side in [u, v, -u, -v] {
        lines.push([a + side, b + side]);
    }
}

/// The circle `center + u cos θ + v sin θ`.
fn circle(lines: &mut Vec<[DVec3; 2]>, center: DVec3, u: DVec3, v: DVec3) {
    let at = |k: usize| {
        let angle = k as f64 * std::f64::consts::TAU / CIRCLE_SEGMENTS as f64;
        center + u * angle.cos() + v * angle.sin()
    };
    lines.extend((0..CIRCLE_SEGMENTS).map(|k| [at(k), at(k + 1)]));
}

/// The twelve edges of a box of half extents `half` turned by `world_from_local` round `center`.
fn box_edges(lines: &mut Vec<[DVec3; 2]>, center: DVec3, half: DVec3, world_from_local: DMat3) {
    let corner = |bits: usize| {
        let sign = |bit: usize| if bits & (1 << bit) != 0 { 1.0 } else { -1.0 };
        center + world_from_local * (half * DVec3::new(sign(0), sign(1), sign(2)))
    };
    for bits in 0..8 {
        for axis in 0..3 {
            if bits & (1 << axis) == 0 {
                lines.push([corner(bits), corner(bits | (1 << axis))]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_outline_is_its_twelve_edges_on_its_corners() {
        let shape = ColliderShape::Box {
            center: DVec3::new(0.0, 0.7, 0.0),
            half: DVec3::new(0.6, 0.02, 0.4),
            world_from_local: DMat3::from_rotation_y(0.5),
        };
        let lines = shape.outline();
        assert_eq!(lines.len(), 12);
        for end in lines.iter().flatten() {
            assert!(shape.distance(*end).abs() < 1e-12, "a corner on the surface: {end}");
        }
        for [a, b] in &lines {
            let length = a.distance(*b);
            assert!([1.2, 0.04, 0.8].iter().any(|l| (length - l).abs() < 1e-12), "an edge's length: {length}");
        }
    }

    #[test]
    fn round_outlines_lie_on_the_surface_and_the_ground_has_none() {
        let shapes = [
            ColliderShape::Sphere { center: DVec3::new(1.0, 2.0, 3.0), radius: 0.3 },
            ColliderShape::Capsule { a: DVec3::ZERO, b: DVec3::new(0.3, 1.0, 0.2), radius: 0.1 },
            ColliderShape::Cylinder {
                center: DVec3::Y,
                radius: 0.5,
                half_height: 0.1,
                world_from_local: DMat3::from_rotation_x(0.4),
            },
        ];
        for shape in shapes {
            let lines = shape.outline();
            assert!(lines.len() > 60, "{shape:?}");
            for end in lines.iter().flatten() {
                assert!(shape.distance(*end).abs() < 1e-9, "{shape:?}: {end} is off the surface");
            }
        }
        assert!(ColliderShape::Ground { height: 0.0 }.outline().is_empty());
    }
}
