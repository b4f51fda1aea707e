//! Semantic checks of a scene that serde cannot express: ranges, limits,
//! ordering, finiteness.
//!
//! Each problem is an [`Issue`] naming the offending value by its path in the
//! file (`keys[0].pins[2].grid`), so the loader can point at its line and
//! column. Issues come in document order.

use std::collections::HashSet;
use std::fmt;

use super::colliders::{Collider, Measure, ParamVec3};
use super::display::{readable_number, readable_vec3};
use super::layers::Layer;
use super::layers::ParamValue;
use super::param::Ease;
use super::param::Param;
use super::plate::{MAX_PLATE_FRAME_OFFSET, Plate, PlatePattern};
use super::references::{Attachment, Reference};
use super::schema::{MAX_LAYER_VALUE, ParamRange, WaveAxis};
use super::shot_camera::ShotCamera;
use super::toon::{MAX_CREASE_DEG, MAX_INK_WIDTH_PX, MAX_TOON_BANDS, MIN_TOON_BANDS, SrgbColor, ToonSettings};
use super::types::{Key, Pin, Scene, View};

/// The only scene file version this Drape reads.
pub const SUPPORTED_VERSION: u32 = 1;
/// Largest cloth width or height, in metres.
pub const MAX_CLOTH_SIZE_M: f64 = 1000.0;
/// Fewest grid points along either side of the cloth.
pub const MIN_GRID_SIDE: u32 = 2;
/// Most grid points along either side of the cloth.
pub const MAX_GRID_SIDE: u32 = 1024;
/// Most grid points in total (512 × 512), which keeps relaxation interactive.
pub const MAX_GRID_POINTS: u64 = 512 * 512;
/// The timeline's start and end, every key's frame and every parameter key's
/// frame lie within ±this many frames (the editor's fields stop there too):
/// enough for over an hour at 24 fps, and frame counts, durations and the
/// distances between keys stay far from overflowing.
pub const MAX_TIMELINE_FRAME: i32 = 100_000;
/// Most pins in one key. Every stage of the rest shape is at most linear in
/// the pins beyond a few dozen (the approximation picks candidates from the
/// pins' Delaunay subdivision), so a key at this limit stays well under a
/// gigabyte; the limit keeps a file's numbers, not its size, from deciding
/// how much memory and time a key takes.
pub const MAX_PINS_PER_KEY: usize = 4096;
/// Most rest-shape points in a scene: keys × grid points (16 keys at
/// 512 × 512, over 5000 on a 33 × 25 curtain). Every key's rest shape is
/// kept while the scene is evaluated (about 25 MB a key at 512 × 512), and
/// a key that settles readily relaxes in about 10 s: at this limit `drape
/// check` takes under 500 MB (docs/editor.md, "Files and safety").
pub const MAX_KEY_POINTS: u64 = 1 << 22;
/// Most layers in the stack; each costs a pass over the cloth every frame:
/// at 512 × 512 the slowest (gusts with 6 octaves) about 15 ms a frame.
pub const MAX_LAYERS: usize = 32;
/// Highest frame rate, in frames per second.
pub const MAX_FPS: f64 = 1000.0;
/// Largest absolute pin coordinate along any axis, in metres.
pub const MAX_PIN_COORD_M: f64 = 10_000.0;
/// A view's pitch stays inside ±this many degrees: at ±90° its up vector would be undefined.
pub const MAX_VIEW_PITCH_DEG: f64 = 89.0;
/// A view's distance to its target, in metres: closer the near plane clips the target, farther depth degrades.
pub const MIN_VIEW_DISTANCE_M: f64 = 1e-3;
pub const MAX_VIEW_DISTANCE_M: f64 = 1e4;
/// Lowest elasticity: 1 is the fabric's own length, never shorter.
pub const MIN_ELASTICITY: f64 = 1.0;
/// Highest elasticity (ten times the fabric's length).
pub const MAX_ELASTICITY: f64 = 10.0;
/// Stiffness lies in [`MIN_STIFFNESS`], [`MAX_STIFFNESS`].
pub const MIN_STIFFNESS: f64 = 0.0;
pub const MAX_STIFFNESS: f64 = 1.0;
/// Most relaxation sweeps per key.
pub const MAX_RELAX_ITERATIONS: u32 = 100_000;
/// Largest relaxation tolerance (a fraction of the grid spacing); it must also be > 0.
pub const MAX_RELAX_TOLERANCE: f64 = 1.0;
/// Largest stretch limit: the layers may make an edge up to (1 + this) × its rest length.
pub const MAX_STRETCH_LIMIT: f64 = 10.0;
/// Most re-relaxation sweeps per in-between (each costs one sweep over the cloth per frame).
pub const MAX_INBETWEEN_RELAX: u32 = 1000;
/// Most colliders in a scene.
pub const MAX_COLLIDERS: usize = 256;
/// Largest friction coefficient.
pub const MAX_FRICTION: f64 = 10.0;
/// Largest thickness the cloth keeps from a collider (m).
pub const MAX_THICKNESS_M: f64 = 0.1;
/// Farthest an attached pin may sit off its surface (m).
pub const MAX_ATTACHMENT_LIFT_M: f64 = 1.0;
/// Longest focal length or widest sensor a shot camera may have (mm).
pub const MAX_LENS_MM: f64 = 10_000.0;
/// Largest side of a picture `drape render` draws and of a shot camera's
/// picture (pixels): a 4096 × 4096 render takes under 1 GB, an 8192 × 8192
/// one 3 GB.
pub const MAX_IMAGE_SIDE_PX: u32 = 4096;
/// Most references (glTF files) in a scene.
pub const MAX_REFERENCES: usize = 64;
/// Fastest a reference's animation may play, as a multiple of its own speed.
pub const MAX_REFERENCE_SPEED: f64 = 1000.0;

/// One problem found in a scene: the path of the offending value
/// (`keys[0].pins[2].grid`, `layers[1].magnitude[0].value`) and a message in
/// the user's terms.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Issue {
    pub path: String,
    pub message: String,
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

