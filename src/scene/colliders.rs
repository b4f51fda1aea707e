//! Colliders: the things in the world the cloth rests on and never enters.
//!
//! Kind and field names are fixed by DESIGN.md ("The world around the
//! cloth"). Every number, each component of a vector included, is a
//! [`Param`]: a plain number or a list of keys, so a table can be pushed and a
//! ball can roll. The math (distance to the surface at a frame) is in
//! `world::collider_shape`; this module is only the document.

use serde::{Deserialize, Serialize};

use super::loaded::LoadedMesh;
use super::param::Param;

/// A vector whose three components are each animatable: `(0.0, 0.72, 0.0)`,
/// or with keys in place of any number.
pub type ParamVec3 = (Param, Param, Param);

/// One collider. A disabled collider is kept in the file and ignored.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Collider {
    /// The plane y = `height`; the cloth stays above it.
    Ground(Ground),
    /// An oriented box (a table top).
    Box(Block),
    /// A cylinder, its axis +Y before rotation (a round table).
    Cylinder(Cylinder),
    Sphere(Sphere),
    /// The segment a–b swollen by `radius` (an arm, a pole).
    Capsule(Capsule),
    /// A closed triangle mesh read from an OBJ or glTF file (a chair, a body).
    Mesh(MeshCollider),
}

/// A triangle mesh from a file, placed: a mesh point m is at
/// `center + rotation · (scale · m)`. (`Mesh` in files and messages.)
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Mesh")]
pub struct MeshCollider {
    #[serde(default)]
    pub name: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    /// An OBJ (`.obj`) or glTF (`.glb`, `.gltf`) file, relative to the scene file.
    pub file: String,
    #[serde(default = "zeros")]
    pub center: ParamVec3,
    /// X, then Y, then Z, degrees, about the centre.
    #[serde(default = "zeros")]
    pub rotation_deg: ParamVec3,
    /// Greater than 0.
    #[serde(default = "one")]
    pub scale: Param,
    /// The solid `file` holds, once read ([`crate::scene::load`] and the
    /// editor read it); not written to the file.
    #[serde(skip)]
    pub solid: LoadedMesh,
}

/// A ground plane.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ground {
    #[serde(default)]
    pub name: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    /// Distance the cloth keeps from the surface (m); absent: the key's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    /// The plane's height (m).
    #[serde(default = "zero")]
    pub height: Param,
}

/// An oriented box: `size` is its full extent along its own axes. (`Box` in
/// files and messages; the Rust name keeps clear of `std`'s.)
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Box")]
pub struct Block {
    #[serde(default)]
    pub name: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    pub center: ParamVec3,
    /// Full extent along the box's own x, y, z (m); each greater than 0.
    pub size: ParamVec3,
    /// X, then Y, then Z, degrees, about the centre.
    #[serde(default = "zeros")]
    pub rotation_deg: ParamVec3,
}

/// A cylinder with flat caps: `height` is its full length along its axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cylinder {
    #[serde(default)]
    pub name: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    pub center: ParamVec3,
    pub radius: Param,
    pub height: Param,
    /// X, then Y, then Z, degrees, about the centre; the axis is +Y before it.
    #[serde(default = "zeros")]
    pub rotation_deg: ParamVec3,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sphere {
    #[serde(default)]
    pub name: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    pub center: ParamVec3,
    pub radius: Param,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Capsule {
    #[serde(default)]
    pub name: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    pub a: ParamVec3,
    pub b: ParamVec3,
    pub radius: Param,
}

pub(super) fn yes() -> bool {
    true
}

pub(super) fn is_true(value: &bool) -> bool {
    *value
}

fn zero() -> Param {
    Param::Constant(0.0)
}

pub(super) fn one() -> Param {
    Param::Constant(1.0)
}

pub(super) fn zeros() -> ParamVec3 {
    (zero(), zero(), zero())
}

/// What a collider's number stands for, for validation and the editor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// A position (m): finite and within the world's bounds.
    Position,
    /// A size or radius (m): greater than 0.
    Length,
    /// An angle (degrees).
    Angle,
    /// A factor without a unit: greater than 0.
    Scale,
}

/// One field of a collider kind: a plain number or a vector of three.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColliderField {
    pub name: &'static str,
    pub vector: bool,
    pub measure: Measure,
}

