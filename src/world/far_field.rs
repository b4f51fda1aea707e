//! Where a closed mesh is certainly far outside: a coarse grid of cells
//! over its box, each marked "near" if the box around a triangle, grown by
//! a cell, touches it, and the cells not near reached from the grid's edge
//! without crossing a near one. A point in a reached cell is outside the
//! solid (no triangle lies between it and the edge) by at least a cell's
//! width, so a contact test can pass it without searching the triangles,
//! with the same answer.
//!
//! Only for closed meshes: through a hole the reached cells could run
//! inside, where the nearest triangle's side says "inside".
//!
//! A row of cells along x is one 64-bit word, so growing and filling work
//! a row at a time: a posed body's grid is made in a fraction of a
//! millisecond.

use glam::DVec3;

/// About how many cells the grid has (at most 64 along x): many enough
/// that a cloth a few centimetres off the body is in clear cells.
const TARGET_CELLS: f64 = 262_144.0;

/// Cells along x: one bit each in a row's word.
const ROW_CELLS: usize = 64;

/// Cells around the box on every side that no triangle reaches, so the
/// fill starts from cells that are certainly outside.
const BORDER_CELLS: usize = 2;

pub struct FarField {
    /// The corner of cell (0, 0, 0).
    origin: DVec3,
    cell_m: f64,
    dims: [usize; 3],
    /// The mesh's box: a point outside it is outside the solid by at least
    /// its distance to it.
    bounds: (DVec3, DVec3),
    /// Per row (y + ny · z), a bit per cell along x: reached from the edge
    /// through cells no triangle is near.
    clear: Vec<u64>,
}

impl FarField {
    /// The grid for `triangles` (corners as positions) inside `bounds`.
    pub fn new(bounds: (DVec3, DVec3), triangles: impl Iterator<Item = [DVec3; 3]>) -> FarField {
        let (lo, hi) = bounds;
        let extent = (hi - lo).max(DVec3::splat(1e-9));
        let cell_m = (extent.x * extent.y * extent.z / TARGET_CELLS)
            .cbrt()
            .max(extent.max_element() / 256.0)
            .max(extent.x / (ROW_CELLS - 2 * BORDER_CELLS - 2) as f64);
        let border = DVec3::splat(cell_m * BORDER_CELLS as f64);
        let origin = lo - border;
        let span = extent + 2.0 * border;
        let dims = [span.x, span.y, span.z].map(|s| (s / cell_m).ceil() as usize + 1);
        let dims = [dims[0].min(ROW_CELLS), dims[1], dims[2]];
        let mut field = FarField { origin, cell_m, dims, bounds, clear: Vec::new() };
        let [nx, ny, nz] = dims;
        let mut touched = vec![0u64; ny * nz];
        for [a, b, c] in triangles {
            let (from, to) = (field.cell_of(a.min(b).min(c)), field.cell_of(a.max(b).max(c)));
            let cells = span_bits(from[0], to[0]);
            for z in from[2]..=to[2] {
                for row in &mut touched[from[1] + ny * z..=to[1] + ny * z] {
                    *row |= cells;
                }
            }
        }
        let all = span_bits(0, nx - 1);
        let near = grown(&touched, [nx, ny, nz], all);
        let free: Vec<u64> = near.iter().map(|row| !row & all).collect();
        field.clear = reached_from_edge(&free, [nx, ny, nz]);
        field
    }

    /// A distance `p` is certainly outside the solid by, if it is. A clear
    /// cell's point is a cell's width from every marked cell; 1 % of it is
    /// left for rounding in finding the cell.
    pub fn outside_by(&self, p: DVec3) -> Option<f64> {
        let off_box = outside_box(self.bounds, p).length();
        let clear = self.clear_at(p).then_some(0.99 * self.cell_m);
        if off_box > 0.0 {
            return Some(off_box.max(clear.unwrap_or(0.0)));
        }
        clear
    }

    fn clear_at(&self, p: DVec3) -> bool {
        let at = (p - self.origin) / self.cell_m;
        if !(at.cmpge(DVec3::ZERO).all()) {
            return false;
        }
        let [x, y, z] = [at.x as usize, at.y as usize, at.z as usize];
        let [nx, ny, nz] = self.dims;
        x < nx && y < ny && z < nz && (self.clear[y + ny * z] >> x) & 1 == 1
    }

    /// The cell holding `p`, clamped into the grid.
    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let at = ((p - self.origin) / self.cell_m).max(DVec3::ZERO);
        let at = [at.x, at.y, at.z];
        std::array::from_fn(|axis| (at[axis] as usize).min(self.dims[axis] - 1))
    }
}

/// The offset from the box `bounds` to `p`, axis by axis (zero inside it):
/// its length is the distance to the box.
pub(super) fn outside_box((lo, hi): (DVec3, DVec3), p: DVec3) -> DVec3 {
    (lo - p).max(p - hi).max(DVec3::ZERO)
}

