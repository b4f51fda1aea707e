//! `drape export`: the cloth at one frame as OBJ, or a frame range as a PC2 or
//! MDD point cache, glTF 2.0, USD or an OBJ sequence, through
//! [`drape::export::export_animation_with`].

use std::path::Path;
use std::time::Instant;

use anyhow::{Result, anyhow, bail};
use clap::ValueEnum;
use drape::animate::{self, Evaluator};
use drape::export::{
    AnimationFormat, ExportError, ExportOptions, ExportSummary, FrameSource, InputFiles, SizeEstimate, check_frames,
    check_output, export_animation_using, write_atomically, write_obj,
};
use drape::scene::{self, Key, Scene};

use crate::FrameRange;
use crate::terminal_progress::{StatusLine, build_key_shapes, frame_bar};

/// `--format`: what to write when the output's extension does not say.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Format {
    /// Wavefront OBJ: one file for a frame, a numbered sequence for --frames.
    Obj,
    /// PC2 point cache (with the base mesh as OBJ beside it).
    Pc2,
    /// MDD point cache, big-endian (with the base mesh as OBJ beside it).
    Mdd,
    /// Binary glTF 2.0 with morph-target animation.
    Glb,
    /// glTF 2.0 JSON with NAME.bin (and the texture as NAME_texture.png) beside it.
    Gltf,
    /// USD text with time-sampled points and normals.
    Usda,
}

