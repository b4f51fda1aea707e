//! PC2 point caches, the format of 3ds Max's Point Cache 2 that Blender's Mesh
//! Cache modifier, Maya and Houdini also read.
//!
//! Layout (all little-endian): the 12 bytes `POINTCACHE2\0`, i32 version (1),
//! i32 point count, f32 start frame, f32 sample rate (frames between samples:
//! 1 here, one sample per frame), i32 sample count; then for each sample, for
//! each point in vertex order `j·cols + i`, f32 x, y, z (metres, Y up).

use std::io::{self, Write};

use super::job::Job;

/// The 12-byte signature at the start of every PC2 file.
pub const SIGNATURE: &[u8; 12] = b"POINTCACHE2\0";
/// Size of the header in bytes.
pub const HEADER_BYTES: usize = 32;

/// Writes the header and then streams each frame's positions.
pub(crate) fn write(job: &mut Job, out: &mut dyn Write) -> io::Result<()> {
    let points = job.source.scene().cloth.cols() * job.source.scene().cloth.rows();
    out.write_all(SIGNATURE)?;
    out.write_all(&1i32.to_le_bytes())?;
    out.write_all(&(points as i32).to_le_bytes())?;
    out.write_all(&(job.first as f32).to_le_bytes())?;
    out.write_all(&1f32.to_le_bytes())?;
    out.write_all(&(job.frame_count() as i32).to_le_bytes())?;
    job.write_positions(out, f32::to_le_bytes)
}
