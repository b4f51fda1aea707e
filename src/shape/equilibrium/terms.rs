//! The cloth's energy as a list of two-point terms: each keeps a pair of
//! grid points' distance `l` within `[min_m, max_m]` with a spring of
//! stiffness `k` outside it, energy ½·k·(l − clamp(l, min_m, max_m))².
//! Equal bounds make a plain spring (stretch), a finite range a dead zone
//! (shear), an infinite maximum a one-sided limit (bending).

use glam::DVec3;

/// One two-point term of the energy.
#[derive(Clone, Copy, Debug)]
pub(super) struct Term {
    pub(super) a: usize,
    pub(super) b: usize,
    pub(super) min_m: f64,
    pub(super) max_m: f64,
    /// Spring stiffness outside the range, in point weights per metre.
    pub(super) k: f64,
}

/// A term's 3 × 3 Hessian block `H_aa` (`H_bb` is the same, `H_ab` its negative).
pub(super) type Block = [[f64; 3]; 3];

impl Term {
    /// The distance this term pulls or pushes towards, if it is outside its range.
    #[inline]
    fn target(&self, l: f64) -> Option<f64> {
        if l > self.max_m {
            Some(self.max_m)
        } else if l < self.min_m {
            Some(self.min_m)
        } else {
            None
        }
    }

    #[inline]
    pub(super) fn energy(&self, x: &[DVec3]) -> f64 {
        let l = x[self.a].distance(x[self.b]);
        match self.target(l) {
            Some(c) => 0.5 * self.k * (l - c) * (l - c),
            None => 0.0,
        }
    }

    /// Where the term pulls: the unit direction from `b` to `a`, the
    /// distance and the distance it pulls towards (`None` inside the range
    /// or with the two points on one another).
    #[inline]
    fn stretch(&self, x: &[DVec3]) -> Option<(DVec3, f64, f64)> {
        let delta = x[self.a] - x[self.b];
        let l = delta.length();
        let c = self.target(l)?;
        (l > 0.0).then(|| (delta / l, l, c))
    }

    /// The energy's gradient with respect to point `a` (`b`'s is its negative).
    #[inline]
    pub(super) fn gradient(&self, x: &[DVec3]) -> Option<DVec3> {
        let (d, l, c) = self.stretch(x)?;
        Some(d * (self.k * (l - c)))
    }

    /// The Hessian block (`None` inside the range). With `definite`, the block's part
    /// across the pair (which is negative where the pair is closer than its
    /// target: a compressed spring buckles either way) is dropped, so every
    /// block is positive semi-definite (projected Newton).
    #[inline]
    pub(super) fn hessian(&self, x: &[DVec3], definite: bool) -> Option<Block> {
        let (d, l, c) = self.stretch(x)?;
        let across = 1.0 - c / l;
        let across = if definite { across.max(0.0) } else { across };
        let along = self.k * (1.0 - across);
        let mut hessian = [[0.0; 3]; 3];
        let d = d.to_array();
        for (r, row) in hessian.iter_mut().enumerate() {
            for (s, h) in row.iter_mut().enumerate() {
                *h = along * d[r] * d[s] + if r == s { self.k * across } else { 0.0 };
            }
        }
        Some(hessian)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient and Hessian match central differences of the energy.
    #[test]
    fn derivatives_match_finite_differences() {
        let terms = [
            Term { a: 0, b: 1, min_m: 1.0, max_m: 1.0, k: 3.0 },
            Term { a: 0, b: 1, min_m: 0.5, max_m: 0.9, k: 2.0 },
            Term { a: 0, b: 1, min_m: 1.6, max_m: f64::INFINITY, k: 5.0 },
        ];
        let x = [DVec3::new(0.1, 0.2, -0.3), DVec3::new(1.0, -0.1, 0.4)];
        let h = 1e-6;
        for term in terms {
            let (Some(gradient), Some(hessian)) = (term.gradient(&x), term.hessian(&x, false)) else {
                panic!("every test term is outside its range");
            };
            for axis in 0..3 {
                let shifted = |s: f64| {
                    let mut y = x;
                    y[0][axis] += s;
                    y
                };
                let numeric = (term.energy(&shifted(h)) - term.energy(&shifted(-h))) / (2.0 * h);
                assert!((numeric - gradient[axis]).abs() < 1e-6, "gradient {axis}: {numeric} vs {}", gradient);
                let (Some(up), Some(down)) = (term.gradient(&shifted(h)), term.gradient(&shifted(-h))) else {
                    panic!("a small shift keeps the term outside its range");
                };
                for other in 0..3 {
                    let numeric = (up[other] - down[other]) / (2.0 * h);
                    assert!((numeric - hessian[other][axis]).abs() < 1e-5, "hessian {other},{axis}");
                }
            }
        }
    }
}
