//! Animatable numbers: a plain constant, or a list of keys.
//!
//! In a scene file a constant is written as a plain number (`magnitude: 0.2`)
//! and an animated value as a list of keys
//! (`magnitude: [(frame: 0, value: 0.0), (frame: 48, value: 0.05, ease: EaseIn)]`).

use std::fmt;

use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::types::Ease;

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
