//! A closed triangle mesh as a solid: signed distances and outward
//! directions from any point, in the mesh's own coordinates.
//!
//! The nearest point is parry3d's (a bounding-volume hierarchy over the
//! triangles); inside or outside is what the angle-weighted pseudo-normal
//! of the nearest feature says ([`MeshSides`]), so a point is inside where
//! the mesh, closed and consistently wound, encloses it. A mesh with holes
//! still answers: its inside is then what the pseudo-normals say near the
//! surface.
//!
//! A solid can be moved to new vertex positions with the same triangles
//! (a skinned body at another pose, [`MeshSolid::moved_to`]): the hierarchy
//! built for the first positions is refitted, not rebuilt, and every move
//! starts from that first build, so a pose's solid never depends on which
//! pose was asked for before.

use std::collections::HashMap;
use std::fmt;
use std::sync::{Arc, OnceLock};

use glam::DVec3;
use parry3d_f64::math::Vector as ParryVector;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{TriMesh, TriMeshFlags, TrianglePointLocation};

use super::far_field::FarField;
use super::mesh_sides::{Feature, MeshSides};
use super::surface_point::SurfacePoint;

/// Most triangles a mesh collider may have: beyond it, queries for every
/// cloth point in every frame would be too slow to scrub.
pub const MAX_MESH_TRIANGLES: usize = 2_000_000;

/// A triangle mesh ready for distance queries.
pub struct MeshSolid {
    trimesh: TriMesh,
    /// What every position of the same triangles shares.
    topology: Arc<Topology>,
    /// Corners of the box around the vertices, in mesh coordinates.
    bounds: (DVec3, DVec3),
    /// A digest of the vertices and triangles: equal meshes, equal digests.
    fingerprint: u64,
    /// Where a closed mesh is certainly far outside, made on first use;
    /// None for a mesh with holes.
    far: OnceLock<Option<FarField>>,
}

/// The triangles as they were given, and what welding them made.
struct Topology {
    /// How many vertices were given.
    given_vertices: usize,
    /// A digest of the triangles as given, for the fingerprint of a moved solid.
    triangles_digest: u64,
    /// For each welded vertex, the given vertex whose position it takes.
    source: Vec<u32>,
    sides: MeshSides,
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
    #[error("{given} vertices were given to move a solid made of {expected}")]
    VertexCount { given: usize, expected: usize },
}

