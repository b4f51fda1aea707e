//! Exporting the evaluated animation of a frame range: the one driver behind
//! `drape export` and the editor's File ▸ Export, for every cached-geometry
//! format (PC2, MDD, glTF, USD, OBJ sequences).
//!
//! [`export_animation`] evaluates the frames one at a time through one
//! [`Evaluator`] and streams each into the output, so memory stays bounded by
//! one mesh plus a few numbers per frame, however long the range. Formats
//! whose layout needs something about every frame before the first frame's
//! data (glTF's accessor bounds, USD's separate points and normals blocks)
//! evaluate the range twice; the evaluator is deterministic, so both passes
//! see the same meshes bit for bit.
//!
//! Every file is written atomically (a temporary file beside it, renamed when
//! complete): an error, a full disk or a cancel leaves any earlier file of that
//! name as it was and no partial or temporary file behind. Formats that write
//! several files (PC2 with its base OBJ, `.gltf` with its `.bin` and texture,
//! OBJ sequences) write them all or none: the side files are finished and
//! renamed only after the streamed one is complete.
//!
//! Frames must lie within the scene's timeline (`start..=end`, both ends
//! included); a range reaching outside it is an error that names both
//! ranges. Without an explicit range the CLI exports the whole timeline.

use std::fs;
use std::io::{self, Write};
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use crate::animate::{EvaluateOptions, Evaluator, Stage};
use crate::atomic_file::{StagedFiles, io_reason, is_special_file, write_atomically};
use crate::mesh::Mesh;
use crate::scene::Scene;

use super::obj::write_obj;
use super::size::readable_bytes;
use super::{gltf, mdd, pc2, usd};

/// A file format for an exported frame range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnimationFormat {
    /// One Wavefront OBJ per frame, `NAME_0000.obj`, … (see [`sequence_file_name`]).
    ObjSequence,
    /// PC2 point cache (little-endian) plus the base mesh as OBJ beside it.
    Pc2,
    /// MDD point cache (big-endian, LightWave's layout) plus the base mesh as OBJ beside it.
    Mdd,
    /// Binary glTF 2.0: one `.glb` with the mesh, morph targets, animation and texture.
    Glb,
    /// glTF 2.0 JSON with the binary data in `NAME.bin` and the texture in `NAME_texture.png` beside it.
    Gltf,
    /// USD as text: a UsdGeomMesh with time-sampled points and normals.
    Usda,
}

impl AnimationFormat {
    pub const ALL: [AnimationFormat; 6] = [
        AnimationFormat::ObjSequence,
        AnimationFormat::Pc2,
        AnimationFormat::Mdd,
        AnimationFormat::Glb,
        AnimationFormat::Gltf,
        AnimationFormat::Usda,
    ];

    /// The format a path's extension names (case-insensitive): `.obj` (a
    /// sequence), `.pc2`, `.mdd`, `.glb`, `.gltf`, `.usda`; `None` otherwise.
    pub fn from_extension(path: &Path) -> Option<AnimationFormat> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        AnimationFormat::ALL.into_iter().find(|f| f.extension() == extension)
    }

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            AnimationFormat::ObjSequence => "obj",
            AnimationFormat::Pc2 => "pc2",
            AnimationFormat::Mdd => "mdd",
            AnimationFormat::Glb => "glb",
            AnimationFormat::Gltf => "gltf",
            AnimationFormat::Usda => "usda",
        }
    }

    /// A short human name, e.g. for a file dialog's filter.
    pub fn description(self) -> &'static str {
        match self {
            AnimationFormat::ObjSequence => "OBJ sequence",
            AnimationFormat::Pc2 => "PC2 point cache",
            AnimationFormat::Mdd => "MDD point cache",
            AnimationFormat::Glb => "glTF 2.0 binary",
            AnimationFormat::Gltf => "glTF 2.0",
            AnimationFormat::Usda => "USD (text)",
        }
    }

    /// How many times an export evaluates each frame (see the module doc);
    /// the progress callback counts frame evaluations.
    pub fn passes(self) -> usize {
        match self {
            AnimationFormat::Glb | AnimationFormat::Gltf | AnimationFormat::Usda => 2,
            AnimationFormat::ObjSequence | AnimationFormat::Pc2 | AnimationFormat::Mdd => 1,
        }
    }
}

