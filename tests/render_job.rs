//! The render job behind `drape render` and the editor's File ▸ Render…:
//! what it writes, what it refuses before any GPU work, and that a cancel
//! stops it with nothing left behind — no frames, no staging directory, no
//! temporary file, no folder it made.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

use drape::image::RgbaImage;
use drape::render::GpuContext;
use drape::render_job::{RenderJobError, RenderKind, RenderRequest, render_to_files};
use drape::scene::{self, Scene};

const SIZE: (u32, u32) = (64, 48);

fn context() -> GpuContext {
    static CONTEXT: OnceLock<GpuContext> = OnceLock::new();
    CONTEXT.get_or_init(|| GpuContext::headless().unwrap_or_else(|error| panic!("{error}"))).clone()
}

fn flag() -> (Scene, PathBuf) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/flag.ron");
    (scene::load(&path).unwrap(), path)
}

/// Every name in `dir`, hidden ones (temporaries, staging) included, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

fn render(
    scene: &Scene,
    path: &Path,
    request: &RenderRequest,
    progress: &mut dyn FnMut(u64, u64),
    cancel: &AtomicBool,
) -> Result<drape::render_job::RenderSummary, RenderJobError> {
    render_to_files(scene, Some(path), request, Some(&context()), progress, cancel)
}

#[test]
fn a_sequence_with_alpha_is_written_frame_by_frame_with_progress() {
    let (scene, path) = flag();
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    let mut request = RenderRequest::new(RenderKind::Sequence, frames.clone(), 10..=12, SIZE);
    request.overlays.alpha = true;
    let mut seen = Vec::new();
    let summary = render(&scene, &path, &request, &mut |done, total| seen.push((done, total)), &AtomicBool::new(false))
        .unwrap_or_else(|error| panic!("{error}"));
    assert_eq!(seen, [(0, 3), (1, 3), (2, 3), (3, 3)]);
    assert_eq!(names_in(&frames), ["flag_0010.png", "flag_0011.png", "flag_0012.png"]);
    assert_eq!(summary.files, ["flag_0010.png", "flag_0011.png", "flag_0012.png"].map(|n| frames.join(n)));
    assert_eq!((summary.frame_count(), summary.size_px), (3, SIZE));
    for file in &summary.files {
        let image = RgbaImage::decode_png(&std::fs::read(file).unwrap()).unwrap();
        assert_eq!((image.width, image.height), SIZE);
        assert_eq!(image.pixel(0, 0)[3], 0, "{}: the corner is off the cloth", file.display());
    }
}

#[test]
fn a_cancel_stops_every_kind_and_leaves_nothing() {
    let (scene, path) = flag();
    let dir = tempfile::tempdir().unwrap();
    let existing = dir.path().join("existing");
    std::fs::create_dir(&existing).unwrap();
    let outputs = [
        (RenderKind::Sequence, dir.path().join("new_folder")),
        (RenderKind::Sequence, existing.clone()),
        (RenderKind::Gif, dir.path().join("flag.gif")),
        (RenderKind::Png, dir.path().join("flag.png")),
    ];
    for (kind, output) in outputs {
        let request = RenderRequest::new(kind, output.clone(), 0..=5, SIZE);
        let cancel = AtomicBool::new(false);
        // Cancelled once the first frame is drawn (a still: before it is written).
        let mut progress = |done: u64, total: u64| {
            if done >= 1 || total == 1 {
                cancel.store(true, Ordering::Relaxed);
            }
        };
        let result = render_to_files(&scene, Some(&path), &request, Some(&context()), &mut progress, &cancel);
        assert!(matches!(result, Err(RenderJobError::Cancelled)), "{kind:?}: {result:?}");
        assert!(cancel.load(Ordering::Relaxed), "{kind:?}: the cancel came during the render");
        assert_eq!(names_in(dir.path()), ["existing"], "{kind:?}: nothing new beside it");
        assert!(names_in(&existing).is_empty(), "{kind:?}: nothing in the existing folder");
    }
    let error = RenderJobError::Cancelled.to_string();
    assert_eq!(error, "the render was cancelled; nothing was written");
}

