//! The layer schema: what each parameter of a layer kind is, as data.
//!
//! A [`ParamSpec`] holds everything about one parameter except its math: its
//! name in the file and the code, a one-line doc, and a [`ParamValue`] with
//! its unit, the values it may take, its default when a file leaves it out,
//! the value a layer added in the editor starts at, and typed access to the
//! field. Each layer kind's list is its `PARAMS` (e.g. [`Sway::PARAMS`]), in
//! file order, and [`Layer::params`](super::Layer::params) gives the list of any layer.
//!
//! The layer kinds in [`super::layers`] are declared by `layer_kinds!` from
//! one entry per parameter: the macro writes the struct field with its doc,
//! the schema entry, and reading the struct from a file by the schema
//! ([`read_layer`]). Everything else reads the schema: validation, the
//! editor's parameter rows, `drape check`'s summary. The schema names the
//! layers only through a [`Family`] marker (`LayerFamily`, beside the kinds),
//! so it does not import the kinds it declares; `scene` exports the schema
//! types bound to the layers (`scene::ParamSpec` and the like).
//!
//! [`Sway::PARAMS`]: super::Sway::PARAMS

use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, DeserializeSeed, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};

use super::param::Param;

/// A world vector (x, y, z) as the file writes it.
pub type Vec3 = (f64, f64, f64);

/// Largest magnitude of any layer parameter: beyond it a value is a typo, not a look.
pub const MAX_LAYER_VALUE: f64 = 1e6;

/// The layers a schema describes, named by a marker type so that the schema
/// does not import the layer kinds it declares (they are built from it).
pub trait Family: Copy + fmt::Debug + 'static {
    /// The enum over every layer kind.
    type Layer: 'static;
}

/// What a wave displaces along.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum WaveAxis {
    /// The surface normal of the layer's input mesh.
    #[default]
    Normal,
    /// A fixed world vector (normalised when used); must not be zero.
    Fixed((f64, f64, f64)),
}

/// One parameter of a layer kind.
#[derive(Clone, Copy, Debug)]
pub struct ParamSpec<F: Family> {
    /// The field's name in the scene file, the code and messages (`magnitude`).
    pub name: &'static str,
    /// What the parameter does, in one line.
    pub doc: &'static str,
    /// What it holds and which values it may take.
    pub value: ParamValue<F>,
}

/// What a parameter holds: its allowed values, default and typed access.
#[derive(Clone, Copy, Debug)]
pub enum ParamValue<F: Family> {
    /// An animatable number: a constant or a list of keys.
    Number(NumberSpec<F>),
    /// A world direction, normalised where used: never zero.
    Direction(DirectionSpec<F>),
    /// The wave's displacement axis: the surface normal or a fixed vector.
    Axis(AxisSpec<F>),
    /// A whole number.
    Count(CountSpec<F>),
}

/// Which values an animatable number may take, at every key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamRange {
    /// Any finite value within ±[`MAX_LAYER_VALUE`].
    Any,
    /// In [lo, hi]; the text, if not empty, follows the range in messages (" seconds").
    Within(f64, f64, &'static str),
    /// Greater than 0 and at most the bound.
    Positive(f64),
}

impl ParamRange {
    /// Whether `v` is allowed; NaN never is.
    pub fn contains(self, v: f64) -> bool {
        match self {
            ParamRange::Any => v.abs() <= MAX_LAYER_VALUE,
            ParamRange::Within(lo, hi, _) => (lo..=hi).contains(&v),
            ParamRange::Positive(hi) => v > 0.0 && v <= hi,
        }
    }
}

/// Reads and writes one field of a layer of a known kind: `None` when the
/// layer is of another kind.
pub struct Access<F: Family, T: 'static> {
    pub(super) read: for<'a> fn(&'a F::Layer) -> Option<&'a T>,
    pub(super) write: for<'a> fn(&'a mut F::Layer) -> Option<&'a mut T>,
}

// Derived Clone/Copy would ask `T: Copy`; fn pointers are Copy for any `T`.
impl<F: Family, T> Clone for Access<F, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<F: Family, T> Copy for Access<F, T> {}

impl<F: Family, T> Access<F, T> {
    /// No field: until `layer_kinds!` binds the entry to its field.
    const UNBOUND: Access<F, T> = Access { read: |_| None, write: |_| None };