impl MeshSolid {
    /// The solid bounded by `triangles` (indices into `vertices`, wound
    /// counter-clockwise seen from outside). Vertices at the same place are
    /// welded into one and triangles without area dropped.
    pub fn new(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Result<MeshSolid, MeshSolidError> {
        MeshSolid::with_parts(vertices, triangles, &[])
    }

    /// [`MeshSolid::new`] for a mesh made of parts (`part[v]` for each
    /// vertex; empty: one part) that are welded only within a part, so
    /// that parts that touch at this position can move apart.
    pub fn with_parts(vertices: &[DVec3], triangles: &[[u32; 3]], part: &[u32]) -> Result<MeshSolid, MeshSolidError> {
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
        // Welded in the order vertices are first named, as parry's own merge does.
        let mut welded: HashMap<(u32, [u64; 3]), u32> = HashMap::new();
        let mut source: Vec<u32> = Vec::new();
        let mut indices: Vec<[u32; 3]> = Vec::with_capacity(triangles.len());
        for t in triangles {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            if (b - a).cross(c - a).length() <= tiny_area {
                continue;
            }
            let weld = t.map(|i| {
                let v = vertices[i as usize];
                // + 0.0 makes -0.0 weld with 0.0.
                let place = (part.get(i as usize).copied().unwrap_or(0), [v.x, v.y, v.z].map(|c| (c + 0.0).to_bits()));
                *welded.entry(place).or_insert_with(|| {
                    source.push(i);
                    source.len() as u32 - 1
                })
            });
            if weld[0] != weld[1] && weld[1] != weld[2] && weld[0] != weld[2] {
                indices.push(weld);
            }
        }
        if indices.is_empty() {
            return Err(MeshSolidError::Degenerate);
        }
        let points: Vec<ParryVector> = source.iter().map(|&i| to_parry(vertices[i as usize])).collect();
        let sides = MeshSides::new(points.len(), &indices);
        let trimesh =
            TriMesh::with_flags(points, indices, TriMeshFlags::DEFORMABLE).map_err(|_| MeshSolidError::Degenerate)?;
        let triangles_digest = digest(triangles.iter().flat_map(|t| t.map(u64::from)));
        let topology = Topology { given_vertices: vertices.len(), triangles_digest, source, sides };
        let fingerprint = fingerprint(vertices, triangles_digest);
        Ok(MeshSolid::around(trimesh, Arc::new(topology), fingerprint))
    }

    /// The same triangles over `vertices` (numbered as the vertices this
    /// solid was first made from): a refit of the first build's hierarchy.
    /// Equal vertices make equal solids, whatever was moved before.
    pub fn moved_to(&self, vertices: &[DVec3]) -> Result<MeshSolid, MeshSolidError> {
        let topology = &self.topology;
        if vertices.len() != topology.given_vertices {
            return Err(MeshSolidError::VertexCount { given: vertices.len(), expected: topology.given_vertices });
        }
        if !vertices.iter().all(|v| v.is_finite()) {
            return Err(MeshSolidError::NotFinite);
        }
        let points: Vec<ParryVector> = topology.source.iter().map(|&i| to_parry(vertices[i as usize])).collect();
        let mut trimesh = self.trimesh.clone();
        trimesh.set_vertices(&points);
        let fingerprint = fingerprint(vertices, topology.triangles_digest);
        Ok(MeshSolid::around(trimesh, topology.clone(), fingerprint))
    }

    fn around(trimesh: TriMesh, topology: Arc<Topology>, fingerprint: u64) -> MeshSolid {
        let aabb = trimesh.local_aabb();
        let bounds =
            (DVec3::new(aabb.mins.x, aabb.mins.y, aabb.mins.z), DVec3::new(aabb.maxs.x, aabb.maxs.y, aabb.maxs.z));
        MeshSolid { trimesh, topology, bounds, fingerprint, far: OnceLock::new() }
    }

    /// Whether `p` is at least `keep` outside the surface: the same answer
    /// as `surface_point(p).distance >= keep`, without searching the
    /// triangles where a closed mesh's [`FarField`] already knows.
    pub fn keeps_clear(&self, p: DVec3, keep: f64) -> bool {
        let far = self.far.get_or_init(|| {
            self.topology.sides.is_closed().then(|| {
                let (vertices, indices) = (self.trimesh.vertices(), self.trimesh.indices());
                let corner = |i: u32| {
                    let v = vertices[i as usize];
                    DVec3::new(v.x, v.y, v.z)
                };
                FarField::new(self.bounds, indices.iter().map(|t| t.map(corner)))
            })
        });
        if far.as_ref().and_then(|far| far.outside_by(p)).is_some_and(|by| by >= keep) {
            return true;
        }
        self.surface_point(p).distance >= keep
    }

    /// Signed distance from `p` (mesh coordinates; negative inside) and the
    /// outward direction there. A point on the surface gets its triangle's
    /// normal; a non-finite point reads as far outside.
    pub fn surface_point(&self, p: DVec3) -> SurfacePoint {
        if !p.is_finite() {
            return SurfacePoint { distance: f64::INFINITY, outward: DVec3::Y };
        }
        // Not solid: the nearest surface point even from inside.
        let (projection, (triangle, location)) = self.trimesh.project_local_point_and_get_location(to_parry(p), false);
        let nearest = DVec3::new(projection.point.x, projection.point.y, projection.point.z);
        let feature = match location {
            TrianglePointLocation::OnVertex(i) => Feature::Vertex(i as u8),
            TrianglePointLocation::OnEdge(i, _) => Feature::Edge(i as u8),
            TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => Feature::Face,
        };
        let pseudo_normal = self.pseudo_normal(triangle as usize, feature);
        let gap = p - nearest;
        let length = gap.length();
        let inside = gap.dot(pseudo_normal) <= 0.0;
        let outward = if length > 1e-12 {
            if inside { -gap / length } else { gap / length }
        } else {
            self.trimesh.triangle(triangle).normal().map_or(DVec3::Y, |n| DVec3::new(n.x, n.y, n.z))
        };
        SurfacePoint { distance: if inside { -length } else { length }, outward }
    }

    fn pseudo_normal(&self, triangle: usize, feature: Feature) -> DVec3 {
        let corner = |i: u32| {
            let v = self.trimesh.vertices()[i as usize];
            DVec3::new(v.x, v.y, v.z)
        };
        self.topology.sides.pseudo_normal(&corner, self.trimesh.indices(), triangle, feature)
    }

    /// The box around the vertices, in mesh coordinates.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.bounds
    }

