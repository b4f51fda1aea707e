//! The catenary: a thread of given arc length hanging between two pins under
//! gravity along −Y.
//!
//! In the vertical plane through the pins the thread is
//! `y(x) = a·cosh((x − x₀)/a) + c`. Internally the curve is kept as the
//! dimensionless hyperbolic arguments `u = (x − x₀)/a` at the pins, which stay
//! bounded in both limits `a → ∞` (nearly taut) and `a → 0` (very slack), so
//! every point is computed without overflow or cancellation. All math is `f64`;
//! no input panics (see [`Catenary::new`] and [`CatenaryKind`]).

use glam::DVec3;

/// Above this `r − 1` (with `r = √(L² − v²)/h`) the pins count as vertically
/// aligned: the catenary then differs from the doubled vertical thread by
/// about `h ≤ L·1e-12`, and its hyperbolic arguments would grow without bound.
const MAX_RATIO_M1: f64 = 1e12;

/// Bound on `|artanh(v/L)|` (the pin slopes) as `|v| → L`; only reachable with
/// subnormal lengths, since `L − |v|` is at least one ulp of `L` otherwise.
const MAX_T: f64 = 40.0;

/// The form a [`Catenary`] takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CatenaryKind {
    /// A straight segment from start to end: the length is at most the chord,
    /// an input is not finite, or the slack is below `f64` resolution.
    Taut,
    /// A proper catenary in the vertical plane through the pins.
    Hanging,
    /// The pins are coincident or (nearly) above one another: the slack hangs
    /// as a doubled vertical thread whose lowest point is `(y_P + y_Q − L)/2`.
    Vertical,
}

/// A thread of fixed arc length hanging from `start` to `end` (Y up, metres).
#[derive(Clone, Debug)]
pub struct Catenary {
    start: DVec3,
    end: DVec3,
    length_m: f64,
    form: Form,
}

#[derive(Clone, Copy, Debug)]
enum Form {
    Taut,
    Vertical,
    Hanging(Hanging),
}

/// The hanging curve in dimensionless form; `λ ∈ [0, 1]` is the horizontal
/// fraction and `u(λ) = u_start + 2ξλ`.
#[derive(Clone, Copy, Debug)]
struct Hanging {
    /// `h / L`.
    eta: f64,
    /// `ξ = h / 2a`, half the span of `u`.
    xi: f64,
    /// `u` at the start pin: `artanh(v/L) − ξ`.
    u_start: f64,
    sinh_start: f64,
    cosh_start: f64,
    /// `sinh(u_end) − sinh(u_start) = L / a`.
    sinh_span: f64,
    /// The catenary parameter `a` in metres.
    a: f64,
}

impl Catenary {
    /// Thread of arc length `length_m` hanging from `start` to `end`.
    ///
    /// - `length_m` ≤ chord (including zero and negative), or any non-finite
    ///   input (NaN or infinite pins or length), gives a taut straight segment.
    /// - Coincident pins, or pins whose horizontal distance is below about
    ///   `1e-12·√(L² − v²)` (`v` the rise from start to end), give the doubled
    ///   vertical thread ([`CatenaryKind::Vertical`]); the catenary is within
    ///   about that distance of it there, so the switch is continuous.
    /// - Very slack threads (e.g. `1e4·chord`) stay finite everywhere.
    /// - Otherwise a catenary; it tends continuously to the straight segment
    ///   as the length tends to the chord.
    pub fn new(start: DVec3, end: DVec3, length_m: f64) -> Catenary {
        Catenary { start, end, length_m, form: classify(start, end, length_m) }
    }

    /// The start pin, exactly as given.
    pub fn start(&self) -> DVec3 {
        self.start
    }

    /// The end pin, exactly as given.
    pub fn end(&self) -> DVec3 {
        self.end
    }

    /// The requested length (the thread's actual length is max(length, chord)).
    ///
    /// Returned as given, even when negative or not finite.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    /// True when length ≤ chord: the thread is a straight segment.
    ///
    /// Also true for non-finite inputs and for slack below `f64` resolution;
    /// same as `kind() == CatenaryKind::Taut`.
    pub fn is_taut(&self) -> bool {
        matches!(self.form, Form::Taut)
    }

    /// Which form the thread takes.
    pub fn kind(&self) -> CatenaryKind {
        match self.form {
            Form::Taut => CatenaryKind::Taut,
            Form::Vertical => CatenaryKind::Vertical,
            Form::Hanging(_) => CatenaryKind::Hanging,
        }
    }

    /// The catenary parameter `a` in metres (radius of curvature at the
    /// vertex), or `None` when taut (`a = ∞`) or vertical (`a → 0`).
    pub fn parameter_m(&self) -> Option<f64> {
        match self.form {
            Form::Hanging(c) => Some(c.a),
            _ => None,
        }
    }

