//! Easing curves: how a segment (between two keys, or two parameter keys)
//! moves from its start value (0) to its end value (1).
//!
//! Every curve maps 0 to exactly 0 and 1 to exactly 1, so keys are hit
//! exactly and segments join without a pop. Linear, Step, EaseIn, EaseOut,
//! EaseInOut and a Bézier whose y1, y2 lie in [0, 1] are monotone; Back,
//! Elastic and Bounce are the exaggeration curves and leave [0, 1] or turn
//! back on purpose.

use crate::scene::Ease;

/// Overshoot of the Back curve (the usual 10% "back" of animation packages).
const BACK_OVERSHOOT: f64 = 1.70158;
/// Elastic: oscillations before the curve settles, and how fast they die out.
const ELASTIC_CYCLES: f64 = 3.0;
const ELASTIC_DECAY: f64 = 6.0;

/// The eased fraction at `x` ∈ [0, 1] (the share of the segment's time that
/// has passed). `x` is clamped to [0, 1]; NaN counts as 0.
pub fn apply(ease: Ease, x: f64) -> f64 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    if x == 0.0 {
        return 0.0;
    }
    if x == 1.0 {
        return 1.0;
    }
    match ease {
        Ease::Linear => x,
        Ease::Step => 0.0,
        Ease::EaseIn => x * x * x,
        Ease::EaseOut => 1.0 - (1.0 - x).powi(3),
        Ease::EaseInOut => {
            if x < 0.5 {
                4.0 * x * x * x
            } else {
                1.0 - 4.0 * (1.0 - x).powi(3)
            }
        }
        Ease::Bezier(x1, y1, x2, y2) => cubic_bezier(x1, y1, x2, y2, x),
        Ease::Back => back_in_out(x),
        Ease::Elastic => elastic_out(x),
        Ease::Bounce => bounce_out(x),
    }
}

/// Anticipation and overshoot: dips below 0 at the start and passes 1 before
/// settling, each by about 10%.
fn back_in_out(x: f64) -> f64 {
    let c = BACK_OVERSHOOT * 1.525;
    if x < 0.5 {
        let y = 2.0 * x;
        y * y * ((c + 1.0) * y - c) / 2.0
    } else {
        let y = 2.0 * x - 2.0;
        (y * y * ((c + 1.0) * y + c) + 2.0) / 2.0
    }
}

/// Shoots past the target and oscillates into it; the oscillation dies
/// exactly at x = 1 so the next segment starts without a jump.
fn elastic_out(x: f64) -> f64 {
    let angle = std::f64::consts::TAU * ELASTIC_CYCLES * x;
    1.0 - angle.cos() * (-ELASTIC_DECAY * x).exp() * (1.0 - x)
}

/// Falls onto the target and bounces three times, each bounce lower.
fn bounce_out(x: f64) -> f64 {
    const N: f64 = 7.5625;
    const D: f64 = 2.75;
    if x < 1.0 / D {
        N * x * x
    } else if x < 2.0 / D {
        let y = x - 1.5 / D;
        N * y * y + 0.75
    } else if x < 2.5 / D {
        let y = x - 2.25 / D;
        N * y * y + 0.9375
    } else {
        let y = x - 2.625 / D;
        N * y * y + 0.984375
    }
}

/// CSS `cubic-bezier(x1, y1, x2, y2)` at time `x`: the curve from (0, 0) to
/// (1, 1) with control points (x1, y1), (x2, y2). x1 and x2 are clamped to
/// [0, 1] (validation rejects others), which makes x(s) monotone, so its
/// inverse is found by Newton steps with a bisection fallback.
fn cubic_bezier(x1: f64, y1: f64, x2: f64, y2: f64, x: f64) -> f64 {
    let (x1, x2) = (x1.clamp(0.0, 1.0), x2.clamp(0.0, 1.0));
    let s = bezier_parameter_at(x1, x2, x);
    bezier_component(y1, y2, s)
}

/// One coordinate of the curve at parameter s: 3(1−s)²s·c1 + 3(1−s)s²·c2 + s³.
fn bezier_component(c1: f64, c2: f64, s: f64) -> f64 {
    let r = 1.0 - s;
    3.0 * r * r * s * c1 + 3.0 * r * s * s * c2 + s * s * s
}

fn bezier_slope(c1: f64, c2: f64, s: f64) -> f64 {
    let r = 1.0 - s;
    3.0 * r * r * c1 + 6.0 * r * s * (c2 - c1) + 3.0 * s * s * (1.0 - c2)
}

