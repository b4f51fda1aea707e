//! A cloth mesh's GPU buffers: positions and normals rewritten in place each
//! frame; UVs, triangle and wireframe indices rebuilt only when the grid changes.

use crate::mesh::{Mesh, grid_triangle_indices, grid_uvs};

/// Triangles are wound so that this is the side their vertex normals point to
/// (checked against [`crate::mesh::grid_normals`] in a test).
pub const FRONT_FACE: wgpu::FrontFace = wgpu::FrontFace::Ccw;

pub struct GpuMesh {
    grid: (usize, usize),
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub uvs: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub wire_indices: wgpu::Buffer,
    pub wire_index_count: u32,
}

/// Structural edges of the grid as a line list: each row's and each column's neighbours.
pub fn grid_edge_indices(cols: usize, rows: usize) -> Vec<u32> {
    let mut indices = Vec::with_capacity(2 * (cols * (rows - 1) + rows * (cols - 1)));
    for j in 0..rows {
        for i in 0..cols {
            let a = (j * cols + i) as u32;
            if i + 1 < cols {
                indices.extend_from_slice(&[a, a + 1]);
            }
            if j + 1 < rows {
                indices.extend_from_slice(&[a, a + cols as u32]);
            }
        }
    }
    indices
}

impl GpuMesh {
    pub fn new(device: &wgpu::Device, mesh: &Mesh) -> GpuMesh {
        let vertex_buffer = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let init = |label, contents: &[u8], usage| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: contents.len() as u64,
                usage,
                mapped_at_creation: true,
            });
            buffer
                .get_mapped_range_mut(..)
                .expect("a buffer mapped at creation can be written")
                .copy_from_slice(contents);
            buffer.unmap();
            buffer
        };
        let (cols, rows) = (mesh.cols, mesh.rows);
        let vertex_bytes = (cols * rows * 12) as u64;
        let indices = grid_triangle_indices(cols, rows);
        let wire = grid_edge_indices(cols, rows);
        let uvs = grid_uvs(cols, rows);
        GpuMesh {
            grid: (cols, rows),
            positions: vertex_buffer("cloth positions", vertex_bytes),
            normals: vertex_buffer("cloth normals", vertex_bytes),
            uvs: init("cloth uvs", bytemuck::cast_slice(&uvs), wgpu::BufferUsages::VERTEX),
            indices: init("cloth indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX),
            index_count: indices.len() as u32,
            wire_indices: init("cloth wire indices", bytemuck::cast_slice(&wire), wgpu::BufferUsages::INDEX),
            wire_index_count: wire.len() as u32,
        }
    }

    /// Writes `mesh`'s positions and normals; rebuilds everything first when its grid differs.
    pub fn update(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, mesh: &Mesh) {
        if self.grid != (mesh.cols, mesh.rows) {
            *self = GpuMesh::new(device, mesh);
        }
        queue.write_buffer(&self.positions, 0, bytemuck::cast_slice(&mesh.positions));
        queue.write_buffer(&self.normals, 0, bytemuck::cast_slice(&mesh.normals));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn triangles_face_where_their_normals_point() {
        // A bumpy, tilted grid so no axis is special.
        let (cols, rows) = (5, 4);
        let positions: Vec<DVec3> = (0..rows)
            .flat_map(|j| {
                (0..cols).map(move |i| {
                    DVec3::new(i as f64 * 0.3, -(j as f64) * 0.25 + i as f64 * 0.05, (i * j) as f64 * 0.02)
                })
            })
            .collect();
        let mesh = Mesh::from_grid(cols, rows, &positions);
        for triangle in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[triangle[k] as usize]);
            // Counter-clockwise front faces: the front is along (b − a) × (c − a).
            let face = (b - a).cross(c - a);
            let front_is_ccw = FRONT_FACE == wgpu::FrontFace::Ccw;
            let sign = if front_is_ccw { 1.0 } else { -1.0 };
            assert!(sign * face.dot(mesh.normals[triangle[0] as usize]) > 0.0);
        }
    }

    #[test]
    fn edge_list_has_every_structural_edge_once() {
        let (cols, rows) = (4, 3);
        let edges = grid_edge_indices(cols, rows);
        assert_eq!(edges.len() / 2, cols * (rows - 1) + rows * (cols - 1));
        let mut seen = std::collections::HashSet::new();
        for pair in edges.chunks(2) {
            let (a, b) = (pair[0] as usize, pair[1] as usize);
            let (ai, aj, bi, bj) = (a % cols, a / cols, b % cols, b / cols);
            assert_eq!(ai.abs_diff(bi) + aj.abs_diff(bj), 1);
            assert!(seen.insert((a.min(b), a.max(b))));
        }
    }
}