    /// Point at arc-length fraction s ∈ [0,1] (clamped; NaN → 0) from start.
    /// s=0 is exactly start, s=1 exactly end (bit-exact).
    ///
    /// When taut this is the linear fraction along the segment; when vertical
    /// it walks straight down from start to the lowest point, then up to end,
    /// with x and z interpolated by `s`. Points are non-finite only when a pin is.
    pub fn point_at_arc_fraction(&self, s: f64) -> DVec3 {
        if s.is_nan() || s <= 0.0 {
            return self.start;
        }
        if s >= 1.0 {
            return self.end;
        }
        match self.form {
            Form::Taut => self.start * (1.0 - s) + self.end * s,
            Form::Vertical => self.vertical_point(s),
            Form::Hanging(c) => self.hanging_point_at_arc(&c, s),
        }
    }

    /// Point at fraction f ∈ [0,1] of the horizontal distance from start
    /// (clamped; NaN → 0). f=0 is exactly start, f=1 exactly end.
    ///
    /// When the pins are vertically aligned or coincident
    /// ([`CatenaryKind::Vertical`]) the horizontal fraction is meaningless and
    /// this falls back to [`Self::point_at_arc_fraction`]; when taut both
    /// fractions agree.
    pub fn point_at_horizontal_fraction(&self, f: f64) -> DVec3 {
        match self.form {
            Form::Hanging(c) if f > 0.0 && f < 1.0 => self.hanging_point(&c, f),
            _ => self.point_at_arc_fraction(f),
        }
    }

    /// The lowest point of the thread (start or end if the vertex of the curve
    /// lies outside the span).
    ///
    /// When taut, the lower pin (start on ties); when vertical, the bottom of
    /// the doubled thread at `(y_P + y_Q − L)/2`.
    pub fn lowest_point(&self) -> DVec3 {
        let lower_pin = if self.end.y < self.start.y { self.end } else { self.start };
        match self.form {
            Form::Taut => lower_pin,
            Form::Vertical => {
                let down = 0.5 * self.length_m - 0.5 * (self.end.y - self.start.y);
                self.vertical_point(down / self.length_m)
            }
            Form::Hanging(c) => {
                // The vertex is at u = 0.
                let lambda = -c.u_start / (2.0 * c.xi);
                if lambda <= 0.0 || lambda >= 1.0 {
                    return lower_pin;
                }
                let p = self.hanging_point(&c, lambda);
                // Rounding may put a vertex right next to a pin a hair above it.
                if p.y > lower_pin.y { lower_pin } else { p }
            }
        }
    }

    fn vertical_point(&self, s: f64) -> DVec3 {
        let length = self.length_m;
        // Arc length from start down to the bottom: (L − v)/2 > 0 as L > |v|.
        let down = 0.5 * length - 0.5 * (self.end.y - self.start.y);
        let y = if s * length <= down { self.start.y - s * length } else { self.end.y - (1.0 - s) * length };
        let xz = self.start * (1.0 - s) + self.end * s;
        DVec3::new(xz.x, y, xz.z)
    }

    /// The point at arc fraction `s ∈ (0, 1)` with one square root and one
    /// logarithm: the height comes from `sinh u` and `cosh u` directly.
    fn hanging_point_at_arc(&self, c: &Hanging, s: f64) -> DVec3 {
        let d = s * c.sinh_span;
        let sinh_u = c.sinh_start + d;
        let cosh_u = (1.0 + sinh_u * sinh_u).sqrt();
        let lambda = c.lambda_at_arc(d, sinh_u, cosh_u);
        // a·(cosh u − cosh u_start) = a·(sinh²u − sinh²u_start)/(cosh u + cosh u_start)
        // with a·(sinh u − sinh u_start) = s·L: no cancellation beyond the
        // genuine zero of sinh u + sinh u_start, and no overflow as a → ∞.
        let y = s * self.length_m * ((sinh_u + c.sinh_start) / (cosh_u + c.cosh_start));
        let dir = self.end - self.start;
        DVec3::new(self.start.x + dir.x * lambda, self.start.y + y, self.start.z + dir.z * lambda)
    }

    fn hanging_point(&self, c: &Hanging, lambda: f64) -> DVec3 {
        let half = c.xi * lambda;
        // a·(cosh u − cosh u_start) = 2a·sinh(mid)·sinh(half), written with
        // sinh(half)/half so that a → ∞ neither overflows nor cancels.
        let y = self.length_m * (c.eta * lambda * (c.u_start + half).sinh() * sinhc(half));
        let d = self.end - self.start;
        DVec3::new(self.start.x + d.x * lambda, self.start.y + y, self.start.z + d.z * lambda)
    }
}

