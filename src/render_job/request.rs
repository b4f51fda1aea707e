//! What a render writes: the kind of output, where, which frames, how large
//! and what it shows.

use std::ops::RangeInclusive;
use std::path::PathBuf;

use crate::picture::SceneOverlays;
use crate::scene::Scene;

/// The size of a still when nothing says otherwise: full-HD-ish.
pub const DEFAULT_PNG_SIZE: (u32, u32) = (1280, 720);
/// The size of a GIF when nothing says otherwise: lighter, as GIFs are shared.
pub const DEFAULT_GIF_SIZE: (u32, u32) = (640, 360);
/// Largest side of a rendered picture, in pixels: the scene's limit for a
/// shot camera's picture, so every camera a scene holds can be rendered.
pub const MAX_SIDE_PX: u32 = crate::scene::MAX_IMAGE_SIDE_PX;

/// How to make a sequence or GIF smaller, for a refusal of its size.
pub(super) const RENDER_REMEDY: &str = "render fewer frames or smaller pictures";

/// How many frames `frames` holds, both ends included (0 when it ends before it starts).
pub(super) fn frame_count(frames: &RangeInclusive<i32>) -> u64 {
    (i64::from(*frames.end()) - i64::from(*frames.start()) + 1).max(0) as u64
}

/// What a render writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderKind {
    /// One PNG of the range's first frame.
    Png,
    /// A numbered PNG sequence `STEM_0000.png …` in a directory.
    Sequence,
    /// An animated GIF at the scene's fps.
    Gif,
}

impl RenderKind {
    pub const ALL: [RenderKind; 3] = [RenderKind::Png, RenderKind::Sequence, RenderKind::Gif];

    /// For menus: `PNG still`, `PNG sequence`, `GIF`.
    pub fn label(self) -> &'static str {
        match self {
            RenderKind::Png => "PNG still",
            RenderKind::Sequence => "PNG sequence",
            RenderKind::Gif => "GIF animation",
        }
    }

    /// Whether the output holds PNGs, which keep an alpha channel.
    pub fn is_png(self) -> bool {
        self != RenderKind::Gif
    }
}

/// A render: everything but the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderRequest {
    pub kind: RenderKind,
    /// The PNG or GIF file, or the directory of a sequence (made when
    /// missing, its parent never).
    pub output: PathBuf,
    /// Both ends included, within the scene's timeline. A PNG still renders
    /// the first frame alone.
    pub frames: RangeInclusive<i32>,
    /// Width and height in pixels, each 1 to [`MAX_SIDE_PX`].
    pub size_px: (u32, u32),
    /// What the pictures show, the camera, style and passes.
    pub overlays: SceneOverlays,
    /// Lays the pictures over the scene's background plate (an error when it
    /// has none; ignored for the alpha and shadow passes, which are meant to
    /// be laid over it later).
    pub plate: bool,
    /// Writes a sequence or GIF even when its size estimate is over 8 GiB or
    /// the free space on its disk.
    pub force: bool,
    /// A sequence into a folder holding frames of an earlier sequence of
    /// the same name that the new one does not write: removes exactly those
    /// files as the new frames move in (else the render is refused with
    /// [`super::RenderJobError::OldFrames`]).
    pub replace_sequence: bool,
}

impl RenderRequest {
    /// A render of `frames` at `size_px` with the default look: lit, no
    /// overlays, no plate, size and old frames checked.
    pub fn new(kind: RenderKind, output: PathBuf, frames: RangeInclusive<i32>, size_px: (u32, u32)) -> RenderRequest {
        RenderRequest {
            kind,
            output,
            frames,
            size_px,
            overlays: SceneOverlays::default(),
            plate: false,
            force: false,
            replace_sequence: false,
        }
    }

    /// The frames written: the first alone for a PNG still.
    pub fn written_frames(&self) -> RangeInclusive<i32> {
        match self.kind {
            RenderKind::Png => *self.frames.start()..=*self.frames.start(),
            RenderKind::Sequence | RenderKind::Gif => self.frames.clone(),
        }
    }
}

/// The picture size of a render of `kind` when nothing says otherwise: the
/// shot camera's image size when the render looks through it (the scene
/// has one and `view_camera` is off), else [`DEFAULT_GIF_SIZE`] for a GIF
/// and [`DEFAULT_PNG_SIZE`] for PNGs.
pub fn default_size_px(scene: &Scene, kind: RenderKind, view_camera: bool) -> (u32, u32) {
    match scene.camera.as_ref().filter(|_| !view_camera) {
        Some(camera) => camera.image_size,
        None if kind == RenderKind::Gif => DEFAULT_GIF_SIZE,
        None => DEFAULT_PNG_SIZE,
    }
}
