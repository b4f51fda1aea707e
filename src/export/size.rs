//! How large an export will be, estimated before anything is written, and
//! the check that refuses one past a sane limit ([`MAX_EXPORT_BYTES`]) or
//! past the free space on the disk it goes to.
//!
//! Binary layouts (PC2, MDD, glTF's buffer) are counted exactly from the
//! grid and the frame count; text (OBJ, USD, glTF's JSON) at
//! [`TEXT_NUMBER_BYTES`] a number, which errs a little on the large side for
//! the shortest round-trip f32s Drape writes (measured on the example scenes:
//! OBJ +9 %, USD +3 %). Rendered pictures are estimated by the caller (a
//! PNG's size depends on what it shows), see [`SizeEstimate::new`].

use std::path::{Path, PathBuf};

use super::animation::AnimationFormat;
use super::error::ExportError;
use super::obj::object_name;
use crate::look::texture_png;
use crate::scene::{Scene, group_thousands};

/// Largest export written without being asked for explicitly (`--force` on
/// the command line): 8 GiB, far above any shot of the example scenes
/// (121 frames of the magic carpet are under 3 MB in every format) and far
/// below what fills a disk by mistake.
pub const MAX_EXPORT_BYTES: u64 = 8 << 30;

/// Bytes a number takes in a text format, with its separator: a shortest
/// round-trip f32 such as `-0.45203248 ` is 9 to 12 characters.
pub const TEXT_NUMBER_BYTES: u64 = 12;

/// What an export is about to write: its estimated size and, for messages,
/// what it is (`the export (PC2 point cache of 825 points × 121 frames)`)
/// and how to make it smaller (`export fewer frames or a coarser grid`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SizeEstimate {
    pub bytes: u64,
    pub what: String,
    pub remedy: String,
}

/// How to make an export of cloth geometry smaller.
const EXPORT_REMEDY: &str = "export fewer frames or a coarser grid";

impl SizeEstimate {
    /// An estimate made elsewhere (rendered frames: the caller knows their size).
    pub fn new(bytes: u64, what: impl Into<String>, remedy: impl Into<String>) -> SizeEstimate {
        SizeEstimate { bytes, what: what.into(), remedy: remedy.into() }
    }

    /// One OBJ of `scene`'s cloth at one frame.
    pub fn obj(scene: &Scene) -> SizeEstimate {
        let points = grid_points(scene);
        let what = format!("the export (an OBJ of {} points)", group_thousands(points));
        SizeEstimate::new(obj_bytes(scene), what, EXPORT_REMEDY)
    }

    /// `frame_count` frames of `scene` in `format`, side files included (a
    /// point cache's base OBJ, a `.gltf`'s `.bin` and texture).
    pub fn animation(scene: &Scene, format: AnimationFormat, frame_count: u64) -> SizeEstimate {
        let points = grid_points(scene);
        let bytes = match format {
            AnimationFormat::ObjSequence => frame_count.saturating_mul(obj_bytes(scene)),
            AnimationFormat::Pc2 => 32 + cache_bytes(points, frame_count) + obj_bytes(scene),
            AnimationFormat::Mdd => 8 + 4 * frame_count + cache_bytes(points, frame_count) + obj_bytes(scene),
            AnimationFormat::Glb | AnimationFormat::Gltf => gltf_bytes(scene, frame_count),
            AnimationFormat::Usda => usda_bytes(scene, frame_count),
        };
        let frames =
            if frame_count == 1 { "1 frame".to_string() } else { format!("{} frames", group_thousands(frame_count)) };
        let what = format!("the export ({} of {} points × {frames})", format.description(), group_thousands(points));
        SizeEstimate::new(bytes, what, EXPORT_REMEDY)
    }
}

fn grid_points(scene: &Scene) -> u64 {
    u64::from(scene.cloth.grid.0) * u64::from(scene.cloth.grid.1)
}

fn triangles(scene: &Scene) -> u64 {
    let (cols, rows) = scene.cloth.grid;
    2 * u64::from(cols.saturating_sub(1)) * u64::from(rows.saturating_sub(1))
}

/// Three f32 per point per frame.
fn cache_bytes(points: u64, frame_count: u64) -> u64 {
    frame_count.saturating_mul(points * 12)
}