/// Choices beyond the format; the default exports the full animation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportOptions {
    pub stage: Stage,
    /// Apply the layer stack (animated stage only).
    pub layers: bool,
    /// The file-name stem of an OBJ sequence written into a directory
    /// (`NAME_0000.obj`); default: the scene's name in lower case with
    /// underscores (`magic_carpet`), or `frame` for an unnamed scene.
    pub sequence_name: Option<String>,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions { stage: Stage::Animated, layers: true, sequence_name: None }
    }
}

/// What an export wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportSummary {
    pub format: AnimationFormat,
    /// Every file written, the main one first (for a sequence: in frame order).
    pub files: Vec<PathBuf>,
    pub first_frame: i32,
    pub last_frame: i32,
    pub frame_count: usize,
    pub vertex_count: usize,
    pub triangle_count: usize,
    pub fps: f64,
    /// Files the format usually writes that were left out, each with why: a
    /// point cache streamed into a device or FIFO gets no base OBJ beside it.
    pub left_out: Vec<String>,
}

/// Why an export failed. Messages name the file or the ranges involved.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error(
        "{} outside the scene's timeline {start}..{end}: choose frames within it (or lengthen the timeline)",
        if first == last { format!("frame {first} is") } else { format!("frames {first}..{last} reach") }
    )]
    FramesOutsideTimeline { first: i32, last: i32, start: i32, end: i32 },
    #[error("the frame range {first}..{last} ends before it starts: give the smaller frame first")]
    EmptyRange { first: i32, last: i32 },
    #[error("the layer stack can only be left out of the animated stage; the {stage:?} stage has no layers")]
    LayersWithoutAnimation { stage: Stage },
    #[error("cannot write {path}: the directory {} does not exist", dir.display(), path = path.display())]
    MissingDirectory { path: PathBuf, dir: PathBuf },
    #[error(
        "{} is not a directory: an OBJ sequence is written into a directory (or name the files with OUT.obj)",
        path.display()
    )]
    NotADirectory { path: PathBuf },
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        path: PathBuf,
        reason: String,
        #[source]
        source: io::Error,
    },
    #[error(
        "{} would take at least {} ({size_bytes} bytes), more than a GLB can hold (4 GiB): export to .gltf instead",
        path.display(),
        readable_bytes(*size_bytes)
    )]
    TooLarge { path: PathBuf, size_bytes: u64 },
    #[error(
        "{what} would take about {}, more than the {} limit: {remedy}",
        readable_bytes(*estimate_bytes),
        readable_bytes(*limit_bytes)
    )]
    OverSizeLimit { what: String, estimate_bytes: u64, limit_bytes: u64, remedy: String },
    #[error(
        "{what} would take about {} but the disk holding {} has only {} free: free some space or write elsewhere",
        readable_bytes(*estimate_bytes),
        dir.display(),
        readable_bytes(*free_bytes)
    )]
    NotEnoughSpace { what: String, estimate_bytes: u64, free_bytes: u64, dir: PathBuf },
    #[error(
        "{} is not a regular file (a device or a FIFO): a .gltf needs its .bin beside it, which Drape does not \
         make next to a special file; write a .glb, which holds everything, instead",
        path.display()
    )]
    SideFilesBesideSpecialFile { path: PathBuf },
    #[error("the export was cancelled; nothing was written")]
    Cancelled,
}

impl ExportError {
    /// An I/O error while writing `path`; a cancel passed up through the writers stays a cancel.
    pub fn write(path: &Path, source: io::Error) -> ExportError {
        if is_cancel(&source) {
            return ExportError::Cancelled;
        }
        ExportError::Write { path: path.to_path_buf(), reason: io_reason(&source), source }
    }
}