impl Scene {
    /// Checks every rule serde cannot: version, limits, ranges, key order, pins
    /// inside the grid, finite numbers. Returns all problems in document order.
    pub fn validate(&self) -> Result<(), Vec<Issue>> {
        let mut check = Checker::default();
        check.scene(self);
        if check.issues.is_empty() { Ok(()) } else { Err(check.issues) }
    }
}

/// `4000000` → `4 000 000`.
pub fn group_thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// `-2147483647` → `-2 147 483 647`.
fn group_thousands_signed(n: i64) -> String {
    let sign = if n < 0 { "-" } else { "" };
    format!("{sign}{}", group_thousands(n.unsigned_abs()))
}

#[derive(Default)]
struct Checker {
    issues: Vec<Issue>,
}

impl Checker {
    fn push(&mut self, path: impl Into<String>, message: impl Into<String>) {
        self.issues.push(Issue { path: path.into(), message: message.into() });
    }

    /// Reports a non-finite number; returns whether it was finite.
    fn finite(&mut self, path: &str, what: &str, v: f64) -> bool {
        if !v.is_finite() {
            self.push(path, format!("{what} must be a finite number, not {}", readable_number(v)));
        }
        v.is_finite()
    }

    /// Reports a frame beyond ±[`MAX_TIMELINE_FRAME`]; returns whether it was within.
    fn frame_within_limit(&mut self, path: &str, what: &str, frame: i32) -> bool {
        let within = (-MAX_TIMELINE_FRAME..=MAX_TIMELINE_FRAME).contains(&frame);
        if !within {
            self.push(
                path,
                format!(
                    "{what} {} is out of range: it must be within ±{} frames",
                    group_thousands_signed(frame.into()),
                    group_thousands(MAX_TIMELINE_FRAME as u64)
                ),
            );
        }
        within
    }

    fn scene(&mut self, scene: &Scene) {
        if scene.version != SUPPORTED_VERSION {
            self.push(
                "version",
                format!("unsupported scene version {} (this Drape reads version {SUPPORTED_VERSION})", scene.version),
            );
        }
        self.cloth(scene);
        self.timeline(scene);
        self.keys(scene);
        if scene.layers.len() > MAX_LAYERS {
            self.push(
                format!("layers[{MAX_LAYERS}]"),
                format!(
                    "the scene has {} layers; the limit is {MAX_LAYERS}",
                    group_thousands(scene.layers.len() as u64)
                ),
            );
        }
        for (index, layer) in scene.layers.iter().enumerate() {
            self.layer(index, layer);
        }
        if scene.colliders.len() > MAX_COLLIDERS {
            self.push(
                format!("colliders[{MAX_COLLIDERS}]"),
                format!(
                    "the scene has {} colliders; the limit is {MAX_COLLIDERS}",
                    group_thousands(scene.colliders.len() as u64)
                ),
            );
        }
        for (index, collider) in scene.colliders.iter().enumerate().take(MAX_COLLIDERS) {
            self.collider(index, collider);
        }
        if scene.references.len() > MAX_REFERENCES {
            self.push(
                format!("references[{MAX_REFERENCES}]"),
                format!("the scene has {} references; the limit is {MAX_REFERENCES}", scene.references.len()),
            );
        }
        for (index, reference) in scene.references.iter().enumerate().take(MAX_REFERENCES) {
            self.reference(index, reference);
        }
        if let Some(follow) = &scene.follow {
            let named = scene.references.iter().filter(|r| r.name == follow.reference).count();
            if named != 1 {
                let why = if named == 0 { "no reference has that name" } else { "several references have that name" };
                self.push("follow.reference", format!("the cloth follows reference {:?}, but {why}", follow.reference));
            }
        }
        if let Some(camera) = &scene.camera {
            self.camera(camera, &scene.references);
        }
        if let Some(plate) = &scene.plate {
            self.plate(plate);
        }
        if let Some(view) = &scene.view {
            self.view(view);
        }
    }

    /// The plate names a PNG or JPEG (or a sequence of them), shifted by a
    /// sane offset, at an opacity of 0 to 1.
    fn plate(&mut self, plate: &Plate) {
        match PlatePattern::parse(&plate.file) {
            Err(why) => self.push("plate.file", format!("plate: {why}")),
            Ok(pattern) => {
                let name = pattern.file_name(0);
                let extension =
                    std::path::Path::new(&name).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
                if !matches!(extension.as_deref(), Some("png" | "jpg" | "jpeg")) {
                    self.push("plate.file", format!("plate: {:?} is not a .png, .jpg or .jpeg file", plate.file));
                }
            }
        }
        if plate.frame_offset.abs() > MAX_PLATE_FRAME_OFFSET {
            self.push(
                "plate.frame_offset",
                format!("plate: frame_offset {} is beyond ±{MAX_PLATE_FRAME_OFFSET} frames", plate.frame_offset),
            );
        }
        self.layer_param("plate.opacity", "plate: opacity", &plate.opacity, ParamRange::Within(0.0, 1.0, ""));
    }

