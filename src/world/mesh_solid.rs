//! A closed triangle mesh as a solid: signed distances and outward
//! directions from any point, in the mesh's own coordinates.
//!
//! The queries are parry3d's (a bounding-volume hierarchy over the
//! triangles, and the angle-weighted pseudo-normals of Bærentzen et al. for
//! inside or outside), so a point is inside where the mesh, closed and
//! consistently wound, encloses it. A mesh with holes still answers: its
//! inside is then what the pseudo-normals say near the surface.

use std::fmt;

use glam::DVec3;
use parry3d_f64::math::Vector as ParryVector;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

use super::surface_point::SurfacePoint;

/// Most triangles a mesh collider may have: beyond it, queries for every
/// cloth point in every frame would be too slow to scrub.
pub const MAX_MESH_TRIANGLES: usize = 2_000_000;

/// A triangle mesh ready for distance queries.
pub struct MeshSolid {
    trimesh: TriMesh,
    /// Corners of the box around the vertices, in mesh coordinates.
    bounds: (DVec3, DVec3),
    /// A digest of the vertices and triangles: equal meshes, equal digests.
    fingerprint: u64,
}

/// Why triangles do not make a solid.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MeshSolidError {
    #[error("it has no triangles")]
    Empty,
    #[error("it has {0} triangles; at most {MAX_MESH_TRIANGLES} can be a collider")]
    TooLarge(usize),
    #[error("a vertex is not a finite number")]
    NotFinite,
    #[error("triangle {triangle} names vertex {vertex}, but there are {vertices}")]
    BadIndex { triangle: usize, vertex: u32, vertices: usize },
    #[error("its triangles have no area")]
    Degenerate,
}

impl MeshSolid {
    /// The solid bounded by `triangles` (indices into `vertices`, wound
    /// counter-clockwise seen from outside). Duplicate vertices are merged
    /// and triangles without area dropped.
    pub fn new(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Result<MeshSolid, MeshSolidError> {
        if triangles.is_empty() {
            return Err(MeshSolidError::Empty);
        }
        if triangles.len() > MAX_MESH_TRIANGLES {
            return Err(MeshSolidError::TooLarge(triangles.len()));
        }
        if !vertices.iter().all(|v| v.is_finite()) {
            return Err(MeshSolidError::NotFinite);
        }
        for (triangle, corners) in triangles.iter().enumerate() {
            if let Some(&vertex) = corners.iter().find(|&&v| v as usize >= vertices.len()) {
                return Err(MeshSolidError::BadIndex { triangle, vertex, vertices: vertices.len() });
            }
        }
        // Triangles without area (corners in a line) have no normal to tell inside by: dropped.
        let (lo, hi) =
            vertices.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        let tiny_area = (hi - lo).length_squared() * 1e-14;
        let kept: Vec<[u32; 3]> = triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| vertices[i as usize]);
                (b - a).cross(c - a).length() > tiny_area
            })
            .copied()
            .collect();
        if kept.is_empty() {
            return Err(MeshSolidError::Degenerate);
        }
        let points: Vec<ParryVector> = vertices.iter().map(|v| ParryVector::new(v.x, v.y, v.z)).collect();
        let flags =
            TriMeshFlags::ORIENTED | TriMeshFlags::MERGE_DUPLICATE_VERTICES | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES;
        let trimesh = TriMesh::with_flags(points, kept, flags).map_err(|_| MeshSolidError::Degenerate)?;
        if trimesh.indices().is_empty() {
            return Err(MeshSolidError::Degenerate);
        }
        let aabb = trimesh.local_aabb();
        let bounds =
            (DVec3::new(aabb.mins.x, aabb.mins.y, aabb.mins.z), DVec3::new(aabb.maxs.x, aabb.maxs.y, aabb.maxs.z));
        Ok(MeshSolid { trimesh, bounds, fingerprint: fingerprint(vertices, triangles) })
    }

    /// Signed distance from `p` (mesh coordinates; negative inside) and the
    /// outward direction there. A point on the surface gets its triangle's
    /// normal; a non-finite point reads as far outside.
    pub fn surface_point(&self, p: DVec3) -> SurfacePoint {
        if !p.is_finite() {
            return SurfacePoint { distance: f64::INFINITY, outward: DVec3::Y };
        }
        let query = ParryVector::new(p.x, p.y, p.z);
        // Not solid: the nearest surface point even from inside; the
        // pseudo-normals set `is_inside`.
        let (projection, (triangle, _)) = self.trimesh.project_local_point_and_get_location(query, false);
        let nearest = DVec3::new(projection.point.x, projection.point.y, projection.point.z);
        let gap = p - nearest;
        let length = gap.length();
        let inside = projection.is_inside;
        let outward = if length > 1e-12 {
            if inside { -gap / length } else { gap / length }
        } else {
            self.trimesh.triangle(triangle).normal().map_or(DVec3::Y, |n| DVec3::new(n.x, n.y, n.z))
        };
        SurfacePoint { distance: if inside { -length } else { length }, outward }
    }

    /// The box around the vertices, in mesh coordinates.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.bounds
    }

    /// The vertices and triangles after merging and dropping, for drawing.
    pub fn triangles(&self) -> (Vec<DVec3>, &[[u32; 3]]) {
        let vertices = self.trimesh.vertices().iter().map(|p| DVec3::new(p.x, p.y, p.z)).collect();
        (vertices, self.trimesh.indices())
    }

    pub fn triangle_count(&self) -> usize {
        self.trimesh.indices().len()
    }

    /// A digest of the vertices and triangles the solid was made from.
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }
}

