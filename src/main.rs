//! The `drape` command line: check scenes and export their rest shapes and animation.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Result, anyhow};
use clap::{Parser, Subcommand};
use drape::picture::SceneOverlays;
use drape::scene;

/// `println!` that ends the program quietly when stdout is closed (`drape
/// check scene.ron | head`) instead of panicking on the broken pipe. When
/// the output file is stdout itself ([`SUMMARY_TO_STDERR`]) it prints to
/// stderr instead.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if crate::SUMMARY_TO_STDERR.load(std::sync::atomic::Ordering::Relaxed) {
            let _ = writeln!(std::io::stderr(), $($arg)*);
        } else if writeln!(std::io::stdout(), $($arg)*).is_err() {
            std::process::exit(0);
        }
    }};
}

/// Set when the output file is the process's own stdout (`-o /dev/stdout`,
/// `-o /dev/fd/1`): the summary then goes to stderr, so it never lands in
/// the data piped on.
static SUMMARY_TO_STDERR: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether `path` is the file, pipe or terminal stdout writes to.
#[cfg(unix)]
fn is_stdout(path: &Path) -> bool {
    use std::os::fd::AsFd as _;
    use std::os::unix::fs::MetadataExt as _;
    let Ok(target) = std::fs::metadata(path) else { return false };
    let Ok(stdout) = std::io::stdout().as_fd().try_clone_to_owned() else { return false };
    let Ok(stdout) = std::fs::File::from(stdout).metadata() else { return false };
    (target.dev(), target.ino()) == (stdout.dev(), stdout.ino())
}

#[cfg(not(unix))]
fn is_stdout(_path: &Path) -> bool {
    false
}

mod check_command;
mod export_command;
mod render_command;
mod terminal_progress;

#[derive(Parser)]
#[command(name = "drape", version, about = "Cloth animation with fake dynamics: pins, catenaries, relaxation.")]
#[command(args_conflicts_with_subcommands = true)]
struct Cli {
    /// Open this scene in the editor (default: the built-in magic carpet).
    scene: Option<PathBuf>,
    /// Close the editor by itself after drawing N frames (smoke tests, scripted runs).
    #[arg(long, value_name = "N")]
    quit_after_frames: Option<u64>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Validate scenes and print a short summary of each; exit code 1, with each error, if any is not valid.
    Check {
        /// The scene files (.ron), one or more: `drape check scenes/*.ron` checks them all.
        #[arg(required = true, value_name = "SCENE")]
        scenes: Vec<PathBuf>,
    },
    /// Write the cloth at a frame as OBJ, or a frame range as a PC2/MDD point cache, glTF, USD or OBJ sequence.
    Export {
        /// The scene file (.ron).
        scene: PathBuf,
        /// Output: out.obj (one frame), out.pc2, out.mdd, out.glb, out.gltf, out.usda (an animation), or a
        /// directory with --frames (an OBJ sequence DIR/NAME_FRAME.obj; out.obj with --frames: out_FRAME.obj).
        #[arg(short, long)]
        output: PathBuf,
        /// Frame to export (default: the timeline's start for OBJ, the whole timeline for the animation formats).
        #[arg(long, allow_negative_numbers = true, conflicts_with = "frames")]
        frame: Option<i32>,
        /// Frame range A..B, both ends included, within the scene's timeline.
        #[arg(long, value_parser = parse_frame_range, allow_hyphen_values = true)]
        frames: Option<FrameRange>,
        /// Output format; by default it follows the output's extension (obj for a sequence into a directory).
        #[arg(long, value_enum)]
        format: Option<export_command::Format>,
        /// What to export: the animated cloth, or the key in effect before (approx) or after (relaxed) relaxation.
        #[arg(long, value_enum, default_value_t = export_command::Stage::Animated)]
        stage: export_command::Stage,
        /// Animated stage only: the blended rest shapes without the layer stack.
        #[arg(long)]
        no_layers: bool,
        /// Write even when the estimated size is over 8 GiB or over the free space on the disk.
        #[arg(long)]
        force: bool,
        /// An OBJ sequence into a folder holding frames of an earlier sequence of the same name that this
        /// one does not write: remove exactly those files as the new frames go in (else it is refused).
        #[arg(long)]
        replace_sequence: bool,
    },
    /// Draw the cloth: a PNG of one frame, a numbered PNG sequence (--frames into a directory) or an animated GIF.
    Render {
        /// The scene file (.ron).
        scene: PathBuf,
        /// out.png (one frame), out.gif (an animation at the scene's fps), or a directory with --frames.
        #[arg(short, long)]
        output: PathBuf,
        /// Frame to render (default: the timeline's start).
        #[arg(long, allow_negative_numbers = true, conflicts_with = "frames")]
        frame: Option<i32>,
        /// Frame range A..B, both ends included (a GIF without it shows the whole timeline).
        #[arg(long, value_parser = parse_frame_range, allow_hyphen_values = true)]
        frames: Option<FrameRange>,
        /// Picture size WIDTHxHEIGHT in pixels (default 1280x720; 640x360 for a GIF).
        #[arg(long, value_parser = render_command::parse_size)]
        size: Option<(u32, u32)>,
        /// Draw the grid's edges over the cloth.
        #[arg(long)]
        wireframe: bool,
        /// Draw the pins of the key in effect as red dots.
        #[arg(long)]
        pins: bool,
        /// Draw the key's catenary network, conflicting catenaries included.
        #[arg(long)]
        catenaries: bool,
        /// Draw the key's triangulation of its pins on the cloth.
        #[arg(long)]
        triangulation: bool,
        /// Leave the scene's colliders out of the picture (they still shape the cloth).
        #[arg(long)]
        no_colliders: bool,
        /// Leave the scene's references (glTF characters and props) out of the picture.
        #[arg(long)]
        no_references: bool,
        /// Look through the scene's shot camera (the default when it has one, at its
        /// image size unless --size says otherwise) or the framing view.
        #[arg(long, value_enum)]
        camera: Option<render_command::CameraChoice>,
        /// PNGs of the cloth alone with an alpha channel (straight alpha): transparent where there
        /// is no cloth, no ground, background, colliders or references drawn.
        #[arg(long)]
        alpha: bool,
        /// Lay the pictures over the scene's background plate (`plate`). It is used by default
        /// when the scene has one and the render looks through the shot camera.
        #[arg(long, conflicts_with = "no_plate")]
        plate: bool,
        /// Leave the background plate out: the ground and background as without one.
        #[arg(long)]
        no_plate: bool,
        /// Which pass to draw: the cloth as usual, or its shadow on the ground alone
        /// (black with straight alpha in PNGs, for laying on a drawn floor).
        #[arg(long, value_enum, default_value = "cloth")]
        pass: render_command::Pass,
        /// How the cloth is drawn: lit, or toon (flat tone bands and ink lines, as the scene's
        /// `cloth.toon` says).
        #[arg(long, value_enum, default_value = "lit")]
        style: render_command::StyleChoice,
        /// Write a sequence or GIF even when its estimated size is over 8 GiB or over the free space on the disk.
        #[arg(long)]
        force: bool,
        /// A PNG sequence into a folder holding frames of an earlier sequence of the same name that this
        /// one does not write: remove exactly those files as the new frames go in (else it is refused).
        #[arg(long)]
        replace_sequence: bool,
    },
}