    /// The field in `layer`; `None` when `layer` is of another kind.
    pub fn get<'a>(&self, layer: &'a F::Layer) -> Option<&'a T> {
        (self.read)(layer)
    }

    /// The field in `layer`, to change; `None` when `layer` is of another kind.
    pub fn get_mut<'a>(&self, layer: &'a mut F::Layer) -> Option<&'a mut T> {
        (self.write)(layer)
    }
}

impl<F: Family, T> fmt::Debug for Access<F, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Access")
    }
}

/// An animatable number ([`Param`]).
#[derive(Clone, Copy, Debug)]
pub struct NumberSpec<F: Family> {
    /// Shown after the value: `m`, `Hz`, `°`; empty for a plain factor.
    pub unit: &'static str,
    pub range: ParamRange,
    /// The value when the file leaves the field out; `None`: the file must give it.
    pub default: Option<f64>,
    /// The value of a layer added in the editor, chosen to show the effect at once.
    pub start: f64,
    pub access: Access<F, Param>,
}

impl<F: Family> NumberSpec<F> {
    /// A number every file must give.
    pub const fn required(unit: &'static str, range: ParamRange, start: f64) -> NumberSpec<F> {
        NumberSpec { unit, range, default: None, start, access: Access::UNBOUND }
    }

    /// A number that is `default` when the file leaves it out; new layers start there too.
    pub const fn optional(unit: &'static str, range: ParamRange, default: f64) -> NumberSpec<F> {
        NumberSpec { unit, range, default: Some(default), start: default, access: Access::UNBOUND }
    }

    /// A new layer starts at `start` instead of the default.
    pub const fn starting_at(self, start: f64) -> NumberSpec<F> {
        NumberSpec { start, ..self }
    }

    pub(super) const fn bind(self, access: Access<F, Param>) -> ParamValue<F> {
        ParamValue::Number(NumberSpec { access, ..self })
    }

    pub(super) fn default_value(&self) -> Param {
        Param::Constant(self.default.unwrap_or(self.start))
    }

    pub(super) fn start_value(&self) -> Param {
        Param::Constant(self.start)
    }
}

/// A world direction.
#[derive(Clone, Copy, Debug)]
pub struct DirectionSpec<F: Family> {
    /// Ends the message for a zero vector: "give a direction to `purpose`".
    pub purpose: &'static str,
    /// The value when the file leaves the field out; `None`: the file must give it.
    pub default: Option<Vec3>,
    /// The value of a layer added in the editor.
    pub start: Vec3,
    pub access: Access<F, Vec3>,
}

impl<F: Family> DirectionSpec<F> {
    /// A direction every file must give.
    pub const fn required(purpose: &'static str, start: Vec3) -> DirectionSpec<F> {
        DirectionSpec { purpose, default: None, start, access: Access::UNBOUND }
    }

    pub(super) const fn bind(self, access: Access<F, Vec3>) -> ParamValue<F> {
        ParamValue::Direction(DirectionSpec { access, ..self })
    }

    pub(super) fn default_value(&self) -> Vec3 {
        self.default.unwrap_or(self.start)
    }

    pub(super) fn start_value(&self) -> Vec3 {
        self.start
    }
}

/// A wave's axis: a fixed vector in it must not be zero.
#[derive(Clone, Copy, Debug)]
pub struct AxisSpec<F: Family> {
    /// Ends the message for a zero fixed vector: "give a direction to `purpose`".
    pub purpose: &'static str,
    /// The value when the file leaves the field out, and a new layer's.
    pub default: WaveAxis,
    pub access: Access<F, WaveAxis>,
}

impl<F: Family> AxisSpec<F> {
    /// An axis that is `default` when the file leaves it out.
    pub const fn optional(purpose: &'static str, default: WaveAxis) -> AxisSpec<F> {
        AxisSpec { purpose, default, access: Access::UNBOUND }
    }

    pub(super) const fn bind(self, access: Access<F, WaveAxis>) -> ParamValue<F> {
        ParamValue::Axis(AxisSpec { access, ..self })
    }

    pub(super) fn default_value(&self) -> WaveAxis {
        self.default
    }