    /// The vertices and triangles after welding and dropping, for drawing.
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

fn to_parry(v: DVec3) -> ParryVector {
    ParryVector::new(v.x, v.y, v.z)
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

/// A digest of the bits of every coordinate, and of the triangles'.
fn fingerprint(vertices: &[DVec3], triangles_digest: u64) -> u64 {
    let coordinates = vertices.iter().flat_map(|v| [v.x, v.y, v.z].map(f64::to_bits));
    digest(coordinates.chain([triangles_digest]))
}

/// FNV-1a over whole words, each word's high bits folded down after its
/// multiply so that every bit reaches the next.
fn digest(words: impl Iterator<Item = u64>) -> u64 {
    words.fold(0xcbf2_9ce4_8422_2325, |hash: u64, word| {
        let hash = (hash ^ word).wrapping_mul(0x0100_0000_01b3);
        hash ^ (hash >> 32)
    })
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

    /// A sphere of radius 0.5: `n` bands from pole to pole, 2n around,
    /// wound outwards.
    fn sphere(n: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let around = 2 * n;
        let mut vertices = vec![DVec3::Y * 0.5, -DVec3::Y * 0.5];
        for band in 1..n {
            let polar = std::f64::consts::PI * f64::from(band) / f64::from(n);
            for k in 0..around {
                let azimuth = std::f64::consts::TAU * f64::from(k) / f64::from(around);
                vertices.push(0.5 * DVec3::new(polar.sin() * azimuth.cos(), polar.cos(), -polar.sin() * azimuth.sin()));
            }
        }
        let at = |band: u32, k: u32| 2 + (band - 1) * around + k % around;
        let mut triangles = Vec::new();
        for k in 0..around {
            triangles.push([0, at(1, k), at(1, k + 1)]);
            triangles.push([1, at(n - 1, k + 1), at(n - 1, k)]);
            for band in 1..n - 1 {
                triangles.push([at(band, k), at(band + 1, k), at(band + 1, k + 1)]);
                triangles.push([at(band, k), at(band + 1, k + 1), at(band, k + 1)]);
            }
        }
        (vertices, triangles)
    }

    /// Points spread through the box ±0.9.
    fn probes() -> impl Iterator<Item = DVec3> {
        (0..4000).map(|i| {
            let t = f64::from(i) * 0.618_034;
            DVec3::new(t.sin(), (1.7 * t).cos(), (2.3 * t + 0.4).sin()) * 0.9
        })
    }

    #[test]
    fn a_moved_solid_answers_as_one_built_where_it_was_moved_to() {
        let (vertices, triangles) = sphere(24);
        let rest = MeshSolid::new(&vertices, &triangles).unwrap();
        assert!(rest.topology.sides.is_closed());
        // Bent and squashed: a pose far from the first build's.
        let bent: Vec<DVec3> = vertices.iter().map(|v| DVec3::new(v.x + 0.6 * v.y * v.y, 0.7 * v.y, v.z)).collect();
        let moved = rest.moved_to(&bent).unwrap();
        let fresh = MeshSolid::new(&bent, &triangles).unwrap();
        assert_eq!(moved, fresh, "the same vertices and triangles");
        assert_eq!(moved.bounds(), fresh.bounds());
        for p in probes() {
            let (a, b) = (moved.surface_point(p), fresh.surface_point(p));
            assert!(
                (a.distance - b.distance).abs() < 1e-12 && a.outward.abs_diff_eq(b.outward, 1e-9),
                "{p}: {a:?} {b:?}"
            );
        }
        // Moving it back gives the first solid's answers, whatever came between.
        let back = moved.moved_to(&vertices).unwrap();
        assert_eq!(back, rest);
        assert!(probes().all(|p| back.surface_point(p) == rest.moved_to(&vertices).unwrap().surface_point(p)));
        assert_eq!(
            rest.moved_to(&bent[1..]).unwrap_err(),
            MeshSolidError::VertexCount { given: bent.len() - 1, expected: bent.len() }
        );
    }

    #[test]
    fn keeps_clear_says_what_the_distance_says_closed_or_not() {
        let (vertices, triangles) = sphere(32);
        let open: Vec<[u32; 3]> = triangles[8..].to_vec();
        for (name, triangles) in [("closed", &triangles), ("open", &open)] {
            let solid = MeshSolid::new(&vertices, triangles).unwrap();
            assert_eq!(solid.topology.sides.is_closed(), name == "closed");
            for keep in [0.0, 0.003, 0.05] {
                for p in probes() {
                    let distance = solid.surface_point(p).distance;
                    assert_eq!(solid.keeps_clear(p, keep), distance >= keep, "{name}, {p} at {distance} for {keep}");
                }
            }
        }
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
