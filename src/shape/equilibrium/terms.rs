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

/// A term's derivatives at the current positions: the gradient with
/// respect to point `a` (point `b`'s is its negative) and the 3 × 3 Hessian
/// block `H_aa` (`H_bb` is the same, `H_ab` its negative).
pub(super) struct Evaluated {
    pub(super) gradient_a: DVec3,
    pub(super) hessian: [[f64; 3]; 3],
}

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

    /// Gradient and Hessian block (`None` inside the range). With `definite`, the block's part
    /// across the pair (which is negative where the pair is closer than its
    /// target: a compressed spring buckles either way) is dropped, so every
    /// block is positive semi-definite (projected Newton).
    #[inline]
    pub(super) fn evaluate(&self, x: &[DVec3], definite: bool) -> Option<Evaluated> {
        let delta = x[self.a] - x[self.b];
        let l = delta.length();
        let c = self.target(l)?;
        if !(l > 0.0) {
            return None;
        }
        let d = delta / l;
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
        Some(Evaluated { gradient_a: DVec3::from_array(d) * (self.k * (l - c)), hessian })
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
            let Some(at) = term.evaluate(&x, false) else {
                panic!("every test term is outside its range");
            };
            for axis in 0..3 {
                let shifted = |s: f64| {
                    let mut y = x;
                    y[0][axis] += s;
                    y
                };
                let numeric = (term.energy(&shifted(h)) - term.energy(&shifted(-h))) / (2.0 * h);
                assert!(
                    (numeric - at.gradient_a[axis]).abs() < 1e-6,
                    "gradient {axis}: {numeric} vs {}",
                    at.gradient_a
                );
                let (Some(up), Some(down)) = (term.evaluate(&shifted(h), false), term.evaluate(&shifted(-h), false))
                else {
                    panic!("a small shift keeps the term outside its range");
                };
                for other in 0..3 {
                    let numeric = (up.gradient_a[other] - down.gradient_a[other]) / (2.0 * h);
                    assert!((numeric - at.hessian[other][axis]).abs() < 1e-5, "hessian {other},{axis}");
                }
            }
        }
    }
}