/// Writes the frames `frames` (both ends included) of `scene`'s animation to
/// `output` in `format`, with the default [`ExportOptions`]. See
/// [`export_animation_with`].
pub fn export_animation(
    scene: &Scene,
    frames: RangeInclusive<i32>,
    output: &Path,
    format: AnimationFormat,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<ExportSummary, ExportError> {
    export_animation_with(scene, frames, output, format, &ExportOptions::default(), progress)
}

/// Writes the frames `frames` (both ends included) of `scene` to `output` in
/// `format`.
///
/// `scene` must be valid (as [`crate::scene::load`] returns it). The frames
/// must lie within the timeline, else [`ExportError::FramesOutsideTimeline`]
/// and nothing is written. `output` is the file to write; for
/// [`AnimationFormat::ObjSequence`] it is either a directory (created if
/// missing; files `DIR/NAME_0000.obj`, NAME from [`ExportOptions::sequence_name`])
/// or a path `DIR/NAME.obj` naming the files `DIR/NAME_0000.obj`, ….
///
/// `progress(done, total)` is called before the first frame with `done = 0`
/// and after each frame evaluation, `total` being the frame count times
/// [`AnimationFormat::passes`]. When it returns `false` the export stops,
/// removes everything it had started writing (earlier files of the same names
/// stay as they were) and returns [`ExportError::Cancelled`].
pub fn export_animation_with(
    scene: &Scene,
    frames: RangeInclusive<i32>,
    output: &Path,
    format: AnimationFormat,
    options: &ExportOptions,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<ExportSummary, ExportError> {
    export_animation_using(scene, frames, output, format, options, Evaluator::new(), progress)
}

/// [`export_animation_with`] through `evaluator`, whose cache may already
/// hold rest shapes of the scene's keys (`drape export` builds them first,
/// showing each key's relaxation). The output is the same either way: the
/// cache only saves work.
pub fn export_animation_using(
    scene: &Scene,
    frames: RangeInclusive<i32>,
    output: &Path,
    format: AnimationFormat,
    options: &ExportOptions,
    evaluator: Evaluator,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<ExportSummary, ExportError> {
    let (first, last) = (*frames.start(), *frames.end());
    check_frames(scene, first, last)?;
    if !options.layers && options.stage != Stage::Animated {
        return Err(ExportError::LayersWithoutAnimation { stage: options.stage });
    }
    let frame_count = (i64::from(last) - i64::from(first) + 1) as usize;
    let mut job = Job {
        source: FrameSource::with_evaluator(scene, options.stage, options.layers, evaluator),
        first,
        last,
        progress: Progress { done: 0, total: frame_count * format.passes(), callback: progress },
    };
    job.progress.report()?;
    let mut left_out = Vec::new();
    let files = match format {
        AnimationFormat::ObjSequence => write_obj_sequence(&mut job, output, options)?,
        AnimationFormat::Pc2 | AnimationFormat::Mdd => write_point_cache(&mut job, output, format, &mut left_out)?,
        AnimationFormat::Glb | AnimationFormat::Gltf => gltf::write(&mut job, output, format == AnimationFormat::Glb)?,
        AnimationFormat::Usda => {
            check_directory(output)?;
            write_atomically(output, |w| usd::write(&mut job, w)).map_err(|e| ExportError::write(output, e))?;
            vec![output.to_path_buf()]
        }
    };
    let mesh = job.source.mesh(first);
    Ok(ExportSummary {
        format,
        files,
        first_frame: first,
        last_frame: last,
        frame_count,
        vertex_count: mesh.vertex_count(),
        triangle_count: mesh.triangle_count(),
        fps: scene.timeline.fps,
        left_out,
    })
}

/// Checks that `first..=last` is a non-empty range within the scene's timeline.
pub fn check_frames(scene: &Scene, first: i32, last: i32) -> Result<(), ExportError> {
    if first > last {
        return Err(ExportError::EmptyRange { first, last });
    }
    let timeline = &scene.timeline;
    if first < timeline.start || last > timeline.end {
        return Err(ExportError::FramesOutsideTimeline { first, last, start: timeline.start, end: timeline.end });
    }
    Ok(())
}

/// The file name of one frame of an OBJ sequence: `NAME_0007.obj`; frame
/// numbers are padded to at least four digits, more when the range needs
/// them, so the files sort in frame order (`NAME_-0005.obj` before zero).
pub fn sequence_file_name(name: &str, frame: i32, frames: RangeInclusive<i32>) -> String {
    let width = frame_number_width(*frames.start(), *frames.end());
    format!("{name}_{}.obj", padded_frame(frame, width))
}

/// Digits for the frame numbers of a sequence: at least 4, more when needed.
pub fn frame_number_width(first: i32, last: i32) -> usize {
    let digits = |f: i32| f.unsigned_abs().to_string().len();
    digits(first).max(digits(last)).max(4)
}

/// `frame` zero-padded to `width` digits, with a leading `-` when negative.
pub fn padded_frame(frame: i32, width: usize) -> String {
    let sign = if frame < 0 { "-" } else { "" };
    format!("{sign}{:0width$}", frame.unsigned_abs())
}

/// A scene name as a file-name stem: lower case, runs of anything but
/// letters and digits as one `_` (`Magic carpet` → `magic_carpet`).
pub fn file_stem_for(name: &str) -> String {
    let mut stem = String::new();
    for c in name.trim().chars() {
        if c.is_alphanumeric() {
            stem.extend(c.to_lowercase());
        } else if !stem.ends_with('_') && !stem.is_empty() {
            stem.push('_');
        }
    }
    let stem = stem.trim_end_matches('_').to_string();
    if stem.is_empty() { "frame".to_string() } else { stem }
}

/// The meshes of the exported frames, through the one evaluator.
pub struct FrameSource<'s> {
    scene: &'s Scene,
    stage: Stage,
    layers: bool,
    evaluator: Evaluator,
    mesh: Mesh,
}

impl<'s> FrameSource<'s> {
    pub fn new(scene: &'s Scene, stage: Stage, layers: bool) -> FrameSource<'s> {
        FrameSource::with_evaluator(scene, stage, layers, Evaluator::new())
    }

    /// A source that evaluates through `evaluator` (its cached rest shapes are used, not rebuilt).
    pub fn with_evaluator(scene: &'s Scene, stage: Stage, layers: bool, evaluator: Evaluator) -> FrameSource<'s> {
        FrameSource { scene, stage, layers, evaluator, mesh: Mesh::default() }
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
pub(crate) struct Progress<'p> {
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

impl Job<'_, '_> {
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
}

/// The I/O error that carries a cancel out of a writer closure.
#[derive(Debug)]
struct CancelMarker;

impl std::fmt::Display for CancelMarker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the export was cancelled")
    }
}

impl std::error::Error for CancelMarker {}

fn cancel_error() -> io::Error {
    io::Error::new(io::ErrorKind::Interrupted, CancelMarker)
}

fn is_cancel(error: &io::Error) -> bool {
    error.get_ref().is_some_and(|inner| inner.is::<CancelMarker>())
}

/// The directory `path` will be written into must exist.
pub(crate) fn check_directory(path: &Path) -> Result<(), ExportError> {
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if dir.is_dir() {
        Ok(())
    } else {
        Err(ExportError::MissingDirectory { path: path.to_path_buf(), dir: dir.to_path_buf() })
    }
}

/// `path` with its extension replaced, e.g. the `.obj` beside a `.pc2`.
pub(crate) fn sibling(path: &Path, extension: &str) -> PathBuf {
    path.with_extension(extension)
}

/// PC2 or MDD, streamed, inside the atomic write of the base OBJ beside it, so
/// that both files appear together or neither does. Into a device or FIFO
/// (`-o /dev/null`) the cache is streamed alone: a base OBJ beside it would be
/// a new file next to a device (`/dev/null.obj`), so it is left out and
/// `left_out` says so.
fn write_point_cache(
    job: &mut Job,
    output: &Path,
    format: AnimationFormat,
    left_out: &mut Vec<String>,
) -> Result<Vec<PathBuf>, ExportError> {
    check_directory(output)?;
    let base_obj = sibling(output, "obj");
    let write_cache = |job: &mut Job| {
        write_atomically(output, |w| match format {
            AnimationFormat::Pc2 => pc2::write(job, w),
            _ => mdd::write(job, w),
        })
        .map_err(|e| ExportError::write(output, e))
    };
    if is_special_file(output) {
        write_cache(job)?;
        left_out.push(format!(
            "the base mesh {}: {} is not a regular file, and no file is made beside a device or FIFO",
            base_obj.display(),
            output.display()
        ));
        return Ok(vec![output.to_path_buf()]);
    }
    let mut obj = Vec::new();
    let name = job.name_or("cloth").to_string();
    write_obj(job.source.mesh(job.first), &name, &mut obj).map_err(|e| ExportError::write(&base_obj, e))?;
    write_around(&base_obj, &obj, || write_cache(job))?;
    Ok(vec![output.to_path_buf(), base_obj])
}

/// Writes `bytes` to `path` atomically around `inner` (the write of the
/// streamed main file): `path` is renamed into place only when `inner`
/// succeeded, and abandoned (temporary file removed) when it failed, so the
/// two appear together or not at all. Returns `inner`'s error first.
pub(crate) fn write_around(
    path: &Path,
    bytes: &[u8],
    inner: impl FnOnce() -> Result<(), ExportError>,
) -> Result<(), ExportError> {
    let mut inner_result = Ok(());
    let outer = write_atomically(path, |w| {
        w.write_all(bytes)?;
        inner_result = inner();
        match inner_result {
            Ok(()) => Ok(()),
            Err(_) => Err(io::Error::other("abandoned: the file it belongs with failed")),
        }
    });
    inner_result?;
    outer.map_err(|e| ExportError::write(path, e))
}

/// One OBJ per frame, written into a hidden staging directory beside the
/// final files ([`StagedFiles`]) and moved into place once every frame is
/// written: an error, a cancel or an interrupt leaves the directory as it was.
fn write_obj_sequence(job: &mut Job, output: &Path, options: &ExportOptions) -> Result<Vec<PathBuf>, ExportError> {
    let named_files = output.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    // A directory this export made is removed again if the export fails.
    let mut created_dir = false;
    let (dir, name) = if named_files {
        check_directory(output)?;
        let dir = match output.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        (dir, stem)
    } else {
        if output.exists() && !output.is_dir() {
            return Err(ExportError::NotADirectory { path: output.to_path_buf() });
        }
        created_dir = ensure_sequence_dir(output)?;
        let name = options.sequence_name.clone().unwrap_or_else(|| file_stem_for(&job.source.scene.name));
        (output.to_path_buf(), name)
    };
    let object_name = job.name_or("cloth").to_string();
    let frames = job.frames();
    let written = StagedFiles::new(&dir, &name).and_then(|mut staged| {
        job.for_each_frame(|_, frame, mesh| {
            staged.write(&sequence_file_name(&name, frame, frames.clone()), |w| write_obj(mesh, &object_name, w))
        })?;
        staged.commit()
    });
    written.map_err(|error| {
        if created_dir {
            let _ = fs::remove_dir(&dir);
        }
        ExportError::write(&dir, error)
    })
}

/// Checks that the directory `dir` a sequence is written into exists or
/// can be made: its parent must exist ([`ExportError::MissingDirectory`]
/// otherwise); Drape makes one directory, never a chain of them.
pub fn check_sequence_dir(dir: &Path) -> Result<(), ExportError> {
    if !dir.is_dir()
        && let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(ExportError::MissingDirectory { path: dir.to_path_buf(), dir: parent.to_path_buf() });
    }
    Ok(())
}

/// Makes sure the directory `dir` a sequence is written into exists: it is
/// created when missing, if [`check_sequence_dir`] allows. Returns whether
/// it was created, so that a failed export can remove it again.
pub fn ensure_sequence_dir(dir: &Path) -> Result<bool, ExportError> {
    check_sequence_dir(dir)?;
    if dir.is_dir() {
        return Ok(false);
    }
    fs::create_dir(dir).map_err(|e| ExportError::write(dir, e))?;
    Ok(true)
}

/// Writes `value` as f32 little-endian.
pub(crate) fn write_f32_le(w: &mut dyn Write, value: f32) -> io::Result<()> {
    w.write_all(&value.to_le_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_follow_the_extension() {
        assert_eq!(AnimationFormat::from_extension(Path::new("a/carpet.PC2")), Some(AnimationFormat::Pc2));
        assert_eq!(AnimationFormat::from_extension(Path::new("x.mdd")), Some(AnimationFormat::Mdd));
        assert_eq!(AnimationFormat::from_extension(Path::new("x.glb")), Some(AnimationFormat::Glb));
        assert_eq!(AnimationFormat::from_extension(Path::new("x.gltf")), Some(AnimationFormat::Gltf));
        assert_eq!(AnimationFormat::from_extension(Path::new("x.usda")), Some(AnimationFormat::Usda));
        assert_eq!(AnimationFormat::from_extension(Path::new("x.obj")), Some(AnimationFormat::ObjSequence));
        assert_eq!(AnimationFormat::from_extension(Path::new("x.fbx")), None);
        assert_eq!(AnimationFormat::from_extension(Path::new("dir")), None);
    }

    #[test]
    fn sequence_numbers_are_padded_to_sort() {
        assert_eq!(sequence_file_name("carpet", 1, 0..=120), "carpet_0001.obj");
        assert_eq!(sequence_file_name("carpet", 120, 0..=120), "carpet_0120.obj");
        assert_eq!(padded_frame(-5, frame_number_width(-5, 123_456)), "-000005");
        assert_eq!(padded_frame(123_456, frame_number_width(-5, 123_456)), "123456");
    }

    #[test]
    fn scene_names_become_file_stems() {
        assert_eq!(file_stem_for("Magic carpet"), "magic_carpet");
        assert_eq!(file_stem_for("  Flag / pole #2 "), "flag_pole_2");
        assert_eq!(file_stem_for(""), "frame");
    }
}
