//! Colliders as triangles, for drawing: each solid's surface (not swollen by
//! its thickness) with outward normals, smooth where the surface is.

use std::f64::consts::{PI, TAU};

use glam::{DMat3, DVec3};

use super::ColliderShape;

/// Triangles with a normal per vertex, wound counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub indices: Vec<u32>,
}

/// Segments round a full circle: smooth at the sizes a viewport shows.
const AROUND: usize = 48;
/// Rings from pole to pole of a sphere (a capsule's two halves share them).
const RINGS: usize = 24;

impl TriangleMesh {
    /// Appends `other`, renumbering its indices.
    pub fn append(&mut self, other: &TriangleMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    fn vertex(&mut self, position: DVec3, normal: DVec3) -> u32 {
        self.positions.push(position);
        self.normals.push(normal);
        (self.positions.len() - 1) as u32
    }

    /// Two triangles a b c, a c d (counter-clockwise seen from outside).
    fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.indices.extend_from_slice(&[a, b, c, a, c, d]);
    }
}

impl ColliderShape {
    /// The solid's surface as triangles; the ground, which has no edge, is
    /// drawn by the renderer's ground and gives none.
    pub fn triangles(&self) -> TriangleMesh {
        let mut mesh = TriangleMesh::default();
        match *self {
            ColliderShape::Ground { .. } => {}
            ColliderShape::Mesh { ref solid, center, world_from_local, scale } => {
                // Flat: a mesh's hard edges stay hard (a table's, a step's).
                let (vertices, triangles) = solid.triangles();
                let place = |m: DVec3| center + world_from_local * (m * scale);
                for t in triangles {
                    let [a, b, c] = t.map(|i| place(vertices[i as usize]));
                    let normal = (b - a).cross(c - a).try_normalize().unwrap_or(DVec3::Y);
                    let ids = [a, b, c].map(|p| mesh.vertex(p, normal));
                    mesh.indices.extend_from_slice(&ids);
                }
            }
            ColliderShape::Sphere { center, radius } => {
                capsule(&mut mesh, center, center, radius, DMat3::IDENTITY);
            }
            ColliderShape::Capsule { a, b, radius } => {
                let axis = b - a;
                let rotation =
                    if axis.length() > 0.0 { rotation_taking_y_to(axis.normalize()) } else { DMat3::IDENTITY };
                capsule(&mut mesh, a, b, radius, rotation);
            }
            ColliderShape::Box { center, half, world_from_local } => {
                for axis in 0..3 {
                    for sign in [-1.0, 1.0] {
                        let mut n = DVec3::ZERO;
                        n[axis] = sign;
                        // Two axes across the face, ordered so that u × v = n.
                        let (mut u, mut v) = (DVec3::ZERO, DVec3::ZERO);
                        u[(axis + 1) % 3] = 1.0;
                        v[(axis + 2) % 3] = sign;
                        let corner = |su: f64, sv: f64| center + world_from_local * ((n + u * su + v * sv) * half);
                        let normal = world_from_local * n;
                        let ids = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                            .map(|(su, sv)| mesh.vertex(corner(su, sv), normal));
                        mesh.quad(ids[0], ids[1], ids[2], ids[3]);
                    }
                }
            }
            ColliderShape::Cylinder { center, radius, half_height, world_from_local } => {
                let at = |angle: f64, y: f64| {
                    center + world_from_local * DVec3::new(radius * angle.cos(), y, radius * -angle.sin())
                };
                let across = |angle: f64| world_from_local * DVec3::new(angle.cos(), 0.0, -angle.sin());
                for k in 0..AROUND {
                    let (a0, a1) = (TAU * k as f64 / AROUND as f64, TAU * (k + 1) as f64 / AROUND as f64);
                    let ids = [
                        mesh.vertex(at(a0, -half_height), across(a0)),
                        mesh.vertex(at(a1, -half_height), across(a1)),
                        mesh.vertex(at(a1, half_height), across(a1)),
                        mesh.vertex(at(a0, half_height), across(a0)),
                    ];
                    mesh.quad(ids[0], ids[1], ids[2], ids[3]);
                }
                for (y, up) in [(half_height, 1.0), (-half_height, -1.0)] {
                    let normal = world_from_local * DVec3::new(0.0, up, 0.0);
                    let middle = mesh.vertex(center + world_from_local * DVec3::new(0.0, y, 0.0), normal);
                    let rim: Vec<u32> =
                        (0..AROUND).map(|k| mesh.vertex(at(TAU * k as f64 / AROUND as f64, y), normal)).collect();
                    for k in 0..AROUND {
                        let (p, q) = (rim[k], rim[(k + 1) % AROUND]);
                        let triangle = if up > 0.0 { [middle, p, q] } else { [middle, q, p] };
                        mesh.indices.extend_from_slice(&triangle);
                    }
                }
            }
        }
        mesh
    }
}

