//! The energy's Hessian over the free points as a sparse upper triangle
//! (three unknowns a point), its pattern built once per pin set, its values
//! assembled from the terms' 3 × 3 blocks at every Newton step.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Par, Side};

use super::terms::{Block, Term};

/// Where a term's blocks go in the value array.
#[derive(Clone, Copy)]
struct Slots {
    /// Unknown of each end (`None` for a pin).
    a: Option<usize>,
    b: Option<usize>,
    /// Each end's step is its unknown's with these signs.
    sign_a: [f64; 3],
    sign_b: [f64; 3],
    /// Position of the lower-ranked end among the higher one's coupled points.
    pair: usize,
}

/// The pattern, its symbolic factorisation, and the factor's and the
/// workspace's memory, all reused from step to step.
pub(super) struct Hessian {
    unknowns: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Per free point, the lower-ranked free points it couples to, sorted.
    coupled: Vec<Vec<usize>>,
    slots: Vec<Slots>,
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    workspace: MemBuffer,
    pub(super) values: Vec<f64>,
}

/// The factorisation failed: the matrix is not positive definite.
pub(super) struct NotDefinite;

impl Hessian {
    /// The pattern for `terms` over `free` unknowns of three: point `v`
    /// moves as unknown `rank[v]` with the signs `sign[v]` (mirrored points
    /// share one).
    pub(super) fn new(rank: &[Option<usize>], sign: &[[f64; 3]], free: usize, terms: &[Term]) -> Hessian {
        let mut coupled: Vec<Vec<usize>> = vec![Vec::new(); free];
        let pairs = terms.iter().filter_map(|t| Some((rank[t.a]?, rank[t.b]?)));
        for (p, q) in pairs.filter(|(p, q)| p != q) {
            coupled[p.max(q)].push(p.min(q));
        }
        for list in &mut coupled {
            list.sort_unstable();
            list.dedup();
        }
        let unknowns = 3 * free;
        let mut col_ptr = Vec::with_capacity(unknowns + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (q, list) in coupled.iter().enumerate() {
            for beta in 0..3 {
                for &p in list {
                    row_idx.extend([3 * p, 3 * p + 1, 3 * p + 2]);
                }
                row_idx.extend((0..=beta).map(|alpha| 3 * q + alpha));
                col_ptr.push(row_idx.len());
            }
        }
        let slots = terms
            .iter()
            .map(|t| {
                let (a, b) = (rank[t.a], rank[t.b]);
                let pair = match (a, b) {
                    (Some(p), Some(q)) if p != q => {
                        let (lo, hi) = (p.min(q), p.max(q));
                        coupled[hi].binary_search(&lo).unwrap_or(0)
                    }
                    _ => 0,
                };
                Slots { a, b, sign_a: sign[t.a], sign_b: sign[t.b], pair }
            })
            .collect();
        let pattern = SymbolicSparseColMatRef::new_checked(unknowns, unknowns, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .expect("a symbolic factorisation of a grid's pattern");
        let workspace = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        let workspace = MemBuffer::new(workspace);
        let factor = vec![0.0; symbolic.len_val()];
        let values = vec![0.0; row_idx.len()];
        Hessian { unknowns, col_ptr, row_idx, coupled, slots, symbolic, factor, workspace, values }
    }

    pub(super) fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Index of entry (row `3p + alpha`, column `3q + beta`), `p < q`.
    #[inline]
    fn off_diagonal(&self, p: usize, q: usize, pair: usize, alpha: usize, beta: usize) -> usize {
        debug_assert!(p < q);
        self.col_ptr[3 * q + beta] + 3 * pair + alpha
    }

    /// Index of entry (row `3q + alpha`, column `3q + beta`), `alpha ≤ beta`.
    #[inline]
    fn diagonal(&self, q: usize, alpha: usize, beta: usize) -> usize {
        self.col_ptr[3 * q + beta] + 3 * self.coupled[q].len() + alpha
    }

    /// Adds term `index`'s blocks: `S_a·K·S_a` and `S_b·K·S_b` on the
    /// diagonal, `−S_a·K·S_b` between the ends (on the diagonal, with its
    /// transpose, where both ends are one unknown).
    pub(super) fn add(&mut self, index: usize, k: &Block) {
        let Slots { a, b, sign_a, sign_b, pair } = self.slots[index];
        let entries = || (0..3).flat_map(|alpha| (0..3).map(move |beta| (alpha, beta)));
        for (end, s) in [(a, sign_a), (b, sign_b)] {
            let Some(end) = end else { continue };
            for (alpha, beta) in entries().filter(|(alpha, beta)| alpha <= beta) {
                let at = self.diagonal(end, alpha, beta);
                self.values[at] += s[alpha] * s[beta] * k[alpha][beta];
            }
        }
        let (Some(p), Some(q)) = (a, b) else { return };
        if p == q {
            for (alpha, beta) in entries().filter(|(alpha, beta)| alpha <= beta) {
                let at = self.diagonal(p, alpha, beta);
                self.values[at] -= (sign_a[alpha] * sign_b[beta] + sign_b[alpha] * sign_a[beta]) * k[alpha][beta];
            }
            return;
        }
        let ((lo, sign_lo), (hi, sign_hi)) =
            if p < q { ((p, sign_a), (q, sign_b)) } else { ((q, sign_b), (p, sign_a)) };
        for (alpha, beta) in entries() {
            let at = self.off_diagonal(lo, hi, pair, alpha, beta);
            self.values[at] -= sign_lo[alpha] * sign_hi[beta] * k[alpha][beta];
        }
    }

    /// Adds a block on point `point`'s own unknown (with its mirror signs).
    pub(super) fn add_point(&mut self, unknown: usize, sign: [f64; 3], k: &Block) {
        for alpha in 0..3 {
            for beta in alpha..3 {
                let at = self.diagonal(unknown, alpha, beta);
                self.values[at] += sign[alpha] * sign[beta] * k[alpha][beta];
            }
        }
    }

    /// Adds the blocks of a site at `share` along term `index`'s pair (from
    /// `a` to `b`) whose own block is `k`: (1 − s)²·k, s²·k on the ends'
    /// diagonals and (1 − s)·s·k between them.
    pub(super) fn add_along(&mut self, index: usize, share: f64, k: &Block) {
        let Slots { a, b, sign_a, sign_b, pair } = self.slots[index];
        let (wa, wb) = (1.0 - share, share);
        let scaled = |w: f64| k.map(|row| row.map(|v| v * w));
        if let Some(p) = a {
            self.add_point(p, sign_a, &scaled(wa * wa));
        }
        if let Some(q) = b {
            self.add_point(q, sign_b, &scaled(wb * wb));
        }
        let (Some(p), Some(q)) = (a, b) else { return };
        let entries = || (0..3).flat_map(|alpha| (0..3).map(move |beta| (alpha, beta)));
        let w = wa * wb;
        if p == q {
            for (alpha, beta) in entries().filter(|(alpha, beta)| alpha <= beta) {
                let at = self.diagonal(p, alpha, beta);
                self.values[at] += w * (sign_a[alpha] * sign_b[beta] + sign_b[alpha] * sign_a[beta]) * k[alpha][beta];
            }
            return;
        }
        let ((lo, sign_lo), (hi, sign_hi)) =
            if p < q { ((p, sign_a), (q, sign_b)) } else { ((q, sign_b), (p, sign_a)) };
        for (alpha, beta) in entries() {
            let at = self.off_diagonal(lo, hi, pair, alpha, beta);
            self.values[at] += w * sign_lo[alpha] * sign_hi[beta] * k[alpha][beta];
        }
    }

    /// Adds `value` to the diagonal entry of unknown `q`'s coordinate `axis`.
    pub(super) fn add_diagonal(&mut self, q: usize, axis: usize, value: f64) {
        let at = self.diagonal(q, axis, axis);
        self.values[at] += value;
    }

    /// Adds `shift` to every diagonal entry (Levenberg–Marquardt).
    pub(super) fn shift_diagonal(&mut self, shift: f64) {
        for q in 0..self.coupled.len() {
            for alpha in 0..3 {
                let at = self.diagonal(q, alpha, alpha);
                self.values[at] += shift;
            }
        }
    }

    /// Largest diagonal entry, a scale for the shift.
    pub(super) fn largest_diagonal(&self) -> f64 {
        let mut largest: f64 = 0.0;
        for q in 0..self.coupled.len() {
            for alpha in 0..3 {
                largest = largest.max(self.values[self.diagonal(q, alpha, alpha)]);
            }
        }
        largest
    }

    /// Solves `H · x = rhs` in place.
    pub(super) fn solve(&mut self, rhs: &mut [f64]) -> Result<(), NotDefinite> {
        let pattern =
            SymbolicSparseColMatRef::new_checked(self.unknowns, self.unknowns, &self.col_ptr, None, &self.row_idx);
        let matrix = SparseColMatRef::new(pattern, &self.values);
        let llt = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                matrix,
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.workspace),
                Default::default(),
            )
            .map_err(|_| NotDefinite)?;
        let column = faer::MatMut::from_column_major_slice_mut(rhs, self.unknowns, 1);
        llt.solve_in_place_with_conj(Conj::No, column, Par::Seq, MemStack::new(&mut self.workspace));
        if rhs.iter().all(|v| v.is_finite()) { Ok(()) } else { Err(NotDefinite) }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::Problem;
    use super::*;
    use crate::shape::RelaxParams;

    /// `H · v` from the assembled upper triangle.
    fn multiply(h: &Hessian, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; v.len()];
        for col in 0..h.unknowns {
            for at in h.col_ptr[col]..h.col_ptr[col + 1] {
                let (row, value) = (h.row_idx[at], h.values[at]);
                out[row] += value * v[col];
                if row != col {
                    out[col] += value * v[row];
                }
            }
        }
        out
    }