/// Digits of the largest 1-based vertex index.
fn index_digits(points: u64) -> u64 {
    points.max(1).to_string().len() as u64
}

/// One OBJ: a header, the object's name, `v`, `vt` and `vn` lines per point
/// and an `f a/a/a b/b/b c/c/c` line per triangle.
fn obj_bytes(scene: &Scene) -> u64 {
    let points = grid_points(scene);
    let header = 64 + object_name(&scene.name).len() as u64;
    let per_point = (2 + 3 * TEXT_NUMBER_BYTES) + (3 + 2 * TEXT_NUMBER_BYTES) + (3 + 3 * TEXT_NUMBER_BYTES);
    let per_triangle = 2 + 3 * (3 * index_digits(points) + 3);
    header + points * per_point + triangles(scene) * per_triangle
}

/// The glTF buffer exactly (as `gltf::Layout` lays it out), the texture, and
/// the JSON at a few hundred bytes per frame (a morph target's accessors and name).
fn gltf_bytes(scene: &Scene, frame_count: u64) -> u64 {
    let points = grid_points(scene);
    let texture = texture_png(scene.cloth.texture).map_or(0, |png| png.len() as u64);
    let static_part = triangles(scene) * 12 + points * 32 + texture;
    let frames_part = frame_count.saturating_mul(points * 24 + 4 + 400);
    let weights = frame_count.saturating_mul(frame_count).saturating_mul(4);
    let json = 4096 + 4 * scene.name.len() as u64;
    static_part.saturating_add(frames_part).saturating_add(weights).saturating_add(json)
}

/// USD text: the topology and UVs once, then each frame's points and normals
/// as `(x, y, z), ` and its extent.
fn usda_bytes(scene: &Scene, frame_count: u64) -> u64 {
    let points = grid_points(scene);
    let topology = triangles(scene) * (3 + 3 * (index_digits(points) + 2)) + points * (2 * TEXT_NUMBER_BYTES + 4);
    let per_frame = 2 * points * (3 * TEXT_NUMBER_BYTES + 4) + 6 * TEXT_NUMBER_BYTES + 64;
    let header = 2048 + 3 * scene.name.len() as u64;
    (header + topology).saturating_add(frame_count.saturating_mul(per_frame))
}

/// Refuses `estimate` when it is over `limit_bytes` or over the free space on
/// the disk that will hold `output` (a file, or the directory of a sequence,
/// made when missing). A device or FIFO has no free space to speak of: only
/// the limit applies to it.
pub fn check_export_size(estimate: &SizeEstimate, output: &Path, limit_bytes: u64) -> Result<(), ExportError> {
    let holder = holding_dir(output);
    let free = holder.as_deref().and_then(free_bytes);
    size_verdict(estimate, limit_bytes, holder.zip(free))
}

/// The decision of [`check_export_size`], given the free space (and where) when known.
fn size_verdict(estimate: &SizeEstimate, limit_bytes: u64, free: Option<(PathBuf, u64)>) -> Result<(), ExportError> {
    if estimate.bytes > limit_bytes {
        return Err(ExportError::OverSizeLimit {
            what: estimate.what.clone(),
            estimate_bytes: estimate.bytes,
            limit_bytes,
            remedy: estimate.remedy.clone(),
        });
    }
    match free {
        Some((dir, free_bytes)) if estimate.bytes > free_bytes => Err(ExportError::NotEnoughSpace {
            what: estimate.what.clone(),
            estimate_bytes: estimate.bytes,
            free_bytes,
            dir,
        }),
        _ => Ok(()),
    }
}

/// The existing directory whose disk `output` will be written to: the
/// nearest existing ancestor (a sequence's directory is made when missing);
/// `None` for a device or FIFO, which is written straight into.
fn holding_dir(output: &Path) -> Option<PathBuf> {
    match std::fs::metadata(output) {
        Ok(meta) if meta.is_dir() => return Some(output.to_path_buf()),
        Ok(meta) if !meta.is_file() => return None,
        _ => {}
    }
    let mut dir = output.parent();
    while let Some(candidate) = dir {
        let candidate = if candidate.as_os_str().is_empty() { Path::new(".") } else { candidate };
        if candidate.is_dir() {
            return Some(candidate.to_path_buf());
        }
        dir = candidate.parent();
    }
    None
}