impl fmt::Debug for MeshSolid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "MeshSolid({} triangles, {:016x})", self.triangle_count(), self.fingerprint)
    }
}

impl PartialEq for MeshSolid {
    /// Made from the same vertices and triangles.
    fn eq(&self, other: &Self) -> bool {
        self.fingerprint == other.fingerprint && self.triangle_count() == other.triangle_count()
    }
}

/// FNV-1a over the bits of every coordinate and index.
fn fingerprint(vertices: &[DVec3], triangles: &[[u32; 3]]) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |word: u64| {
        for byte in word.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for v in vertices {
        [v.x, v.y, v.z].into_iter().for_each(|c| eat(c.to_bits()));
    }
    for t in triangles {
        t.iter().for_each(|&i| eat(u64::from(i)));
    }
    hash
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube centred at the origin, wound outwards.
    pub(crate) fn cube() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let vertices: Vec<DVec3> = (0..8)
            .map(|i| {
                DVec3::new(
                    if i & 1 == 0 { -0.5 } else { 0.5 },
                    if i & 2 == 0 { -0.5 } else { 0.5 },
                    if i & 4 == 0 { -0.5 } else { 0.5 },
                )
            })
            .collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        (vertices, triangles)
    }

    #[test]
    fn a_cube_measures_like_a_box() {
        let (vertices, triangles) = cube();
        let solid = MeshSolid::new(&vertices, &triangles).unwrap();
        let above = solid.surface_point(DVec3::new(0.1, 0.8, -0.2));
        assert!((above.distance - 0.3).abs() < 1e-12 && above.outward.abs_diff_eq(DVec3::Y, 1e-12), "{above:?}");
        let inside = solid.surface_point(DVec3::new(0.0, 0.0, 0.4));
        assert!((inside.distance + 0.1).abs() < 1e-12 && inside.outward.abs_diff_eq(DVec3::Z, 1e-12), "{inside:?}");
        let corner = solid.surface_point(DVec3::new(1.5, 1.5, 1.5));
        assert!((corner.distance - 3f64.sqrt()).abs() < 1e-12, "{corner:?}");
        let on = solid.surface_point(DVec3::new(0.5, 0.1, 0.1));
        assert!(on.distance.abs() < 1e-12 && on.outward.abs_diff_eq(DVec3::X, 1e-9), "{on:?}");
        assert_eq!(solid.bounds(), (DVec3::splat(-0.5), DVec3::splat(0.5)));
        assert_eq!(solid.surface_point(DVec3::NAN).distance, f64::INFINITY);
    }

    #[test]
    fn broken_triangles_are_refused_with_a_reason() {
        let (vertices, mut triangles) = cube();
        assert_eq!(MeshSolid::new(&vertices, &[]).unwrap_err(), MeshSolidError::Empty);
        let mut nan = vertices.clone();
        nan[3].y = f64::NAN;
        assert_eq!(MeshSolid::new(&nan, &triangles).unwrap_err(), MeshSolidError::NotFinite);
        triangles[5][1] = 99;
        assert_eq!(
            MeshSolid::new(&vertices, &triangles).unwrap_err(),
            MeshSolidError::BadIndex { triangle: 5, vertex: 99, vertices: 8 }
        );
        let flat = [[0, 0, 1]];
        assert_eq!(MeshSolid::new(&vertices, &flat).unwrap_err(), MeshSolidError::Degenerate);
    }

    #[test]
    fn equal_meshes_have_equal_fingerprints() {
        let (vertices, triangles) = cube();
        let a = MeshSolid::new(&vertices, &triangles).unwrap();
        let b = MeshSolid::new(&vertices, &triangles).unwrap();
        assert_eq!(a.fingerprint(), b.fingerprint());
        let mut moved = vertices.clone();
        moved[0].x -= 0.01;
        assert_ne!(MeshSolid::new(&moved, &triangles).unwrap().fingerprint(), a.fingerprint());
    }
}