#[test]
fn bad_requests_are_refused_before_anything_is_drawn() {
    let (scene, path) = flag();
    let dir = tempfile::tempdir().unwrap();
    let never = AtomicBool::new(false);
    let refused = |request: RenderRequest| {
        // No device is given: a refusal must come before one is opened.
        let mut progress = |_, _| panic!("nothing is drawn for {request:?}");
        render_to_files(&scene, Some(&path), &request, None, &mut progress, &never).unwrap_err().to_string()
    };
    let mut gif = RenderRequest::new(RenderKind::Gif, dir.path().join("a.gif"), 0..=3, SIZE);
    gif.overlays.alpha = true;
    assert!(refused(gif).contains("a GIF has no alpha channel"));
    let mut plate = RenderRequest::new(RenderKind::Png, dir.path().join("a.png"), 0..=0, SIZE);
    plate.plate = true;
    assert!(refused(plate).contains("no background plate"));
    let outside = RenderRequest::new(RenderKind::Sequence, dir.path().join("s"), 0..=100_000, SIZE);
    assert!(refused(outside).contains("outside the scene's timeline"));
    let nowhere = RenderRequest::new(RenderKind::Png, dir.path().join("no/such/a.png"), 0..=0, SIZE);
    assert!(refused(nowhere).contains("does not exist"));
    let deep = RenderRequest::new(RenderKind::Sequence, dir.path().join("no/such"), 0..=1, SIZE);
    assert!(refused(deep).contains("does not exist"));
    assert!(refused(RenderRequest::new(RenderKind::Png, PathBuf::new(), 0..=0, SIZE)).contains("no output"));
    assert!(refused(RenderRequest::new(RenderKind::Png, dir.path().join("z.png"), 0..=0, (0, 10))).contains("0×10"));
    assert!(names_in(dir.path()).is_empty(), "nothing written");
}

/// A sequence into a folder holding more frames of an earlier one is held
/// back before anything is drawn, naming them; allowed to replace them, it
/// removes exactly those and says so.
#[test]
fn an_earlier_sequence_s_other_frames_are_held_back_or_replaced() {
    let (scene, path) = flag();
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    for frame in 0..5 {
        std::fs::write(frames.join(format!("flag_{frame:04}.png")), "old").unwrap();
    }
    std::fs::write(frames.join("flag_0009.png.txt"), "mine").unwrap();
    let never = AtomicBool::new(false);
    let mut request = RenderRequest::new(RenderKind::Sequence, frames.clone(), 0..=1, SIZE);
    let mut nothing_drawn = |_, _| panic!("nothing is drawn for a refused render");
    let error = render_to_files(&scene, Some(&path), &request, None, &mut nothing_drawn, &never).unwrap_err();
    assert!(matches!(error, RenderJobError::OldFrames(_)), "{error}");
    assert!(error.to_string().contains("(frames 2–4: flag_0002.png … flag_0004.png)"), "{error}");
    assert_eq!(names_in(&frames).len(), 6);

    request.replace_sequence = true;
    let summary = render(&scene, &path, &request, &mut |_, _| {}, &never).unwrap_or_else(|error| panic!("{error}"));
    assert_eq!(summary.removed, ["flag_0002.png", "flag_0003.png", "flag_0004.png"].map(|n| frames.join(n)));
    assert_eq!(names_in(&frames), ["flag_0000.png", "flag_0001.png", "flag_0009.png.txt"]);
}

/// A render never writes over the scene file or a plate picture it shows,
/// whatever the output is called.
#[test]
fn a_render_never_writes_over_what_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene_file = dir.path().join("flag.png");
    std::fs::copy(manifest.join("scenes/flag.ron"), &scene_file).unwrap();
    let scene = scene::load(&scene_file).unwrap();
    let never = AtomicBool::new(false);
    let mut nothing_drawn = |_, _| panic!("nothing is drawn for a refused render");
    let request = RenderRequest::new(RenderKind::Png, scene_file.clone(), 0..=0, SIZE);
    let error = render_to_files(&scene, Some(&scene_file), &request, None, &mut nothing_drawn, &never).unwrap_err();
    assert!(error.to_string().contains("the scene file, which would be lost"), "{error}");

    let mut carpet = scene::load(&manifest.join("scenes/magic_carpet.ron")).unwrap();
    let plate = dir.path().join("plate.png");
    std::fs::copy(manifest.join("assets/magic_carpet_plate.png"), &plate).unwrap();
    carpet.plate.as_mut().expect("the carpet has a plate").file = "plate.png".into();
    let carpet_file = dir.path().join("carpet.ron");
    let mut request = RenderRequest::new(RenderKind::Png, plate.clone(), 0..=0, SIZE);
    request.plate = true;
    let error = render_to_files(&carpet, Some(&carpet_file), &request, None, &mut nothing_drawn, &never).unwrap_err();
    assert!(error.to_string().contains("a file the scene reads, which would be lost"), "{error}");
    assert_eq!(names_in(dir.path()), ["flag.png", "plate.png"]);
}
