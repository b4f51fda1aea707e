//! One export in progress: the meshes of its frames through the one
//! evaluator, the progress report that may cancel it, and the frame loop
//! every format streams through.

use std::io::{self, Write};
use std::ops::RangeInclusive;

use super::error::{ExportError, cancel_error};
use crate::animate::{EvaluateOptions, Evaluator, Stage};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// The meshes of the exported frames, through the one evaluator.
pub struct FrameSource<'s> {
    scene: &'s Scene,
    stage: Stage,
    layers: bool,
    evaluator: Evaluator,
    /// The evaluator's count of rest shapes built when it came.
    builds_before: u64,
    mesh: Mesh,
}

impl<'s> FrameSource<'s> {
    pub fn new(scene: &'s Scene, stage: Stage, layers: bool) -> FrameSource<'s> {
        FrameSource::with_evaluator(scene, stage, layers, Evaluator::new())
    }

    /// A source that evaluates through `evaluator` (its cached rest shapes are used, not rebuilt).
    pub fn with_evaluator(scene: &'s Scene, stage: Stage, layers: bool, evaluator: Evaluator) -> FrameSource<'s> {
        let builds_before = evaluator.cache().builds();
        FrameSource { scene, stage, layers, evaluator, builds_before, mesh: Mesh::default() }
    }

    /// Rest shapes relaxed through this source so far (not counting those its evaluator came with).
    pub fn rest_shapes_built(&self) -> u64 {
        self.evaluator.cache().builds() - self.builds_before
    }

    pub fn scene(&self) -> &'s Scene {
        self.scene
    }

    /// The mesh at `frame` (buffers reused between calls).
    pub fn mesh(&mut self, frame: i32) -> &Mesh {
        let options = EvaluateOptions { layers: self.layers };
        self.evaluator.stage_mesh_into(self.scene, f64::from(frame), self.stage, options, &mut self.mesh);
        &self.mesh
    }
}

/// Counts frame evaluations and asks the caller whether to go on.
struct Progress<'p> {
    done: usize,
    total: usize,
    callback: &'p mut dyn FnMut(usize, usize) -> bool,
}

impl Progress<'_> {
    fn report(&mut self) -> Result<(), ExportError> {
        if (self.callback)(self.done, self.total) { Ok(()) } else { Err(ExportError::Cancelled) }
    }
}

/// One export in progress: the frames, their source and the progress report.
pub(crate) struct Job<'s, 'p> {
    pub source: FrameSource<'s>,
    pub first: i32,
    pub last: i32,
    progress: Progress<'p>,
}

impl<'s, 'p> Job<'s, 'p> {
    /// A job over `frames` whose progress counts `passes` evaluations of each
    /// frame; it reports `0` done before returning, and a cancel right away
    /// is [`ExportError::Cancelled`].
    pub fn start(
        source: FrameSource<'s>,
        frames: RangeInclusive<i32>,
        passes: usize,
        callback: &'p mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Job<'s, 'p>, ExportError> {
        let (first, last) = (*frames.start(), *frames.end());
        let mut job = Job { source, first, last, progress: Progress { done: 0, total: 0, callback } };
        job.progress.total = job.frame_count() * passes;
        job.progress.report()?;
        Ok(job)
    }

    pub fn frames(&self) -> RangeInclusive<i32> {
        self.first..=self.last
    }

    pub fn frame_count(&self) -> usize {
        (i64::from(self.last) - i64::from(self.first) + 1) as usize
    }

    pub fn fps(&self) -> f64 {
        self.source.scene.timeline.fps
    }

    /// The scene's name, or `fallback` when it has none.
    pub fn name_or<'a>(&'a self, fallback: &'a str) -> &'a str {
        let name = self.source.scene.name.trim();
        if name.is_empty() { fallback } else { name }
    }

    /// Evaluates each frame in order and hands its mesh to `each` with the
    /// frame's index in the range; reports progress after every frame. A
    /// cancel comes out as an I/O error that [`ExportError::write`] turns
    /// back into [`ExportError::Cancelled`].
    pub fn for_each_frame(&mut self, mut each: impl FnMut(usize, i32, &Mesh) -> io::Result<()>) -> io::Result<()> {
        for (index, frame) in (self.first..=self.last).enumerate() {
            each(index, frame, self.source.mesh(frame))?;
            self.progress.done += 1;
            if self.progress.report().is_err() {
                return Err(cancel_error());
            }
        }
        Ok(())
    }

    /// Streams every frame's positions, frame after frame, as f32 x, y, z in
    /// vertex order, each number's bytes as `encode` gives them (the format's
    /// byte order): the body of the PC2 and MDD point caches.
    pub fn write_positions(&mut self, out: &mut dyn Write, encode: fn(f32) -> [u8; 4]) -> io::Result<()> {
        let scene = self.source.scene();
        let mut bytes = Vec::with_capacity(scene.cloth.cols() * scene.cloth.rows() * 12);
        self.for_each_frame(|_, _, mesh| {
            bytes.clear();
            for p in &mesh.positions {
                for c in p.to_array() {
                    bytes.extend_from_slice(&encode(c));
                }
            }
            out.write_all(&bytes)
        })
    }
}