/// The bits `from..=to` of a row.
fn span_bits(from: usize, to: usize) -> u64 {
    let width = to + 1 - from;
    let ones = if width >= 64 { u64::MAX } else { (1u64 << width) - 1 };
    ones << from
}

/// `rows` grown by one cell along each axis in turn: each cell and its 26
/// neighbours (`all`: the bits of cells in the grid).
fn grown(rows: &[u64], [_, ny, nz]: [usize; 3], all: u64) -> Vec<u64> {
    let along_x: Vec<u64> = rows.iter().map(|&r| (r | r << 1 | r >> 1) & all).collect();
    let mut along_y = along_x.clone();
    for z in 0..nz {
        for y in 0..ny {
            let i = y + ny * z;
            if y > 0 {
                along_y[i] |= along_x[i - 1];
            }
            if y + 1 < ny {
                along_y[i] |= along_x[i + 1];
            }
        }
    }
    let mut along_z = along_y.clone();
    for z in 0..nz {
        for y in 0..ny {
            let i = y + ny * z;
            if z > 0 {
                along_z[i] |= along_y[i - ny];
            }
            if z + 1 < nz {
                along_z[i] |= along_y[i + ny];
            }
        }
    }
    along_z
}

/// The cells of `free` joined to the grid's edge through `free` cells,
/// sweeping the rows forward and back until nothing changes: the same
/// cells a flood fill reaches.
fn reached_from_edge(free: &[u64], [nx, ny, nz]: [usize; 3]) -> Vec<u64> {
    let ends = 1u64 | 1u64 << (nx - 1);
    let mut reached: Vec<u64> = (0..free.len())
        .map(|i| {
            let (y, z) = (i % ny, i / ny);
            let edge_row = y == 0 || z == 0 || y + 1 == ny || z + 1 == nz;
            free[i] & if edge_row { u64::MAX } else { ends }
        })
        .collect();
    // Spreads a row's reached cells along the row's free cells.
    let along = |mut row: u64, free: u64| loop {
        let next = (row | row << 1 | row >> 1) & free;
        if next == row {
            return row;
        }
        row = next;
    };
    let visit = |i: usize, reached: &mut [u64]| {
        let (y, z) = (i % ny, i / ny);
        let mut from = reached[i];
        if y > 0 {
            from |= reached[i - 1];
        }
        if y + 1 < ny {
            from |= reached[i + 1];
        }
        if z > 0 {
            from |= reached[i - ny];
        }
        if z + 1 < nz {
            from |= reached[i + ny];
        }
        let row = along(from & free[i], free[i]);
        let changed = row != reached[i];
        reached[i] = row;
        changed
    };
    loop {
        let mut changed = false;
        for i in 0..free.len() {
            changed |= visit(i, &mut reached);
        }
        for i in (0..free.len()).rev() {
            changed |= visit(i, &mut reached);
        }
        if !changed {
            return reached;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The twelve triangles of the box `lo`..`hi`.
    fn box_triangles(lo: DVec3, hi: DVec3) -> Vec<[DVec3; 3]> {
        let corner = |i: usize| {
            DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]].map(|t| t.map(corner))).collect()
    }

    #[test]
    fn far_outside_is_clear_and_inside_never_is() {
        let (lo, hi) = (DVec3::splat(-0.5), DVec3::splat(0.5));
        // A hollow box: a big one with a small one inside, which the fill cannot reach.
        let mut triangles = box_triangles(lo, hi);
        triangles.extend(box_triangles(DVec3::splat(-0.1), DVec3::splat(0.1)));
        let field = FarField::new((lo, hi), triangles.into_iter());
        assert_eq!(field.outside_by(DVec3::new(3.0, 0.0, 0.0)), Some(2.5));
        // Just off a face: near a marked cell, only as far as the box.
        assert!(field.outside_by(DVec3::new(0.0, 0.501, 0.0)).is_some_and(|by| (by - 0.001).abs() < 1e-12));
        assert_eq!(field.outside_by(DVec3::new(0.0, 0.499, 0.0)), None);
        // Inside, between the walls: never reached.
        assert_eq!(field.outside_by(DVec3::new(0.3, 0.3, 0.3)), None);
        assert_eq!(field.outside_by(DVec3::ZERO), None);
        // Every point it calls outside is farther than its bound from every face.
        for i in 0..2000 {
            let t = f64::from(i) * 0.618_034;
            let p = DVec3::new(t.sin(), (1.7 * t).cos(), (2.3 * t).sin()) * 0.9;
            let Some(by) = field.outside_by(p) else { continue };
            let distance = (lo - p).max(p - hi).max(DVec3::ZERO).length();
            assert!(distance >= by - 1e-12 && distance > 0.0, "{p} is only {distance} outside, said {by}");
        }
    }
}
