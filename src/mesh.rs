//! The cloth as a triangle mesh: positions, normals, UVs and indices of the grid.
//!
//! Vertex order is `j·cols + i` everywhere (mesh, OBJ, caches). Each grid quad
//! is split into two triangles wound counter-clockwise around the normal
//! `∂p/∂v × ∂p/∂u`, which for a curtain hanging in the XY plane (u along +X,
//! v down) points towards +Z.

use glam::{DVec3, Vec2, Vec3, Vec3A, Vec4};

/// A grid cloth ready to draw or export.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub cols: usize,
    pub rows: usize,
    pub positions: Vec<Vec3>,
    /// Unit vertex normals (area-weighted, see [`grid_normals`]); a vertex whose faces are all degenerate gets +Y.
    pub normals: Vec<Vec3>,
    /// `(i/(cols−1), j/(rows−1))`.
    pub uvs: Vec<Vec2>,
    /// Triangle list, two triangles per grid quad.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Builds the mesh of a `cols × rows` grid from its positions in vertex order.
    ///
    /// Panics if `positions.len() != cols·rows` or either side is below 2: those are
    /// programming errors, since every grid comes from a validated scene.
    pub fn from_grid(cols: usize, rows: usize, positions: &[DVec3]) -> Mesh {
        assert!(cols >= 2 && rows >= 2, "grid must be at least 2 × 2");
        assert_eq!(positions.len(), cols * rows, "positions must hold cols·rows points");
        let positions: Vec<Vec3> = positions.iter().map(|p| p.as_vec3()).collect();
        let indices = grid_triangle_indices(cols, rows);
        let mut normals = Vec::new();
        grid_normals(&positions, cols, rows, &mut normals);
        let uvs = grid_uvs(cols, rows);
        Mesh { cols, rows, positions, normals, uvs, indices }
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// Triangle indices of a `cols × rows` grid: quads (a b / c d) → (a c b), (b c d).
pub fn grid_triangle_indices(cols: usize, rows: usize) -> Vec<u32> {
    let mut indices = Vec::with_capacity((cols - 1) * (rows - 1) * 6);
    for j in 0..rows - 1 {
        for i in 0..cols - 1 {
            let a = (j * cols + i) as u32;
            let b = a + 1;
            let c = a + cols as u32;
            let d = c + 1;
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    indices
}

/// UVs `(i/(cols−1), j/(rows−1))` in vertex order.
pub fn grid_uvs(cols: usize, rows: usize) -> Vec<Vec2> {
    let mut uvs = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            uvs.push(Vec2::new(i as f32 / (cols - 1) as f32, j as f32 / (rows - 1) as f32));
        }
    }
    uvs
}

/// Unit vertex normals of a `cols × rows` grid, written into `out`: each
/// vertex sums the area vectors of the (up to four) grid quads around it —
/// a quad's from its diagonals, (c − b) × (d − a), which equals the sum of its
/// two triangles' for a flat quad — oriented as `∂p/∂v × ∂p/∂u`. A vertex whose
/// quads are all degenerate (or not finite) gets +Y rather than NaN.
pub fn grid_normals(positions: &[Vec3], cols: usize, rows: usize, out: &mut Vec<Vec3>) {
    assert_eq!(positions.len(), cols * rows, "positions must hold cols·rows points");
    out.clear();
    out.resize(cols * rows, Vec3::ZERO);
    if cols < 2 || rows < 2 {
        out.fill(Vec3::Y);
        return;
    }
    // Two rows of quad area vectors in flight (above and below the vertex
    // row); each vertex sums its up to four quads. SIMD vectors inside, and
    // the normalisation runs four normals per square root and division: this
    // runs on every frame, several times when waves follow the normals.
    let quads = cols - 1;
    let mut above = vec![Vec3A::ZERO; quads + 2];
    let mut below = vec![Vec3A::ZERO; quads + 2];
    let quad_row = |j: usize, row: &mut [Vec3A]| {
        let top = &positions[j * cols..(j + 1) * cols];
        let bottom = &positions[(j + 1) * cols..(j + 2) * cols];
        // row[0] and row[quads + 1] stay zero: the missing quads beyond the sides.
        for (area, (t, b)) in row[1..=quads].iter_mut().zip(top.windows(2).zip(bottom.windows(2))) {
            let (a, b1, c, d) = (Vec3A::from(t[0]), Vec3A::from(t[1]), Vec3A::from(b[0]), Vec3A::from(b[1]));
            *area = (c - b1).cross(d - a);
        }
    };
    out.clear();
    out.reserve(cols * rows);
    for j in 0..rows {
        std::mem::swap(&mut above, &mut below);
        if j + 1 < rows {
            quad_row(j, &mut below);
        } else {
            below.fill(Vec3A::ZERO);
        }
        let (up, down) = (&above, &below);
        // Vertex i touches quads i − 1 and i, stored at i and i + 1.
        for (upper, lower) in up.windows(2).zip(down.windows(2)) {
            out.push(Vec3::from(upper[0] + upper[1] + lower[0] + lower[1]));
        }
    }
    normalize_all(out);
}

/// Scales every vector to unit length, four at a time; a zero, tiny or
/// non-finite vector becomes +Y.
fn normalize_all(vectors: &mut [Vec3]) {
    let mut chunks = vectors.chunks_exact_mut(4);
    for chunk in &mut chunks {
        let length2 = Vec4::new(
            chunk[0].length_squared(),
            chunk[1].length_squared(),
            chunk[2].length_squared(),
            chunk[3].length_squared(),
        );
        let inverse = Vec4::ONE / length2.sqrt();
        for (k, v) in chunk.iter_mut().enumerate() {
            let (l2, inv) = (length2[k], inverse[k]);
            *v = if l2 > 0.0 && l2.is_finite() && inv.is_finite() { *v * inv } else { Vec3::Y };
        }
    }
    for v in chunks.into_remainder() {
        let length2 = v.length_squared();
        let inverse = 1.0 / length2.sqrt();
        *v = if length2 > 0.0 && length2.is_finite() && inverse.is_finite() { *v * inverse } else { Vec3::Y };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curtain(cols: usize, rows: usize) -> Vec<DVec3> {
        let mut p = Vec::new();
        for j in 0..rows {
            for i in 0..cols {
                p.push(DVec3::new(i as f64, -(j as f64), 0.0));
            }
        }
        p
    }

    #[test]
    fn flat_curtain_faces_plus_z() {
        let mesh = Mesh::from_grid(4, 3, &curtain(4, 3));
        assert_eq!(mesh.triangle_count(), 3 * 2 * 2);
        for n in &mesh.normals {
            assert!((*n - Vec3::Z).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn vertex_order_and_uvs() {
        let mesh = Mesh::from_grid(3, 2, &curtain(3, 2));
        assert_eq!(mesh.positions[1 * 3 + 2], Vec3::new(2.0, -1.0, 0.0));
        assert_eq!(mesh.uvs[1 * 3 + 2], Vec2::new(1.0, 1.0));
        assert_eq!(mesh.uvs[1], Vec2::new(0.5, 0.0));
        assert!(mesh.indices.iter().all(|&i| (i as usize) < 6));
    }

    #[test]
    fn normals_follow_a_folded_grid() {
        // One ridge along column 2: the flanks' normals tilt away from it.
        let mut p = curtain(5, 3);
        for (k, q) in p.iter_mut().enumerate() {
            q.z = if k % 5 == 2 { 1.0 } else { 0.0 };
        }
        let mesh = Mesh::from_grid(5, 3, &p);
        let middle = &mesh.normals[5..10];
        assert!((middle[2] - Vec3::Z).length() < 1e-6, "a symmetric ridge points straight out");
        assert!(middle[1].x < -0.3 && middle[3].x > 0.3, "{middle:?}");
    }

    #[test]
    fn grid_normals_match_triangle_area_weights_on_a_curved_sheet() {
        let (cols, rows) = (6, 5);
        let p: Vec<Vec3> = (0..cols * rows)
            .map(|k| {
                let (i, j) = ((k % cols) as f32, (k / cols) as f32);
                Vec3::new(i, -j, 0.1 * i * i - 0.05 * j * j)
            })
            .collect();
        let indices = grid_triangle_indices(cols, rows);
        let mut triangle_sum = vec![Vec3::ZERO; p.len()];
        for t in indices.chunks_exact(3) {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            let n = (p[b] - p[a]).cross(p[c] - p[a]);
            for v in [a, b, c] {
                triangle_sum[v] += n;
            }
        }
        let mut normals = Vec::new();
        grid_normals(&p, cols, rows, &mut normals);
        for (n, t) in normals.iter().zip(&triangle_sum) {
            assert!(n.dot(t.normalize()) > 0.99, "{n} vs {t}");
        }
    }

    #[test]
    fn collapsed_grid_gets_finite_normals() {
        let mesh = Mesh::from_grid(3, 3, &vec![DVec3::ZERO; 9]);
        assert!(mesh.normals.iter().all(|n| *n == Vec3::Y));
        let nan = Mesh::from_grid(2, 2, &vec![DVec3::NAN; 4]);
        assert!(nan.normals.iter().all(|n| n.is_finite()));
        let huge = Mesh::from_grid(
            3,
            2,
            &[DVec3::ZERO, DVec3::X * 1e30, DVec3::X * 2e30, -DVec3::Y, DVec3::Y * 1e30, DVec3::ONE],
        );
        assert!(huge.normals.iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5), "{:?}", huge.normals);
    }
}
