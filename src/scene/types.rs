//! The scene document: the serde types of a `.ron` scene file.
//!
//! Field names are fixed by DESIGN.md so that scenes written by other tools keep
//! loading: never rename them. New fields must carry a serde default. Unknown
//! fields are rejected (`deny_unknown_fields`) so a typo such as `elastisity`
//! is reported instead of silently ignored. The layer kinds and their
//! parameters are in [`super::layers`].

use serde::{Deserialize, Serialize};

use super::colliders::Collider;
use super::layers::Layer;
use super::param::Ease;
use super::plate::Plate;
use super::references::{Attachment, Follow, Reference};
use super::shot_camera::ShotCamera;
use super::toon::ToonSettings;

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
    /// What the cloth rests on and never enters, in every key and frame.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub colliders: Vec<Collider>,
    /// glTF files of the shot (characters, props), drawn with the cloth and
    /// played on its timeline.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub references: Vec<Reference>,
    /// A node of a reference the cloth follows: its keys are carried by how
    /// the node moves (`animate::follow`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub follow: Option<Follow>,
    /// The shot camera: what `drape render` looks through by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<ShotCamera>,
    /// The background plate: a picture or a sequence behind the cloth,
    /// through the shot camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plate: Option<Plate>,
    /// Where the editor's camera looked when the scene was saved (with the
    /// playhead and Follow); absent, views frame the cloth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub view: Option<View>,
}

/// Format version 1, a 1 m square cloth on a 33 × 33 grid, the default
/// timeline, and nothing else: no key yet, so not valid until one is added
/// (a literal names what it needs and takes the rest from here).
impl Default for Scene {
    fn default() -> Scene {
        Scene {
            version: 1,
            name: String::new(),
            cloth: Cloth::new((1.0, 1.0), (33, 33)),
            timeline: Timeline::default(),
            keys: Vec::new(),
            layers: Vec::new(),
            colliders: Vec::new(),
            references: Vec::new(),
            follow: None,
            camera: None,
            plate: None,
            view: None,
        }
    }
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
    /// How much longer than its rest length the layers may make any edge
    /// along a row or column, as a fraction (0.1: 10 %); 0 turns the limit
    /// off. See `animate::stretch_limit`.
    #[serde(default = "default_stretch_limit")]
    pub stretch_limit: f64,
    /// How the toon style draws this cloth (the style is chosen where the
    /// picture is made); left out of the file while it is the default.
    #[serde(default, skip_serializing_if = "ToonSettings::is_default")]
    pub toon: ToonSettings,
}

/// The stretch limit a cloth gets when its file names none: 10 %.
pub const DEFAULT_STRETCH_LIMIT: f64 = 0.1;

fn default_stretch_limit() -> f64 {
    DEFAULT_STRETCH_LIMIT
}

impl Cloth {
    /// A plain cloth of `size` (width, height) metres on a `grid` of (cols, rows) points.
    pub fn new(size: (f64, f64), grid: (u32, u32)) -> Cloth {
        Cloth {
            size,
            grid,
            texture: ClothTexture::Plain,
            stretch_limit: DEFAULT_STRETCH_LIMIT,
            toon: ToonSettings::default(),
        }
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
    /// The editor's playhead when the view was saved: a scene opens there
    /// (kept on the timeline). Absent: the timeline's start.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<i32>,
    /// Whether the editor's camera follows the cloth as it travels.
    #[serde(default, skip_serializing_if = "View::is_false")]
    pub follow: bool,
    /// Whether the editor was looking through the shot camera: a scene
    /// opens that way again (one with a shot camera and no view does too).
    #[serde(default, skip_serializing_if = "View::is_false")]
    pub through_camera: bool,
}

impl View {
    fn default_fov_y_deg() -> f64 {
        35.0
    }

    fn is_false(value: &bool) -> bool {
        !*value
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
    /// Where the cloth hangs from; no grid point twice. Empty only when
    /// colliders hold the cloth up: it then falls from its `placement`.
    pub pins: Vec<Pin>,
    /// Where a key without pins starts, flat; keys with pins ignore it.
    /// None: [`Placement::default`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub placement: Option<Placement>,
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
    /// Metres the cloth keeps from colliders' surfaces (a collider may
    /// override it); at least 0.
    #[serde(default = "default_thickness")]
    pub thickness: f64,
    /// How much the cloth holds where it rests on a collider: 0 slides off,
    /// 1 and more hold (Coulomb's coefficient). At least 0.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// Where a key without pins starts: the flat cloth with u along +X and v
/// along +Z, centred at `center`, then turned by `rotation_deg` (about X,
/// then Y, then Z, degrees, about the centre).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// World position of the cloth's middle (m).
    pub center: (f64, f64, f64),
    #[serde(default)]
    pub rotation_deg: (f64, f64, f64),
}

impl Default for Placement {
    /// Level, its middle 1 m above the origin.
    fn default() -> Self {
        Placement { center: (0.0, 1.0, 0.0), rotation_deg: (0.0, 0.0, 0.0) }
    }
}

impl Key {
    /// Where the cloth starts when the key has no pins.
    pub fn placement_or_default(&self) -> Placement {
        self.placement.unwrap_or_default()
    }
}

/// The friction a key gets when its file names none.
pub const DEFAULT_FRICTION: f64 = 0.5;

pub fn default_friction() -> f64 {
    DEFAULT_FRICTION
}

/// The thickness a key gets when its file names none: 3 mm.
pub const DEFAULT_THICKNESS_M: f64 = 0.003;

pub fn default_thickness() -> f64 {
    DEFAULT_THICKNESS_M
}

pub fn default_elasticity() -> f64 {
    1.0
}
pub fn default_stiffness() -> f64 {
    0.2
}

/// A grid point held at a world position (metres), or bound to a reference.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pin {
    /// Grid index (i, j).
    pub grid: (u32, u32),
    /// World position in metres. For an attached pin, where its attachment
    /// was at the key's frame when it was attached: the attachment decides.
    pub pos: (f64, f64, f64),
    /// What the pin is bound to: it then sits exactly on its attachment at
    /// every frame (`animate::attachments`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attach: Option<Attachment>,
}

impl Pin {
    /// A loose pin at `pos`.
    pub fn at(grid: (u32, u32), pos: (f64, f64, f64)) -> Pin {
        Pin { grid, pos, attach: None }
    }
}

/// When relaxation stops: once no constraint asks any point to move by more
/// than `tolerance` × the grid spacing in a sweep, or, unsettled, after
/// `iterations` sweeps per grid level. The cap never changes a shape that
/// settles within it (the coarsest level's settling is a fixed schedule on
/// top of it). The default, 40 000, lets stiff cloth pinned tightly finish
/// its slow slides: a stiff strip on one pin needs 5 612 sweeps
/// (BENCHMARKS.md, "Stiff cloth").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RelaxSettings {
    pub iterations: u32,
    pub tolerance: f64,
}

impl Default for RelaxSettings {
    fn default() -> Self {
        RelaxSettings { iterations: 40_000, tolerance: 1e-5 }
    }
}