/// An inclusive frame range `A..B`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FrameRange {
    first: i32,
    last: i32,
}

impl FrameRange {
    /// How many frames the range holds, both ends included.
    fn frame_count(self) -> u64 {
        (i64::from(self.last) - i64::from(self.first) + 1) as u64
    }
}

fn parse_frame_range(text: &str) -> Result<FrameRange, String> {
    let (a, b) =
        text.split_once("..").ok_or_else(|| format!("`{text}` is not a range: write it as A..B, e.g. 0..120"))?;
    let number =
        |s: &str| s.trim().parse::<i32>().map_err(|_| format!("`{s}` in `{text}` is not a whole frame number"));
    let (first, last) = (number(a)?, number(b.strip_prefix('=').unwrap_or(b))?);
    if first > last {
        return Err(format!("the range {text} ends before it starts: write the smaller frame first"));
    }
    Ok(FrameRange { first, last })
}

fn main() -> ExitCode {
    quiet_wayland_probe();
    // Temporary files and staging directories go with the process on Ctrl+C or SIGTERM.
    if let Err(error) = drape::atomic_file::remove_temporaries_on_signals() {
        eprintln!("warning: cannot handle Ctrl+C, temporary files may be left behind on interrupt: {error}");
    }
    let cli = Cli::parse();
    let Some(command) = cli.command else {
        return match open_editor(cli.scene, cli.quit_after_frames) {
            Ok(()) => ExitCode::SUCCESS,
            Err(error) => {
                eprintln!("error: {error}");
                ExitCode::FAILURE
            }
        };
    };
    if let Command::Export { output, .. } | Command::Render { output, .. } = &command
        && is_stdout(output)
    {
        SUMMARY_TO_STDERR.store(true, std::sync::atomic::Ordering::Relaxed);
    }
    let result = match command {
        Command::Check { scenes } => check_command::check_all(&scenes),
        Command::Export { scene, output, frame, frames, format, stage, no_layers, force, replace_sequence } => {
            let layers = !no_layers;
            let request =
                export_command::ExportRequest { frame, frames, format, stage, layers, force, replace_sequence };
            export_command::export(&scene, &output, request)
        }
        Command::Render {
            scene,
            output,
            frame,
            frames,
            size,
            wireframe,
            pins,
            catenaries,
            triangulation,
            no_colliders,
            no_references,
            camera,
            alpha,
            plate,
            no_plate,
            pass,
            style,
            force,
            replace_sequence,
        } => {
            let overlays = SceneOverlays {
                wireframe,
                pins,
                catenaries,
                triangulation,
                hide_colliders: no_colliders,
                hide_references: no_references,
                view_camera: camera == Some(render_command::CameraChoice::View),
                alpha,
                shadow_pass: pass == render_command::Pass::Shadow,
                toon: style == render_command::StyleChoice::Toon,
            };
            let shot = camera == Some(render_command::CameraChoice::Shot);
            let plate = match (plate, no_plate) {
                (true, _) => Some(true),
                (_, true) => Some(false),
                _ => None,
            };
            let request = render_command::RenderRequest {
                frame,
                frames,
                size_px: size,
                overlays,
                shot,
                plate,
                force,
                replace_sequence,
            };
            render_command::render(&scene, &output, request)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Each error already names its file and cause in one line.
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

/// Opens the editor on `path` (the magic carpet without one). A scene that
/// cannot be opened is reported in the window — over a new, untitled scene —
/// as well as on stderr: started from a file manager, nobody reads stderr.
fn open_editor(path: Option<PathBuf>, quit_after_frames: Option<u64>) -> Result<()> {
    let (scene, path, problem) = match path {
        Some(path) => match scene::load(&path) {
            Ok(scene) => (scene, Some(path), None),
            Err(error) => {
                eprintln!("error: {error}");
                (drape::editor::files::new_scene(), None, Some(format!("Could not open the scene:\n{error}")))
            }
        },
        None => {
            let mut scene = scene::parse(drape::editor::DEFAULT_SCENE, "magic_carpet.ron")?;
            locate_bundled_plate(&mut scene);
            (scene, None, None)
        }
    };
    drape::editor::run(scene, path, quit_after_frames, problem)
        .map_err(|e| anyhow!("the editor window could not run: {e}"))
}

/// The default scene is the bundled magic carpet, unsaved: its plate's
/// path, relative to `scenes/`, is made absolute in the source tree Drape
/// was built from; where that tree is gone the scene opens without a plate.
fn locate_bundled_plate(scene: &mut scene::Scene) {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let Some(plate) = &mut scene.plate else { return };
    let path = scenes.join(&plate.file);
    match path.canonicalize() {
        Ok(found) => plate.file = found.display().to_string(),
        Err(_) => scene.plate = None,
    }
}

/// Mesa's Vulkan driver probes for a Wayland display when the device opens,
/// and libwayland prints "error: XDG_RUNTIME_DIR is invalid or not set" when
/// that variable is missing (a headless shell, CI), although rendering works.
/// Pointing it at the temporary directory, which holds no Wayland socket,
/// makes the probe fail silently. Runs before any thread exists.
fn quiet_wayland_probe() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        // SAFETY: called first thing in `main`, while the process has one thread.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir()) };
    }
}

/// Refuses an output `estimate` says is too large for the limit or the disk,
/// unless `force`; the message says how to go on anyway.
fn check_size(estimate: &drape::export::SizeEstimate, output: &Path, force: bool) -> Result<()> {
    if force {
        return Ok(());
    }
    drape::export::check_export_size(estimate, output, drape::export::MAX_EXPORT_BYTES).map_err(force_hint)
}

/// A refusal of an output's size, saying how to write it anyway.
fn force_hint(error: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("{error}, or pass --force to write it anyway")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_parse_and_say_what_is_wrong() {
        assert_eq!(parse_frame_range("0..120"), Ok(FrameRange { first: 0, last: 120 }));
        assert_eq!(parse_frame_range("-10..-2"), Ok(FrameRange { first: -10, last: -2 }));
        assert_eq!(parse_frame_range("5..=5"), Ok(FrameRange { first: 5, last: 5 }));
        assert_eq!(parse_frame_range("12"), Err("`12` is not a range: write it as A..B, e.g. 0..120".into()));
        assert_eq!(parse_frame_range("a..3"), Err("`a` in `a..3` is not a whole frame number".into()));
        assert_eq!(
            parse_frame_range("9..3"),
            Err("the range 9..3 ends before it starts: write the smaller frame first".into())
        );
    }
}
