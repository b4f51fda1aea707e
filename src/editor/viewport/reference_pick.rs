//! A ray against the references' posed triangles: the skin point of a
//! character under the pointer, named as a surface attachment names it
//! (mesh, triangle, barycentric weights), so it is the same skin point at
//! every pose. Brute force over the triangles: a character's twenty thousand
//! are a millisecond, and a click asks once.

use glam::DVec3;

use crate::animate::references_at::reference_at;
use crate::scene::Scene;

/// Where a ray first meets a reference's surface.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceHit {
    /// The reference's index in the scene.
    pub reference: usize,
    /// The mesh and triangle, as [`crate::scene::SurfaceAttachment`] counts them.
    pub mesh: usize,
    pub triangle: usize,
    /// Weights of the triangle's corners: each at least 0, summing to 1.
    pub barycentric: (f64, f64, f64),
    /// How far along the ray (in the ray direction's units).
    pub along: f64,
}

/// The nearest point where the ray from `origin` along `direction` meets a
/// visible reference of `scene` posed at `frame`, either face of a triangle;
/// None when it meets none (or no reference has been read).
pub fn pick_reference_surface(scene: &Scene, frame: f64, origin: DVec3, direction: DVec3) -> Option<SurfaceHit> {
    let mut nearest: Option<SurfaceHit> = None;
    for (index, reference) in scene.references.iter().enumerate() {
        if !reference.visible {
            continue;
        }
        let Some(posed) = reference_at(scene, index, frame) else { continue };
        for (mesh, (rig_mesh, placed)) in posed.rig.meshes().iter().zip(posed.meshes()).enumerate() {
            for (triangle, corners) in rig_mesh.indices.chunks_exact(3).enumerate() {
                let [a, b, c] = [corners[0], corners[1], corners[2]].map(|i| placed.positions[i as usize]);
                let Some((along, barycentric)) = ray_triangle(origin, direction, [a, b, c]) else { continue };
                if nearest.as_ref().is_none_or(|n| along < n.along) {
                    nearest = Some(SurfaceHit { reference: index, mesh, triangle, barycentric, along });
                }
            }
        }
    }
    nearest
}

/// Where the ray meets triangle `abc` (Möller–Trumbore): how far along it,
/// and the corners' weights, clamped to at least 0 and summing to 1. None
/// for a miss, a hit behind the origin or a ray along the triangle's plane.
pub fn ray_triangle(origin: DVec3, direction: DVec3, [a, b, c]: [DVec3; 3]) -> Option<(f64, (f64, f64, f64))> {
    let (ab, ac) = (b - a, c - a);
    let p = direction.cross(ac);
    let determinant = ab.dot(p);
    if determinant.abs() < 1e-15 {
        return None;
    }
    let inverse = 1.0 / determinant;
    let s = origin - a;
    let u = s.dot(p) * inverse;
    let q = s.cross(ab);
    let v = direction.dot(q) * inverse;
    let along = ac.dot(q) * inverse;
    let inside = (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0;
    if !inside || !(along > 0.0) {
        return None;
    }
    // Rounding can leave a weight a hair below 0; validation wants them at least 0, summing to 1.
    let weights = [1.0 - u - v, u, v].map(|w| w.max(0.0));
    let sum: f64 = weights.iter().sum();
    Some((along, (weights[0] / sum, weights[1] / sum, weights[2] / sum)))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRIANGLE: [DVec3; 3] = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];

    #[test]
    fn a_ray_through_a_triangle_gives_the_point_s_weights() {
        let (along, (w0, w1, w2)) = ray_triangle(DVec3::new(0.25, 0.5, 2.0), DVec3::NEG_Z, TRIANGLE).unwrap();
        assert!((along - 2.0).abs() < 1e-12);
        assert!((w0 - 0.25).abs() < 1e-12 && (w1 - 0.25).abs() < 1e-12 && (w2 - 0.5).abs() < 1e-12);
        // From behind it meets the other face the same way.
        let (_, weights) = ray_triangle(DVec3::new(0.25, 0.5, -2.0), DVec3::Z, TRIANGLE).unwrap();
        assert!((weights.2 - 0.5).abs() < 1e-12);
    }

    #[test]
    fn misses_are_none() {
        assert_eq!(ray_triangle(DVec3::new(0.8, 0.8, 2.0), DVec3::NEG_Z, TRIANGLE), None, "beside it");
        assert_eq!(ray_triangle(DVec3::new(0.2, 0.2, 2.0), DVec3::Z, TRIANGLE), None, "behind the origin");
        assert_eq!(ray_triangle(DVec3::new(-1.0, 0.2, 0.0), DVec3::X, TRIANGLE), None, "along its plane");
    }

    #[test]
    fn a_corner_hit_has_weights_validation_accepts() {
        let (_, (w0, w1, w2)) = ray_triangle(DVec3::new(1.0, 0.0, 1.0), DVec3::NEG_Z, TRIANGLE).unwrap();
        assert!(w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0);
        assert!((w0 + w1 + w2 - 1.0).abs() < 1e-12);
    }
}
