//! References: glTF 2.0 files of the shot (a character, a prop, a flight
//! path) placed in the scene, their animation playing on the scene's clock.
//!
//! The document only: where the file is, how it is placed and timed,
//! whether it is drawn and whether it keeps the cloth out. The rig it holds is read by
//! [`super::read_references`]; posing it is `world::rig`'s, sampling it at a
//! frame `animate`'s.

use serde::{Deserialize, Serialize};

use super::colliders::{ParamVec3, is_true, one, yes, zeros};
use super::loaded::LoadedRig;
use super::param::Param;

/// A glTF file in the scene. A reference point m of the file is at
/// `center + rotation · (scale · m)` in the scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Reference {
    #[serde(default)]
    pub name: String,
    /// A glTF 2.0 file (`.glb`, or `.gltf` with its `.bin` beside it), relative to the scene file.
    pub file: String,
    /// The animation that plays, by name; absent: every animation of the
    /// file together (none if it has none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<String>,
    /// The scene frame at which the animation's time 0 plays (may be negative).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub start_frame: i32,
    /// How fast the animation plays: 1 as authored, 0.5 half speed; greater than 0.
    #[serde(default = "one_f64", skip_serializing_if = "is_one")]
    pub speed: f64,
    /// Plays the animation over and over (a walk cycle) instead of holding
    /// its first and last poses outside it.
    #[serde(default, skip_serializing_if = "is_false")]
    pub repeat: bool,
    #[serde(default = "zeros")]
    pub center: ParamVec3,
    /// X, then Y, then Z, degrees, about the centre.
    #[serde(default = "zeros")]
    pub rotation_deg: ParamVec3,
    /// Greater than 0.
    #[serde(default = "one")]
    pub scale: Param,
    /// Drawn in the viewport and in renders.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub visible: bool,
    /// Its meshes keep the cloth out at every frame's pose, like a mesh
    /// collider's (each closed part of the file a solid).
    #[serde(default, skip_serializing_if = "is_false")]
    pub collider: bool,
    /// Distance the cloth keeps from its surface (m) when it is a collider; absent: the key's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<Param>,
    /// The rig `file` holds, once read; not written to the file.
    #[serde(skip)]
    pub rig: LoadedRig,
}

impl Reference {
    /// How messages and panels name it: its name, else "reference N" (1-based).
    pub fn label(&self, index: usize) -> String {
        if self.name.trim().is_empty() {
            format!("reference {}", index + 1)
        } else {
            format!("reference {:?}", self.name)
        }
    }

    /// The clips that play (indices into the rig's clips): the named one,
    /// else every clip of the file together (Blender exports a skeleton's
    /// action and its mesh's shape-key action as two); empty when the rig is
    /// not read, has none or lacks the named one.
    pub fn playing_clips(&self) -> Vec<usize> {
        let Some(rig) = self.rig.0.as_deref() else { return Vec::new() };
        match &self.animation {
            Some(name) => rig.clip_named(name).into_iter().collect(),
            None => (0..rig.clips().len()).collect(),
        }
    }

    /// The span (s) of the clips that play together: from the earliest key
    /// of any to the latest; None without a clip.
    pub fn clip_span_secs(&self) -> Option<(f64, f64)> {
        let rig = self.rig.0.as_deref()?;
        let spans = self.playing_clips().into_iter().map(|c| rig.clips()[c].span_secs());
        spans.reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }

    /// Where its clips play on a timeline at `fps`: the inverse of
    /// [`Reference::clip_time_secs`] at their first and last key; None
    /// without a clip ([`Reference::playing_clips`]).
    pub fn clip_frames(&self, fps: f64) -> Option<ClipFrames> {
        let rig = self.rig.0.as_deref()?;
        let secs = self.clip_span_secs()?;
        let names: Vec<&str> = self.playing_clips().into_iter().map(|c| rig.clips()[c].name.as_str()).collect();
        let frame_at = |t: f64| f64::from(self.start_frame) + t * fps / self.speed;
        Some(ClipFrames {
            name: names.join(" + "),
            secs,
            frames: (frame_at(secs.0), frame_at(secs.1)),
            repeat: self.repeat,
        })
    }

    /// The time (s) on the animation's clock at scene frame `frame` of a
    /// timeline at `fps`, for an animation spanning `span_secs`: repeated
    /// within the span when `repeat` is on.
    pub fn clip_time_secs(&self, frame: f64, fps: f64, span_secs: (f64, f64)) -> f64 {
        let t = (frame - self.start_frame as f64) / fps * self.speed;
        let (first, last) = span_secs;
        if self.repeat && last > first { first + (t - first).rem_euclid(last - first) } else { t }
    }
}

