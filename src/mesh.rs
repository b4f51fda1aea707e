//! The cloth as a triangle mesh: positions, normals, UVs and indices of the grid.
//!
//! Vertex order is `j·cols + i` everywhere (mesh, OBJ, caches). Each grid quad
//! is split into two triangles wound counter-clockwise around the normal
//! `∂p/∂v × ∂p/∂u`, which for a curtain hanging in the XY plane (u along +X,
//! v down) points towards +Z.

use glam::{DVec3, Vec2, Vec3, Vec4};

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

/// Points of a grid with x, y and z in separate arrays (vertex order
/// `j·cols + i`), so per-vertex loops are plain f32 arithmetic over slices
/// that the compiler turns into SIMD. The animation works on this form and
/// writes [`Mesh::positions`] once at the end.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointArrays {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
}

impl PointArrays {
    pub fn from_vec3s(points: &[Vec3]) -> PointArrays {
        let mut split = PointArrays::default();
        split.set_from_vec3s(points);
        split
    }

    /// Replaces the points with `points`, reusing the buffers.
    pub fn set_from_vec3s(&mut self, points: &[Vec3]) {
        for (axis, values) in [&mut self.x, &mut self.y, &mut self.z].into_iter().enumerate() {
            values.clear();
            values.extend(points.iter().map(|p| p[axis]));
        }
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    pub fn get(&self, k: usize) -> Vec3 {
        Vec3::new(self.x[k], self.y[k], self.z[k])
    }

    pub fn set(&mut self, k: usize, p: Vec3) {
        (self.x[k], self.y[k], self.z[k]) = (p.x, p.y, p.z);
    }
}

/// Unit vertex normals of a `cols × rows` grid, written into `out`; see
/// [`for_each_normal_row`] for how they are computed.
pub fn grid_normals(positions: &[Vec3], cols: usize, rows: usize, out: &mut Vec<Vec3>) {
    assert_eq!(positions.len(), cols * rows, "positions must hold cols·rows points");
    out.clear();
    out.reserve(cols * rows);
    let mut points = PointArrays::from_vec3s(positions);
    for_each_normal_row(&mut points, cols, rows, |_, [nx, ny, nz], _| {
        out.extend(nx.iter().zip(ny).zip(nz).map(|((&x, &y), &z)| Vec3::new(x, y, z)));
    });
}

/// Unit vertex normals of a `cols × rows` grid, one row at a time: calls
/// `row(j, normals, points)` for j = 0, 1, … with row j's normals and row j of
/// `points` (each as x, y, z slices `cols` long). Every normal is computed
/// from the points as they were on entry: row j is not read again after its
/// call, so `row` may move its points (a wave displacing the mesh along the
/// normals of its input) without a separate normal buffer.
///
/// Each vertex sums the area vectors of the (up to four) grid quads around
/// it — a quad's from its diagonals, (c − b) × (d − a), which equals the sum of
/// its two triangles' for a flat quad — oriented as `∂p/∂v × ∂p/∂u`. A vertex
/// whose quads are all degenerate (or not finite) gets +Y rather than NaN, and
/// so does every vertex of a grid with fewer than two columns or rows.
///
/// Panics if `points` does not hold `cols·rows` points.
pub fn for_each_normal_row(
    points: &mut PointArrays,
    cols: usize,
    rows: usize,
    mut row: impl FnMut(usize, [&[f32]; 3], [&mut [f32]; 3]),
) {
    let n = cols * rows;
    assert!(points.x.len() == n && points.y.len() == n && points.z.len() == n, "points must hold cols·rows points");
    let row_range = |j: usize| j * cols..(j + 1) * cols;
    if cols < 2 || rows < 2 {
        let (zeros, ones) = (vec![0.0f32; cols], vec![1.0f32; cols]);
        for j in 0..rows {
            let r = row_range(j);
            let [x, y, z] = [&mut points.x, &mut points.y, &mut points.z].map(|axis| &mut axis[r.clone()]);
            row(j, [&zeros, &ones, &zeros], [x, y, z]);
        }
        return;
    }
    // Called several times per frame, so everything is x, y, z slices that
    // vectorise. The sums run in a fixed order, so results do not depend on
    // how they were vectorised. Area vectors of the quads above and below the
    // current vertex row carry a zero quad on each side: vertex i touches
    // padded quads i and i + 1.
    let mut above = [vec![0.0f32; cols + 1], vec![0.0; cols + 1], vec![0.0; cols + 1]];
    let mut below = [vec![0.0f32; cols + 1], vec![0.0; cols + 1], vec![0.0; cols + 1]];
    let mut sum = [vec![0.0f32; cols], vec![0.0; cols], vec![0.0; cols]];
    for j in 0..rows {
        std::mem::swap(&mut above, &mut below);
        if j + 1 < rows {
            let (top, bottom) = (row_range(j), row_range(j + 1));
            let top = [&points.x[top.clone()], &points.y[top.clone()], &points.z[top]];
            let bottom = [&points.x[bottom.clone()], &points.y[bottom.clone()], &points.z[bottom]];
            quad_areas(top, bottom, &mut below);
        } else {
            below.iter_mut().for_each(|row| row.fill(0.0));
        }
        for axis in 0..3 {
            // Quads left and right of each vertex, as slices of equal length
            // so that the loop vectorises.
            let (up_left, up_right) = (&above[axis][..cols], &above[axis][1..=cols]);
            let (down_left, down_right) = (&below[axis][..cols], &below[axis][1..=cols]);
            for (i, total) in sum[axis].iter_mut().enumerate() {
                *total = (up_left[i] + up_right[i]) + (down_left[i] + down_right[i]);
            }
        }
        let [nx, ny, nz] = &mut sum;
        normalize_soa(nx, ny, nz);
        let r = row_range(j);
        let [x, y, z] = [&mut points.x, &mut points.y, &mut points.z].map(|axis| &mut axis[r.clone()]);
        row(j, [nx, ny, nz], [x, y, z]);
    }
}

/// Scales the vectors (xs[i], ys[i], zs[i]) to unit length, four per SIMD
/// step; a zero, tiny or non-finite vector becomes +Y.
fn normalize_soa(xs: &mut [f32], ys: &mut [f32], zs: &mut [f32]) {
    let unit = |x: Vec4, y: Vec4, z: Vec4| {
        let length2 = x * x + y * y + z * z;
        let inverse = Vec4::ONE / length2.sqrt();
        let infinity = Vec4::splat(f32::INFINITY);
        let good = length2.cmpgt(Vec4::ZERO) & length2.cmplt(infinity) & inverse.cmplt(infinity);
        (
            Vec4::select(good, x * inverse, Vec4::ZERO),
            Vec4::select(good, y * inverse, Vec4::ONE),
            Vec4::select(good, z * inverse, Vec4::ZERO),
        )
    };
    let n = xs.len();
    let whole = n / 4 * 4;
    for start in (0..whole).step_by(4) {
        let range = start..start + 4;
        let (x, y, z) = unit(
            Vec4::from_slice(&xs[range.clone()]),
            Vec4::from_slice(&ys[range.clone()]),
            Vec4::from_slice(&zs[range.clone()]),
        );
        x.write_to_slice(&mut xs[range.clone()]);
        y.write_to_slice(&mut ys[range.clone()]);
        z.write_to_slice(&mut zs[range]);
    }
    for k in whole..n {
        let (x, y, z) = unit(Vec4::splat(xs[k]), Vec4::splat(ys[k]), Vec4::splat(zs[k]));
        (xs[k], ys[k], zs[k]) = (x.x, y.x, z.x);
    }
}

/// Area vectors (c − b) × (d − a) of the quads between two grid rows given
/// as x, y, z slices (a, b the quad's top corners, c, d its bottom ones),
/// written to `areas[axis][1..cols]`; entries 0 and `cols` stay zero.
fn quad_areas(top: [&[f32]; 3], bottom: [&[f32]; 3], areas: &mut [Vec<f32>; 3]) {
    let n = top[0].len() - 1;
    // a, b, c, d of one coordinate of every quad, each n long, so the loop has
    // no bounds checks left to stop it vectorising.
    let corners = |axis: usize| (&top[axis][..n], &top[axis][1..=n], &bottom[axis][..n], &bottom[axis][1..=n]);
    let ((ax, bx, cx, dx), (ay, by, cy, dy), (az, bz, cz, dz)) = (corners(0), corners(1), corners(2));
    let [out_x, out_y, out_z] = areas;
    let (out_x, out_y, out_z) = (&mut out_x[1..=n], &mut out_y[1..=n], &mut out_z[1..=n]);
    for i in 0..n {
        let (ex, ey, ez) = (cx[i] - bx[i], cy[i] - by[i], cz[i] - bz[i]);
        let (fx, fy, fz) = (dx[i] - ax[i], dy[i] - ay[i], dz[i] - az[i]);
        out_x[i] = ey * fz - ez * fy;
        out_y[i] = ez * fx - ex * fz;
        out_z[i] = ex * fy - ey * fx;
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