    /// The shot camera: where it is and what it looks at within the world,
    /// a lens and sensor greater than 0, a picture of sensible size; a
    /// reference's camera it follows names one reference of `references`
    /// (whether that file has the camera is known once it is read:
    /// [`super::read_references`]). Numbers a following camera does not use
    /// are checked too, so letting go of the reference never finds them bad.
    fn camera(&mut self, camera: &ShotCamera, references: &[Reference]) {
        if let Some(from) = &camera.from_reference {
            let named = references.iter().filter(|r| r.name == from.reference).count();
            if named != 1 {
                let names: Vec<String> = references.iter().map(|r| format!("{:?}", r.name)).collect();
                let why = match (named, names.is_empty()) {
                    (0, true) => "the scene has no references".to_owned(),
                    (0, false) => format!("no reference has that name (the scene has {})", names.join(", ")),
                    _ => "several references have that name".to_owned(),
                };
                self.push(
                    "camera.from_reference.reference",
                    format!("camera: from_reference names reference {:?}, but {why}", from.reference),
                );
            }
            if from.camera.trim().is_empty() {
                self.push(
                    "camera.from_reference.camera",
                    format!("camera: from_reference.camera is empty: name a camera of reference {:?}", from.reference),
                );
            }
        }
        let world = ParamRange::Within(-MAX_PIN_COORD_M, MAX_PIN_COORD_M, " m");
        self.vector_param("camera.position", "camera: position", &camera.position, world);
        self.vector_param("camera.target", "camera: target", &camera.target, world);
        let lens = ParamRange::Positive(MAX_LENS_MM);
        self.layer_param("camera.focal_length_mm", "camera: focal_length_mm", &camera.focal_length_mm, lens);
        self.layer_param("camera.sensor_width_mm", "camera: sensor_width_mm", &camera.sensor_width_mm, lens);
        let (width, height) = camera.image_size;
        if !(1..=MAX_IMAGE_SIDE_PX).contains(&width) || !(1..=MAX_IMAGE_SIDE_PX).contains(&height) {
            self.push(
                "camera.image_size",
                format!("camera: image_size {width} × {height} must be 1 to {MAX_IMAGE_SIDE_PX} pixels a side"),
            );
        }
    }

    /// Each component of a vector of parameters at `path` (`path[0]` …),
    /// named `what x` … in messages, within `range` at every key.
    fn vector_param(&mut self, path: &str, what: &str, (x, y, z): &ParamVec3, range: ParamRange) {
        for (axis, param) in [x, y, z].into_iter().enumerate() {
            let name = ["x", "y", "z"][axis];
            self.layer_param(&format!("{path}[{axis}]"), &format!("{what} {name}"), param, range);
        }
    }

    /// A reference's file is a glTF file; its clock runs forwards at a sane
    /// speed from a frame on the timeline's scale; its placement and
    /// thickness are within range at every key.
    fn reference(&mut self, index: usize, reference: &Reference) {
        let label = reference.label(index);
        let path = |field: &str| format!("references[{index}].{field}");
        let extension = std::path::Path::new(&reference.file).extension().and_then(|e| e.to_str());
        if reference.file.trim().is_empty() {
            self.push(
                path("file"),
                format!("{label}: file is empty: name a .glb or .gltf file (relative to the scene file)"),
            );
        } else if !extension.is_some_and(|e| ["glb", "gltf"].contains(&e.to_ascii_lowercase().as_str())) {
            self.push(
                path("file"),
                format!("{label}: {:?} is not a glTF file: a reference is a .glb or .gltf", reference.file),
            );
        }
        if !(reference.speed > 0.0 && reference.speed <= MAX_REFERENCE_SPEED) {
            self.push(
                path("speed"),
                format!(
                    "{label}: speed {} must be greater than 0 and at most {MAX_REFERENCE_SPEED}",
                    readable_number(reference.speed)
                ),
            );
        }
        if reference.start_frame.abs() > MAX_TIMELINE_FRAME {
            self.push(
                path("start_frame"),
                format!("{label}: start_frame {} is beyond ±{MAX_TIMELINE_FRAME}", reference.start_frame),
            );
        }
        let world = ParamRange::Within(-MAX_PIN_COORD_M, MAX_PIN_COORD_M, " m");
        self.vector_param(&path("center"), &format!("{label}: center"), &reference.center, world);
        self.vector_param(
            &path("rotation_deg"),
            &format!("{label}: rotation_deg"),
            &reference.rotation_deg,
            ParamRange::Any,
        );
        self.layer_param(
            &path("scale"),
            &format!("{label}: scale"),
            &reference.scale,
            ParamRange::Positive(MAX_PIN_COORD_M),
        );
        if let Some(thickness) = &reference.thickness {
            let range = ParamRange::Within(0.0, MAX_THICKNESS_M, " m");
            self.layer_param(&path("thickness"), &format!("{label}: thickness"), thickness, range);
        }
    }

    /// Every number of the collider: finite at every key, positions within
    /// the world, sizes greater than 0, the thickness within its range.
    fn collider(&mut self, index: usize, collider: &Collider) {
        let label = collider.label(index);
        for number in collider.numbers() {
            let Some(param) = collider.param(number) else { continue };
            let range = match number.field.measure {
                Measure::Position => ParamRange::Within(-MAX_PIN_COORD_M, MAX_PIN_COORD_M, " m"),
                Measure::Length | Measure::Scale => ParamRange::Positive(MAX_PIN_COORD_M),
                Measure::Angle => ParamRange::Any,
            };
            let (path, what) =
                (format!("colliders[{index}].{}", number.path()), format!("{label}: {}", number.label()));
            self.layer_param(&path, &what, param, range);
        }
        if let Collider::Mesh(mesh) = collider {
            let extension = std::path::Path::new(&mesh.file).extension().and_then(|e| e.to_str());
            let known = extension.is_some_and(|e| ["obj", "glb", "gltf"].contains(&e.to_ascii_lowercase().as_str()));
            if mesh.file.trim().is_empty() {
                self.push(
                    format!("colliders[{index}].file"),
                    format!("{label}: file is empty: name an .obj, .glb or .gltf file (relative to the scene file)"),
                );
            } else if !known {
                self.push(
                    format!("colliders[{index}].file"),
                    format!("{label}: {:?} is not a mesh file Drape reads: .obj, .glb or .gltf", mesh.file),
                );
            }
        }
        if let Some(thickness) = collider.thickness() {
            let range = ParamRange::Within(0.0, MAX_THICKNESS_M, " m");
            self.layer_param(
                &format!("colliders[{index}].thickness"),
                &format!("{label}: thickness"),
                thickness,
                range,
            );
        }
    }