impl Hanging {
    /// Horizontal fraction where `sinh(u) = sinh(u_start) + d` (`d = s·L/a` at
    /// arc fraction `s`), given `sinh u` and `cosh u`.
    fn lambda_at_arc(&self, d: f64, sinh_u: f64, cosh_u: f64) -> f64 {
        // tanh((u − u_start)/2) = (sinh u − sinh u_start)/(cosh u + cosh u_start):
        // no cancellation for small steps, unlike asinh(sinh_u) − u_start.
        let z = d / (cosh_u + self.cosh_start);
        let delta = if z < 0.5 {
            2.0 * z.atanh()
        } else {
            // atanh near 1 is ill-conditioned; here delta > 1 so the
            // difference is well-conditioned instead.
            asinh(sinh_u) - self.u_start
        };
        (delta / (2.0 * self.xi)).clamp(0.0, 1.0)
    }
}

fn classify(start: DVec3, end: DVec3, length: f64) -> Form {
    let d = end - start;
    let h = hypot(d.x, d.z);
    let v = d.y;
    let chord = hypot(h, v);
    // A finite chord implies finite pins (inf − inf is NaN).
    if !(chord.is_finite() && length.is_finite() && length > chord) {
        return Form::Taut;
    }
    if h == 0.0 {
        return Form::Vertical;
    }
    // Everything scaled by L, so huge lengths cannot overflow.
    let eta = h / length;
    let nu = v / length;
    // w² − η² = (L² − h² − v²)/L², subtracting the smaller square from
    // (L − m)(L + m)/L² for the larger leg m: L − m is exact when nearly taut.
    let slack2 = if v.abs() >= h {
        ((length - v.abs()) / length) * (1.0 + nu.abs()) - eta * eta
    } else {
        ((length - h) / length) * (1.0 + eta) - nu * nu
    };
    let w = (eta * eta + slack2).sqrt();
    let r_m1 = slack2 / (eta * (w + eta));
    if r_m1.is_nan() || r_m1 <= 0.0 {
        return Form::Taut;
    }
    if r_m1 > MAX_RATIO_M1 {
        return Form::Vertical;
    }
    let xi = solve_xi(r_m1);
    if xi.is_nan() || xi <= 0.0 {
        return Form::Taut;
    }
    // t = artanh(v/L), taken as asinh(ν/w) so that the curve ends exactly at
    // height v whatever the rounding in w; clamped as |v| → L.
    let t = asinh(nu / w).clamp(-MAX_T, MAX_T);
    let u_start = t - xi;
    // One exponential for both, of |u| so that e = expm1 + 1 cannot cancel;
    // |u_start| ≤ MAX_T + ξ stays far from overflow.
    let em1 = u_start.abs().exp_m1();
    let e = em1 + 1.0;
    Form::Hanging(Hanging {
        eta,
        xi,
        u_start,
        sinh_start: (0.5 * em1 * (1.0 + 1.0 / e)).copysign(u_start),
        cosh_start: 0.5 * (e + 1.0 / e),
        // L/a = 2ξ·L/h.
        sinh_span: 2.0 * xi / eta,
        a: h / (2.0 * xi),
    })
}

/// `asinh(x)` as `ln(1 + |x| + x²/(1 + √(1 + x²)))` with the sign of `x`,
/// without the `hypot` that `f64::asinh` spends where `x²` cannot overflow.
fn asinh(x: f64) -> f64 {
    let ax = x.abs();
    if ax < 1e150 { (ax + ax * ax / (1.0 + (1.0 + ax * ax).sqrt())).ln_1p().copysign(x) } else { x.asinh() }
}

/// `√(a² + b²)`: a plain square root where the squares can neither overflow
/// nor lose precision to underflow, `f64::hypot` otherwise.
fn hypot(a: f64, b: f64) -> f64 {
    let sum = a * a + b * b;
    if sum > 1e-280 && sum < 1e280 { sum.sqrt() } else { a.hypot(b) }
}

/// The positive root ξ of `sinh(ξ)/ξ = 1 + r_m1` (`r_m1 > 0`), to ~1e-15
/// relative: Newton on the convex increasing `sinh ξ/ξ − r` (on
/// `ln(sinh ξ/ξ) − ln r` where `sinh` would overflow), kept inside a shrinking
/// bracket and bisecting whenever a step would leave it. The initial guess is
/// within 2.3% everywhere, so one to four steps suffice.
fn solve_xi(r_m1: f64) -> f64 {
    let mut lo = 0.0_f64;
    // sinh(ξ)/ξ ≥ 1 + ξ²/6, so the root is at most √(6(r − 1)).
    let mut hi = (6.0 * r_m1).sqrt();
    let mut x = initial_xi(r_m1).min(hi);
    for _ in 0..200 {
        let (g, slope) = sinhc_residual(x, r_m1);
        if g == 0.0 {
            return x;
        }
        if g > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let step = -g / slope;
        // Newton converges quadratically (the error after a step is about
        // step²/ξ), so a step below 1e-8·ξ leaves an error below ~1e-16. Tested
        // before the bracket: a step below half an ulp would land on x itself.
        if step.abs() <= 1e-8 * x {
            return (x + step).clamp(lo, hi);
        }
        let mut next = x + step;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if hi - lo <= 1e-15 * hi {
            return next;
        }
        x = next;
    }
    x
}

