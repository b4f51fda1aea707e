//! The layer kinds and their parameters: each parameter is listed once, here.
//!
//! An entry gives a parameter's doc, its name and type, and its
//! [schema](super::schema) entry: unit, allowed values, default when a file
//! leaves it out, and the value a layer added in the editor starts at. Every
//! kind also has `name`, `enabled`, `weight` (first) and `falloff` (last).
//! Reading files, validation, the editor's parameter rows and `drape check`
//! all follow these entries, so adding a parameter is one entry here plus
//! its math in `animate`.
//!
//! Field and kind names are the scene file's (DESIGN.md): never rename one
//! without `formerly`, which keeps older files loading.

use super::param::Param;
use super::schema::{self, Access, Family, MAX_LAYER_VALUE, ParamRange, WaveAxis, layer_kinds};

/// The layer kinds below, for the schema's accessors.
#[derive(Clone, Copy, Debug)]
pub struct LayerFamily;

impl Family for LayerFamily {
    type Layer = Layer;
}

/// One parameter of a layer kind: see [`schema::ParamSpec`].
pub type ParamSpec = schema::ParamSpec<LayerFamily>;
/// What a parameter holds: see [`schema::ParamValue`].
pub type ParamValue = schema::ParamValue<LayerFamily>;
/// An animatable number's schema.
pub type NumberSpec = schema::NumberSpec<LayerFamily>;
/// A world direction's schema.
pub type DirectionSpec = schema::DirectionSpec<LayerFamily>;
/// A wave axis's schema.
pub type AxisSpec = schema::AxisSpec<LayerFamily>;
/// A whole number's schema.
pub type CountSpec = schema::CountSpec<LayerFamily>;

/// Largest falloff exponent; it must also be ≥ 0.
pub const MAX_FALLOFF: f64 = 16.0;
/// Gust octaves lie in 1..=[`MAX_GUST_OCTAVES`].
pub const MAX_GUST_OCTAVES: u32 = 6;
/// Longest follow-through lag, in seconds.
pub const MAX_LAG_SECS: f64 = 60.0;

layer_kinds! {
    /// Paper eq. 2: displacement = a · magnitude · speed · normalize(direction) · osc(t),
    /// where osc = 1 unless `frequency` > 0, then sin(2π·frequency·t + phase).
    Sway {
        /// How far the cloth sways, in metres.
        magnitude: Param = NumberSpec::required("m", ParamRange::Any, 0.1),
        /// The world direction of the sway; must not be zero.
        direction: (f64, f64, f64) = DirectionSpec::required("sway along", (1.0, 0.0, 0.0)),
        /// Multiplies the magnitude (the paper's speed).
        speed: Param = NumberSpec::optional("", ParamRange::Any, 1.0),
        /// Oscillations per second; 0 or less holds the sway still (osc = 1).
        frequency: Param = NumberSpec::optional("Hz", ParamRange::Any, 0.0).starting_at(0.5),
        /// The oscillation's phase in radians, used with `frequency`.
        phase: Param = NumberSpec::optional("rad", ParamRange::Any, 0.0),
    }

    /// Paper eqs. 3–4: displacement = a · magnitude · sin(x·frequency + phase + t·speed) along
    /// `axis`, where x = u·cos(direction) + v·sin(direction) is the material coordinate along
    /// the wave.
    Wave {
        /// How far the wave lifts the cloth, in metres.
        magnitude: Param = NumberSpec::required("m", ParamRange::Any, 0.03),
        /// Radians per metre of material distance along the wave.
        frequency: Param = NumberSpec::optional("rad/m", ParamRange::Any, 1.0).starting_at(8.0),
        /// The wave's phase in radians.
        phase: Param = NumberSpec::optional("rad", ParamRange::Any, 0.0),
        /// Radians per second the wave travels.
        speed: Param = NumberSpec::optional("rad/s", ParamRange::Any, 1.0).starting_at(4.0),
        /// Direction of travel in material space, degrees from +u towards +v.
        direction_deg: Param = NumberSpec::optional("°", ParamRange::Any, 0.0),
        /// What the wave displaces along: the surface normal, or a fixed world vector (not zero).
        axis: WaveAxis = AxisSpec::optional("displace along", WaveAxis::Normal),
    }

    /// Wind gusts: smooth, seeded turbulence scrolling with the wind.
    ///
    /// displacement = a · amplitude · ((1 − turbulence) · gust · normalize(direction)
    ///                + turbulence · swirl), where gust ∈ [0, 1] and swirl ∈ [−1, 1]³
    /// are smooth noise sampled at (p − normalize(direction) · speed · t) / scale,
    /// p the point's position in the layer's input mesh. The same `seed` gives the
    /// same gusts on every machine.
    Gusts formerly "Noise" {
        /// How far the gusts push the cloth, in metres.
        amplitude: Param = NumberSpec::required("m", ParamRange::Any, 0.05),
        /// Size of a gust in metres; greater than 0.
        scale: Param = NumberSpec::optional("m", ParamRange::Positive(MAX_LAYER_VALUE), 0.5),
        /// Metres per second the gusts travel along `direction`.
        speed: Param = NumberSpec::optional("m/s", ParamRange::Any, 1.0),
        /// The world wind direction; must not be zero.
        direction: (f64, f64, f64) = DirectionSpec::required("blow along", (1.0, 0.0, 0.0)),
        /// Share of the displacement that swirls in every direction rather than pushing downwind.
        turbulence: Param = NumberSpec::optional(
            "",
            ParamRange::Within(0.0, 1.0, " (0 pushes downwind only, 1 swirls only)"),
            0.3,
        ),
        /// Layers of detail, each at half the size and half the strength of the previous.
        octaves: u32 = CountSpec::optional(1, MAX_GUST_OCTAVES, 2),
        /// Picks the gusts: the same seed gives the same gusts on every machine.
        seed: u32 = CountSpec::optional(0, u32::MAX, 0),
    }

    /// Overlapping action without physics: a point far from the pins follows the
    /// keyed motion late. It moves by key_blend(t − lag · a) − key_blend(t), where
    /// key_blend is the vertex blend of the rest shapes and a = (d_cp/d_max)^falloff.
    FollowThrough {
        /// Seconds the farthest point trails behind the pins.
        lag: Param = NumberSpec::optional("s", ParamRange::Within(0.0, MAX_LAG_SECS, " seconds"), 0.25),
    }
}