    fn view(&mut self, view: &View) {
        let (x, y, z) = view.target;
        if ![x, y, z].iter().all(|c| c.is_finite() && c.abs() <= MAX_PIN_COORD_M) {
            self.push(
                "view.target",
                format!("view target {} must be finite and within ±10 000 m", readable_vec3(view.target)),
            );
        }
        self.finite("view.yaw_deg", "view yaw", view.yaw_deg);
        let ranges = [
            ("view.pitch_deg", "view pitch", view.pitch_deg, -MAX_VIEW_PITCH_DEG, MAX_VIEW_PITCH_DEG, "°"),
            ("view.distance_m", "view distance", view.distance_m, MIN_VIEW_DISTANCE_M, MAX_VIEW_DISTANCE_M, " m"),
            ("view.fov_y_deg", "view field of view", view.fov_y_deg, 5.0, 120.0, "°"),
        ];
        for (path, what, v, min, max, unit) in ranges {
            if self.finite(path, what, v) && !(min..=max).contains(&v) {
                self.push(
                    path,
                    format!(
                        "{what} {}{unit} is out of range: it must be between {min}{unit} and {max}{unit}",
                        readable_number(v)
                    ),
                );
            }
        }
    }

    fn cloth(&mut self, scene: &Scene) {
        let (width, height) = scene.cloth.size;
        for (index, what, v) in [(0, "cloth width", width), (1, "cloth height", height)] {
            let path = format!("cloth.size[{index}]");
            if !self.finite(&path, what, v) {
                continue;
            }
            if v <= 0.0 {
                self.push(path, format!("{what} must be greater than 0 m (it is {} m)", readable_number(v)));
            } else if v > MAX_CLOTH_SIZE_M {
                self.push(
                    path,
                    format!("{what} {} m is larger than the limit of {MAX_CLOTH_SIZE_M} m", readable_number(v)),
                );
            }
        }

        let (cols, rows) = scene.cloth.grid;
        let points = u64::from(cols) * u64::from(rows);
        if cols < MIN_GRID_SIDE || rows < MIN_GRID_SIDE {
            self.push(
                "cloth.grid",
                format!(
                    "grid {cols} × {rows} is too small: the cloth needs at least {MIN_GRID_SIDE} points along each side"
                ),
            );
        } else if points > MAX_GRID_POINTS {
            self.push(
                "cloth.grid",
                format!(
                    "grid {cols} × {rows} has {} points; the limit is {} (512 × 512)",
                    group_thousands(points),
                    group_thousands(MAX_GRID_POINTS)
                ),
            );
        } else if cols > MAX_GRID_SIDE || rows > MAX_GRID_SIDE {
            self.push(
                "cloth.grid",
                format!(
                    "grid {cols} × {rows} is too long: the limit is {} points along each side",
                    group_thousands(MAX_GRID_SIDE.into())
                ),
            );
        }

        let limit = scene.cloth.stretch_limit;
        if self.finite("cloth.stretch_limit", "stretch limit", limit) && !(0.0..=MAX_STRETCH_LIMIT).contains(&limit) {
            self.push(
                "cloth.stretch_limit",
                format!(
                    "stretch limit {} is out of range: it must be between 0 (off) and {MAX_STRETCH_LIMIT} \
                     (edges up to {}× their rest length)",
                    readable_number(limit),
                    1.0 + MAX_STRETCH_LIMIT
                ),
            );
        }
        self.toon(&scene.cloth.toon);
    }

    /// The toon settings: 2 or 3 bands, an ink width of 0 to
    /// [`MAX_INK_WIDTH_PX`] pixels, a crease angle of 0 to 180°, colours in 0..1.
    fn toon(&mut self, toon: &ToonSettings) {
        if !(MIN_TOON_BANDS..=MAX_TOON_BANDS).contains(&toon.bands) {
            self.push(
                "cloth.toon.bands",
                format!("toon: bands {} must be {MIN_TOON_BANDS} or {MAX_TOON_BANDS} (flat tones)", toon.bands),
            );
        }
        let width = toon.ink_width_px;
        if self.finite("cloth.toon.ink_width_px", "toon: ink_width_px", width)
            && !(0.0..=MAX_INK_WIDTH_PX).contains(&width)
        {
            self.push(
                "cloth.toon.ink_width_px",
                format!(
                    "toon: ink_width_px {} must be between 0 (no ink) and {MAX_INK_WIDTH_PX} pixels",
                    readable_number(width)
                ),
            );
        }
        self.srgb_color("ink_color", toon.ink_color);
        let crease = toon.crease_deg;
        if self.finite("cloth.toon.crease_deg", "toon: crease_deg", crease) && !(0.0..=MAX_CREASE_DEG).contains(&crease)
        {
            self.push(
                "cloth.toon.crease_deg",
                format!(
                    "toon: crease_deg {}° must be between 0 (ink every bend) and {MAX_CREASE_DEG}° (no creases)",
                    readable_number(crease)
                ),
            );
        }
        for (name, color) in [("front", toon.front), ("back", toon.back)] {
            if let Some(color) = color {
                self.srgb_color(name, color);
            }
        }
    }

    /// A toon colour `cloth.toon.<name>`: each sRGB component finite and in 0..1.
    fn srgb_color(&mut self, name: &str, (r, g, b): SrgbColor) {
        for (index, v) in [r, g, b].into_iter().enumerate() {
            let path = format!("cloth.toon.{name}[{index}]");
            let what = format!("toon: {name} {}", ["red", "green", "blue"][index]);
            if self.finite(&path, &what, v) && !(0.0..=1.0).contains(&v) {
                self.push(path, format!("{what} {} must be between 0 and 1 (sRGB)", readable_number(v)));
            }
        }
    }

    fn timeline(&mut self, scene: &Scene) {
        let timeline = &scene.timeline;
        if self.finite("timeline.fps", "fps", timeline.fps) && !(timeline.fps > 0.0 && timeline.fps <= MAX_FPS) {
            self.push(
                "timeline.fps",
                format!(
                    "fps {} is out of range: it must be greater than 0 and at most {MAX_FPS}",
                    readable_number(timeline.fps)
                ),
            );
        }
        let mut within = true;
        for (path, what, frame) in [("timeline.start", "start", timeline.start), ("timeline.end", "end", timeline.end)]
        {
            if !(-MAX_TIMELINE_FRAME..=MAX_TIMELINE_FRAME).contains(&frame) {
                within = false;
                self.push(
                    path,
                    format!(
                        "timeline {what} {} is out of range: it must be within ±{} frames",
                        group_thousands_signed(frame.into()),
                        group_thousands(MAX_TIMELINE_FRAME as u64)
                    ),
                );
            }
        }
        if within && timeline.start > timeline.end {
            self.push(
                "timeline.end",
                format!(
                    "the timeline ends at frame {} before it starts at frame {}: end must not be before start",
                    timeline.end, timeline.start
                ),
            );
        }
    }

