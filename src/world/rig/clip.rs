//! An animation clip: keyed node properties, sampled at any time by the
//! glTF 2.0 rules (spec §3.11 and Appendix C "Interpolation").
//!
//! Before the first key a channel holds its first value, after the last its
//! last. LINEAR blends translations, scales and morph weights straight and
//! rotations by the shortest-path spherical blend; STEP holds a key's value
//! until the next; CUBICSPLINE is the Hermite spline through the values with
//! the file's in- and out-tangents (scaled by the key interval), a rotation
//! then normalised.

use glam::{DQuat, DVec3};

/// What a channel animates on its node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
    /// The weights of the node's mesh's morph targets.
    MorphWeights,
}

/// How a channel's values run between its keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Linear,
    Step,
    CubicSpline,
}

/// One keyed property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node it animates (index into the rig's nodes).
    pub node: usize,
    pub property: Property,
    pub interpolation: Interpolation,
    /// Key times (s), strictly increasing; at least one.
    pub times_secs: Vec<f64>,
    /// `width` numbers per key (3 for a translation or scale, 4 for a
    /// rotation x y z w, the number of morph targets for weights); for
    /// CUBICSPLINE three groups per key: in-tangent, value, out-tangent.
    pub values: Vec<f64>,
    pub width: usize,
}

/// A named animation: every channel runs on the same clock.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    pub name: String,
    pub channels: Vec<Channel>,
}

impl Clip {
    /// The span of its keys (s): from the earliest key of any channel to the
    /// latest; (0, 0) for a clip without channels.
    pub fn span_secs(&self) -> (f64, f64) {
        let mut span: Option<(f64, f64)> = None;
        for channel in &self.channels {
            let (Some(&first), Some(&last)) = (channel.times_secs.first(), channel.times_secs.last()) else { continue };
            span = Some(span.map_or((first, last), |(a, b)| (a.min(first), b.max(last))));
        }
        span.unwrap_or((0.0, 0.0))
    }
}

impl Channel {
    /// The channel's value at `t_secs`, `width` numbers written to `out`.
    /// A NaN time reads as the first key.
    pub fn sample_into(&self, t_secs: f64, out: &mut [f64]) {
        let width = self.width;
        let keys = self.times_secs.len();
        let groups = if self.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        // The value (not a tangent) of key k.
        let value = |k: usize| &self.values[(k * groups + groups / 2) * width..][..width];
        let first = self.times_secs[0];
        let last = self.times_secs[keys - 1];
        if !(t_secs > first) || keys == 1 {
            out[..width].copy_from_slice(value(0));
            return;
        }
        if t_secs >= last {
            out[..width].copy_from_slice(value(keys - 1));
            return;
        }
        // The key at or before t: t is within (first, last) here.
        let k = self.times_secs.partition_point(|&time| time <= t_secs) - 1;
        let interval = self.times_secs[k + 1] - self.times_secs[k];
        let s = (t_secs - self.times_secs[k]) / interval;
        let (a, b) = (value(k), value(k + 1));
        match self.interpolation {
            Interpolation::Step => out[..width].copy_from_slice(a),
            Interpolation::Linear if self.property == Property::Rotation => {
                let q = quat(a).slerp(quat(b), s);
                out[..4].copy_from_slice(&q.to_array());
            }
            Interpolation::Linear => {
                for i in 0..width {
                    out[i] = a[i] + (b[i] - a[i]) * s;
                }
            }
            Interpolation::CubicSpline => {
                let out_tangent = &self.values[(k * 3 + 2) * width..][..width];
                let in_tangent = &self.values[((k + 1) * 3) * width..][..width];
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = (s3 - 2.0 * s2 + s) * interval;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = (s3 - s2) * interval;
                for i in 0..width {
                    out[i] = h00 * a[i] + h10 * out_tangent[i] + h01 * b[i] + h11 * in_tangent[i];
                }
                if self.property == Property::Rotation {
                    let q = quat(&out[..4]).normalize();
                    out[..4].copy_from_slice(&q.to_array());
                }
            }
        }
    }

    /// The channel's value as a vector (translation or scale).
    pub fn sample_vec3(&self, t_secs: f64) -> DVec3 {
        let mut out = [0.0; 3];
        self.sample_into(t_secs, &mut out);
        DVec3::from_array(out)
    }

    /// The channel's value as a unit rotation.
    pub fn sample_quat(&self, t_secs: f64) -> DQuat {
        let mut out = [0.0; 4];
        self.sample_into(t_secs, &mut out);
        quat(&out).normalize()
    }
}