const fn field(name: &'static str, vector: bool, measure: Measure) -> ColliderField {
    ColliderField { name, vector, measure }
}

const GROUND_FIELDS: &[ColliderField] = &[field("height", false, Measure::Position)];
const BOX_FIELDS: &[ColliderField] = &[
    field("center", true, Measure::Position),
    field("size", true, Measure::Length),
    field("rotation_deg", true, Measure::Angle),
];
const CYLINDER_FIELDS: &[ColliderField] = &[
    field("center", true, Measure::Position),
    field("radius", false, Measure::Length),
    field("height", false, Measure::Length),
    field("rotation_deg", true, Measure::Angle),
];
const SPHERE_FIELDS: &[ColliderField] =
    &[field("center", true, Measure::Position), field("radius", false, Measure::Length)];
const MESH_FIELDS: &[ColliderField] = &[
    field("center", true, Measure::Position),
    field("rotation_deg", true, Measure::Angle),
    field("scale", false, Measure::Scale),
];
const CAPSULE_FIELDS: &[ColliderField] = &[
    field("a", true, Measure::Position),
    field("b", true, Measure::Position),
    field("radius", false, Measure::Length),
];

/// One number of a collider: a field and, in a vector, its component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColliderNumber {
    pub field: ColliderField,
    /// 0, 1, 2 for x, y, z in a vector; `None` for a plain number.
    pub component: Option<usize>,
}

impl ColliderNumber {
    /// The number's path below the collider, as validation reports it: `center[1]`.
    pub fn path(&self) -> String {
        match self.component {
            Some(index) => format!("{}[{index}]", self.field.name),
            None => self.field.name.to_string(),
        }
    }

    /// The number's name in messages and the editor: `center y`, `radius`.
    pub fn label(&self) -> String {
        match self.component {
            Some(index) => format!("{} {}", self.field.name, ["x", "y", "z"][index.min(2)]),
            None => self.field.name.to_string(),
        }
    }
}