    pub(super) fn start_value(&self) -> WaveAxis {
        self.default
    }
}

/// A whole number in `min..=max`.
#[derive(Clone, Copy, Debug)]
pub struct CountSpec<F: Family> {
    pub min: u32,
    pub max: u32,
    /// The value when the file leaves the field out, and a new layer's.
    pub default: u32,
    pub access: Access<F, u32>,
}

impl<F: Family> CountSpec<F> {
    /// A whole number in `min..=max` that is `default` when the file leaves it out.
    pub const fn optional(min: u32, max: u32, default: u32) -> CountSpec<F> {
        CountSpec { min, max, default, access: Access::UNBOUND }
    }

    pub(super) const fn bind(self, access: Access<F, u32>) -> ParamValue<F> {
        ParamValue::Count(CountSpec { access, ..self })
    }

    pub(super) fn default_value(&self) -> u32 {
        self.default
    }

    pub(super) fn start_value(&self) -> u32 {
        self.default
    }
}

impl<F: Family> ParamSpec<F> {
    /// Whether a file must give this parameter (it has no default).
    pub fn is_required(&self) -> bool {
        match self.value {
            ParamValue::Number(n) => n.default.is_none(),
            ParamValue::Direction(d) => d.default.is_none(),
            ParamValue::Axis(_) | ParamValue::Count(_) => false,
        }
    }

    /// The unit shown after the value; empty for plain factors and non-numbers.
    pub fn unit(&self) -> &'static str {
        match self.value {
            ParamValue::Number(n) => n.unit,
            _ => "",
        }
    }

    /// The animatable number this entry names in `layer`; `None` for another
    /// kind of value or a layer of another kind.
    pub fn number<'a>(&self, layer: &'a F::Layer) -> Option<&'a Param> {
        match self.value {
            ParamValue::Number(n) => n.access.get(layer),
            _ => None,
        }
    }

    /// [`number`](Self::number), to change.
    pub fn number_mut<'a>(&self, layer: &'a mut F::Layer) -> Option<&'a mut Param> {
        match self.value {
            ParamValue::Number(n) => n.access.get_mut(layer),
            _ => None,
        }
    }
}

/// The fields of one layer kind as [`read_layer`] fills them.
pub(super) trait LayerFields<F: Family>: Sized + 'static {
    /// The struct's name, which ron's messages name (`Sway`).
    const KIND: &'static str;
    /// `name`, `enabled`, then every [`ParamSpec`]'s name in order.
    const FIELDS: &'static [&'static str];
    /// The entries behind `FIELDS[2..]`.
    const PARAMS: &'static [ParamSpec<F>];
    /// One writer per name in `FIELDS`, in the same order.
    const SLOTS: &'static [for<'a> fn(&'a mut Self) -> Slot<'a>];
    /// Every field at its default; a required one at its start value until the file gives it.
    fn with_defaults() -> Self;
}

/// Where [`read_layer`] stores one field's value.
pub(super) enum Slot<'a> {
    Text(&'a mut String),
    Flag(&'a mut bool),
    Number(&'a mut Param),
    Vector(&'a mut Vec3),
    Axis(&'a mut WaveAxis),
    Count(&'a mut u32),
}

impl<'a> From<&'a mut Param> for Slot<'a> {
    fn from(v: &'a mut Param) -> Self {
        Slot::Number(v)
    }
}
impl<'a> From<&'a mut Vec3> for Slot<'a> {
    fn from(v: &'a mut Vec3) -> Self {
        Slot::Vector(v)
    }
}
impl<'a> From<&'a mut WaveAxis> for Slot<'a> {
    fn from(v: &'a mut WaveAxis) -> Self {
        Slot::Axis(v)
    }
}
impl<'a> From<&'a mut u32> for Slot<'a> {
    fn from(v: &'a mut u32) -> Self {
        Slot::Count(v)
    }
}

impl<'de> DeserializeSeed<'de> for Slot<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        match self {
            Slot::Text(v) => *v = String::deserialize(deserializer)?,
            Slot::Flag(v) => *v = bool::deserialize(deserializer)?,
            Slot::Number(v) => *v = Param::deserialize(deserializer)?,
            Slot::Vector(v) => *v = Vec3::deserialize(deserializer)?,
            Slot::Axis(v) => *v = WaveAxis::deserialize(deserializer)?,
            Slot::Count(v) => *v = u32::deserialize(deserializer)?,
        }
        Ok(())
    }
}

