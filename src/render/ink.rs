//! The toon style's ink lines, found on the CPU each frame from the mesh and
//! the eye: the open border (an edge with one triangle), the silhouette (an
//! edge between a triangle facing the eye and one facing away) and creases
//! (an edge whose two faces' normals differ by more than a threshold).
//!
//! The edges and their triangles are worked out once per topology
//! ([`InkEdges::new`]); [`InkEdges::lines`] then costs one pass over the
//! triangles and one over the edges. The renderer draws the lines as
//! screen-space segments that the depth test hides behind the cloth.

use glam::Vec3;

/// Why an edge is inked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InkKind {
    /// The cloth's open boundary.
    Border,
    /// Between a triangle that faces the eye and one that faces away.
    Silhouette,
    /// The faces bend by more than the crease threshold.
    Crease,
}

/// One inked edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InkLine {
    pub a: Vec3,
    pub b: Vec3,
    pub kind: InkKind,
}

/// No second triangle: the edge is on the border.
const NONE: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Edge {
    a: u32,
    b: u32,
    first: u32,
    /// The other triangle, or [`NONE`].
    second: u32,
}

/// The edges of a triangle list with the (one or two) triangles on each,
/// and scratch space for the per-frame face normals.
#[derive(Clone, Debug, Default)]
pub struct InkEdges {
    /// What the edges were built from.
    indices: Vec<u32>,
    vertex_count: usize,
    edges: Vec<Edge>,
    normals: Vec<Vec3>,
}

impl InkEdges {
    /// The edges of the triangles `indices` (three per triangle) over
    /// `vertex_count` vertices. Triangles with an index out of range or a
    /// repeated vertex are left out; an edge shared by more than two
    /// triangles pairs the first two and leaves the others' sides as border.
    pub fn new(indices: &[u32], vertex_count: usize) -> InkEdges {
        let mut sides: Vec<(u32, u32, u32)> = Vec::with_capacity(indices.len());
        for (t, tri) in indices.chunks_exact(3).enumerate() {
            let [a, b, c] = [tri[0], tri[1], tri[2]];
            let usable = [a, b, c].iter().all(|&v| (v as usize) < vertex_count) && a != b && b != c && a != c;
            if !usable {
                continue;
            }
            for (p, q) in [(a, b), (b, c), (c, a)] {
                sides.push((p.min(q), p.max(q), t as u32));
            }
        }
        sides.sort_unstable();
        let mut edges = Vec::with_capacity(sides.len() / 2 + 1);
        let mut k = 0;
        while k < sides.len() {
            let (a, b, first) = sides[k];
            let paired = sides.get(k + 1).filter(|next| next.0 == a && next.1 == b);
            let second = paired.map_or(NONE, |next| next.2);
            edges.push(Edge { a, b, first, second });
            k += if paired.is_some() { 2 } else { 1 };
        }
        InkEdges { indices: indices.to_vec(), vertex_count, edges, normals: Vec::new() }
    }

    /// Whether these edges were built from `indices` over `vertex_count` vertices.
    pub fn is_for(&self, indices: &[u32], vertex_count: usize) -> bool {
        self.vertex_count == vertex_count && self.indices == indices
    }