/// Bytes an unprivileged process may still write on the filesystem holding
/// `dir` (`statvfs`: available blocks × fragment size); `None` when unknown.
#[cfg(unix)]
pub fn free_bytes(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt as _;
    let path = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    // SAFETY: `statvfs` is plain old data, fully written by a successful call.
    let mut stats: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: `path` is a NUL-terminated string and `stats` a valid, writable statvfs.
    if unsafe { libc::statvfs(path.as_ptr(), &mut stats) } != 0 {
        return None;
    }
    // The field types differ between platforms (u32 on some 32-bit ones).
    #[allow(clippy::useless_conversion)]
    let (available, fragment) = (u64::from(stats.f_bavail), u64::from(stats.f_frsize));
    Some(available.saturating_mul(fragment))
}

/// Free space is only known on Unix; elsewhere only the limit applies.
#[cfg(not(unix))]
pub fn free_bytes(_dir: &Path) -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse;

    const CURTAIN: &str = include_str!("../../scenes/curtain.ron");

    fn curtain() -> Scene {
        parse(CURTAIN, "curtain.ron").unwrap()
    }

    #[test]
    fn binary_layouts_are_counted_exactly() {
        let scene = curtain();
        let obj = obj_bytes(&scene);
        let pc2 = SizeEstimate::animation(&scene, AnimationFormat::Pc2, 121);
        assert_eq!(pc2.bytes, 32 + 121 * 825 * 12 + obj);
        assert_eq!(pc2.what, "the export (PC2 point cache of 825 points × 121 frames)");
        let mdd = SizeEstimate::animation(&scene, AnimationFormat::Mdd, 1);
        assert_eq!(mdd.bytes, 8 + 4 + 825 * 12 + obj);
        assert_eq!(mdd.what, "the export (MDD point cache of 825 points × 1 frame)");
        let sequence = SizeEstimate::animation(&scene, AnimationFormat::ObjSequence, 10);
        assert_eq!(sequence.bytes, 10 * obj);
    }

    #[test]
    fn the_largest_scene_and_timeline_do_not_overflow() {
        let mut scene = curtain();
        scene.cloth.grid = (512, 512);
        for format in AnimationFormat::ALL {
            let estimate = SizeEstimate::animation(&scene, format, 200_001);
            assert!(estimate.bytes > MAX_EXPORT_BYTES, "{format:?}: {}", estimate.bytes);
            assert!(estimate.bytes < u64::MAX / 2, "{format:?}: {}", estimate.bytes);
        }
    }

    #[test]
    fn refusals_name_the_estimate_and_the_limit_or_the_free_space() {
        let estimate = SizeEstimate::new(12 << 30, "the render (a GIF of 9 frames)", "render fewer frames");
        let error = size_verdict(&estimate, MAX_EXPORT_BYTES, None).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the render (a GIF of 9 frames) would take about 12.0 GiB, more than the 8.0 GiB limit: render fewer frames"
        );
        let small = SizeEstimate { bytes: 3 << 20, ..SizeEstimate::obj(&curtain()) };
        assert!(size_verdict(&small, MAX_EXPORT_BYTES, None).is_ok());
        assert!(size_verdict(&small, MAX_EXPORT_BYTES, Some((PathBuf::from("/out"), 4 << 20))).is_ok());
        let error = size_verdict(&small, MAX_EXPORT_BYTES, Some((PathBuf::from("/out"), 1 << 20))).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the export (an OBJ of 825 points) would take about 3.0 MiB but the disk holding /out has only 1.0 MiB \
             free: free some space or write elsewhere"
        );
    }

    #[test]
    fn the_free_space_is_looked_up_where_the_file_goes() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(holding_dir(&dir.path().join("a.pc2")), Some(dir.path().to_path_buf()));
        assert_eq!(holding_dir(&dir.path().join("new/deeper/seq")), Some(dir.path().to_path_buf()));
        assert_eq!(holding_dir(Path::new("bare.obj")), Some(PathBuf::from(".")));
        assert_eq!(holding_dir(Path::new("/dev/null")), None, "a device has no free space to speak of");
        let free = free_bytes(dir.path()).expect("statvfs works on a temporary directory");
        assert!(free > 0);
    }
}
