//! The cloth as a triangle mesh: positions, normals, UVs and indices of the grid.
//!
//! Vertex order is `j·cols + i` everywhere (mesh, OBJ, caches). Each grid quad
//! is split into two triangles wound counter-clockwise around the normal
//! `∂p/∂v × ∂p/∂u`, which for a curtain hanging in the XY plane (u along +X,
//! v down) points towards +Z.
//!
//! The animation keeps points as [`PointArrays`] (x, y, z apart) and gets
//! their normals a row at a time from [`NormalRows`]; [`grid_normals`] is the
//! same computation for a plain list of positions.

use glam::{DVec3, Vec2, Vec3};

/// A grid cloth ready to draw or export. The default is the empty mesh
/// (0 × 0, no vertices): a buffer for the evaluator to fill.
#[derive(Clone, Debug, Default, PartialEq)]
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
/// writes [`Mesh::positions`] once at the end. The three arrays always hold
/// the same number of points.
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
/// [`NormalRows`] for how they are computed.
pub fn grid_normals(positions: &[Vec3], cols: usize, rows: usize, out: &mut Vec<Vec3>) {
    assert_eq!(positions.len(), cols * rows, "positions must hold cols·rows points");
    out.clear();
    out.reserve(cols * rows);
    let mut points = PointArrays::from_vec3s(positions);
    let mut walk = NormalRows::default();
    walk.start(cols, rows);
    while let Some((_, [nx, ny, nz], _)) = walk.next_row(&mut points) {
        out.extend(nx.iter().zip(ny).zip(nz).map(|((&x, &y), &z)| Vec3::new(x, y, z)));
    }
}

/// Unit vertex normals of a grid, one row at a time: after
/// [`NormalRows::start`], each [`NormalRows::next_row`] gives the next row's
/// normals together with that row of the points (x, y, z slices `cols`
/// long). Every normal is computed from the points as they were at the
/// start: a row is not read again once it has been handed out, so the caller
/// may move its points (a wave displacing the mesh along the normals of its
/// input) without a separate normal buffer. The scratch rows are kept
/// between walks.
///
/// Each vertex sums the area vectors of the (up to four) grid quads around
/// it — a quad's from its diagonals, (c − b) × (d − a), which equals the sum of
/// its two triangles' for a flat quad — oriented as `∂p/∂v × ∂p/∂u`. A vertex
/// whose quads are all degenerate (or not finite) gets +Y rather than NaN, and
/// so does every vertex of a grid with fewer than two columns or rows.
#[derive(Clone, Debug, Default)]
pub struct NormalRows {
    cols: usize,
    rows: usize,
    /// The row the next call hands out.
    next: usize,
    /// Area vectors of the quads above and below the current vertex row,
    /// with a zero quad on each side: vertex i touches padded quads i and i + 1.
    above: [Vec<f32>; 3],
    below: [Vec<f32>; 3],
    normals: [Vec<f32>; 3],
}

impl NormalRows {
    /// Starts a walk over a `cols × rows` grid from its first row.
    pub fn start(&mut self, cols: usize, rows: usize) {
        (self.cols, self.rows, self.next) = (cols, rows, 0);
        for row in self.above.iter_mut().chain(&mut self.below) {
            row.clear();
            row.resize(cols + 1, 0.0);
        }
        for (axis, row) in self.normals.iter_mut().enumerate() {
            row.clear();
            // Degenerate grids keep these: +Y everywhere.
            row.resize(cols, if axis == 1 { 1.0 } else { 0.0 });
        }
    }

