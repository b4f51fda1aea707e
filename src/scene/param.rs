//! Animatable numbers: a plain constant, or a list of keys.
//!
//! In a scene file a constant is written as a plain number (`magnitude: 0.2`)
//! and an animated value as a list of keys
//! (`magnitude: [(frame: 0, value: 0.0), (frame: 48, value: 0.05, ease: EaseIn)]`).

use std::fmt;

use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A number that may change over time.
#[derive(Clone, Debug, PartialEq)]
pub enum Param {
    Constant(f64),
    /// Keys in strictly increasing frame order; at least one.
    Keys(Vec<ParamKey>),
}

/// One key of an animated parameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamKey {
    pub frame: i32,
    pub value: f64,
    /// The curve that arrives at this key from the previous one.
    #[serde(default)]
    pub ease: Ease,
}

impl Param {
    /// The value when the parameter is constant, or the first key's value.
    pub fn first_value(&self) -> f64 {
        match self {
            Param::Constant(v) => *v,
            Param::Keys(keys) => keys.first().map_or(0.0, |k| k.value),
        }
    }

    /// Every number the parameter holds (for validation).
    pub fn values(&self) -> Vec<f64> {
        match self {
            Param::Constant(v) => vec![*v],
            Param::Keys(keys) => keys.iter().map(|k| k.value).collect(),
        }
    }
}

impl From<f64> for Param {
    fn from(v: f64) -> Self {
        Param::Constant(v)
    }
}

impl Serialize for Param {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Param::Constant(v) => serializer.serialize_f64(*v),
            Param::Keys(keys) => keys.serialize(serializer),
        }
    }
}

impl<'de> Deserialize<'de> for Param {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ParamVisitor;
        impl<'de> Visitor<'de> for ParamVisitor {
            type Value = Param;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or a list of keys like [(frame: 0, value: 1.0)]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Param, E> {
                Ok(Param::Constant(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Param, E> {
                Ok(Param::Constant(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Param, E> {
                Ok(Param::Constant(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Param, A::Error> {
                let mut keys = Vec::new();
                while let Some(key) = seq.next_element::<ParamKey>()? {
                    keys.push(key);
                }
                Ok(Param::Keys(keys))
            }
        }
        deserializer.deserialize_any(ParamVisitor)
    }
}

/// Interpolation curve of a segment (between two keys) or of a parameter key.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Ease {
    Linear,
    /// Hold the earlier value until the next key.
    Step,
    EaseIn,
    EaseOut,
    #[default]
    EaseInOut,
    /// CSS `cubic-bezier(x1, y1, x2, y2)`; x1 and x2 in [0, 1].
    Bezier(f64, f64, f64, f64),
    /// Anticipation/overshoot past the target, then settle.
    Back,
    Elastic,
    Bounce,
}

impl Ease {
    /// Every easing, in menu order; Bézier with CSS's ease-in-out handles.
    pub const ALL: [Ease; 9] = [
        Ease::Linear,
        Ease::Step,
        Ease::EaseIn,
        Ease::EaseOut,
        Ease::EaseInOut,
        Ease::Bezier(0.42, 0.0, 0.58, 1.0),
        Ease::Back,
        Ease::Elastic,
        Ease::Bounce,
    ];

    /// The easing's name in menus and on the timeline.
    pub fn label(self) -> &'static str {
        match self {
            Ease::Linear => "Linear",
            Ease::Step => "Step",
            Ease::EaseIn => "Ease in",
            Ease::EaseOut => "Ease out",
            Ease::EaseInOut => "Ease in-out",
            Ease::Bezier(..) => "Bézier",
            Ease::Back => "Back",
            Ease::Elastic => "Elastic",
            Ease::Bounce => "Bounce",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_easing_is_listed_once_under_its_own_name() {
        let names: std::collections::BTreeSet<_> = Ease::ALL.iter().map(|e| e.label()).collect();
        assert_eq!(names.len(), Ease::ALL.len());
        assert_eq!(Ease::Bezier(0.1, 0.2, 0.3, 0.4).label(), "Bézier");
    }
}