/// A node the whole cloth follows (`follow` in the scene): every key is
/// authored where the node is at the key's frame, and at any frame the
/// blended cloth is carried by how the node has moved since.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Follow {
    /// The reference's `name`.
    pub reference: String,
    /// The node's name in its file (any node, a skin's joint included).
    pub node: String,
}

/// What an attached pin is bound to, in a reference named by its `name`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Attachment {
    /// A point carried by a node (a joint of a skin, or any node).
    Node(NodeAttachment),
    /// A point on a mesh's surface, following its skinning and morphs.
    Surface(SurfaceAttachment),
}

/// A point fixed in a node's coordinates: `offset` there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeAttachment {
    /// The reference's `name`.
    pub reference: String,
    /// The node's name in the file.
    pub node: String,
    /// In the node's coordinates (the file's units, before the reference's scale).
    #[serde(default)]
    pub offset: (f64, f64, f64),
}

/// A point on triangle `triangle` of mesh `mesh` (the file's triangle
/// meshes in the order Drape reads them: `drape check` lists them), at
/// barycentric weights of its three corners, lifted `lift_m` along the
/// triangle's outward normal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceAttachment {
    /// The reference's `name`.
    pub reference: String,
    #[serde(default)]
    pub mesh: usize,
    pub triangle: usize,
    /// Weights of the triangle's corners: each at least 0, summing to 1.
    pub barycentric: (f64, f64, f64),
    /// Metres off the surface along its outward normal (a cape's seam sits
    /// a thickness out); may be negative.
    #[serde(default, skip_serializing_if = "is_zero_f64")]
    pub lift_m: f64,
}

impl Attachment {
    /// The `name` of the reference it is bound to.
    pub fn reference(&self) -> &str {
        match self {
            Attachment::Node(node) => &node.reference,
            Attachment::Surface(surface) => &surface.reference,
        }
    }
}

/// Where a reference's clip plays on the scene's timeline.
#[derive(Clone, Debug, PartialEq)]
pub struct ClipFrames {
    /// The clips' names in the file, joined by " + ".
    pub name: String,
    /// Its first and last key on its own clock (s).
    pub secs: (f64, f64),
    /// The scene frames (fractional) where its first and last key play, the first time.
    pub frames: (f64, f64),
    /// Whether it plays over and over.
    pub repeat: bool,
}

fn one_f64() -> f64 {
    1.0
}

fn is_one(value: &f64) -> bool {
    *value == 1.0
}

fn is_zero_f64(value: &f64) -> bool {
    *value == 0.0
}

fn is_zero(value: &i32) -> bool {
    *value == 0
}

fn is_false(value: &bool) -> bool {
    !*value
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(text: &str) -> Reference {
        ron::from_str(text).unwrap()
    }

    #[test]
    fn a_reference_needs_only_its_file() {
        let r = reference(r#"(file: "hero.glb")"#);
        assert_eq!((r.start_frame, r.speed, r.repeat, r.visible, r.collider), (0, 1.0, false, true, false));
        assert_eq!(r.scale, Param::Constant(1.0));
        assert_eq!(r.label(2), "reference 3");
        let written = ron::to_string(&r).unwrap();
        assert_eq!(reference(&written), r, "{written}");
    }

    #[test]
    fn the_clock_starts_at_start_frame_and_runs_at_speed() {
        let mut r = reference(r#"(file: "hero.glb", start_frame: 24, speed: 0.5)"#);
        // 24 fps: frame 72 is 2 s after the start, at half speed 1 s of the clip.
        assert_eq!(r.clip_time_secs(72.0, 24.0, (0.0, 1.0)), 1.0);
        assert_eq!(r.clip_time_secs(0.0, 24.0, (0.0, 1.0)), -0.5, "before the start: held by the sampler");
        r.repeat = true;
        assert_eq!(r.clip_time_secs(84.0, 24.0, (0.0, 1.0)), 0.25, "1.25 s wraps to 0.25");
        assert_eq!(r.clip_time_secs(0.0, 24.0, (0.0, 1.0)), 0.5, "−0.5 s wraps to 0.5");
        assert_eq!(r.clip_time_secs(30.0, 24.0, (0.0, 0.0)), 0.125, "an empty span does not wrap");
    }
}