/// Starting point for [`solve_xi`], within 2.3% of the root everywhere: the
/// series inversion `ξ² ≈ 6ρ − 1.8ρ² + (144/175)ρ³` (error O(ρ⁴)) for small
/// `ρ = r − 1`; above, the asymptotic `ξ − ln ξ = ln 2r` (from `sinh ξ ≈ e^ξ/2`)
/// by one Newton step from `ln 2r + ln ln 2r`.
fn initial_xi(r_m1: f64) -> f64 {
    if r_m1 < SERIES_UP_TO {
        return (r_m1 * (6.0 - r_m1 * (1.8 - r_m1 * (144.0 / 175.0)))).sqrt();
    }
    let l = (2.0 * (1.0 + r_m1)).ln();
    let x = l + l.ln();
    x - (x - x.ln() - l) / (1.0 - 1.0 / x)
}

/// Where the series guess and the asymptotic one are equally good (both 2.3%).
const SERIES_UP_TO: f64 = 0.9;

/// Residual of [`solve_xi`]'s equation at `x > 0` and its derivative: with
/// `sinh(x)/x − 1` by its series for small `x` (no cancellation), from one
/// exponential up to 20, and in logarithmic form beyond (no overflow).
fn sinhc_residual(x: f64, r_m1: f64) -> (f64, f64) {
    if x < 0.5 {
        let x2 = x * x;
        let slope =
            x * (1.0 / 3.0 + x2 * (1.0 / 30.0 + x2 * (1.0 / 840.0 + x2 * (1.0 / 45360.0 + x2 * (1.0 / 3991680.0)))));
        (sinhc_m1_small(x) - r_m1, slope)
    } else if x < 20.0 {
        let e = x.exp();
        let (sinh, cosh) = (0.5 * (e - 1.0 / e), 0.5 * (e + 1.0 / e));
        let sinhc = sinh / x;
        (sinhc - (1.0 + r_m1), (cosh - sinhc) / x)
    } else {
        (ln_sinhc(x) - r_m1.ln_1p(), d_ln_sinhc(x))
    }
}

/// `sinh(x)/x − 1` for `|x| < 0.5`, by its Taylor series (no cancellation).
fn sinhc_m1_small(x: f64) -> f64 {
    let x2 = x * x;
    x2 / 6.0 * (1.0 + x2 / 20.0 * (1.0 + x2 / 42.0 * (1.0 + x2 / 72.0 * (1.0 + x2 / 110.0 * (1.0 + x2 / 156.0)))))
}

/// `sinh(x)/x`, 1 at 0.
fn sinhc(x: f64) -> f64 {
    if x.abs() < 0.5 { 1.0 + sinhc_m1_small(x) } else { x.sinh() / x }
}

/// `ln(sinh(x)/x)` for `x ≥ 0`, accurate near 0 and without overflow for large `x`.
fn ln_sinhc(x: f64) -> f64 {
    if x < 0.5 {
        sinhc_m1_small(x).ln_1p()
    } else if x < 20.0 {
        (x.sinh() / x).ln()
    } else {
        x - std::f64::consts::LN_2 - x.ln() + (-(-2.0 * x).exp()).ln_1p()
    }
}