    fn keys(&mut self, scene: &Scene) {
        if scene.keys.is_empty() {
            self.push("keys", "the scene has no keys: it needs at least one key with pins");
        }
        let (cols, rows) = scene.cloth.grid;
        let points = u64::from(cols) * u64::from(rows);
        if (1..=MAX_GRID_POINTS).contains(&points) && scene.keys.len() as u64 * points > MAX_KEY_POINTS {
            let most = MAX_KEY_POINTS / points;
            self.push(
                format!("keys[{most}]"),
                format!(
                    "the scene has {} keys on a {cols} × {rows} grid; at most {} fit, since keys × grid points \
                     may not pass {}: use fewer keys or a coarser grid",
                    group_thousands(scene.keys.len() as u64),
                    group_thousands(most),
                    group_thousands(MAX_KEY_POINTS)
                ),
            );
        }
        for (index, key) in scene.keys.iter().enumerate() {
            let path = format!("keys[{index}]");
            // A frame out of range says nothing more by its order.
            let within = self.frame_within_limit(&format!("{path}.frame"), "key frame", key.frame);
            if within && index > 0 {
                let previous = scene.keys[index - 1].frame;
                if key.frame == previous {
                    self.push(
                        format!("{path}.frame"),
                        format!("two keys at frame {}: each key needs a frame of its own", key.frame),
                    );
                } else if key.frame < previous {
                    self.push(
                        format!("{path}.frame"),
                        format!(
                            "key at frame {} comes after the key at frame {previous}: keys must be in increasing frame order",
                            key.frame
                        ),
                    );
                }
            }
            self.key(&path, key, scene);
        }
    }

    fn key(&mut self, path: &str, key: &Key, scene: &Scene) {
        let at = format!("the key at frame {}", key.frame);
        if key.pins.is_empty() && !scene.colliders.iter().any(|c| c.enabled()) {
            self.push(
                format!("{path}.pins"),
                format!(
                    "key at frame {} has no pins and no collider holds the cloth up: it needs at least one pin, or an enabled collider under its placement",
                    key.frame
                ),
            );
        }
        if let Some(placement) = &key.placement {
            self.placement(&format!("{path}.placement"), placement, &at);
        }
        if key.pins.len() > MAX_PINS_PER_KEY {
            self.push(
                format!("{path}.pins[{MAX_PINS_PER_KEY}]"),
                format!(
                    "key at frame {} has {} pins; the limit is {} pins per key",
                    key.frame,
                    group_thousands(key.pins.len() as u64),
                    group_thousands(MAX_PINS_PER_KEY as u64)
                ),
            );
        }
        let mut pinned = HashSet::new();
        for (index, pin) in key.pins.iter().enumerate().take(MAX_PINS_PER_KEY) {
            self.pin(&format!("{path}.pins[{index}]"), pin, &at, scene, &mut pinned);
        }

        let e_path = format!("{path}.elasticity");
        if self.finite(&e_path, &format!("elasticity in {at}"), key.elasticity)
            && !(MIN_ELASTICITY..=MAX_ELASTICITY).contains(&key.elasticity)
        {
            self.push(
                e_path,
                format!(
                    "elasticity {} in {at} is out of range: it must be between {MIN_ELASTICITY} (the fabric's own length) and {MAX_ELASTICITY}",
                    readable_number(key.elasticity)
                ),
            );
        }
        let s_path = format!("{path}.stiffness");
        if self.finite(&s_path, &format!("stiffness in {at}"), key.stiffness)
            && !(MIN_STIFFNESS..=MAX_STIFFNESS).contains(&key.stiffness)
        {
            self.push(
                s_path,
                format!(
                    "stiffness {} in {at} is out of range: it must be between {MIN_STIFFNESS} (limp) and {MAX_STIFFNESS} (stiff)",
                    readable_number(key.stiffness)
                ),
            );
        }
        if key.relax.iterations > MAX_RELAX_ITERATIONS {
            self.push(
                format!("{path}.relax.iterations"),
                format!(
                    "relax iterations {} in {at} is above the limit of {}",
                    group_thousands(key.relax.iterations.into()),
                    group_thousands(MAX_RELAX_ITERATIONS.into())
                ),
            );
        }
        let t_path = format!("{path}.relax.tolerance");
        let tolerance = key.relax.tolerance;
        if self.finite(&t_path, &format!("relax tolerance in {at}"), tolerance)
            && !(tolerance > 0.0 && tolerance <= MAX_RELAX_TOLERANCE)
        {
            self.push(
                t_path,
                format!(
                    "relax tolerance {} in {at} is out of range: it must be greater than 0 and at most {MAX_RELAX_TOLERANCE}",
                    readable_number(tolerance)
                ),
            );
        }
        self.ease(&format!("{path}.ease"), &format!("ease of {at}"), &key.ease);
        let thickness_path = format!("{path}.thickness");
        if self.finite(&thickness_path, &format!("thickness in {at}"), key.thickness)
            && !(0.0..=MAX_THICKNESS_M).contains(&key.thickness)
        {
            self.push(
                thickness_path,
                format!(
                    "thickness {} m in {at} is out of range: it must be between 0 and {MAX_THICKNESS_M} m",
                    readable_number(key.thickness)
                ),
            );
        }
        let friction_path = format!("{path}.friction");
        if self.finite(&friction_path, &format!("friction in {at}"), key.friction)
            && !(0.0..=MAX_FRICTION).contains(&key.friction)
        {
            self.push(
                friction_path,
                format!(
                    "friction {} in {at} is out of range: it must be between 0 (slides off) and {MAX_FRICTION}",
                    readable_number(key.friction)
                ),
            );
        }
        if key.inbetween_relax > MAX_INBETWEEN_RELAX {
            self.push(
                format!("{path}.inbetween_relax"),
                format!(
                    "inbetween_relax {} in {at} is above the limit of {MAX_INBETWEEN_RELAX} sweeps",
                    group_thousands(key.inbetween_relax.into())
                ),
            );
        }
    }