impl Collider {
    /// Every kind as the scene file writes it, in the editor's order.
    pub const KINDS: &'static [&'static str] = &["Ground", "Box", "Cylinder", "Sphere", "Capsule", "Mesh"];

    /// The kind as the scene file writes it.
    pub fn kind(&self) -> &'static str {
        match self {
            Collider::Ground(_) => "Ground",
            Collider::Box(_) => "Box",
            Collider::Cylinder(_) => "Cylinder",
            Collider::Sphere(_) => "Sphere",
            Collider::Capsule(_) => "Capsule",
            Collider::Mesh(_) => "Mesh",
        }
    }

    /// The kind's fields but name, enabled and thickness, in file order.
    pub fn fields(&self) -> &'static [ColliderField] {
        match self {
            Collider::Ground(_) => GROUND_FIELDS,
            Collider::Box(_) => BOX_FIELDS,
            Collider::Cylinder(_) => CYLINDER_FIELDS,
            Collider::Sphere(_) => SPHERE_FIELDS,
            Collider::Capsule(_) => CAPSULE_FIELDS,
            Collider::Mesh(_) => MESH_FIELDS,
        }
    }

    /// Every number of [`fields`](Self::fields), vectors by component, in file order.
    pub fn numbers(&self) -> Vec<ColliderNumber> {
        let mut out = Vec::new();
        for &field in self.fields() {
            if field.vector {
                out.extend((0..3).map(|c| ColliderNumber { field, component: Some(c) }));
            } else {
                out.push(ColliderNumber { field, component: None });
            }
        }
        out
    }

    /// The value of `number`; `None` when this kind has no such number.
    pub fn param(&self, number: ColliderNumber) -> Option<&Param> {
        let (plain, vector) = match self {
            Collider::Ground(c) => (vec![("height", &c.height)], vec![]),
            Collider::Box(c) => {
                (vec![], vec![("center", &c.center), ("size", &c.size), ("rotation_deg", &c.rotation_deg)])
            }
            Collider::Cylinder(c) => (
                vec![("radius", &c.radius), ("height", &c.height)],
                vec![("center", &c.center), ("rotation_deg", &c.rotation_deg)],
            ),
            Collider::Sphere(c) => (vec![("radius", &c.radius)], vec![("center", &c.center)]),
            Collider::Capsule(c) => (vec![("radius", &c.radius)], vec![("a", &c.a), ("b", &c.b)]),
            Collider::Mesh(c) => {
                (vec![("scale", &c.scale)], vec![("center", &c.center), ("rotation_deg", &c.rotation_deg)])
            }
        };
        let name = number.field.name;
        match number.component {
            None => plain.into_iter().find(|(n, _)| *n == name).map(|(_, p)| p),
            Some(c) => vector.into_iter().find(|(n, _)| *n == name).and_then(|(_, v)| component(v, c)),
        }
    }

    /// [`param`](Self::param), to change.
    pub fn param_mut(&mut self, number: ColliderNumber) -> Option<&mut Param> {
        let (plain, vector) = match self {
            Collider::Ground(c) => (vec![("height", &mut c.height)], vec![]),
            Collider::Box(c) => {
                (vec![], vec![("center", &mut c.center), ("size", &mut c.size), ("rotation_deg", &mut c.rotation_deg)])
            }
            Collider::Cylinder(c) => (
                vec![("radius", &mut c.radius), ("height", &mut c.height)],
                vec![("center", &mut c.center), ("rotation_deg", &mut c.rotation_deg)],
            ),
            Collider::Sphere(c) => (vec![("radius", &mut c.radius)], vec![("center", &mut c.center)]),
            Collider::Capsule(c) => (vec![("radius", &mut c.radius)], vec![("a", &mut c.a), ("b", &mut c.b)]),
            Collider::Mesh(c) => {
                (vec![("scale", &mut c.scale)], vec![("center", &mut c.center), ("rotation_deg", &mut c.rotation_deg)])
            }
        };
        let name = number.field.name;
        match number.component {
            None => plain.into_iter().find(|(n, _)| *n == name).map(|(_, p)| p),
            Some(c) => vector.into_iter().find(|(n, _)| *n == name).and_then(|(_, v)| component_mut(v, c)),
        }
    }

    /// The fields every kind has: name, enabled, thickness.
    fn common(&self) -> (&String, &bool, &Option<Param>) {
        match self {
            Collider::Ground(c) => (&c.name, &c.enabled, &c.thickness),
            Collider::Box(c) => (&c.name, &c.enabled, &c.thickness),
            Collider::Cylinder(c) => (&c.name, &c.enabled, &c.thickness),
            Collider::Sphere(c) => (&c.name, &c.enabled, &c.thickness),
            Collider::Capsule(c) => (&c.name, &c.enabled, &c.thickness),
            Collider::Mesh(c) => (&c.name, &c.enabled, &c.thickness),
        }
    }

    /// [`common`](Self::common), to change.
    fn common_mut(&mut self) -> (&mut String, &mut bool, &mut Option<Param>) {
        match self {
            Collider::Ground(c) => (&mut c.name, &mut c.enabled, &mut c.thickness),
            Collider::Box(c) => (&mut c.name, &mut c.enabled, &mut c.thickness),
            Collider::Cylinder(c) => (&mut c.name, &mut c.enabled, &mut c.thickness),
            Collider::Sphere(c) => (&mut c.name, &mut c.enabled, &mut c.thickness),
            Collider::Capsule(c) => (&mut c.name, &mut c.enabled, &mut c.thickness),
            Collider::Mesh(c) => (&mut c.name, &mut c.enabled, &mut c.thickness),
        }
    }

    pub fn name(&self) -> &str {
        self.common().0
    }

    pub fn name_mut(&mut self) -> &mut String {
        self.common_mut().0
    }

    pub fn enabled(&self) -> bool {
        *self.common().1
    }

    pub fn enabled_mut(&mut self) -> &mut bool {
        self.common_mut().1
    }

    /// The collider's own thickness (m), if it overrides the key's.
    pub fn thickness(&self) -> Option<&Param> {
        self.common().2.as_ref()
    }

    pub fn thickness_mut(&mut self) -> &mut Option<Param> {
        self.common_mut().2
    }

    /// Whether no number of the collider is animated: it is the same solid at every frame.
    pub fn is_still(&self) -> bool {
        let constant = |p: Option<&Param>| p.is_none_or(|p| matches!(p, Param::Constant(_)));
        constant(self.thickness()) && self.numbers().into_iter().all(|n| constant(self.param(n)))
    }

    /// The label used in messages: `Box collider "table"`, or `Box collider 2` when unnamed.
    pub fn label(&self, index: usize) -> String {
        let (kind, name) = (self.kind(), self.name());
        if name.is_empty() {
            format!("{kind} collider {}", index + 1)
        } else {
            format!("{kind} collider {:?}", super::truncated_name(name))
        }
    }

    /// A collider of `kind` as the editor adds it, sized for a cloth of a
    /// metre or two: a table top at 72 cm, a ball at 1 m. `None` when `kind`
    /// is none of [`Collider::KINDS`].
    pub fn with_start_values(kind: &str) -> Option<Collider> {
        let v = |x: f64, y: f64, z: f64| (Param::Constant(x), Param::Constant(y), Param::Constant(z));
        let (name, enabled, thickness) = (String::new(), true, None);
        Some(match kind {
            "Ground" => Collider::Ground(Ground { name, enabled, thickness, height: zero() }),
            "Box" => Collider::Box(Block {
                name,
                enabled,
                thickness,
                center: v(0.0, 0.72, 0.0),
                size: v(1.2, 0.04, 0.8),
                rotation_deg: zeros(),
            }),
            "Cylinder" => Collider::Cylinder(Cylinder {
                name,
                enabled,
                thickness,
                center: v(0.0, 0.72, 0.0),
                radius: Param::Constant(0.6),
                height: Param::Constant(0.04),
                rotation_deg: zeros(),
            }),
            "Sphere" => Collider::Sphere(Sphere {
                name,
                enabled,
                thickness,
                center: v(0.0, 1.0, 0.0),
                radius: Param::Constant(0.3),
            }),
            "Capsule" => Collider::Capsule(Capsule {
                name,
                enabled,
                thickness,
                a: v(-0.3, 1.4, 0.0),
                b: v(0.3, 1.4, 0.0),
                radius: Param::Constant(0.08),
            }),
            // No file yet: the editor asks for one.
            "Mesh" => Collider::Mesh(MeshCollider {
                name,
                enabled,
                thickness,
                file: String::new(),
                center: zeros(),
                rotation_deg: zeros(),
                scale: one(),
                solid: LoadedMesh::default(),
            }),
            _ => return None,
        })
    }
}

