//! Which of the cloth's triangles (or edges) lie near a box: a uniform hash
//! grid over their bounding boxes, rebuilt from positions when needed.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec3;

use crate::mesh::grid_triangle_indices;

/// The grid's triangles as the mesh has them ([`grid_triangle_indices`]):
/// quad (i, j) gives (a, c, b) and (b, c, d) with a = (i, j), b = (i + 1, j),
/// c = (i, j + 1), d = (i + 1, j + 1).
pub fn grid_triangles(cols: usize, rows: usize) -> Vec<[u32; 3]> {
    grid_triangle_indices(cols, rows).chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
}

/// The grid's edges: rows, columns and each quad's b–c diagonal (the edges
/// of [`grid_triangles`]), each once.
pub fn grid_edges(cols: usize, rows: usize) -> Vec<[u32; 2]> {
    let mut edges = Vec::with_capacity(3 * cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            let a = (j * cols + i) as u32;
            if i + 1 < cols {
                edges.push([a, a + 1]);
            }
            if j + 1 < rows {
                edges.push([a, a + cols as u32]);
            }
            if i + 1 < cols && j + 1 < rows {
                edges.push([a + 1, a + cols as u32]);
            }
        }
    }
    edges
}

/// A multiply–rotate hash for cell coordinates and grid point indices: the
/// keys are small integers made here, not input an attacker picks, and the
/// default SipHash would be most of the cost of counting crossings.
#[derive(Default, Clone, Copy)]
pub(crate) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
        for &byte in chunks.remainder() {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_u64(&mut self, n: u64) {
        self.0 = (self.0.rotate_left(5) ^ n).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_usize(&mut self, n: usize) {
        self.write_u64(n as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// Items (triangles or edges, as vertex lists) hashed by the cells their
/// padded bounding boxes touch.
pub struct BoxGrid {
    cell_m: f64,
    cells: HashMap<[i64; 3], Vec<u32>, BuildHasherDefault<CellHasher>>,
    /// Per item, the last query that met it, so a query lists each once.
    seen: Vec<u32>,
    query: u32,
}

impl BoxGrid {
    /// Hashes `items` of `positions`, each box grown by `pad_m`, in cells of
    /// `cell_m` (positive). Items with a non-finite corner are left out.
    pub fn new<const K: usize>(positions: &[DVec3], items: &[[u32; K]], cell_m: f64, pad_m: f64) -> BoxGrid {
        let mut grid = BoxGrid { cell_m, cells: HashMap::default(), seen: vec![u32::MAX; items.len()], query: 0 };
        for (t, item) in items.iter().enumerate() {
            let corners = item.map(|k| positions[k as usize]);
            if !corners.iter().all(|p| p.is_finite()) {
                continue;
            }
            let lo = corners.iter().fold(DVec3::INFINITY, |m, p| m.min(*p)) - DVec3::splat(pad_m);
            let hi = corners.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p)) + DVec3::splat(pad_m);
            let Some((lo, hi)) = grid.cell_range(lo, hi) else { continue };
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        grid.cells.entry([x, y, z]).or_default().push(t as u32);
                    }
                }
            }
        }
        grid
    }

    /// Cells spanned by a box; `None` for a non-finite box or one spanning an
    /// absurd number of cells (only bad input makes those).
    fn cell_range(&self, lo: DVec3, hi: DVec3) -> Option<([i64; 3], [i64; 3])> {
        let cell = |p: DVec3| (p / self.cell_m).floor();
        let (lo, hi) = (cell(lo), cell(hi));
        let span = hi - lo;
        if !lo.is_finite() || !hi.is_finite() || span.max_element() > 64.0 {
            return None;
        }
        Some(([lo.x as i64, lo.y as i64, lo.z as i64], [hi.x as i64, hi.y as i64, hi.z as i64]))
    }

    /// Calls `visit` once for each item whose padded box may meet the box
    /// `lo..hi`.
    pub fn near(&mut self, lo: DVec3, hi: DVec3, visit: &mut dyn FnMut(u32)) {
        self.query = self.query.wrapping_add(1);
        if self.query == u32::MAX {
            self.seen.fill(u32::MAX);
            self.query = 0;
        }
        let Some((lo, hi)) = self.cell_range(lo, hi) else { return };
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let Some(list) = self.cells.get(&[x, y, z]) else { continue };
                    for &t in list {
                        if self.seen[t as usize] != self.query {
                            self.seen[t as usize] = self.query;
                            visit(t);
                        }
                    }
                }
            }
        }
    }
}
