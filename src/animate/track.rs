//! Animated parameters: the value of a [`Param`] at any (fractional) frame.

use super::ease;
use glam::DVec3;

use crate::scene::{Param, ParamKey, ParamVec3};

/// The value of `param` at `frame` (fractional frames are in-betweens).
///
/// Before the first key it holds the first value, after the last key the last
/// one; between two keys it eases with the later key's curve (the curve that
/// arrives at it). An empty key list reads 0; a non-finite frame reads the
/// first value. Keys must be in increasing frame order, as validation ensures.
pub fn sample(param: &Param, frame: f64) -> f64 {
    match param {
        Param::Constant(v) => *v,
        Param::Keys(keys) => sample_keys(keys, frame),
    }
}

fn sample_keys(keys: &[ParamKey], frame: f64) -> f64 {
    let (Some(first), Some(last)) = (keys.first(), keys.last()) else { return 0.0 };
    if !frame.is_finite() || frame <= f64::from(first.frame) {
        return first.value;
    }
    if frame >= f64::from(last.frame) {
        return last.value;
    }
    // The first key after `frame`; keys[0] is at or before it, so next ≥ 1.
    let next = keys.partition_point(|k| f64::from(k.frame) <= frame);
    let (from, to) = (&keys[next - 1], &keys[next]);
    let span = f64::from(to.frame) - f64::from(from.frame);
    let x = (frame - f64::from(from.frame)) / span;
    let e = ease::apply(to.ease, x);
    from.value + (to.value - from.value) * e
}

/// A vector of three parameters at `frame`, each component [`sample`]d.
pub fn sample_vec3((x, y, z): &ParamVec3, frame: f64) -> DVec3 {
    DVec3::new(sample(x, frame), sample(y, frame), sample(z, frame))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Ease;

    fn keys(list: &[(i32, f64, Ease)]) -> Param {
        Param::Keys(list.iter().map(|&(frame, value, ease)| ParamKey { frame, value, ease }).collect())
    }

    #[test]
    fn constants_are_constant() {
        assert_eq!(sample(&Param::Constant(0.3), -1e9), 0.3);
        assert_eq!(sample(&Param::Constant(0.3), f64::NAN), 0.3);
    }

    #[test]
    fn keys_hold_outside_and_hit_every_key() {
        let p = keys(&[(10, 1.0, Ease::Linear), (20, 3.0, Ease::Linear), (40, -1.0, Ease::EaseIn)]);
        assert_eq!(sample(&p, 0.0), 1.0);
        assert_eq!(sample(&p, 10.0), 1.0);
        assert_eq!(sample(&p, 20.0), 3.0);
        assert_eq!(sample(&p, 40.0), -1.0);
        assert_eq!(sample(&p, 1e12), -1.0);
        assert_eq!(sample(&p, 15.0), 2.0, "linear halfway");
        // The curve arriving at frame 40 is EaseIn: halfway is 1/8 of the way.
        assert!((sample(&p, 30.0) - (3.0 - 4.0 / 8.0)).abs() < 1e-12);
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        assert_eq!(sample(&Param::Keys(vec![]), 5.0), 0.0);
        let one = keys(&[(3, 2.5, Ease::Bounce)]);
        assert_eq!(sample(&one, -7.0), 2.5);
        assert_eq!(sample(&one, 7.0), 2.5);
        let p = keys(&[(0, 1.0, Ease::Linear), (10, 2.0, Ease::Linear)]);
        assert_eq!(sample(&p, f64::NAN), 1.0);
        assert_eq!(sample(&p, f64::INFINITY), 1.0);
        assert_eq!(sample(&p, f64::NEG_INFINITY), 1.0);
    }
}