/// A rotation from x y z w; the file's quaternions are unit length (a
/// validator checks), and blends normalise.
fn quat(xyzw: &[f64]) -> DQuat {
    DQuat::from_xyzw(xyzw[0], xyzw[1], xyzw[2], xyzw[3])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(property: Property, interpolation: Interpolation, times: &[f64], values: &[f64]) -> Channel {
        let groups = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        let width = values.len() / (times.len() * groups);
        Channel { node: 0, property, interpolation, times_secs: times.to_vec(), values: values.to_vec(), width }
    }

    #[test]
    fn linear_translation_blends_between_keys_and_holds_outside() {
        let c = channel(Property::Translation, Interpolation::Linear, &[1.0, 3.0], &[0.0, 0.0, 0.0, 2.0, -4.0, 6.0]);
        assert_eq!(c.sample_vec3(0.0), DVec3::ZERO, "before the first key: the first value");
        assert_eq!(c.sample_vec3(1.5), DVec3::new(0.5, -1.0, 1.5));
        assert_eq!(c.sample_vec3(3.0), DVec3::new(2.0, -4.0, 6.0));
        assert_eq!(c.sample_vec3(9.0), DVec3::new(2.0, -4.0, 6.0), "after the last key: the last value");
        assert_eq!(c.sample_vec3(f64::NAN), DVec3::ZERO);
    }

    #[test]
    fn step_holds_each_key_until_the_next() {
        let c = channel(
            Property::Scale,
            Interpolation::Step,
            &[0.0, 1.0, 2.0],
            &[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0],
        );
        assert_eq!(c.sample_vec3(0.999), DVec3::ONE);
        assert_eq!(c.sample_vec3(1.0), DVec3::splat(2.0));
        assert_eq!(c.sample_vec3(1.999), DVec3::splat(2.0));
        assert_eq!(c.sample_vec3(2.5), DVec3::splat(3.0));
    }

    #[test]
    fn linear_rotation_is_the_shortest_spherical_blend() {
        // 0° to 90° about Y: a quarter of the way is 22.5°.
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let c = channel(
            Property::Rotation,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 1.0, 0.0, half, 0.0, half],
        );
        let q = c.sample_quat(0.25);
        let expected = DQuat::from_rotation_y(22.5f64.to_radians());
        assert!(q.dot(expected).abs() > 1.0 - 1e-12, "{q:?}");
        // The same end written as −q (equal rotations): still the short way, not 337.5°.
        let c = channel(
            Property::Rotation,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 1.0, 0.0, -half, 0.0, -half],
        );
        let q = c.sample_quat(0.25);
        assert!(q.dot(expected).abs() > 1.0 - 1e-12, "{q:?}");
    }

    #[test]
    fn cubic_spline_follows_the_hermite_formula() {
        // One number keyed at t = 0 (value 1, out-tangent 2) and t = 2 (value 5,
        // in-tangent −1): at s = 0.5 (t = 1), td = 2,
        // p = 0.5·1 + 0.125·2·2 + 0.5·5 + (−0.125)·2·(−1) = 0.5 + 0.5 + 2.5 + 0.25 = 3.75.
        let values = [0.0, 1.0, 2.0, -1.0, 5.0, 0.0];
        let c = channel(Property::MorphWeights, Interpolation::CubicSpline, &[0.0, 2.0], &values);
        let mut out = [0.0];
        c.sample_into(1.0, &mut out);
        assert!((out[0] - 3.75).abs() < 1e-12, "{}", out[0]);
        c.sample_into(2.0, &mut out);
        assert_eq!(out[0], 5.0, "a key's value, not its tangent");
        c.sample_into(-1.0, &mut out);
        assert_eq!(out[0], 1.0);
        // At s = 0.25 (t = 0.5): h00 = 0.84375, h10 = 0.140625·2, h01 = 0.15625, h11 = −0.046875·2.
        c.sample_into(0.5, &mut out);
        let expected = 0.84375 * 1.0 + 0.28125 * 2.0 + 0.15625 * 5.0 + (-0.09375) * (-1.0);
        assert!((out[0] - expected).abs() < 1e-12, "{} vs {expected}", out[0]);
    }

    #[test]
    fn cubic_spline_rotations_come_out_unit_length() {
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let values = [
            0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, half, 0.0, half, 0.0,
            0.0, 0.0, 0.0,
        ];
        let c = channel(Property::Rotation, Interpolation::CubicSpline, &[0.0, 1.0], &values);
        let q = c.sample_quat(0.5);
        assert!((q.length() - 1.0).abs() < 1e-12);
        // Zero tangents: the blend is symmetric, so halfway is 45° about Y.
        assert!(q.dot(DQuat::from_rotation_y(45f64.to_radians())).abs() > 1.0 - 1e-12, "{q:?}");
    }

    #[test]
    fn a_clip_spans_its_channels() {
        let a = channel(Property::Translation, Interpolation::Linear, &[0.5, 1.0], &[0.0; 6]);
        let b = channel(Property::Scale, Interpolation::Step, &[0.0, 2.0], &[1.0; 6]);
        let clip = Clip { name: "walk".into(), channels: vec![a, b] };
        assert_eq!(clip.span_secs(), (0.0, 2.0));
        assert_eq!(Clip { name: String::new(), channels: vec![] }.span_secs(), (0.0, 0.0));
    }
}