    /// The assembled exact Hessian times a direction is the gradient's
    /// change along it: every term's blocks land in the right slots.
    #[test]
    fn the_assembled_hessian_is_the_gradients_derivative() {
        let (cols, rows) = (5, 4);
        let params = RelaxParams {
            rest_u_m: 0.1,
            rest_v_m: 0.12,
            stiffness: 1.0,
            thickness_m: 0.0,
            max_iterations: 10,
            tolerance: 1e-7,
        };
        let pinned: Vec<bool> = (0..cols * rows).map(|k| k == 0 || k == 3).collect();
        let x: Vec<DVec3> = (0..cols * rows)
            .map(|k| {
                let (i, j) = ((k % cols) as f64, (k / cols) as f64);
                DVec3::new(
                    0.09 * i + 0.01 * (3.0 * j).sin(),
                    -0.1 * j + 0.02 * (i * j).cos(),
                    0.03 * (i + 2.0 * j).sin(),
                )
            })
            .collect();
        let problem = Problem::new(cols, rows, &pinned, &params);
        let sign = vec![[1.0; 3]; cols * rows];
        let mut hessian = Hessian::new(&problem.rank, &sign, problem.free.len(), &problem.terms);
        let orbits = super::super::Orbits::new(&pinned, &[]);
        problem.assemble(&x, &mut hessian, &orbits, false);
        let unknowns = 3 * problem.free.len();
        let direction: Vec<f64> = (0..unknowns).map(|k| ((k * 7 + 3) % 11) as f64 / 11.0 - 0.5).collect();
        let shifted = |s: f64| {
            let mut y = x.clone();
            for (rank, &point) in problem.free.iter().enumerate() {
                y[point] += DVec3::new(direction[3 * rank], direction[3 * rank + 1], direction[3 * rank + 2]) * s;
            }
            y
        };
        let h = 1e-7;
        let (mut up, mut down) = (vec![0.0; unknowns], vec![0.0; unknowns]);
        problem.gradient(&shifted(h), &mut up);
        problem.gradient(&shifted(-h), &mut down);
        let product = multiply(&hessian, &direction);
        let scale = product.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for k in 0..unknowns {
            let numeric = (up[k] - down[k]) / (2.0 * h);
            assert!((numeric - product[k]).abs() < 1e-5 * scale, "entry {k}: {numeric} vs {}", product[k]);
        }
    }
}