    fn pin(&mut self, path: &str, pin: &Pin, at: &str, scene: &Scene, pinned: &mut HashSet<(u32, u32)>) {
        let (i, j) = pin.grid;
        let (cols, rows) = scene.cloth.grid;
        if i >= cols || j >= rows {
            self.push(format!("{path}.grid"), format!("pin ({i}, {j}) is outside the {cols} × {rows} grid"));
        } else if !pinned.insert(pin.grid) {
            self.push(format!("{path}.grid"), format!("pin ({i}, {j}) is pinned twice in {at}"));
        }
        let pos = pin.pos;
        let pos_path = format!("{path}.pos");
        for (axis, v) in [("x", pos.0), ("y", pos.1), ("z", pos.2)] {
            if !v.is_finite() {
                self.push(
                    &pos_path,
                    format!("pin ({i}, {j}) in {at} has position {axis} = {v}: it must be a finite number"),
                );
                return;
            }
        }
        if [pos.0, pos.1, pos.2].iter().any(|v| v.abs() > MAX_PIN_COORD_M) {
            self.push(
                pos_path,
                format!(
                    "pin ({i}, {j}) in {at} is at {}, too far out: each coordinate must be within ±{} m",
                    readable_vec3(pos),
                    group_thousands(MAX_PIN_COORD_M as u64)
                ),
            );
        }
        if let Some(attachment) = &pin.attach {
            self.attachment(&format!("{path}.attach"), attachment, &format!("pin ({i}, {j}) in {at}"), scene);
        }
    }

    /// An attachment names one reference by its name, and its numbers are
    /// finite: an offset within the world, barycentric weights of a point on
    /// the triangle. What the file holds is checked once it is read.
    fn attachment(&mut self, path: &str, attachment: &Attachment, what: &str, scene: &Scene) {
        let name = attachment.reference();
        let named = scene.references.iter().filter(|r| r.name == name).count();
        let field = |f: &str| format!("{path}.{f}");
        if named != 1 {
            let why = if named == 0 { "no reference has that name" } else { "several references have that name" };
            self.push(field("reference"), format!("{what} is attached to reference {name:?}, but {why}"));
        }
        match attachment {
            Attachment::Node(node) => {
                let (x, y, z) = node.offset;
                if ![x, y, z].iter().all(|c| c.is_finite() && c.abs() <= MAX_PIN_COORD_M) {
                    self.push(
                        field("offset"),
                        format!("{what}: the offset {} is not a point in the world", readable_vec3(node.offset)),
                    );
                }
            }
            Attachment::Surface(surface) => {
                let (a, b, c) = surface.barycentric;
                let weights = [a, b, c];
                if !weights.iter().all(|w| w.is_finite() && *w >= -1e-9) || ((a + b + c) - 1.0).abs() > 1e-6 {
                    self.push(
                        field("barycentric"),
                        format!(
                            "{what}: barycentric {} must be three weights of at least 0 summing to 1",
                            readable_vec3(surface.barycentric)
                        ),
                    );
                }
                if !(surface.lift_m.is_finite() && surface.lift_m.abs() <= MAX_ATTACHMENT_LIFT_M) {
                    self.push(
                        field("lift_m"),
                        format!(
                            "{what}: lift_m {} must be within ±{MAX_ATTACHMENT_LIFT_M} m",
                            readable_number(surface.lift_m)
                        ),
                    );
                }
            }
        }
    }

    /// A pinless key's start: finite, its centre within the world's bounds.
    fn placement(&mut self, path: &str, placement: &super::Placement, at: &str) {
        for (field, v, limit, unit) in [
            ("center", placement.center, MAX_PIN_COORD_M, " m"),
            ("rotation_deg", placement.rotation_deg, super::MAX_LAYER_VALUE, "°"),
        ] {
            let field_path = format!("{path}.{field}");
            if let Some((axis, bad)) = [("x", v.0), ("y", v.1), ("z", v.2)].into_iter().find(|(_, c)| !c.is_finite()) {
                self.push(
                    field_path,
                    format!("placement {field} in {at} has {axis} = {bad}: it must be a finite number"),
                );
            } else if [v.0, v.1, v.2].iter().any(|c| c.abs() > limit) {
                self.push(
                    field_path,
                    format!(
                        "placement {field} in {at} is {}, too far out: each component must be within ±{}{unit}",
                        readable_vec3(v),
                        group_thousands(limit as u64)
                    ),
                );
            }
        }
    }

    /// Bezier control points: all finite, x1 and x2 in [0, 1].
    fn ease(&mut self, path: &str, what: &str, ease: &Ease) {
        let Ease::Bezier(x1, y1, x2, y2) = *ease else { return };
        for (index, (name, v)) in [("x1", x1), ("y1", y1), ("x2", x2), ("y2", y2)].into_iter().enumerate() {
            let element = format!("{path}[{index}]");
            if !v.is_finite() {
                self.push(
                    element,
                    format!("{what}: Bezier {name} must be a finite number, not {}", readable_number(v)),
                );
            } else if (name == "x1" || name == "x2") && !(0.0..=1.0).contains(&v) {
                self.push(
                    element,
                    format!(
                        "{what}: Bezier {name} = {} is out of range: x1 and x2 must be between 0 and 1",
                        readable_number(v)
                    ),
                );
            }
        }
    }