impl From<Format> for AnimationFormat {
    fn from(format: Format) -> AnimationFormat {
        match format {
            Format::Obj => AnimationFormat::ObjSequence,
            Format::Pc2 => AnimationFormat::Pc2,
            Format::Mdd => AnimationFormat::Mdd,
            Format::Glb => AnimationFormat::Glb,
            Format::Gltf => AnimationFormat::Gltf,
            Format::Usda => AnimationFormat::Usda,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Stage {
    /// The surface approximated from the catenary network of the key in effect.
    Approx,
    /// The rest shape of the key in effect, after relaxation.
    Relaxed,
    /// The full animation: blended rest shapes and the layer stack.
    Animated,
}

impl From<Stage> for animate::Stage {
    fn from(stage: Stage) -> animate::Stage {
        match stage {
            Stage::Approx => animate::Stage::Approx,
            Stage::Relaxed => animate::Stage::Relaxed,
            Stage::Animated => animate::Stage::Animated,
        }
    }
}

pub struct ExportRequest {
    pub frame: Option<i32>,
    pub frames: Option<FrameRange>,
    pub format: Option<Format>,
    pub stage: Stage,
    pub layers: bool,
    /// Write even when the size estimate is over the limit or the free space.
    pub force: bool,
    /// Remove an earlier sequence's frames that the new sequence does not write.
    pub replace_sequence: bool,
}

pub fn export(path: &Path, output: &Path, request: ExportRequest) -> Result<()> {
    let scene = scene::load(path)?;
    if !request.layers && request.stage != Stage::Animated {
        bail!("--no-layers applies to the animated stage only; the {:?} stage has no layers", request.stage);
    }
    let format = match (request.format, AnimationFormat::from_extension(output)) {
        (Some(format), _) => AnimationFormat::from(format),
        (None, Some(format)) => format,
        // A range into a directory: the OBJ sequence, as before the other formats existed.
        (None, None) if request.frames.is_some() && output.extension().is_none() => AnimationFormat::ObjSequence,
        (None, None) => match output.extension() {
            Some(other) => bail!(
                "cannot tell the format from the extension .{} of {}: use .obj, .pc2, .mdd, .glb, .gltf or .usda, \
                 or --format",
                other.to_string_lossy(),
                output.display()
            ),
            None => bail!(
                "{} has no extension: name it .obj, .pc2, .mdd, .glb, .gltf or .usda, or pass --format \
                 (--frames into a directory writes an OBJ sequence)",
                output.display()
            ),
        },
    };
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
    let options = ExportOptions {
        stage: request.stage.into(),
        layers: request.layers,
        sequence_name: Some(stem),
        scene_path: Some(path.to_path_buf()),
        replace_sequence: request.replace_sequence,
    };
    let one_obj = format == AnimationFormat::ObjSequence && request.frames.is_none();
    if request.replace_sequence && (one_obj || format != AnimationFormat::ObjSequence) {
        bail!(
            "--replace-sequence applies to an OBJ sequence (--frames into a directory, or OUT.obj with --frames); \
             {} is one file",
            output.display()
        );
    }

    if one_obj {
        let frame = request.frame.unwrap_or(scene.timeline.start);
        check_frames(&scene, frame, frame)?;
        InputFiles::of_scene(&scene, Some(path)).check(output, None)?;
        crate::check_size(&SizeEstimate::obj(&scene), output, request.force)?;
        let evaluator = evaluator_with_key_shapes(&scene, request.stage, frame, frame);
        return export_one_obj(&scene, frame, output, &options, evaluator);
    }
    let (first, last) = match (request.frames, request.frame) {
        (Some(range), _) => (range.first, range.last),
        (None, Some(frame)) => (frame, frame),
        // An animation format without a range: the whole timeline.
        (None, None) => (scene.timeline.start, scene.timeline.end),
    };
    // Nothing is written, and no key relaxed, before the range, the output and the size are known to be fine.
    check_frames(&scene, first, last)?;
    check_output(&scene, first..=last, output, format, &options).map_err(replace_hint)?;
    let frame_count = (i64::from(last) - i64::from(first) + 1) as u64;
    crate::check_size(&SizeEstimate::animation(&scene, format, frame_count), output, request.force)?;
    let started = Instant::now();
    let evaluator = evaluator_with_key_shapes(&scene, request.stage, first, last);
    let mut bar: Option<indicatif::ProgressBar> = None;
    let mut progress = |done: usize, total: usize| {
        let bar = bar.get_or_insert_with(|| frame_bar(total as u64, "frames evaluated"));
        bar.set_position(done as u64);
        true
    };
    let summary = export_animation_using(&scene, first..=last, output, format, &options, evaluator, &mut progress);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    report(&summary.map_err(replace_hint)?, output, &describe(&scene, &options, first), started);
    Ok(())
}

/// A refusal of an earlier sequence's frames says how to replace them.
pub fn replace_hint(error: ExportError) -> anyhow::Error {
    match error {
        ExportError::OldFrames { .. } => anyhow!("{error} with --replace-sequence, which removes exactly those files"),
        other => anyhow!(other),
    }
}

/// The summary's line for an earlier sequence's frames removed, if any.
pub fn removed_line(removed: &[std::path::PathBuf]) -> Option<String> {
    let name = |p: &std::path::PathBuf| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let (first, last) = (removed.first()?, removed.last()?);
    let count = removed.len();
    let files = if count == 1 { name(first) } else { format!("{} … {}", name(first), name(last)) };
    Some(format!("  removed {count} frame{} of the earlier sequence: {files}", if count == 1 { "" } else { "s" }))
}

/// An evaluator holding the rest shapes the frames `first..=last` need
/// (every key for the animation, the keys in effect for a single key's
/// stage), built while the terminal shows each key's relaxation.
fn evaluator_with_key_shapes(scene: &Scene, stage: Stage, first: i32, last: i32) -> Evaluator {
    let in_effect_first = scene.key_in_effect(f64::from(first));
    let keys: Vec<&Key> = match stage {
        Stage::Animated => scene.keys.iter().collect(),
        Stage::Approx | Stage::Relaxed => scene
            .keys
            .iter()
            .filter(|key| std::ptr::eq(*key, in_effect_first) || (first < key.frame && key.frame <= last))
            .collect(),
    };
    let mut evaluator = Evaluator::new();
    let mut status = StatusLine::on_stderr();
    build_key_shapes(&mut evaluator, scene, keys.iter().copied(), &mut status);
    // The files are written all the same: the verdict says what to change.
    for key in keys {
        let shape = evaluator.key_shape(scene, key);
        if !shape.settled(key.thickness) {
            eprintln!("drape: warning: the key at frame {} is {}", key.frame, shape.verdict(key.thickness));
        }
    }
    evaluator
}

fn export_one_obj(
    scene: &Scene,
    frame: i32,
    output: &Path,
    options: &ExportOptions,
    evaluator: Evaluator,
) -> Result<()> {
    let mut source = FrameSource::with_evaluator(scene, options.stage, options.layers, evaluator);
    let mesh = source.mesh(frame);
    write_atomically(output, |w| write_obj(mesh, &scene.name, w)).map_err(|e| ExportError::write(output, e))?;
    say!(
        "wrote {} ({} vertices, {} triangles; frame {frame}, {})",
        output.display(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        describe(scene, options, frame)
    );
    Ok(())
}

fn describe(scene: &Scene, options: &ExportOptions, frame: i32) -> String {
    let key_frame = || scene.key_in_effect(f64::from(frame)).frame;
    match options.stage {
        animate::Stage::Animated if options.layers => "animated".to_string(),
        animate::Stage::Animated => "animated, no layers".to_string(),
        animate::Stage::Approx => format!("approximated key at frame {}", key_frame()),
        animate::Stage::Relaxed => format!("relaxed key at frame {}", key_frame()),
    }
}

fn report(summary: &ExportSummary, output: &Path, what: &str, started: Instant) {
    let count = summary.frame_count;
    let frames = format!(
        "frames {}..{}, {count} frame{} at {} fps",
        summary.first_frame,
        summary.last_frame,
        if count == 1 { "" } else { "s" },
        summary.fps
    );
    let secs = started.elapsed().as_secs_f64();
    let name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    if summary.format == AnimationFormat::ObjSequence {
        let (first, last) = (summary.files.first(), summary.files.last());
        let dir = first.and_then(|f| f.parent()).unwrap_or(output);
        say!(
            "wrote {count} file{} to {} ({frames}, {what}; {} … {}) in {secs:.1} s",
            if count == 1 { "" } else { "s" },
            dir.display(),
            first.map(|f| name(f)).unwrap_or_default(),
            last.map(|f| name(f)).unwrap_or_default(),
        );
        if let Some(line) = removed_line(&summary.removed) {
            say!("{line}");
        }
        return;
    }
    let files: Vec<String> = summary.files.iter().map(|f| f.display().to_string()).collect();
    say!(
        "wrote {} ({}, {frames}, {} vertices, {} triangles, {what}) in {secs:.1} s",
        files.join(" + "),
        summary.format.description(),
        summary.vertex_count,
        summary.triangle_count
    );
    for left_out in &summary.left_out {
        say!("  not written: {left_out}");
    }
}
