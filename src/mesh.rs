//! The cloth as a triangle mesh: positions, normals, UVs and indices of the grid.
//!
//! Vertex order is `j·cols + i` everywhere (mesh, OBJ, caches). Each grid quad
//! is split into two triangles wound counter-clockwise around the normal
//! `∂p/∂v × ∂p/∂u`, which for a curtain hanging in the XY plane (u along +X,
//! v down) points towards +Z.

use glam::{DVec3, Vec2, Vec3};

/// A grid cloth ready to draw or export.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub cols: usize,
    pub rows: usize,
    pub positions: Vec<Vec3>,
    /// Unit vertex normals (area-weighted); a vertex whose faces are all degenerate gets +Y.
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
        let normals = vertex_normals(&positions, &indices);
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

/// Area-weighted vertex normals; degenerate neighbourhoods get +Y rather than NaN.
pub fn vertex_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        // Unnormalised cross product: weights each face by its area.
        let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    for n in &mut normals {
        *n = n.try_normalize().unwrap_or(Vec3::Y);
    }
    normals
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
    fn collapsed_grid_gets_finite_normals() {
        let mesh = Mesh::from_grid(3, 3, &vec![DVec3::ZERO; 9]);
        assert!(mesh.normals.iter().all(|n| *n == Vec3::Y));
        let nan = Mesh::from_grid(2, 2, &vec![DVec3::NAN; 4]);
        assert!(nan.normals.iter().all(|n| n.is_finite()));
    }
}
