//! The scene document: the serde types of a `.ron` scene file.
//!
//! Field names are fixed by DESIGN.md so that scenes written by other tools keep
//! loading: never rename them. New fields must carry a serde default. Unknown
//! fields are rejected (`deny_unknown_fields`) so a typo such as `elastisity`
//! is reported instead of silently ignored.

use serde::{Deserialize, Serialize};

use super::param::Param;

/// The whole document: one cloth, its timeline, its rest-shape keys and its layer stack.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// File format version; only `1` exists.
    pub version: u32,
    #[serde(default)]
    pub name: String,
    pub cloth: Cloth,
    #[serde(default)]
    pub timeline: Timeline,
    /// Rest-shape keys in strictly increasing frame order; at least one.
    pub keys: Vec<Key>,
    #[serde(default)]
    pub layers: Vec<Layer>,
    /// Where the editor's camera looked when the scene was saved; absent, views frame the cloth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub view: Option<View>,
}

impl Scene {
    /// The key in effect at `frame`: the last one at or before it, else the
    /// first (frames before the first key hold it). Panics on a scene with no
    /// keys, which validation rejects.
    pub fn key_in_effect(&self, frame: f64) -> &Key {
        self.keys.iter().rev().find(|k| k.frame as f64 <= frame).unwrap_or(&self.keys[0])
    }
}

/// The cloth's material: a rectangle of `size` metres sampled by a `grid` of points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cloth {
    /// (width, height) in metres: the material extent along u (i) and v (j).
    pub size: (f64, f64),
    /// (cols, rows): number of grid points along u and v, each at least 2.
    pub grid: (u32, u32),
    /// The picture on the cloth.
    #[serde(default)]
    pub texture: ClothTexture,
}

impl Cloth {
    /// A plain cloth of `size` (width, height) metres on a `grid` of (cols, rows) points.
    pub fn new(size: (f64, f64), grid: (u32, u32)) -> Cloth {
        Cloth { size, grid, texture: ClothTexture::Plain }
    }

    pub fn cols(&self) -> usize {
        self.grid.0 as usize
    }
    pub fn rows(&self) -> usize {
        self.grid.1 as usize
    }
    pub fn width_m(&self) -> f64 {
        self.size.0
    }
    pub fn height_m(&self) -> f64 {
        self.size.1
    }
    /// Material spacing between neighbouring columns (metres).
    pub fn spacing_u_m(&self) -> f64 {
        self.size.0 / (self.grid.0.max(2) - 1) as f64
    }
    /// Material spacing between neighbouring rows (metres).
    pub fn spacing_v_m(&self) -> f64 {
        self.size.1 / (self.grid.1.max(2) - 1) as f64
    }
    /// Material coordinates (u, v) in metres of grid point (i, j).
    pub fn material_uv(&self, i: usize, j: usize) -> (f64, f64) {
        (i as f64 * self.spacing_u_m(), j as f64 * self.spacing_v_m())
    }
}

/// An orbit camera: it looks at `target` from `distance_m` away, turned
/// `yaw_deg` about +Y (0° looks along −Z) and raised `pitch_deg` above the
/// target's horizon.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct View {
    /// The point the camera orbits (m).
    pub target: (f64, f64, f64),
    pub yaw_deg: f64,
    /// −89 to 89.
    pub pitch_deg: f64,
    /// Greater than 0.
    pub distance_m: f64,
    /// Vertical field of view, 5 to 120.
    #[serde(default = "View::default_fov_y_deg")]
    pub fov_y_deg: f64,
}

impl View {
    fn default_fov_y_deg() -> f64 {
        35.0
    }
}

/// The picture on the cloth: none (a plain dyed fabric) or one of the textures
/// Drape ships in `assets/`, mapped once across the cloth by its UVs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ClothTexture {
    #[default]
    Plain,
    /// A woven rug: borders, a medallion, a diamond field.
    Carpet,
    /// A UV checker: shows stretch, flips and seams.
    Checker,
}