impl Layer {
    /// The label used in messages: `Wave layer "ripple"`, or `Wave layer 2`
    /// when unnamed; a long name is cut with `…` ([`super::truncated_name`]),
    /// control characters are escaped.
    pub fn label(&self, index: usize) -> String {
        let (kind, name) = (self.kind(), self.name());
        if name.is_empty() {
            format!("{kind} layer {}", index + 1)
        } else {
            format!("{kind} layer {:?}", super::truncated_name(name))
        }
    }

    /// The parameter `name` if it is an animatable number of this layer.
    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params().iter().find(|spec| spec.name == name)?.number(self)
    }

    /// [`param`](Self::param), to change.
    pub fn param_mut(&mut self, name: &str) -> Option<&mut Param> {
        let spec = self.params().iter().find(|spec| spec.name == name)?;
        spec.number_mut(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::schema::ParamValue;

    #[test]
    fn every_kind_has_weight_first_and_falloff_last() {
        for kind in Layer::KINDS {
            let Some(layer) = Layer::with_start_values(kind) else { panic!("{kind} has no start values") };
            let names: Vec<&str> = layer.params().iter().map(|spec| spec.name).collect();
            assert_eq!(names.first(), Some(&"weight"), "{kind}");
            assert_eq!(names.last(), Some(&"falloff"), "{kind}");
            assert_eq!(layer.kind(), *kind);
        }
        assert!(Layer::with_start_values("Swirl").is_none());
    }

    #[test]
    fn every_entry_reaches_its_own_field_and_no_other_kind() {
        let layers: Vec<Layer> = Layer::KINDS.iter().filter_map(|kind| Layer::with_start_values(kind)).collect();
        for layer in &layers {
            for spec in layer.params() {
                let reached = match spec.value {
                    ParamValue::Number(n) => n.access.get(layer).is_some(),
                    ParamValue::Direction(d) => d.access.get(layer).is_some(),
                    ParamValue::Axis(a) => a.access.get(layer).is_some(),
                    ParamValue::Count(c) => c.access.get(layer).is_some(),
                };
                assert!(reached, "{} {}", layer.kind(), spec.name);
                assert!(!spec.doc.is_empty() && !spec.doc.starts_with(' '), "{} {}", layer.kind(), spec.name);
            }
            for other in layers.iter().filter(|other| other.kind() != layer.kind()) {
                let Some(spec) = other.params().iter().find(|spec| matches!(spec.value, ParamValue::Number(_))) else {
                    continue;
                };
                let mut layer = layer.clone();
                assert!(spec.number_mut(&mut layer).is_none(), "{}'s entry reached a {}", other.kind(), layer.kind());
            }
        }
    }

    #[test]
    fn parameters_are_found_by_name() {
        let Some(mut wave) = Layer::with_start_values("Wave") else { panic!("no Wave") };
        assert_eq!(wave.param("speed"), Some(&Param::Constant(4.0)));
        if let Some(speed) = wave.param_mut("speed") {
            *speed = Param::Constant(2.0);
        }
        let Layer::Wave(w) = &wave else { panic!("a Wave") };
        assert_eq!(w.speed, Param::Constant(2.0));
        assert_eq!(wave.param("axis"), None, "the axis is not an animatable number");
        assert_eq!(wave.param("nonsense"), None);
    }
}