/// Reads a layer struct as serde's derive would with `deny_unknown_fields`,
/// with the defaults from the schema: an unknown or repeated field is an
/// error when it is read, a missing required one after the last field, each
/// with the struct's name for ron's message.
pub(super) fn read_layer<'de, F: Family, T: LayerFields<F>, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<T, D::Error> {
    deserializer.deserialize_struct(T::KIND, T::FIELDS, LayerVisitor(PhantomData))
}

struct LayerVisitor<F, T>(PhantomData<(F, T)>);

impl<'de, F: Family, T: LayerFields<F>> Visitor<'de> for LayerVisitor<F, T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "struct {}", T::KIND)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<T, A::Error> {
        let mut layer = T::with_defaults();
        let mut given = vec![false; T::FIELDS.len()];
        while let Some(index) = map.next_key_seed(FieldIndex(T::FIELDS))? {
            if given[index] {
                return Err(de::Error::duplicate_field(T::FIELDS[index]));
            }
            given[index] = true;
            map.next_value_seed((T::SLOTS[index])(&mut layer))?;
        }
        let params_given = &given[T::FIELDS.len() - T::PARAMS.len()..];
        if let Some((spec, _)) = T::PARAMS.iter().zip(params_given).find(|(spec, given)| spec.is_required() && !**given)
        {
            return Err(de::Error::missing_field(spec.name));
        }
        Ok(layer)
    }
}

/// A field name, read as its index in the list; an unknown one is an error listing them all.
struct FieldIndex(&'static [&'static str]);

impl<'de> DeserializeSeed<'de> for FieldIndex {
    type Value = usize;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<usize, D::Error> {
        deserializer.deserialize_identifier(self)
    }
}

impl Visitor<'_> for FieldIndex {
    type Value = usize;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("field identifier")
    }

    fn visit_str<E: de::Error>(self, name: &str) -> Result<usize, E> {
        self.0.iter().position(|field| *field == name).ok_or_else(|| E::unknown_field(name, self.0))
    }
}