/// Frames are integers; `t_secs = frame / fps`. The range includes both ends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Timeline {
    pub fps: f64,
    pub start: i32,
    pub end: i32,
}

impl Default for Timeline {
    fn default() -> Self {
        Timeline { fps: 24.0, start: 0, end: 120 }
    }
}

/// One rest-shape key: the pose of the cloth at `frame`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Key {
    pub frame: i32,
    /// Where the cloth hangs from; at least one, no grid point twice.
    pub pins: Vec<Pin>,
    /// ≥ 1: scales the fabric's length (catenary arc length and relaxation rest length).
    #[serde(default = "default_elasticity")]
    pub elasticity: f64,
    /// Bending resistance in [0, 1].
    #[serde(default = "default_stiffness")]
    pub stiffness: f64,
    #[serde(default)]
    pub relax: RelaxSettings,
    /// Interpolation from this key towards the next one.
    #[serde(default)]
    pub ease: Ease,
    /// Relaxation sweeps applied to each in-between of the segment from this
    /// key to the next, starting from the vertex blend with the pins at their
    /// interpolated positions: restores the cloth's length where straight
    /// blending shortens it. 0 (the default) keeps the plain blend.
    #[serde(default)]
    pub inbetween_relax: u32,
}

pub fn default_elasticity() -> f64 {
    1.0
}
pub fn default_stiffness() -> f64 {
    0.2
}

/// A grid point held at a fixed world position (metres).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pin {
    /// Grid index (i, j).
    pub grid: (u32, u32),
    /// World position in metres.
    pub pos: (f64, f64, f64),
}

/// When relaxation stops: once no constraint asks any point to move by more
/// than `tolerance` × the grid spacing in a sweep, or, unsettled, after
/// `iterations` sweeps per grid level. The cap never changes a shape that
/// settles within it (the coarsest level's settling is a fixed schedule on
/// top of it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RelaxSettings {
    pub iterations: u32,
    pub tolerance: f64,
}

impl Default for RelaxSettings {
    fn default() -> Self {
        RelaxSettings { iterations: 10000, tolerance: 1e-5 }
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

/// One deformer of the layer stack, applied in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Layer {
    Sway(Sway),
    Wave(Wave),
    Noise(Noise),
    FollowThrough(FollowThrough),
}

impl Layer {
    /// The kind as written in the scene file (`Sway`, `Wave`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Layer::Sway(_) => "Sway",
            Layer::Wave(_) => "Wave",
            Layer::Noise(_) => "Noise",
            Layer::FollowThrough(_) => "FollowThrough",
        }
    }

    pub fn name(&self) -> &str {
        match self {
            Layer::Sway(l) => &l.name,
            Layer::Wave(l) => &l.name,
            Layer::Noise(l) => &l.name,
            Layer::FollowThrough(l) => &l.name,
        }
    }

    pub fn enabled(&self) -> bool {
        match self {
            Layer::Sway(l) => l.enabled,
            Layer::Wave(l) => l.enabled,
            Layer::Noise(l) => l.enabled,
            Layer::FollowThrough(l) => l.enabled,
        }
    }

    pub fn enabled_mut(&mut self) -> &mut bool {
        match self {
            Layer::Sway(l) => &mut l.enabled,
            Layer::Wave(l) => &mut l.enabled,
            Layer::Noise(l) => &mut l.enabled,
            Layer::FollowThrough(l) => &mut l.enabled,
        }
    }

    pub fn weight(&self) -> &Param {
        match self {
            Layer::Sway(l) => &l.weight,
            Layer::Wave(l) => &l.weight,
            Layer::Noise(l) => &l.weight,
            Layer::FollowThrough(l) => &l.weight,
        }
    }

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
}

fn default_true() -> bool {
    true
}
fn default_one() -> Param {
    Param::Constant(1.0)
}
fn default_zero() -> Param {
    Param::Constant(0.0)
}
fn default_noise_scale() -> Param {
    Param::Constant(0.5)
}
fn default_turbulence() -> Param {
    Param::Constant(0.3)
}
fn default_octaves() -> u32 {
    2
}
fn default_lag() -> Param {
    Param::Constant(0.25)
}

