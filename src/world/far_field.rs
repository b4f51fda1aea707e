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

use glam::DVec3;

/// About how many cells the grid has: few enough to mark and fill in a
/// fraction of a millisecond for a posed body, many enough that a cloth
/// a few centimetres off the body is in clear cells.
const TARGET_CELLS: f64 = 65_536.0;

/// Unmarked cells around the box on every side, so the fill starts from
/// cells that are certainly outside.
const BORDER_CELLS: usize = 2;

pub struct FarField {
    /// The corner of cell (0, 0, 0).
    origin: DVec3,
    cell_m: f64,
    dims: [usize; 3],
    /// The mesh's box: a point outside it is outside the solid by at least
    /// its distance to it.
    bounds: (DVec3, DVec3),
    /// Per cell: reached from the edge through cells no triangle is near.
    clear: Vec<bool>,
}

impl FarField {
    /// The grid for `triangles` (corners as positions) inside `bounds`.
    pub fn new(bounds: (DVec3, DVec3), triangles: impl Iterator<Item = [DVec3; 3]>) -> FarField {
        let (lo, hi) = bounds;
        let extent = (hi - lo).max(DVec3::splat(1e-9));
        let cell_m = (extent.x * extent.y * extent.z / TARGET_CELLS).cbrt().max(extent.max_element() / 256.0);
        let border = DVec3::splat(cell_m * BORDER_CELLS as f64);
        let origin = lo - border;
        let span = extent + 2.0 * border;
        let dims = [span.x, span.y, span.z].map(|s| (s / cell_m).ceil() as usize + 1);
        let mut field = FarField { origin, cell_m, dims, bounds, clear: Vec::new() };
        let mut near = vec![false; dims[0] * dims[1] * dims[2]];
        for [a, b, c] in triangles {
            // The triangle's box, grown by a cell: every cell with a neighbour it touches.
            let (from, to) = (field.cell_of(a.min(b).min(c)), field.cell_of(a.max(b).max(c)));
            let from = from.map(|c| c.saturating_sub(1));
            let to: [usize; 3] = std::array::from_fn(|i| (to[i] + 1).min(dims[i] - 1));
            for z in from[2]..=to[2] {
                for y in from[1]..=to[1] {
                    let row = field.index([0, y, z]);
                    near[row + from[0]..=row + to[0]].fill(true);
                }
            }
        }
        field.clear = field.fill_from_edge(&near);
        field
    }

    /// A distance `p` is certainly outside the solid by, if it is. A clear
    /// cell's point is a cell's width from every marked cell; 1 % of it is
    /// left for rounding in finding the cell.
    pub fn outside_by(&self, p: DVec3) -> Option<f64> {
        let (lo, hi) = self.bounds;
        let off_box = (lo - p).max(p - hi).max(DVec3::ZERO).length();
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
        let cell = [at.x as usize, at.y as usize, at.z as usize];
        cell.iter().zip(&self.dims).all(|(c, d)| c < d) && self.clear[self.index(cell)]
    }

    /// The cell holding `p`, clamped into the grid.
    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let at = ((p - self.origin) / self.cell_m).max(DVec3::ZERO);
        let at = [at.x, at.y, at.z];
        std::array::from_fn(|axis| (at[axis] as usize).min(self.dims[axis] - 1))
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        x + self.dims[0] * (y + self.dims[1] * z)
    }

    /// The cells not `near` joined to the grid's edge by cells not `near`:
    /// outside, since no triangle comes between.
    fn fill_from_edge(&self, near: &[bool]) -> Vec<bool> {
        let [nx, ny, nz] = self.dims;
        let (sy, sz) = (nx, nx * ny);
        let mut reached = vec![false; near.len()];
        let mut todo: Vec<u32> = Vec::new();
        let visit = |i: usize, reached: &mut Vec<bool>, todo: &mut Vec<u32>| {
            if !near[i] && !reached[i] {
                reached[i] = true;
                todo.push(i as u32);
            }
        };
        // The six faces of the grid.
        for z in 0..nz {
            for y in 0..ny {
                for x in [0, nx - 1] {
                    visit(self.index([x, y, z]), &mut reached, &mut todo);
                }
            }
            for x in 0..nx {
                for y in [0, ny - 1] {
                    visit(self.index([x, y, z]), &mut reached, &mut todo);
                }
            }
        }
        for y in 0..ny {
            for x in 0..nx {
                for z in [0, nz - 1] {
                    visit(self.index([x, y, z]), &mut reached, &mut todo);
                }
            }
        }
        while let Some(i) = todo.pop() {
            let i = i as usize;
            let (x, y, z) = (i % nx, (i / sy) % ny, i / sz);
            if x > 0 {
                visit(i - 1, &mut reached, &mut todo);
            }
            if x + 1 < nx {
                visit(i + 1, &mut reached, &mut todo);
            }
            if y > 0 {
                visit(i - sy, &mut reached, &mut todo);
            }
            if y + 1 < ny {
                visit(i + sy, &mut reached, &mut todo);
            }
            if z > 0 {
                visit(i - sz, &mut reached, &mut todo);
            }
            if z + 1 < nz {
                visit(i + sz, &mut reached, &mut todo);
            }
        }
        reached
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