fn component(v: &ParamVec3, index: usize) -> Option<&Param> {
    match index {
        0 => Some(&v.0),
        1 => Some(&v.1),
        2 => Some(&v.2),
        _ => None,
    }
}

fn component_mut(v: &mut ParamVec3, index: usize) -> Option<&mut Param> {
    match index {
        0 => Some(&mut v.0),
        1 => Some(&mut v.1),
        2 => Some(&mut v.2),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_number_of_every_kind_is_reached() {
        for kind in Collider::KINDS {
            let Some(mut collider) = Collider::with_start_values(kind) else { panic!("{kind} has no start values") };
            assert_eq!(collider.kind(), *kind);
            for number in collider.numbers() {
                assert!(collider.param(number).is_some(), "{kind} {}", number.label());
                let Some(param) = collider.param_mut(number) else { panic!("{kind} {}", number.label()) };
                *param = Param::Constant(7.5);
                assert_eq!(collider.param(number), Some(&Param::Constant(7.5)));
            }
        }
        assert!(Collider::with_start_values("Torus").is_none());
    }

    #[test]
    fn colliders_read_with_defaults_and_reject_unknown_fields() {
        let text = "[Ground((name: \"floor\")), Box((center: (0.0, 0.72, 0.0), size: (1.2, 0.04, 0.8)))]";
        let Ok(colliders) = ron::from_str::<Vec<Collider>>(text) else { panic!("reads") };
        assert_eq!(colliders[0].param(colliders[0].numbers()[0]), Some(&Param::Constant(0.0)));
        assert!(colliders.iter().all(Collider::enabled));
        let Collider::Box(table) = &colliders[1] else { panic!("a box") };
        assert_eq!(table.rotation_deg, zeros());
        assert!(ron::from_str::<Collider>("Sphere((center: (0, 1, 0), radius: 0.3, radious: 1))").is_err());
        let keyed = "Sphere((center: (0, [(frame: 0, value: 1.0), (frame: 24, value: 2.0)], 0), radius: 0.3))";
        let Ok(Collider::Sphere(ball)) = ron::from_str::<Collider>(keyed) else { panic!("reads keys") };
        assert!(matches!(ball.center.1, Param::Keys(ref keys) if keys.len() == 2));
    }
}
