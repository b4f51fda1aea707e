//! Exporting the evaluated animation of a frame range: the one driver behind
//! `drape export` and the editor's File ▸ Export, for every cached-geometry
//! format (PC2, MDD, glTF, USD, OBJ sequences).
//!
//! [`export_animation`] evaluates the frames one at a time through one
//! [`Evaluator`] (see [`super::job`]) and streams each into the output, so memory stays bounded by
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
//!
//! [`check_output`] refuses, before anything is evaluated, an export that
//! would write over a file it reads (the scene file, the files the scene
//! names: compared by identity on disk, not by name), and an OBJ sequence
//! into a folder holding frames of an earlier sequence of the same name
//! that the new one would leave mixed with its own — unless
//! [`ExportOptions::replace_sequence`], which removes exactly those files
//! as the new frames move in.

use std::fs;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use super::error::ExportError;
use super::job::{FrameSource, Job};
use super::obj::write_obj;
use super::output::{InputFiles, check_directory, sibling, write_around};
use super::sequence::{SequenceFiles, ensure_sequence_dir, file_stem_for};
use super::{gltf, mdd, pc2, usd};
use crate::animate::{Evaluator, Stage};
use crate::atomic_file::{StagedFiles, is_special_file, write_atomically};
use crate::scene::Scene;

/// A file format for an exported frame range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnimationFormat {
    /// One Wavefront OBJ per frame, `NAME_0000.obj`, … (see [`super::sequence_file_name`]).
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
    /// The file the scene was read from: the export never writes over it,
    /// nor over the files the scene names (whatever the output's name).
    pub scene_path: Option<PathBuf>,
    /// An OBJ sequence into a folder holding frames of an earlier sequence
    /// of the same name that the new one does not write: remove exactly
    /// those files as the new frames move in (else the export is refused).
    pub replace_sequence: bool,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            stage: Stage::Animated,
            layers: true,
            sequence_name: None,
            scene_path: None,
            replace_sequence: false,
        }
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
    /// Frames of an earlier sequence removed as the new one moved in
    /// ([`ExportOptions::replace_sequence`]), in frame order.
    pub removed: Vec<PathBuf>,
    /// Key rest shapes the export relaxed itself (0 when every one came
    /// with the evaluator it was given).
    pub rest_shapes_built: u64,
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
    check_output(scene, frames.clone(), output, format, options)?;
    let source = FrameSource::with_evaluator(scene, options.stage, options.layers, evaluator);
    let mut job = Job::start(source, frames, format.passes(), progress)?;
    let mut left_out = Vec::new();
    let mut removed = Vec::new();
    let files = match format {
        AnimationFormat::ObjSequence => write_obj_sequence(&mut job, output, options, &mut removed)?,
        AnimationFormat::Pc2 | AnimationFormat::Mdd => write_point_cache(&mut job, output, format, &mut left_out)?,
        AnimationFormat::Glb | AnimationFormat::Gltf => gltf::write(&mut job, output, format == AnimationFormat::Glb)?,
        AnimationFormat::Usda => {
            check_directory(output)?;
            write_atomically(output, |w| usd::write(&mut job, w)).map_err(|e| ExportError::write(output, e))?;
            vec![output.to_path_buf()]
        }
    };
    let frame_count = job.frame_count();
    let rest_shapes_built = job.source.rest_shapes_built();
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
        removed,
        rest_shapes_built,
    })
}