    /// The next row j: (j, its unit normals, its points), or None after the
    /// last row. Panics if `points` does not hold `cols·rows` points; every
    /// call of one walk must pass the same points.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    pub fn next_row<'a>(
        &'a mut self,
        points: &'a mut PointArrays,
    ) -> Option<(usize, [&'a [f32]; 3], [&'a mut [f32]; 3])> {
        let (cols, rows, j) = (self.cols, self.rows, self.next);
        let n = cols * rows;
        assert!(points.x.len() == n && points.y.len() == n && points.z.len() == n, "points must hold cols·rows points");
        if j >= rows {
            return None;
        }
        self.next += 1;
        let row_range = |j: usize| j * cols..(j + 1) * cols;
        if cols >= 2 && rows >= 2 {
            // Plain f32 slices that vectorise; the sums run in a fixed order,
            // so results do not depend on how they were vectorised.
            std::mem::swap(&mut self.above, &mut self.below);
            if j + 1 < rows {
                let (top, bottom) = (row_range(j), row_range(j + 1));
                let top = [&points.x[top.clone()], &points.y[top.clone()], &points.z[top]];
                let bottom = [&points.x[bottom.clone()], &points.y[bottom.clone()], &points.z[bottom]];
                quad_areas(top, bottom, &mut self.below);
            } else {
                self.below.iter_mut().for_each(|row| row.fill(0.0));
            }
            let [nx, ny, nz] = &mut self.normals;
            sum_and_normalize(&self.above, &self.below, nx, ny, nz);
        }
        let [nx, ny, nz] = &self.normals;
        let r = row_range(j);
        let [x, y, z] = [&mut points.x, &mut points.y, &mut points.z].map(|axis| &mut axis[r.clone()]);
        Some((j, [nx, ny, nz], [x, y, z]))
    }
}

/// The unit normals of one vertex row from the area vectors of the padded
/// quads above and below it (vertex i touches quads i and i + 1 of each): their
/// sum, scaled to unit length; a zero, tiny or non-finite sum becomes +Y.
#[inline(always)]
fn sum_and_normalize(
    above: &[Vec<f32>; 3],
    below: &[Vec<f32>; 3],
    out_x: &mut [f32],
    out_y: &mut [f32],
    out_z: &mut [f32],
) {
    let cols = out_x.len();
    // Every operand a slice `cols` long and every output its own argument,
    // so the loop has no bounds or overlap checks and vectorises (square root
    // and division included, which are exact in any lane width).
    fn quads(areas: &[Vec<f32>; 3], shift: usize, cols: usize) -> [&[f32]; 3] {
        [0, 1, 2].map(|axis| &areas[axis][shift..shift + cols])
    }
    let ([ulx, uly, ulz], [urx, ury, urz]) = (quads(above, 0, cols), quads(above, 1, cols));
    let ([dlx, dly, dlz], [drx, dry, drz]) = (quads(below, 0, cols), quads(below, 1, cols));
    let (out_y, out_z) = (&mut out_y[..cols], &mut out_z[..cols]);
    for i in 0..cols {
        let x = (ulx[i] + urx[i]) + (dlx[i] + drx[i]);
        let y = (uly[i] + ury[i]) + (dly[i] + dry[i]);
        let z = (ulz[i] + urz[i]) + (dlz[i] + drz[i]);
        let length2 = x * x + y * y + z * z;
        let inverse = 1.0 / length2.sqrt();
        // A positive length2 keeps the inverse finite (at most about 2.7e22
        // for the smallest subnormal), so only length2 needs checking.
        let good = (length2 > 0.0) & (length2 < f32::INFINITY);
        out_x[i] = if good { x * inverse } else { 0.0 };
        out_y[i] = if good { y * inverse } else { 1.0 };
        out_z[i] = if good { z * inverse } else { 0.0 };
    }
}

/// Area vectors (c − b) × (d − a) of the quads between two grid rows given
/// as x, y, z slices (a, b the quad's top corners, c, d its bottom ones),
/// written to `areas[axis][1..cols]`; entries 0 and `cols` stay zero.
#[inline(always)]
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
        let (row, col) = (1, 2);
        assert_eq!(mesh.positions[row * 3 + col], Vec3::new(2.0, -1.0, 0.0));
        assert_eq!(mesh.uvs[row * 3 + col], Vec2::new(1.0, 1.0));
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
        let mesh = Mesh::from_grid(3, 3, &[DVec3::ZERO; 9]);
        assert!(mesh.normals.iter().all(|n| *n == Vec3::Y));
        let nan = Mesh::from_grid(2, 2, &[DVec3::NAN; 4]);
        assert!(nan.normals.iter().all(|n| n.is_finite()));
        let huge = Mesh::from_grid(
            3,
            2,
            &[DVec3::ZERO, DVec3::X * 1e30, DVec3::X * 2e30, -DVec3::Y, DVec3::Y * 1e30, DVec3::ONE],
        );
        assert!(huge.normals.iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5), "{:?}", huge.normals);
    }
}