/// Paper eq. 2: displacement = a · magnitude · speed · normalize(direction) · osc(t).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sway {
    #[serde(default)]
    pub name: String,
    #[serde(default = "default_true")]
    pub enabled: bool,
    #[serde(default = "default_one")]
    pub weight: Param,
    /// Metres.
    pub magnitude: Param,
    /// World direction; must not be zero.
    pub direction: (f64, f64, f64),
    #[serde(default = "default_one")]
    pub speed: Param,
    /// Hz; ≤ 0 means no built-in oscillation (osc = 1).
    #[serde(default = "default_zero")]
    pub frequency: Param,
    /// Radians, used with `frequency`.
    #[serde(default = "default_zero")]
    pub phase: Param,
    /// Exponent of the pin-distance attenuation a = (d_cp/d_max)^falloff.
    #[serde(default = "default_one")]
    pub falloff: Param,
}

/// Paper eqs. 3–4: displacement = a · magnitude · sin(x·frequency + phase + t·speed) along `axis`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Wave {
    #[serde(default)]
    pub name: String,
    #[serde(default = "default_true")]
    pub enabled: bool,
    #[serde(default = "default_one")]
    pub weight: Param,
    /// Metres.
    pub magnitude: Param,
    /// Radians per metre of material distance along the wave.
    #[serde(default = "default_one")]
    pub frequency: Param,
    /// Radians.
    #[serde(default = "default_zero")]
    pub phase: Param,
    /// Radians per second.
    #[serde(default = "default_one")]
    pub speed: Param,
    /// Direction of travel in material space, degrees from +u towards +v.
    #[serde(default = "default_zero")]
    pub direction_deg: Param,
    #[serde(default)]
    pub axis: WaveAxis,
    #[serde(default = "default_one")]
    pub falloff: Param,
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

/// Wind gusts: smooth, seeded turbulence scrolling with the wind.
///
/// displacement = a · amplitude · ((1 − turbulence) · gust · normalize(direction)
///                + turbulence · swirl), where gust ∈ [0, 1] and swirl ∈ [−1, 1]³
/// are smooth noise sampled at (p − normalize(direction) · speed · t) / scale,
/// p the point's position in the layer's input mesh. The same `seed` gives the
/// same gusts on every machine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Noise {
    #[serde(default)]
    pub name: String,
    #[serde(default = "default_true")]
    pub enabled: bool,
    #[serde(default = "default_one")]
    pub weight: Param,
    /// Metres.
    pub amplitude: Param,
    /// Size of a gust in metres; greater than 0.
    #[serde(default = "default_noise_scale")]
    pub scale: Param,
    /// Metres per second the gusts travel along `direction`.
    #[serde(default = "default_one")]
    pub speed: Param,
    /// World wind direction; must not be zero.
    pub direction: (f64, f64, f64),
    /// Share in [0, 1] of the displacement that swirls in every direction
    /// rather than pushing downwind.
    #[serde(default = "default_turbulence")]
    pub turbulence: Param,
    /// Layers of detail, each at half the size and half the strength of the previous: 1 to 6.
    #[serde(default = "default_octaves")]
    pub octaves: u32,
    #[serde(default)]
    pub seed: u32,
    #[serde(default = "default_one")]
    pub falloff: Param,
}

/// Overlapping action without physics: a point far from the pins follows the
/// keyed motion late. It moves by key_blend(t − lag · a) − key_blend(t), where
/// key_blend is the vertex blend of the rest shapes and a = (d_cp/d_max)^falloff.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FollowThrough {
    #[serde(default)]
    pub name: String,
    #[serde(default = "default_true")]
    pub enabled: bool,
    #[serde(default = "default_one")]
    pub weight: Param,
    /// Seconds the farthest point trails behind the pins; at least 0.
    #[serde(default = "default_lag")]
    pub lag: Param,
    #[serde(default = "default_one")]
    pub falloff: Param,
}