    /// A layer parameter: finite and within `range` at every key.
    fn layer_param(&mut self, path: &str, what: &str, param: &Param, range: ParamRange) {
        self.param(path, what, param);
        let values: Vec<(String, String, f64)> = match param {
            Param::Constant(v) => vec![(path.to_string(), what.to_string(), *v)],
            Param::Keys(keys) => keys
                .iter()
                .enumerate()
                .map(|(index, key)| {
                    (format!("{path}[{index}].value"), format!("{what} at frame {}", key.frame), key.value)
                })
                .collect(),
        };
        // A non-finite value is already reported.
        for (value_path, what, v) in values.into_iter().filter(|(_, _, v)| v.is_finite() && !range.contains(*v)) {
            let message = match range {
                ParamRange::Any => format!("{what} is {v:e}: it must be within ±{MAX_LAYER_VALUE:e}"),
                ParamRange::Within(lo, hi, why) => {
                    format!("{what} is {}: it must be between {lo} and {hi}{why}", readable_number(v))
                }
                ParamRange::Positive(hi) => {
                    let shown = if v.abs() > hi { format!("{v:e}") } else { readable_number(v) };
                    format!("{what} is {shown}: it must be greater than 0 and at most {hi:e}")
                }
            };
            self.push(value_path, message);
        }
    }

    fn param(&mut self, path: &str, what: &str, param: &Param) {
        match param {
            Param::Constant(v) => {
                self.finite(path, what, *v);
            }
            Param::Keys(keys) => {
                if keys.is_empty() {
                    self.push(
                        path,
                        format!("{what} has an empty list of keys: write a plain number or at least one key"),
                    );
                }
                for (index, key) in keys.iter().enumerate() {
                    let key_path = format!("{path}[{index}]");
                    let within =
                        self.frame_within_limit(&format!("{key_path}.frame"), &format!("{what} key frame"), key.frame);
                    if within && index > 0 {
                        let previous = keys[index - 1].frame;
                        if key.frame == previous {
                            self.push(
                                format!("{key_path}.frame"),
                                format!(
                                    "{what} has two keys at frame {}: each key needs a frame of its own",
                                    key.frame
                                ),
                            );
                        } else if key.frame < previous {
                            self.push(
                                format!("{key_path}.frame"),
                                format!(
                                    "{what} key at frame {} comes after the key at frame {previous}: keys must be in increasing frame order",
                                    key.frame
                                ),
                            );
                        }
                    }
                    self.finite(&format!("{key_path}.value"), &format!("{what} at frame {}", key.frame), key.value);
                    self.ease(&format!("{key_path}.ease"), &format!("{what} key at frame {}", key.frame), &key.ease);
                }
            }
        }
    }

    fn direction(&mut self, path: &str, what: &str, v: (f64, f64, f64), purpose: &str) {
        if ![v.0, v.1, v.2].iter().all(|c| c.is_finite()) {
            self.push(path, format!("{what} {} must be finite numbers", readable_vec3(v)));
        } else if v.0 == 0.0 && v.1 == 0.0 && v.2 == 0.0 {
            self.push(path, format!("{what} is zero: give a direction to {purpose}"));
        } else if !(v.0 * v.0 + v.1 * v.1 + v.2 * v.2).sqrt().is_finite() {
            self.push(path, format!("{what} {} is too long to normalise", readable_vec3(v)));
        }
    }

