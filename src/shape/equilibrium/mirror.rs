//! Mirror symmetry kept exactly. Where pins and start are mirror images
//! across a vertical plane (x or z constant) under a flip of the grid's
//! columns or rows, the problem is symmetric, but its equilibrium may be a
//! saddle between two buckled shapes; the factorisation's rounding is not
//! symmetric and would tip the cloth into one of them. Averaging every
//! step's points with their mirror images keeps the cloth on the shape its
//! symmetric start chose; the Newton steps are solved for one point of each
//! orbit (`orbits`), so they are symmetric to begin with.

use glam::DVec3;

/// One mirror: each point's partner and the plane `coordinate[axis] == centre`.
pub(super) struct Mirror {
    partner: Vec<usize>,
    axis: usize,
    centre: f64,
}

/// Largest mismatch, relative to the cloth's size, still taken as symmetric.
const SAME: f64 = 1e-9;

impl Mirror {
    /// The mirrors `positions` (pins and start) have, flipping columns or rows.
    pub(super) fn find(positions: &[DVec3], cols: usize, rows: usize, pinned: &[bool]) -> Vec<Mirror> {
        let size = positions.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max).max(1e-9);
        let flip_columns = |k: usize| (k / cols) * cols + (cols - 1 - k % cols);
        let flip_rows = |k: usize| (rows - 1 - k / cols) * cols + k % cols;
        let flips: [Vec<usize>; 2] =
            [(0..cols * rows).map(flip_columns).collect(), (0..cols * rows).map(flip_rows).collect()];
        let mut mirrors = Vec::new();
        for partner in flips {
            if (0..partner.len()).any(|k| pinned[k] != pinned[partner[k]]) {
                continue;
            }
            for axis in [0, 2] {
                let Some(first) = (0..partner.len()).find(|&k| pinned[k]) else { continue };
                let centre = 0.5 * (positions[first][axis] + positions[partner[first]][axis]);
                let mirror = Mirror { partner: partner.clone(), axis, centre };
                let matches = (0..partner.len())
                    .all(|k| positions[k].distance(mirror.reflect(positions[partner[k]])) <= SAME * size);
                if matches {
                    mirrors.push(mirror);
                    break;
                }
            }
        }
        mirrors
    }

    /// The point this mirror maps `point` onto.
    pub(super) fn partner(&self, point: usize) -> usize {
        self.partner[point]
    }

    pub(super) fn axis(&self) -> usize {
        self.axis
    }

    fn reflect(&self, mut p: DVec3) -> DVec3 {
        p[self.axis] = 2.0 * self.centre - p[self.axis];
        p
    }

    /// Makes the free points exact mirror images: each pair becomes the
    /// average of one and the other's reflection.
    pub(super) fn apply(&self, x: &mut [DVec3], pinned: &[bool]) {
        for k in 0..x.len() {
            let q = self.partner[k];
            if pinned[k] || q < k {
                continue;
            }
            if q == k {
                x[k][self.axis] = self.centre;
                continue;
            }
            let mean = 0.5 * (x[k] + self.reflect(x[q]));
            x[k] = mean;
            x[q] = self.reflect(mean);
        }
    }
}