/// Derivative of [`ln_sinhc`]: `coth(x) − 1/x`.
fn d_ln_sinhc(x: f64) -> f64 {
    if x < 0.5 {
        let x2 = x * x;
        x * (1.0 / 3.0 - x2 * (1.0 / 45.0 - x2 * (2.0 / 945.0 - x2 * (1.0 / 4725.0))))
    } else if x < 20.0 {
        1.0 / x.tanh() - 1.0 / x
    } else {
        1.0 - 1.0 / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn v3(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    fn chord(c: &Catenary) -> f64 {
        c.start().distance(c.end())
    }

    fn horizontal(d: DVec3) -> f64 {
        d.x.hypot(d.z)
    }

    fn samples(c: &Catenary, n: usize) -> Vec<DVec3> {
        (0..=n).map(|i| c.point_at_arc_fraction(i as f64 / n as f64)).collect()
    }

    fn polyline_length(points: &[DVec3]) -> f64 {
        points.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    /// Root of sinh(ξ)/ξ = r by plain bisection, independent of the solver.
    fn bisect_xi(r: f64) -> f64 {
        let (mut lo, mut hi) = (1e-9_f64, 50.0_f64);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid.sinh() / mid > r {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        0.5 * (lo + hi)
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// Inputs covering every kind and degenerate case.
    fn all_cases() -> Vec<(DVec3, DVec3, f64)> {
        let p = v3(1.0, 2.0, 3.0);
        let q = v3(4.0, 1.0, -1.0);
        let ch = p.distance(q);
        let big = v3(1e300, -1e300, 1e300);
        vec![
            (v3(0.0, 0.0, 0.0), v3(2.0, 0.0, 0.0), 2.5),
            (p, q, 1.5 * ch),
            (p, q, ch),
            (p, q, 0.5 * ch),
            (p, q, 0.0),
            (p, q, -3.0),
            (p, q, ch * (1.0 + 1e-12)),
            (p, q, ch * (1.0 + 1e-9)),
            (p, q, ch * 1e4),
            (p, q, ch * 1e15),
            (v3(1.0, 2.0, 3.0), v3(1.0, 5.0, 3.0), 10.0),
            (v3(1.0, 5.0, 3.0), v3(1.0, 2.0, 3.0), 10.0),
            (v3(1.0, 1.0, 1.0), v3(1.0, 1.0, 1.0), 2.0),
            (v3(1.0, 1.0, 1.0), v3(1.0, 1.0, 1.0), 0.0),
            (v3(0.0, 0.0, 0.0), v3(1e-8, 1.0 - 1e-15, 0.0), 1.0),
            (v3(0.0, 0.0, 0.0), v3(1e-8, -(1.0 - 1e-15), 0.0), 1.0),
            (v3(0.0, 0.0, 0.0), v3(0.9e-12, 0.0, 0.0), 1.0),
            (v3(0.0, 0.0, 0.0), v3(1.1e-12, 0.0, 0.0), 1.0),
            (v3(0.0, 0.0, 0.0), v3(1e-300, 0.0, 1e-300), 1e-290),
            (p, q, f64::NAN),
            (p, q, f64::INFINITY),
            (p, q, f64::NEG_INFINITY),
            (-big, big, 1.0),
            (big, big + v3(1e285, 0.0, 0.0), 2e285),
            (v3(0.0, 0.0, 0.0), v3(1e150, 1e150, 0.0), 1e300),
        ]
    }

    #[test]
    fn closed_form_symmetric_span() {
        let c = Catenary::new(v3(0.0, 0.0, 0.0), v3(2.0, 0.0, 0.0), 2.5);
        assert_eq!(c.kind(), CatenaryKind::Hanging);
        let a = c.parameter_m().unwrap();
        // h/2a = 1/a solves sinh(ξ)/ξ = 1.25.
        let a_ref = 1.0 / bisect_xi(1.25);
        assert!(rel(a, a_ref) < 1e-12, "{a} vs {a_ref}");
        assert!(rel(2.0 * a * (1.0 / a).sinh(), 2.5) < 1e-12);
        let low = c.lowest_point();
        let sag = -low.y;
        assert!(rel(sag, a_ref * ((1.0 / a_ref).cosh() - 1.0)) < 1e-12);
        assert!((low.x - 1.0).abs() < 1e-12 && low.z == 0.0);

        // Off-axis, raised and in other regimes: the same closed forms.
        for (h, l) in [(10.0, 10.001), (10.0, 100.0), (3.0, 3.0 * (1.0 + 1e-9))] {
            let dir = v3(0.6, 0.0, -0.8);
            let p = v3(5.0, 7.0, -2.0);
            let c = Catenary::new(p, p + dir * h, l);
            let a = c.parameter_m().unwrap();
            let xi = h / (2.0 * a);
            assert!(rel(2.0 * a * xi.sinh(), l) < 1e-12);
            // Loose: the test's bisection on sinh(ξ)/ξ itself loses digits as ξ → 0.
            assert!(rel(xi, bisect_xi(l / h)) < 1e-6);
            // 2a·sinh²(ξ/2) is a(cosh ξ − 1) without cancellation.
            let sag = 2.0 * a * (0.5 * xi).sinh().powi(2);
            // Absolute slack for the rounding of p.y in the test's own subtraction.
            let err = (p.y - c.lowest_point().y - sag).abs();
            assert!(err <= 1e-12 * sag + 4.0 * f64::EPSILON * p.y.abs(), "{h} {l}: {err}");
        }
    }

    #[test]
    fn solver_across_regimes() {
        for e in -150..=120 {
            let r_m1 = 10f64.powf(e as f64 / 10.0);
            let xi = solve_xi(r_m1);
            assert!(xi > 0.0 && xi.is_finite());
            if xi < 700.0 {
                assert!(rel(xi.sinh() / xi, 1.0 + r_m1) < 1e-14, "{r_m1}: {xi}");
            }
            if r_m1 < 1e-8 {
                // sinh(ξ)/ξ − 1 = ξ²/6·(1 + ξ²/20 + …).
                let x2 = xi * xi;
                assert!(rel(x2 / 6.0 * (1.0 + x2 / 20.0), r_m1) < 1e-14, "{r_m1}: {xi}");
            }
        }
    }

    #[test]
    fn nearly_taut_sag_matches_asymptote() {
        // sag ≈ h·√(3ε/8) for L = h(1 + ε).
        for eps in [1e-12, 1e-9, 1e-6] {
            let c = Catenary::new(v3(0.0, 0.0, 0.0), v3(4.0, 0.0, 0.0), 4.0 * (1.0 + eps));
            let sag = -c.lowest_point().y;
            assert!(rel(sag, 4.0 * (3.0 * eps / 8.0).sqrt()) < 1e-3, "{eps}: {sag}");
        }
    }

    #[test]
    fn arc_fraction_is_arc_length() {
        let n = 2000;
        let cases = [
            (v3(0.0, 0.0, 0.0), v3(3.0, 1.0, 4.0), 7.0),
            (v3(1.0, 2.0, 3.0), v3(-2.0, -5.0, 1.0), 1.5 * 62f64.sqrt()),
            (v3(0.0, 0.0, 0.0), v3(1.0, 10.0, 0.0), 10.1),
            (v3(0.0, 0.0, 0.0), v3(1.0, -10.0, 0.0), 10.1),
            (v3(0.0, 0.0, 0.0), v3(2.0, 10.0, 1.0), 10.3),
            (v3(0.0, 0.0, 0.0), v3(5.0, 1.0, 0.0), 5.1 * (1.0 + 1e-9)),
        ];
        for (p, q, l) in cases {
            let c = Catenary::new(p, q, l);
            assert_eq!(c.kind(), CatenaryKind::Hanging);
            let a = c.parameter_m().unwrap();
            let pts = samples(&c, n);
            let total = polyline_length(&pts);
            assert!(rel(total, l) < 1e-6, "{p} {q} {l}: {total}");
            // Each chord is shorter than its arc by about (κ·Δs)²/24.
            let ds = l / n as f64;
            let tol = (ds / a).powi(2) / 24.0 * 1.5 + 1e-9;
            for w in pts.windows(2) {
                let e = w[0].distance(w[1]) / ds - 1.0;
                assert!(e <= 1e-9 && e >= -tol, "{p} {q} {l}: spacing {e}");
            }
        }
    }

    #[test]
    fn horizontal_fraction_is_on_curve() {
        let cases = [
            (v3(0.0, 0.0, 0.0), v3(3.0, 1.0, 4.0), 7.0),
            (v3(0.0, 0.0, 0.0), v3(1.0, -10.0, 0.0), 10.1),
            (v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0), 1e4),
            (v3(0.0, 0.0, 0.0), v3(1.0, 0.5, 0.0), 1.2f64.sqrt() * (1.0 + 1e-12)),
        ];
        for (p, q, l) in cases {
            let c = Catenary::new(p, q, l);
            let h = horizontal(q - p);
            for i in 0..=100 {
                let f = i as f64 / 100.0;
                let x = c.point_at_horizontal_fraction(f);
                assert!((horizontal(x - p) - f * h).abs() <= 1e-12 * h);
            }
            for i in 0..=100 {
                let s = c.point_at_arc_fraction(i as f64 / 100.0);
                let x = c.point_at_horizontal_fraction(horizontal(s - p) / h);
                assert!(x.distance(s) <= 1e-9 * l, "{p} {q} {l}: {x} vs {s}");
            }
        }
        // Vertical pins fall back to the arc fraction.
        let c = Catenary::new(v3(0.0, 0.0, 0.0), v3(0.0, 1.0, 0.0), 3.0);
        assert_eq!(c.point_at_horizontal_fraction(0.3), c.point_at_arc_fraction(0.3));
    }

    #[test]
    fn endpoints_are_exact() {
        let same = |a: DVec3, b: DVec3| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits);
        for (p, q, l) in all_cases() {
            let c = Catenary::new(p, q, l);
            for s in [0.0, -0.0, -1.0, f64::NAN, f64::NEG_INFINITY] {
                assert!(same(c.point_at_arc_fraction(s), p), "{p} {q} {l} at {s}");
                assert!(same(c.point_at_horizontal_fraction(s), p));
            }
            for s in [1.0, 2.0, f64::INFINITY] {
                assert!(same(c.point_at_arc_fraction(s), q), "{p} {q} {l} at {s}");
                assert!(same(c.point_at_horizontal_fraction(s), q));
            }
            assert!(same(c.start(), p) && same(c.end(), q));
        }
    }

    #[test]
    fn every_case_is_finite_and_lowest_is_lowest() {
        for (p, q, l) in all_cases() {
            let c = Catenary::new(p, q, l);
            let low = c.lowest_point();
            assert!(low.is_finite(), "{p} {q} {l}");
            assert!(low.y <= p.y && low.y <= q.y, "{p} {q} {l}: {low}");
            for i in 0..=200 {
                let f = i as f64 / 200.0;
                let a = c.point_at_arc_fraction(f);
                let b = c.point_at_horizontal_fraction(f);
                assert!(a.is_finite() && b.is_finite(), "{p} {q} {l} at {f}: {a} {b} {:?}", c.form);
                assert!(a.y >= low.y - 1e-12 * (1.0 + low.y.abs()), "{p} {q} {l} at {f}: {a} {low} {:?}", c.form);
            }
        }
    }

    #[test]
    fn taut_cases() {
        let p = v3(1.0, 2.0, 3.0);
        let q = v3(4.0, 1.0, -1.0);
        let ch = p.distance(q);
        for l in [ch, 0.5 * ch, 0.0, -3.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let c = Catenary::new(p, q, l);
            assert!(c.is_taut() && c.kind() == CatenaryKind::Taut && c.parameter_m().is_none());
            let m = c.point_at_arc_fraction(0.25);
            assert!(m.distance(p.lerp(q, 0.25)) < 1e-12);
            assert_eq!(c.lowest_point(), q);
            assert_eq!(c.length_m().to_bits(), l.to_bits());
        }
    }

    #[test]
    fn non_finite_pins_do_not_panic() {
        let p = v3(1.0, 2.0, 3.0);
        for bad in [v3(f64::NAN, 0.0, 0.0), v3(0.0, f64::INFINITY, 0.0)] {
            for (a, b) in [(bad, p), (p, bad), (bad, bad)] {
                let c = Catenary::new(a, b, 10.0);
                assert!(c.is_taut());
                let _ = c.point_at_arc_fraction(0.5);
                let _ = c.point_at_horizontal_fraction(0.5);
                let _ = c.lowest_point();
            }
        }
    }

    #[test]
    fn vertical_and_coincident() {
        // Doubled thread: down 1 from start to y = −1, then up 2 to end.
        let c = Catenary::new(v3(0.0, 0.0, 0.0), v3(0.0, 1.0, 0.0), 3.0);
        assert_eq!(c.kind(), CatenaryKind::Vertical);
        assert_eq!(c.lowest_point(), v3(0.0, -1.0, 0.0));
        assert!((c.point_at_arc_fraction(0.25).y + 0.75).abs() < 1e-15);
        assert!((c.point_at_arc_fraction(0.5).y + 0.5).abs() < 1e-15);
        assert!((c.point_at_arc_fraction(0.75).y - 0.25).abs() < 1e-15);

        let c = Catenary::new(v3(1.0, 1.0, 1.0), v3(1.0, 1.0, 1.0), 2.0);
        assert_eq!(c.kind(), CatenaryKind::Vertical);
        assert_eq!(c.lowest_point(), v3(1.0, 0.0, 1.0));
        assert_eq!(c.point_at_arc_fraction(0.5), v3(1.0, 0.0, 1.0));
        assert_eq!(c.point_at_arc_fraction(0.75), v3(1.0, 0.5, 1.0));

        // Continuous across the hanging/vertical threshold.
        let below = Catenary::new(v3(0.0, 0.0, 0.0), v3(0.9e-12, 0.0, 0.0), 1.0);
        let above = Catenary::new(v3(0.0, 0.0, 0.0), v3(1.1e-12, 0.0, 0.0), 1.0);
        assert_eq!(below.kind(), CatenaryKind::Vertical);
        assert_eq!(above.kind(), CatenaryKind::Hanging);
        for i in 0..=100 {
            let s = i as f64 / 100.0;
            let d = below.point_at_arc_fraction(s).distance(above.point_at_arc_fraction(s));
            assert!(d < 1e-10, "{s}: {d}");
        }
    }

    #[test]
    fn very_slack_tends_to_doubled_thread() {
        let (p, q) = (v3(0.0, 0.0, 0.0), v3(1.0, 0.5, 0.0));
        let l = 1e4 * p.distance(q);
        let c = Catenary::new(p, q, l);
        assert_eq!(c.kind(), CatenaryKind::Hanging);
        // The vertex sits about a above the doubled thread's bottom.
        assert!((c.lowest_point().y - (p.y + q.y - l) / 2.0).abs() < 1.0);
        assert!(rel(polyline_length(&samples(&c, 100_000)), l) < 1e-4);
    }

    #[test]
    fn v_close_to_length() {
        let (p, q) = (v3(0.0, 0.0, 0.0), v3(1e-8, 1.0 - 1e-15, 0.0));
        let c = Catenary::new(p, q, 1.0);
        assert_eq!(c.kind(), CatenaryKind::Hanging);
        // a ≈ 1.4e-9: the hook at the start is far below the sample spacing, so
        // only bound the polyline: no chord longer than its arc, deficit < Δs.
        let n = 1000;
        let pts = samples(&c, n);
        assert!(pts.iter().all(|x| x.is_finite()));
        let ds = 1.0 / n as f64;
        assert!(pts.windows(2).all(|w| w[0].distance(w[1]) <= ds * (1.0 + 1e-9)));
        assert!(polyline_length(&pts) >= 1.0 - ds);
        // Continuous into the end pin.
        assert!(c.point_at_arc_fraction(1.0 - 1e-12).distance(q) < 1e-9);
    }

    #[test]
    fn continuous_into_taut() {
        let (p, q) = (v3(1.0, 2.0, 3.0), v3(4.0, 1.0, -1.0));
        let ch = p.distance(q);
        let dir = (q - p) / ch;
        for eps in [1e-16, 1e-15, 1e-12, 1e-9, 1e-6, 1e-3] {
            let c = Catenary::new(p, q, ch * (1.0 + eps));
            for i in 0..=100 {
                let x = c.point_at_arc_fraction(i as f64 / 100.0);
                let off = (x - p).reject_from_normalized(dir).length();
                assert!(off <= 2.0 * ch * eps.sqrt() + 1e-14, "{eps}: {off}");
            }
        }
    }

    proptest! {
        #[test]
        fn random_threads(
            p in prop::array::uniform3(-100.0..100.0f64),
            q in prop::array::uniform3(-100.0..100.0f64),
            k in 1.0..20.0f64,
        ) {
            let (p, q) = (DVec3::from_array(p), DVec3::from_array(q));
            let l = k * p.distance(q);
            let c = Catenary::new(p, q, l);
            let n = 500;
            let pts = samples(&c, n);
            prop_assert!(pts.iter().all(|x| x.is_finite()));
            prop_assert_eq!(pts[0], p);
            prop_assert_eq!(pts[n], q);
            prop_assert!((0..=n).all(|i| c.point_at_horizontal_fraction(i as f64 / n as f64).is_finite()));
            let actual = l.max(chord(&c));
            let ds = actual / n as f64;
            for w in pts.windows(2) {
                prop_assert!(w[0].distance(w[1]) <= ds * (1.0 + 1e-9));
            }
            // Polyline deficit: ≈ Δs²/24·∫κ² ≤ π·Δs²/(48a) when resolved;
            // never more than π²/8·Δs (total turning ≤ π).
            let resolved = c
                .parameter_m()
                .map_or(f64::INFINITY, |a| std::f64::consts::PI * ds * ds / (48.0 * a) * 1.5);
            let deficit = resolved.min(std::f64::consts::PI.powi(2) / 8.0 * ds).max(1e-4 * actual);
            let total = polyline_length(&pts);
            prop_assert!(total <= actual * (1.0 + 1e-9) && total >= actual - deficit,
                "{} vs {} ({:?})", total, actual, c.kind());
        }

        #[test]
        fn random_extreme_threads(
            p in prop::array::uniform3(-100.0..100.0f64),
            dir in prop::array::uniform3(-1.0..1.0f64),
            horizontal_exp in -16.0..0.0f64,
            slack_exp in -16.0..6.0f64,
        ) {
            // Near-vertical pins and lengths from barely slack to 1e6·chord.
            let p = DVec3::from_array(p);
            let d = DVec3::from_array(dir) * 100.0;
            let q = p + DVec3::new(d.x * 10f64.powf(horizontal_exp), d.y, d.z * 10f64.powf(horizontal_exp));
            let l = p.distance(q) * (1.0 + 10f64.powf(slack_exp));
            let c = Catenary::new(p, q, l);
            let n = 500;
            let pts = samples(&c, n);
            let actual = l.max(chord(&c));
            let ds = actual / n as f64;
            let low = c.lowest_point();
            prop_assert!(low.is_finite() && low.y <= p.y && low.y <= q.y);
            for w in pts.windows(2) {
                prop_assert!(w[0].is_finite());
                // Also checks the curve really ends at the pins.
                prop_assert!(w[0].distance(w[1]) <= ds * (1.0 + 1e-9) + 1e-12, "{:?}", c.kind());
                prop_assert!(w[0].y >= low.y - 1e-9 * actual);
            }
            let total = polyline_length(&pts);
            prop_assert!(total >= actual - std::f64::consts::PI.powi(2) / 8.0 * ds);
        }
    }
}