    /// Every parameter of the layer, as its schema entry allows.
    fn layer(&mut self, index: usize, layer: &Layer) {
        let label = layer.label(index);
        for spec in layer.params() {
            let (path, what) = (format!("layers[{index}].{}", spec.name), format!("{label}: {}", spec.name));
            match spec.value {
                ParamValue::Number(number) => {
                    if let Some(param) = number.access.get(layer) {
                        self.layer_param(&path, &what, param, number.range);
                    }
                }
                ParamValue::Direction(direction) => {
                    if let Some(v) = direction.access.get(layer) {
                        self.direction(&path, &what, *v, direction.purpose);
                    }
                }
                ParamValue::Axis(axis) => {
                    if let Some(WaveAxis::Fixed(v)) = axis.access.get(layer) {
                        self.direction(&path, &what, *v, axis.purpose);
                    }
                }
                ParamValue::Count(count) => {
                    if let Some(n) = count.access.get(layer)
                        && !(count.min..=count.max).contains(n)
                    {
                        self.push(path, format!("{what} is {n}: it must be between {} and {}", count.min, count.max));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Cloth, FollowThrough, ParamKey, RelaxSettings, Wave};

    fn scene() -> Scene {
        Scene {
            name: "t".into(),
            cloth: Cloth::new((2.0, 1.5), (33, 25)),
            keys: vec![Key {
                frame: 0,
                pins: vec![Pin::at((0, 0), (-1.0, 2.0, 0.0)), Pin::at((32, 0), (1.0, 2.0, 0.0))],
                elasticity: 1.1,
                stiffness: 0.2,
                relax: RelaxSettings::default(),
                ease: Ease::EaseInOut,
                inbetween_relax: 0,
                thickness: crate::scene::DEFAULT_THICKNESS_M,
                friction: crate::scene::DEFAULT_FRICTION,
                placement: None,
            }],
            ..Scene::default()
        }
    }

    fn messages(scene: &Scene) -> Vec<String> {
        scene.validate().err().unwrap_or_default().iter().map(ToString::to_string).collect()
    }

    #[test]
    fn a_good_scene_passes() {
        assert_eq!(scene().validate(), Ok(()));
    }

    #[test]
    fn pins_per_key_are_limited() {
        let mut s = scene();
        s.cloth.grid = (100, 100);
        s.keys[0].pins = (0..MAX_PINS_PER_KEY as u32).map(|k| Pin::at((k % 100, k / 100), (0.0, 1.0, 0.0))).collect();
        assert_eq!(s.validate(), Ok(()), "exactly the limit is allowed");
        s.keys[0].pins.push(Pin::at((99, 99), (0.0, 1.0, 0.0)));
        s.keys[0].pins.push(Pin::at((999, 0), (0.0, 1.0, 0.0)));
        assert_eq!(
            messages(&s),
            ["keys[0].pins[4096]: key at frame 0 has 4 098 pins; the limit is 4 096 pins per key"],
            "the pins beyond the limit are not checked one by one"
        );
    }

    #[test]
    fn keys_times_grid_points_are_limited() {
        let mut s = scene();
        s.cloth.grid = (512, 512);
        s.keys[0].pins[1].grid = (511, 0);
        s.keys = (0..17).map(|frame| Key { frame, ..s.keys[0].clone() }).collect();
        assert_eq!(
            messages(&s),
            ["keys[16]: the scene has 17 keys on a 512 × 512 grid; at most 16 fit, since keys × grid points \
              may not pass 4 194 304: use fewer keys or a coarser grid"]
        );
        s.keys.pop();
        assert_eq!(s.validate(), Ok(()));
    }

    #[test]
    fn layers_are_limited() {
        let mut s = scene();
        let layer = Layer::FollowThrough(FollowThrough { lag: 0.1.into(), ..FollowThrough::with_start_values() });
        s.layers = vec![layer; MAX_LAYERS];
        assert_eq!(s.validate(), Ok(()));
        s.layers.push(s.layers[0].clone());
        assert_eq!(messages(&s), ["layers[32]: the scene has 33 layers; the limit is 32"]);
    }

    #[test]
    fn key_frames_lie_within_the_timeline_limit() {
        let mut s = scene();
        s.keys[0].frame = -100_000;
        assert_eq!(s.validate(), Ok(()));
        s.keys[0].frame = i32::MIN;
        assert_eq!(
            messages(&s),
            ["keys[0].frame: key frame -2 147 483 648 is out of range: it must be within ±100 000 frames"]
        );
        s.keys[0].frame = 0;
        s.layers.push(Layer::FollowThrough(FollowThrough {
            name: "lag".into(),
            lag: Param::Keys(vec![
                ParamKey { frame: 0, value: 0.1, ease: Ease::Linear },
                ParamKey { frame: 100_001, value: 0.2, ease: Ease::Linear },
            ]),
            ..FollowThrough::with_start_values()
        }));
        assert_eq!(
            messages(&s),
            ["layers[0].lag[1].frame: FollowThrough layer \"lag\": lag key frame 100 001 is out of range: \
                 it must be within ±100 000 frames"]
        );
    }

    #[test]
    fn absurd_toon_settings_are_refused_by_name() {
        let mut s = scene();
        s.cloth.toon = crate::scene::ToonSettings {
            bands: 5,
            ink_width_px: -1.0,
            ink_color: (0.0, f64::NAN, 0.0),
            crease_deg: 200.0,
            front: Some((1.5, 0.0, 0.0)),
            back: None,
        };
        assert_eq!(
            messages(&s),
            [
                "cloth.toon.bands: toon: bands 5 must be 2 or 3 (flat tones)",
                "cloth.toon.ink_width_px: toon: ink_width_px -1 must be between 0 (no ink) and 32 pixels",
                "cloth.toon.ink_color[1]: toon: ink_color green must be a finite number, not NaN",
                "cloth.toon.crease_deg: toon: crease_deg 200° must be between 0 (ink every bend) and 180° (no creases)",
                "cloth.toon.front[0]: toon: front red 1.5 must be between 0 and 1 (sRGB)",
            ]
        );
        s.cloth.toon.ink_width_px = 33.0;
        s.cloth.toon.bands = 2;
        s.cloth.toon.crease_deg = 180.0;
        s.cloth.toon.ink_color = (0.0, 0.0, 0.0);
        s.cloth.toon.front = None;
        assert_eq!(
            messages(&s),
            ["cloth.toon.ink_width_px: toon: ink_width_px 33 must be between 0 (no ink) and 32 pixels"]
        );
    }

    #[test]
    fn grid_limits_are_stated() {
        let mut s = scene();
        s.cloth.grid = (2000, 2000);
        s.keys[0].pins.truncate(1);
        assert_eq!(
            messages(&s),
            ["cloth.grid: grid 2000 × 2000 has 4 000 000 points; the limit is 262 144 (512 × 512)"]
        );
        s.cloth.grid = (1025, 2);
        assert_eq!(messages(&s), ["cloth.grid: grid 1025 × 2 is too long: the limit is 1 024 points along each side"]);
        s.cloth.grid = (1, 5);
        assert_eq!(
            messages(&s),
            ["cloth.grid: grid 1 × 5 is too small: the cloth needs at least 2 points along each side"]
        );
    }

    #[test]
    fn every_problem_is_reported_in_document_order() {
        let mut s = scene();
        s.version = 2;
        s.keys[0].elasticity = f64::NAN;
        s.keys[0].pins[1].grid = (0, 0);
        s.layers.push(Layer::Wave(Wave {
            weight: Param::Constant(f64::INFINITY),
            magnitude: Param::Keys(vec![
                ParamKey { frame: 5, value: 0.0, ease: Ease::Linear },
                ParamKey { frame: 5, value: 1.0, ease: Ease::Bezier(0.0, 0.0, -0.5, 1.0) },
            ]),
            axis: WaveAxis::Fixed((0.0, 0.0, 0.0)),
            ..Wave::with_start_values()
        }));
        assert_eq!(
            messages(&s),
            [
                "version: unsupported scene version 2 (this Drape reads version 1)",
                "keys[0].pins[1].grid: pin (0, 0) is pinned twice in the key at frame 0",
                "keys[0].elasticity: elasticity in the key at frame 0 must be a finite number, not NaN",
                "layers[0].weight: Wave layer 1: weight must be a finite number, not inf",
                "layers[0].magnitude[1].frame: Wave layer 1: magnitude has two keys at frame 5: each key needs a frame of its own",
                "layers[0].magnitude[1].ease[2]: Wave layer 1: magnitude key at frame 5: Bezier x2 = -0.5 is out of range: x1 and x2 must be between 0 and 1",
                "layers[0].axis: Wave layer 1: axis is zero: give a direction to displace along",
            ]
        );
    }

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(group_thousands(0), "0");
        assert_eq!(group_thousands(999), "999");
        assert_eq!(group_thousands(262_144), "262 144");
        assert_eq!(group_thousands(4_000_000), "4 000 000");
    }
}
