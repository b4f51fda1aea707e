//! MDD point caches, LightWave's format as Blender's Mesh Cache modifier and
//! its MDD importer read it.
//!
//! Layout (all big-endian): i32 frame count, i32 point count, the frame count
//! times f32 (each frame's time in seconds, `frame / fps`), then for each
//! frame, for each point in vertex order `j·cols + i`, f32 x, y, z (metres, Y up).

use std::io::{self, Write};

use super::job::Job;
use crate::animate::frame_time_secs;

/// Writes the header with every frame's time, then streams each frame's positions.
pub(crate) fn write(job: &mut Job, out: &mut dyn Write) -> io::Result<()> {
    let scene = job.source.scene();
    let points = scene.cloth.cols() * scene.cloth.rows();
    out.write_all(&(job.frame_count() as i32).to_be_bytes())?;
    out.write_all(&(points as i32).to_be_bytes())?;
    for frame in job.frames() {
        out.write_all(&(frame_time_secs(&scene.timeline, f64::from(frame)) as f32).to_be_bytes())?;
    }
    job.write_positions(out, f32::to_be_bytes)
}