/// A capsule from `a` to `b` (along the rotation's +Y), or a sphere when they meet.
fn capsule(mesh: &mut TriangleMesh, a: DVec3, b: DVec3, radius: f64, rotation: DMat3) {
    let first = mesh.positions.len() as u32;
    // Rings from the top pole (at b) to the bottom one (at a); the upper half
    // hangs off b, the lower off a, and the equator is doubled between them.
    let mut rings = 0;
    for ring in 0..=RINGS {
        let halves: &[DVec3] = if ring == RINGS / 2 {
            &[b, a]
        } else if ring < RINGS / 2 {
            &[b]
        } else {
            &[a]
        };
        for &base in halves {
            let polar = PI * ring as f64 / RINGS as f64;
            for k in 0..=AROUND {
                let azimuth = TAU * k as f64 / AROUND as f64;
                let n = rotation * DVec3::new(polar.sin() * azimuth.cos(), polar.cos(), -polar.sin() * azimuth.sin());
                mesh.vertex(base + n * radius, n);
            }
            rings += 1;
        }
    }
    let row = (AROUND + 1) as u32;
    for r in 0..(rings - 1) as u32 {
        for k in 0..AROUND as u32 {
            let (p, q) = (first + r * row + k, first + (r + 1) * row + k);
            mesh.quad(p, q, q + 1, p + 1);
        }
    }
}

/// A rotation that takes +Y to the unit vector `to`.
fn rotation_taking_y_to(to: DVec3) -> DMat3 {
    let from = DVec3::Y;
    let cos = from.dot(to);
    if cos > 1.0 - 1e-12 {
        return DMat3::IDENTITY;
    }
    if cos < -1.0 + 1e-12 {
        return DMat3::from_rotation_x(PI);
    }
    DMat3::from_axis_angle(from.cross(to).normalize(), cos.clamp(-1.0, 1.0).acos())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every vertex on the surface, every normal outward, every triangle facing out.
    fn assert_closed_surface(shape: ColliderShape) {
        let mesh = shape.triangles();
        assert!(!mesh.indices.is_empty());
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!(shape.distance(*p).abs() < 1e-9, "{shape:?}: {p} is off the surface");
            assert!((shape.surface_point(*p + *n * 1e-3).distance - 1e-3).abs() < 1e-6, "{shape:?}: {n} at {p}");
        }
        for t in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
            let face = (b - a).cross(c - a);
            if face.length() < 1e-12 {
                continue; // a sliver at a pole
            }
            let centroid = (a + b + c) / 3.0;
            assert!(
                shape.distance(centroid + face.normalize() * 1e-3) > shape.distance(centroid),
                "{shape:?}: a triangle faces in"
            );
        }
    }

    #[test]
    fn every_kind_is_a_closed_surface_facing_out() {
        let turned = ColliderShape::rotation_from_deg(20.0, 30.0, 40.0);
        assert_closed_surface(ColliderShape::Sphere { center: DVec3::new(0.0, 1.0, 0.0), radius: 0.3 });
        assert_closed_surface(ColliderShape::Capsule {
            a: DVec3::new(-0.3, 1.4, 0.1),
            b: DVec3::new(0.3, 1.2, 0.0),
            radius: 0.08,
        });
        assert_closed_surface(ColliderShape::Box {
            center: DVec3::Y,
            half: DVec3::new(0.6, 0.02, 0.4),
            world_from_local: turned,
        });
        assert_closed_surface(ColliderShape::Cylinder {
            center: DVec3::Y,
            radius: 0.6,
            half_height: 0.02,
            world_from_local: turned,
        });
        assert!(ColliderShape::Ground { height: 0.0 }.triangles().indices.is_empty());
    }
}