    /// The inked edges of the triangles at `positions` seen from `eye`, into
    /// `out` (cleared first): every border edge, every silhouette edge, and
    /// every edge whose faces' normals differ by more than `crease_deg`
    /// (none at 180° or more, or NaN). An edge next to a degenerate triangle
    /// (no area) is inked only on the border. Positions must be the ones the
    /// edges were built for: with fewer, nothing is inked.
    pub fn lines(&mut self, positions: &[Vec3], eye: Vec3, crease_deg: f32, out: &mut Vec<InkLine>) {
        out.clear();
        if positions.len() != self.vertex_count {
            return;
        }
        self.normals.clear();
        self.normals.extend(self.indices.chunks_exact(3).map(|tri| {
            let at = |k: usize| positions.get(tri[k] as usize).copied().unwrap_or(Vec3::ZERO);
            (at(1) - at(0)).cross(at(2) - at(0))
        }));
        let creases = crease_deg < 180.0;
        let crease_cos = crease_deg.to_radians().cos();
        for edge in &self.edges {
            let (a, b) = (positions[edge.a as usize], positions[edge.b as usize]);
            let kind = if edge.second == NONE {
                Some(InkKind::Border)
            } else {
                let (n1, n2) = (self.normals[edge.first as usize], self.normals[edge.second as usize]);
                let (u1, u2) = (n1.normalize_or_zero(), n2.normalize_or_zero());
                if u1 == Vec3::ZERO || u2 == Vec3::ZERO {
                    None
                } else if (n1.dot(eye - a) > 0.0) != (n2.dot(eye - a) > 0.0) {
                    Some(InkKind::Silhouette)
                } else if creases && u1.dot(u2) < crease_cos {
                    Some(InkKind::Crease)
                } else {
                    None
                }
            };
            if let Some(kind) = kind {
                out.push(InkLine { a, b, kind });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use glam::DVec3;

    fn grid(cols: usize, rows: usize, at: impl Fn(usize, usize) -> DVec3) -> Mesh {
        let positions: Vec<DVec3> =
            (0..rows).flat_map(|j| (0..cols).map(move |i| (i, j))).map(|(i, j)| at(i, j)).collect();
        Mesh::from_grid(cols, rows, &positions)
    }

    fn ink(mesh: &Mesh, eye: Vec3, crease_deg: f32) -> Vec<InkLine> {
        let mut edges = InkEdges::new(&mesh.indices, mesh.positions.len());
        let mut out = Vec::new();
        edges.lines(&mesh.positions, eye, crease_deg, &mut out);
        out
    }

    fn count(lines: &[InkLine], kind: InkKind) -> usize {
        lines.iter().filter(|l| l.kind == kind).count()
    }

    #[test]
    fn a_flat_sheet_has_its_border_and_nothing_else() {
        let (cols, rows) = (5, 4);
        let mesh = grid(cols, rows, |i, j| DVec3::new(i as f64 * 0.1, -(j as f64) * 0.1, 0.0));
        for eye in [Vec3::new(0.2, -0.1, 3.0), Vec3::new(-1.0, 2.0, -3.0)] {
            let lines = ink(&mesh, eye, 0.0);
            assert_eq!(lines.len(), 2 * (cols - 1) + 2 * (rows - 1), "from {eye}");
            assert!(lines.iter().all(|l| l.kind == InkKind::Border));
        }
    }

    #[test]
    fn a_sheet_folded_ninety_degrees_has_its_fold() {
        // Flat in z = 0 up to column 2, then straight back along −z.
        let (cols, rows) = (5, 3);
        let mesh = grid(cols, rows, |i, j| {
            let y = -(j as f64) * 0.1;
            if i <= 2 { DVec3::new(i as f64 * 0.1, y, 0.0) } else { DVec3::new(0.2, y, -((i - 2) as f64) * 0.1) }
        });
        // From the front right: both halves face the eye.
        let lines = ink(&mesh, Vec3::new(2.0, 0.0, 2.0), 40.0);
        assert_eq!(count(&lines, InkKind::Silhouette), 0);
        let creases: Vec<&InkLine> = lines.iter().filter(|l| l.kind == InkKind::Crease).collect();
        assert_eq!(creases.len(), rows - 1, "the fold's edges, and no diagonal");
        assert!(creases.iter().all(|l| l.a.x == 0.2 && l.b.x == 0.2 && l.a.z == 0.0 && l.b.z == 0.0));
        // A threshold above the fold's 90°: no crease.
        assert_eq!(count(&ink(&mesh, Vec3::new(2.0, 0.0, 2.0), 95.0), InkKind::Crease), 0);
        // A threshold of 180° or NaN inks no crease either.
        assert_eq!(count(&ink(&mesh, Vec3::new(2.0, 0.0, 2.0), 180.0), InkKind::Crease), 0);
        assert_eq!(count(&ink(&mesh, Vec3::new(2.0, 0.0, 2.0), f32::NAN), InkKind::Crease), 0);
    }

    #[test]
    fn a_ridge_seen_past_one_slope_is_a_silhouette() {
        // A roof: rising along x to a ridge at column 2, falling after it.
        let (cols, rows) = (5, 3);
        let mesh = grid(cols, rows, |i, j| {
            let height = 0.2 - (i as f64 - 2.0).abs() * 0.1;
            DVec3::new(i as f64 * 0.1, height, j as f64 * 0.1)
        });
        // High above: both slopes face up, towards the eye. No creases asked for.
        let above = ink(&mesh, Vec3::new(0.2, 5.0, 0.1), 180.0);
        assert_eq!(count(&above, InkKind::Silhouette), 0);
        // Low on the left, below the far slope's plane: the near slope faces
        // the eye, the far one away, and the ridge is the silhouette.
        let low = ink(&mesh, Vec3::new(-3.0, 0.5, 0.1), 180.0);
        let silhouette: Vec<&InkLine> = low.iter().filter(|l| l.kind == InkKind::Silhouette).collect();
        assert_eq!(silhouette.len(), rows - 1);
        assert!(silhouette.iter().all(|l| (l.a.x - 0.2).abs() < 1e-6 && (l.b.x - 0.2).abs() < 1e-6));
    }

    #[test]
    fn bad_triangles_and_positions_never_panic() {
        let mut edges = InkEdges::new(&[0, 1, 2, 0, 1, 9, 3, 3, 1, 0], 4);
        let mut out = Vec::new();
        edges.lines(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE], Vec3::Z, 40.0, &mut out);
        assert_eq!(out.len(), 3, "one good triangle's three border edges");
        edges.lines(&[Vec3::ZERO], Vec3::Z, 40.0, &mut out);
        assert!(out.is_empty(), "positions for another mesh");
        // A degenerate (zero-area) triangle next to a good one: no silhouette or crease from it.
        let mut edges = InkEdges::new(&[0, 1, 2, 1, 0, 3], 4);
        edges.lines(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0], Vec3::Z, 0.0, &mut out);
        assert_eq!(count(&out, InkKind::Border), 4);
        assert_eq!(out.len(), 4);
    }
}