/// The parameter s ∈ [0, 1] where the curve's x equals `x`, to ~1e-12.
fn bezier_parameter_at(x1: f64, x2: f64, x: f64) -> f64 {
    let mut s = x;
    for _ in 0..8 {
        let error = bezier_component(x1, x2, s) - x;
        if error.abs() < 1e-12 {
            return s;
        }
        let slope = bezier_slope(x1, x2, s);
        if slope.abs() < 1e-9 {
            break;
        }
        let next = s - error / slope;
        if !(0.0..=1.0).contains(&next) {
            break;
        }
        s = next;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if bezier_component(x1, x2, mid) < x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every easing, and a Bézier that overshoots both ways.
    fn all() -> impl Iterator<Item = Ease> {
        Ease::ALL.into_iter().chain([Ease::Bezier(0.3, -0.6, 0.7, 1.6)])
    }
    const MONOTONE: [Ease; 7] = [
        Ease::Linear,
        Ease::Step,
        Ease::EaseIn,
        Ease::EaseOut,
        Ease::EaseInOut,
        Ease::Bezier(0.42, 0.0, 0.58, 1.0),
        Ease::Bezier(0.0, 1.0, 1.0, 0.0),
    ];

    fn samples() -> impl Iterator<Item = f64> {
        (0..=1000).map(|k| k as f64 / 1000.0)
    }

    #[test]
    fn every_curve_hits_zero_and_one_exactly() {
        for ease in all() {
            assert_eq!(apply(ease, 0.0), 0.0, "{ease:?}");
            assert_eq!(apply(ease, 1.0), 1.0, "{ease:?}");
        }
    }

    #[test]
    fn monotone_curves_never_turn_back() {
        for ease in MONOTONE {
            let mut previous = 0.0;
            for x in samples() {
                let y = apply(ease, x);
                assert!(y >= previous - 1e-12, "{ease:?} falls at {x}: {y} < {previous}");
                assert!((0.0..=1.0).contains(&y), "{ease:?} leaves [0, 1] at {x}: {y}");
                previous = y;
            }
        }
    }

    #[test]
    fn curves_are_continuous_except_step() {
        for ease in all().filter(|e| *e != Ease::Step) {
            let mut previous = apply(ease, 0.0);
            for x in samples().skip(1) {
                let y = apply(ease, x);
                assert!((y - previous).abs() < 0.05, "{ease:?} jumps at {x}: {previous} → {y}");
                previous = y;
            }
        }
    }

    #[test]
    fn shapes_are_as_named() {
        assert_eq!(apply(Ease::Linear, 0.25), 0.25);
        assert_eq!(apply(Ease::Step, 0.999), 0.0, "holds until the next key");
        assert!(apply(Ease::EaseIn, 0.5) < 0.5, "slow start");
        assert!(apply(Ease::EaseOut, 0.5) > 0.5, "slow end");
        assert_eq!(apply(Ease::EaseInOut, 0.5), 0.5);
        assert!((apply(Ease::EaseIn, 0.5) - 0.125).abs() < 1e-15);
        let back: Vec<f64> = samples().map(|x| apply(Ease::Back, x)).collect();
        let (min, max) = back.iter().fold((0.0f64, 0.0f64), |(lo, hi), &y| (lo.min(y), hi.max(y)));
        assert!((-0.11..-0.09).contains(&min), "anticipation dips about 10%: {min}");
        assert!((1.09..1.11).contains(&max), "overshoot about 10%: {max}");
        assert!(samples().any(|x| apply(Ease::Elastic, x) > 1.1), "elastic overshoots");
        let bounce: Vec<f64> = samples().map(|x| apply(Ease::Bounce, x)).collect();
        let turns = bounce.windows(3).filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0).count();
        assert_eq!(turns, 6, "three bounces, each a fall and a rise");
        assert!(bounce.iter().all(|y| (0.0..=1.0).contains(y)));
    }

    #[test]
    fn bezier_matches_css_reference_values() {
        // CSS `ease` = cubic-bezier(0.25, 0.1, 0.25, 1): at x = 0.5 browsers give ≈ 0.8024.
        let y = apply(Ease::Bezier(0.25, 0.1, 0.25, 1.0), 0.5);
        assert!((y - 0.802_403_8).abs() < 1e-6, "{y}");
        // The diagonal control points give the identity.
        for x in samples() {
            assert!((apply(Ease::Bezier(0.3, 0.3, 0.7, 0.7), x) - x).abs() < 1e-9);
        }
        // Flat handles (x1 = 0 or x2 = 1) still invert x(s) to full precision.
        for x in samples() {
            let y = apply(Ease::Bezier(0.0, 0.0, 1.0, 1.0), x);
            assert!(y.is_finite() && (0.0..=1.0).contains(&y));
        }
    }

    #[test]
    fn out_of_range_and_nan_inputs_are_clamped() {
        for ease in all() {
            assert_eq!(apply(ease, -3.0), 0.0);
            assert_eq!(apply(ease, 7.0), 1.0);
            assert_eq!(apply(ease, f64::NAN), 0.0);
            assert_eq!(apply(ease, f64::INFINITY), 1.0);
            assert_eq!(apply(ease, f64::NEG_INFINITY), 0.0);
        }
    }
}