/// Declares the layer kinds from one entry per parameter.
///
/// For each kind it writes the struct (`name`, `enabled`, `weight`, the
/// listed parameters, `falloff`), its `PARAMS` schema,
/// `with_start_values()` (a layer as the editor adds it) and reading it from a file by the schema; then the
/// [`Layer`](super::Layer) enum over all kinds. `formerly "Old"` after a kind's name keeps
/// files that wrote the old name loading.
macro_rules! layer_kinds {
    ($(
        $(#[doc = $kind_doc:literal])+
        $kind:ident $(formerly $old:literal)? {
            $( $(#[doc = $doc:literal])+ $field:ident: $ty:ty = $spec:expr, )*
        }
    )*) => {
        $(
            $crate::scene::schema::layer_kind! {
                $(#[doc = $kind_doc])+
                $kind {
                    /// Scales the layer's displacement: 0 leaves the cloth as it is.
                    weight: Param = NumberSpec::optional("", ParamRange::Any, 1.0),
                    $( $(#[doc = $doc])+ $field: $ty = $spec, )*
                    /// Exponent of the pin-distance attenuation a = (d_cp/d_max)^falloff.
                    falloff: Param = NumberSpec::optional("", ParamRange::Within(0.0, MAX_FALLOFF, ""), 1.0),
                }
            }
        )*

        /// One deformer of the layer stack, applied in order.
        #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        pub enum Layer {
            $( $(#[serde(alias = $old)])? $kind($kind), )*
        }

        impl Layer {
            /// Every kind as the scene file writes it, in the editor's order.
            pub const KINDS: &'static [&'static str] = &[$(stringify!($kind)),*];

            /// Every kind with its schema, as in [`Layer::KINDS`].
            pub const KIND_PARAMS: &'static [(&'static str, &'static [ParamSpec])] =
                &[$((stringify!($kind), $kind::PARAMS)),*];

            /// Names earlier versions wrote for a kind, still read: (old, current).
            pub const FORMER_KINDS: &'static [(&'static str, &'static str)] =
                &[$($(($old, stringify!($kind)),)?)*];

            /// The kind as written in the scene file (`Sway`, `Wave`, …).
            pub fn kind(&self) -> &'static str {
                match self {
                    $(Layer::$kind(_) => stringify!($kind),)*
                }
            }

            /// The layer's parameters, in file order: its kind's schema.
            pub fn params(&self) -> &'static [ParamSpec] {
                match self {
                    $(Layer::$kind(_) => $kind::PARAMS,)*
                }
            }

            /// A layer of `kind` as the editor adds it: every parameter at its
            /// start value. `None` when `kind` is none of [`Layer::KINDS`].
            pub fn with_start_values(kind: &str) -> Option<Layer> {
                $(if kind == stringify!($kind) {
                    return Some(Layer::$kind($kind::with_start_values()));
                })*
                None
            }

            pub fn name(&self) -> &str {
                match self {
                    $(Layer::$kind(l) => &l.name,)*
                }
            }

            pub fn name_mut(&mut self) -> &mut String {
                match self {
                    $(Layer::$kind(l) => &mut l.name,)*
                }
            }

            pub fn enabled(&self) -> bool {
                match self {
                    $(Layer::$kind(l) => l.enabled,)*
                }
            }

            pub fn enabled_mut(&mut self) -> &mut bool {
                match self {
                    $(Layer::$kind(l) => &mut l.enabled,)*
                }
            }

            pub fn weight(&self) -> &Param {
                match self {
                    $(Layer::$kind(l) => &l.weight,)*
                }
            }
        }
    };
}

/// One kind for [`layer_kinds!`]: the struct, its schema, its start values and reading it.
macro_rules! layer_kind {
    (
        $(#[doc = $kind_doc:literal])+
        $kind:ident {
            $( $(#[doc = $doc:literal])+ $field:ident: $ty:ty = $spec:expr, )*
        }
    ) => {
        $(#[doc = $kind_doc])+
        #[derive(Clone, Debug, PartialEq, serde::Serialize)]
        pub struct $kind {
            /// Shown in the editor and in messages; may be empty.
            pub name: String,
            /// A disabled layer leaves the cloth as it is.
            pub enabled: bool,
            $( $(#[doc = $doc])+ pub $field: $ty, )*
        }

        impl $kind {
            /// The kind's parameters in file order, each with its unit, range,
            /// default and doc: the schema everything else reads.
            pub const PARAMS: &'static [ParamSpec] = &[$(
                ParamSpec {
                    name: stringify!($field),
                    doc: concat!($($doc),+).trim_ascii(),
                    value: $spec.bind(Access {
                        read: |layer| match layer {
                            Layer::$kind(l) => Some(&l.$field),
                            _ => None,
                        },
                        write: |layer| match layer {
                            Layer::$kind(l) => Some(&mut l.$field),
                            _ => None,
                        },
                    }),
                },
            )*];

            /// The layer as the editor adds it, unnamed and enabled: every
            /// parameter at its start value.
            pub fn with_start_values() -> $kind {
                $kind { name: String::new(), enabled: true, $($field: $spec.start_value(),)* }
            }
        }

        impl $crate::scene::schema::LayerFields<LayerFamily> for $kind {
            const KIND: &'static str = stringify!($kind);
            const FIELDS: &'static [&'static str] = &["name", "enabled", $(stringify!($field)),*];
            const PARAMS: &'static [ParamSpec] = $kind::PARAMS;
            const SLOTS: &'static [for<'a> fn(&'a mut Self) -> $crate::scene::schema::Slot<'a>] = &[
                |l| $crate::scene::schema::Slot::Text(&mut l.name),
                |l| $crate::scene::schema::Slot::Flag(&mut l.enabled),
                $(|l| (&mut l.$field).into(),)*
            ];

            fn with_defaults() -> $kind {
                $kind { name: String::new(), enabled: true, $($field: $spec.default_value(),)* }
            }
        }

        impl<'de> serde::Deserialize<'de> for $kind {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<$kind, D::Error> {
                $crate::scene::schema::read_layer(deserializer)
            }
        }
    };
}

pub(super) use {layer_kind, layer_kinds};
