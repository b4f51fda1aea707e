//! Static Coulomb friction on the places resting on a collider. Where a
//! site first touches a surface it is anchored; moving it along the surface
//! away from its anchor by y costs μ·N·f₀(y), with N the normal force the
//! barrier presses it with and f₀ the smoothed absolute value of Li et al.'s
//! incremental potential contact (quadratic within [`STICK_M`], linear
//! beyond). The force it resists with is μ·N·f₀′(y) ≤ μ·N along the surface:
//! inside the friction cone while it sticks, on its edge once it slides.
//! N and the surface's normal are taken from the last step (lagged) and
//! brought up to date after every step, so at the answer the residual
//! weighs each site's friction with its own normal force.

use std::collections::BTreeMap;

use glam::DVec3;

use super::terms::Block;

/// How far a sticking site may creep before its friction is full (m).
pub(super) const STICK_M: f64 = 1e-4;

/// Where a site sticks and how hard it presses there.
#[derive(Clone, Copy, Debug)]
pub(super) struct Anchor {
    /// The site's place when it first touched (solve coordinates).
    pub(super) at: DVec3,
    /// The surface's outward direction and the normal force, at the last step.
    pub(super) normal: DVec3,
    pub(super) press: f64,
}

/// The anchors of one solve, by (site, obstacle).
#[derive(Default)]
pub(super) struct Friction {
    pub(super) coefficient: f64,
    /// Ordered, so sums over them are the same every run.
    pub(super) anchors: BTreeMap<(usize, usize), Anchor>,
}

impl Anchor {
    /// The site's slide from its anchor along the surface.
    #[inline]
    fn slide(&self, p: DVec3) -> DVec3 {
        let d = p - self.at;
        d - self.normal * d.dot(self.normal)
    }

    pub(super) fn energy(&self, coefficient: f64, p: DVec3) -> f64 {
        coefficient * self.press * f0(self.slide(p).length())
    }

    pub(super) fn gradient(&self, coefficient: f64, p: DVec3) -> DVec3 {
        let u = self.slide(p);
        coefficient * self.press * f1_over_y(u.length()) * u
    }

    /// The energy's Hessian for the site's position (semi-definite).
    pub(super) fn hessian(&self, coefficient: f64, p: DVec3) -> Block {
        let u = self.slide(p);
        let y = u.length();
        let scale = coefficient * self.press;
        let across = scale * f1_over_y(y);
        let along = scale * f1_slope(y);
        let unit = if y > 0.0 { u / y } else { DVec3::ZERO };
        let n = self.normal.to_array();
        let t = unit.to_array();
        let mut block = [[0.0; 3]; 3];
        for (r, row) in block.iter_mut().enumerate() {
            for (s, h) in row.iter_mut().enumerate() {
                let tangent = if r == s { 1.0 } else { 0.0 } - n[r] * n[s];
                *h = across * (tangent - t[r] * t[s]) + along * t[r] * t[s];
            }
        }
        block
    }
}

/// The smoothed |y|: y²/ε − y³/(3ε²) + ε/3 within ε, y beyond.
fn f0(y: f64) -> f64 {
    let e = STICK_M;
    if y >= e { y } else { y * y / e - y * y * y / (3.0 * e * e) + e / 3.0 }
}

/// f₀′(y) / y, finite at 0.
fn f1_over_y(y: f64) -> f64 {
    let e = STICK_M;
    if y >= e { 1.0 / y } else { 2.0 / e - y / (e * e) }
}

/// f₀″(y).
fn f1_slope(y: f64) -> f64 {
    let e = STICK_M;
    if y >= e { 0.0 } else { 2.0 / e - 2.0 * y / (e * e) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient and Hessian match differences of the energy, sticking and sliding.
    #[test]
    fn derivatives_match_finite_differences() {
        let anchor = Anchor { at: DVec3::new(0.1, 0.2, 0.3), normal: DVec3::new(0.0, 0.6, 0.8), press: 3.0 };
        for offset in [DVec3::new(3e-5, 1e-5, -2e-5), DVec3::new(4e-4, -1e-4, 2e-4)] {
            let p = anchor.at + offset;
            let h = 1e-8;
            let g = anchor.gradient(0.4, p);
            let k = anchor.hessian(0.4, p);
            for axis in 0..3 {
                let e = DVec3::from_array(std::array::from_fn(|i| if i == axis { h } else { 0.0 }));
                let numeric = (anchor.energy(0.4, p + e) - anchor.energy(0.4, p - e)) / (2.0 * h);
                assert!((numeric - g[axis]).abs() < 1e-5 * g.length().max(1e-3), "gradient {axis}");
                let change = (anchor.gradient(0.4, p + e) - anchor.gradient(0.4, p - e)) / (2.0 * h);
                for other in 0..3 {
                    let scale = k.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
                    assert!((change[other] - k[other][axis]).abs() < 1e-4 * scale, "hessian {other},{axis}");
                }
            }
            // Never more than μ·N along the surface.
            assert!(g.length() <= 0.4 * 3.0 * (1.0 + 1e-12));
        }
    }
}