/// Checks, before anything is evaluated or written, where the export of
/// `frames` to `output` goes: none of the files it writes over (side files
/// and a sequence's frames included) is one it reads — the scene file
/// `options.scene_path` or a file the scene names, compared by identity on
/// disk — and an OBJ sequence's folder holds no frames of an earlier
/// sequence of its name that it does not write, unless
/// `options.replace_sequence`. [`export_animation_using`] checks this
/// itself; `drape export` and the editor call it first, before relaxing any
/// key.
pub fn check_output(
    scene: &Scene,
    frames: RangeInclusive<i32>,
    output: &Path,
    format: AnimationFormat,
    options: &ExportOptions,
) -> Result<(), ExportError> {
    let inputs = InputFiles::of_scene(scene, options.scene_path.as_deref());
    inputs.check(output, None)?;
    let beside = |what: &str| Some(format!("{what} beside {}", output.display()));
    match format {
        AnimationFormat::ObjSequence => {
            obj_sequence_files(scene, output, options, frames)?.check_directory(&inputs, options.replace_sequence)?;
        }
        AnimationFormat::Pc2 | AnimationFormat::Mdd if !is_special_file(output) => {
            inputs.check(&sibling(output, "obj"), beside("the base mesh"))?;
        }
        AnimationFormat::Gltf => {
            let (bin, texture) = gltf::side_files(output);
            inputs.check(&bin, beside("the buffer"))?;
            inputs.check(&texture, beside("the texture"))?;
        }
        AnimationFormat::Pc2 | AnimationFormat::Mdd | AnimationFormat::Glb | AnimationFormat::Usda => {}
    }
    Ok(())
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

/// The files of an OBJ sequence to `output`: `DIR/NAME_0000.obj …` into a
/// directory (NAME from [`ExportOptions::sequence_name`], else the scene's
/// name), or `DIR/OUT_0000.obj …` beside a path `DIR/OUT.obj`. A path that
/// exists and is neither is [`ExportError::NotADirectory`].
fn obj_sequence_files(
    scene: &Scene,
    output: &Path,
    options: &ExportOptions,
    frames: RangeInclusive<i32>,
) -> Result<SequenceFiles, ExportError> {
    if names_files(output) {
        let dir = match output.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        return Ok(SequenceFiles::new(dir, &stem, "obj", frames));
    }
    if output.exists() && !output.is_dir() {
        return Err(ExportError::NotADirectory { path: output.to_path_buf() });
    }
    let name = options.sequence_name.clone().unwrap_or_else(|| file_stem_for(&scene.name));
    Ok(SequenceFiles::new(output, &name, "obj", frames))
}

/// Whether an OBJ sequence's `output` names its files (`DIR/OUT.obj`)
/// rather than the directory they go into.
fn names_files(output: &Path) -> bool {
    output.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// One OBJ per frame, written into a hidden staging directory beside the
/// final files ([`StagedFiles`]) and moved into place once every frame is
/// written: an error, a cancel or an interrupt leaves the directory as it
/// was. Frames of an earlier sequence that the new one does not write are
/// removed in the same step when the options allow it (into `removed`),
/// else the export is refused.
fn write_obj_sequence(
    job: &mut Job,
    output: &Path,
    options: &ExportOptions,
    removed: &mut Vec<PathBuf>,
) -> Result<Vec<PathBuf>, ExportError> {
    let scene = job.source.scene();
    let sequence = obj_sequence_files(scene, output, options, job.frames())?;
    let inputs = InputFiles::of_scene(scene, options.scene_path.as_deref());
    // A directory this export made is removed again if the export fails.
    let created_dir = if names_files(output) {
        check_directory(output)?;
        false
    } else {
        ensure_sequence_dir(output)?
    };
    let dir = sequence.dir.clone();
    let written = write_staged_objs(job, &sequence, &inputs, options.replace_sequence);
    match written {
        Ok(committed) => {
            *removed = committed.removed;
            Ok(committed.files)
        }
        Err(error) => {
            if created_dir {
                let _ = fs::remove_dir(&dir);
            }
            Err(error)
        }
    }
}

fn write_staged_objs(
    job: &mut Job,
    sequence: &SequenceFiles,
    inputs: &InputFiles,
    replace: bool,
) -> Result<crate::atomic_file::Committed, ExportError> {
    let dir = &sequence.dir;
    let object_name = job.name_or("cloth").to_string();
    let mut staged = StagedFiles::new(dir, &sequence.name).map_err(|e| ExportError::write(dir, e))?;
    job.for_each_frame(|_, frame, mesh| staged.write(&sequence.file_name(frame), |w| write_obj(mesh, &object_name, w)))
        .map_err(|e| ExportError::write(dir, e))?;
    // The folder may have changed while the frames were written.
    let old = sequence.check_directory(inputs, replace)?;
    staged.commit_replacing(&old.names()).map_err(|e| ExportError::write(dir, e))
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
}
