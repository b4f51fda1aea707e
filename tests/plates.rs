//! The film kit's pictures on a real (software) GPU: renders over a
//! background plate, a plate sequence with a frame missing, `--alpha`
//! frames composited over the plate, and the shadow pass.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use drape::export::write_png;
use drape::image::RgbaImage;
use drape::picture::plate::{plate_fitted, straight_over};
use drape::picture::{SceneOverlays, SceneRenderer};
use drape::render::GpuContext;
use drape::scene::{self, PlateFiles, load_plate_image};

const SIZE: (u32, u32) = (320, 180);

fn context() -> GpuContext {
    static CONTEXT: OnceLock<GpuContext> = OnceLock::new();
    CONTEXT.get_or_init(|| GpuContext::headless().unwrap_or_else(|error| panic!("{error}"))).clone()
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(format!("{name}.ron"))
}

fn drape(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_drape")).args(args).output().unwrap()
}

fn read_png(path: &Path) -> RgbaImage {
    RgbaImage::decode_png(&std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

fn channel_gap(a: &[u8], b: &[u8]) -> u8 {
    a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0)
}

/// The magic carpet's `--alpha` frame laid over its plate by a compositor's
/// straight-alpha "over" is the render over the plate: off the cloth the
/// plate exactly, on it the cloth, its rim blended alike.
#[test]
fn an_alpha_frame_over_the_plate_is_the_render_over_the_plate() {
    let path = scene_path("magic_carpet");
    let scene = scene::load(&path).unwrap();
    let plate = scene.plate.clone().expect("the magic carpet has a plate");
    let files = PlateFiles::scan(&plate, path.parent().unwrap()).unwrap();
    let mut with_plate = SceneRenderer::new(context(), &scene, SIZE, SceneOverlays::default());
    with_plate.set_plate(Some((files.clone(), plate.opacity.clone())));
    let overlays = SceneOverlays { alpha: true, ..SceneOverlays::default() };
    let mut alpha = SceneRenderer::new(context(), &scene, SIZE, overlays);
    let fitted = plate_fitted(&load_plate_image(&files.frame(36).path).unwrap(), SIZE.0, SIZE.1);
    for frame in [0, 36, 100] {
        let rendered = with_plate.render_frame(&scene, frame as f64).unwrap();
        let cloth = alpha.render_frame(&scene, frame as f64).unwrap();
        let composited = straight_over(&cloth, &fitted);
        let (mut covered, mut rim, mut off) = (0, 0, 0);
        for ((r, c), (a, p)) in rendered
            .pixels
            .chunks_exact(4)
            .zip(composited.pixels.chunks_exact(4))
            .zip(cloth.pixels.chunks_exact(4).zip(fitted.pixels.chunks_exact(4)))
        {
            match a[3] {
                0 => {
                    off += 1;
                    assert_eq!(&r[..3], &p[..3], "frame {frame}: off the cloth the render is the plate");
                }
                255 => covered += 1,
                _ => rim += 1,
            }
            // Straight alpha rounds its colours to bytes: a rim pixel of little alpha may move a few levels.
            let allowed = if a[3] == 0 || a[3] == 255 { 1 } else { 4 };
            assert!(channel_gap(&r[..3], &c[..3]) <= allowed, "frame {frame}: {r:?} rendered, {c:?} composited");
        }
        assert!(covered > 500 && rim > 50 && off > 40_000, "frame {frame}: {covered} covered, {rim} rim, {off} off");
    }
}

/// A plate sequence with frame 2's file missing: `drape render` says so in
/// one warning and frame 2 shows the nearest file's picture (frames 1 and 3
/// are as near: the earlier wins).
#[test]
fn a_missing_plate_frame_shows_the_nearest_and_is_said_once() {
    let dir = tempfile::tempdir().unwrap();
    let flag = std::fs::read_to_string(scene_path("flag")).unwrap();
    let end = flag.rfind(')').unwrap();
    let scene_text = format!(
        "{}    camera: (position: (0.0, 1.5, 6.0), target: (0.0, 1.5, 0.0), image_size: (64, 36)),\n    \
         plate: (file: \"plates/bg_##.png\", frame_offset: 10),\n)",
        &flag[..end]
    );
    let scene_file = dir.path().join("flag.ron");
    std::fs::write(&scene_file, scene_text).unwrap();
    std::fs::create_dir(dir.path().join("plates")).unwrap();
    let colours = [(10, [200, 30, 30, 255]), (11, [30, 200, 30, 255]), (13, [30, 30, 200, 255])];
    for (number, rgba) in colours {
        let image = RgbaImage { width: 8, height: 8, pixels: rgba.repeat(64) };
        let mut file = std::fs::File::create(dir.path().join(format!("plates/bg_{number}.png"))).unwrap();
        write_png(&image, &mut file).unwrap();
    }
    let out = dir.path().join("frames");
    let run = drape(&["render", scene_file.to_str().unwrap(), "--frames", "0..3", "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(warnings[0].contains("no file for frame 2 ") && warnings[0].contains("bg_##.png"), "{}", warnings[0]);
    let corner = |frame: u32| read_png(&out.join(format!("flag_{frame:04}.png"))).pixel(0, 0);
    assert_eq!(corner(0), colours[0].1);
    assert_eq!(corner(1), colours[1].1);
    assert_eq!(corner(2), colours[1].1, "frame 2 holds file 11, the nearer earlier one");
    assert_eq!(corner(3), colours[2].1);
    // --no-plate: the usual background.
    let bare = dir.path().join("bare.png");
    let run =
        drape(&["render", scene_file.to_str().unwrap(), "--frame", "2", "-o", bare.to_str().unwrap(), "--no-plate"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert_ne!(read_png(&bare).pixel(0, 0), colours[1].1);
}

/// A plate that is not there, or not a picture, stops the render (and
/// `drape check`) with a message naming it; `--plate` without one is refused.
#[test]
fn a_wrong_plate_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let flag = std::fs::read_to_string(scene_path("flag")).unwrap();
    let end = flag.rfind(')').unwrap();
    let with_plate = |file: &str| {
        format!(
            "{}    camera: (position: (0.0, 1.5, 6.0), target: (0.0, 1.5, 0.0), image_size: (64, 36)),\n    \
             plate: (file: \"{file}\"),\n)",
            &flag[..end]
        )
    };
    let missing = dir.path().join("missing.ron");
    std::fs::write(&missing, with_plate("plates/sky.png")).unwrap();
    let out = dir.path().join("out.png");
    for args in [
        vec!["render", missing.to_str().unwrap(), "-o", out.to_str().unwrap()],
        vec!["check", missing.to_str().unwrap()],
    ] {
        let run = drape(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success() && stderr.contains("no image \"plates/sky.png\""), "{args:?}: {stderr}");
    }
    std::fs::write(dir.path().join("broken.png"), b"not a picture").unwrap();
    let broken = dir.path().join("broken.ron");
    std::fs::write(&broken, with_plate("broken.png")).unwrap();
    let run = drape(&["render", broken.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && stderr.contains("broken.png") && stderr.contains("PNG"), "{stderr}");
    assert!(!out.exists(), "nothing written");
    let run = drape(&["render", scene_path("flag").to_str().unwrap(), "-o", out.to_str().unwrap(), "--plate"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && stderr.contains("no background plate"), "{stderr}");
}

/// `--pass shadow`: black with alpha where the cloth's shadow falls on the
/// ground, transparent everywhere else (the cloth itself is not drawn).
#[test]
fn the_shadow_pass_is_black_shadow_over_transparency() {
    let scene =
        scene::load(&scene_path("tablecloth_pull")).unwrap_or_else(|_| scene::load(&scene_path("flag")).unwrap());
    let shadow = SceneOverlays { shadow_pass: true, view_camera: true, ..SceneOverlays::default() };
    let image = SceneRenderer::new(context(), &scene, SIZE, shadow).render_frame(&scene, 0.0).unwrap();
    assert!(image.pixels.chunks_exact(4).all(|p| p[..3] == [0, 0, 0]), "only black");
    let shaded = image.pixels.chunks_exact(4).filter(|p| p[3] > 0).count();
    let darkest = image.pixels.chunks_exact(4).map(|p| p[3]).max().unwrap_or(0);
    assert!(shaded > 200 && darkest > 25, "{shaded} pixels in shadow, the darkest of alpha {darkest}");
    for x in 0..SIZE.0 {
        assert_eq!(image.pixel(x, 0)[3], 0, "the sky holds no shadow");
    }
    // The full render is darker where the shadow pass says the shadow is.
    let full =
        SceneRenderer::new(context(), &scene, SIZE, SceneOverlays { view_camera: true, ..SceneOverlays::default() })
            .render_frame(&scene, 0.0)
            .unwrap();
    assert!(full.pixels != image.pixels);
}

/// The curtain with `plate: (file: FILE)` (and `frame_offset` when not 0),
/// written into `dir`; the scene file and where its `file` value starts
/// (`LINE:COL`).
fn curtain_with_plate(dir: &Path, file: &str) -> (PathBuf, String) {
    let curtain = std::fs::read_to_string(scene_path("curtain")).unwrap();
    let end = curtain.rfind(')').unwrap();
    let text = format!("{}    plate: (file: {file:?}),\n)\n", &curtain[..end]);
    let (line, col) = text
        .lines()
        .enumerate()
        .find_map(|(index, line)| Some((index + 1, line.find("(file: ")? + "(file: ".len() + 1)))
        .unwrap();
    let scene_file = dir.join("curtain.ron");
    std::fs::write(&scene_file, text).unwrap();
    (scene_file, format!("{line}:{col}"))
}

/// A PNG of `width × height` pixels of one colour, as Drape writes it.
fn png_bytes(width: u32, height: u32) -> Vec<u8> {
    let image = RgbaImage { width, height, pixels: [90, 140, 200, 255].repeat((width * height) as usize) };
    let mut bytes = Vec::new();
    write_png(&image, &mut bytes).unwrap();
    bytes
}

/// A PNG's signature and header chunk claiming `width × height`, then an
/// empty picture-data chunk and the end chunk: a whole file, all header.
fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &byte in bytes {
            crc ^= u32::from(byte);
            for _ in 0..8 {
                crc = if crc & 1 == 1 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
            }
        }
        !crc
    }
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut header = width.to_be_bytes().to_vec();
    header.extend(height.to_be_bytes());
    header.extend([8, 6, 0, 0, 0]);
    for (kind, data) in [(&b"IHDR"[..], &header[..]), (b"IDAT", &[]), (b"IEND", &[])] {
        bytes.extend((data.len() as u32).to_be_bytes());
        let body = [kind, data].concat();
        bytes.extend(&body);
        bytes.extend(crc32(&body).to_be_bytes());
    }
    bytes
}

/// A plate that is a folder, a byte, a cut-short PNG, a text file named
/// `.jpg` or a PNG claiming 100 000 × 100 000 pixels: `drape check` reads
/// its header and refuses it at the line and column of its `file`, saying
/// what is wrong, and so does the scan the editor's Shot panel and viewport
/// show; nothing is said to be valid.
#[test]
fn check_reads_the_plates_header_and_says_what_is_wrong_where() {
    let whole = png_bytes(64, 36);
    let cases: [(&str, Option<Vec<u8>>, &str); 5] = [
        ("folder.png", None, "it is a folder, not a regular file"),
        ("byte.png", Some(b"x".to_vec()), "the file is 1 byte long: too short for a PNG or JPEG picture"),
        ("cut.png", Some(whole[..whole.len() / 2].to_vec()), "the PNG is cut short"),
        (
            "fake.jpg",
            Some(b"\xFF\xD8 a text file named .jpg".to_vec()),
            "not a readable JPEG: no segment marker at byte 2",
        ),
        (
            "huge.png",
            Some(png_claiming(100_000, 100_000)),
            "its header claims 100000 × 100000 pixels; a plate may be at most 4096 pixels a side, \
             the largest picture Drape renders: scale it down",
        ),
    ];
    for (file, bytes, why) in cases {
        let dir = tempfile::tempdir().unwrap();
        match bytes {
            Some(bytes) => std::fs::write(dir.path().join(file), bytes).unwrap(),
            None => std::fs::create_dir(dir.path().join(file)).unwrap(),
        }
        let (scene_file, at) = curtain_with_plate(dir.path(), file);
        let run = drape(&["check", scene_file.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        let expected = format!("error: {}:{at}: plate: cannot use {file:?}: {why}", scene_file.display());
        assert!(!run.status.success() && stderr.starts_with(&expected), "{file}:\n{stderr}\nexpected {expected}");
        assert!(!String::from_utf8_lossy(&run.stdout).contains("valid"), "{file}: nothing is called valid");
        let scene = scene::load(&scene_file).unwrap();
        let scanned = PlateFiles::scan(scene.plate.as_ref().unwrap(), dir.path()).unwrap_err();
        assert!(scanned.starts_with(&format!("plate: cannot use {file:?}: {why}")), "{file}: {scanned}");
    }
}

/// A sequence: every file the timeline shows has its header read, the
/// summary says so, and a file cut short is named with the frame that
/// shows it; files no frame shows are not asked about.
#[test]
fn check_reads_every_file_of_a_sequence_the_timeline_shows() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("plates")).unwrap();
    let whole = png_bytes(8, 6);
    for number in [0, 1, 3, 500] {
        std::fs::write(dir.path().join(format!("plates/bg_{number:04}.png")), &whole).unwrap();
    }
    let (scene_file, at) = curtain_with_plate(dir.path(), "plates/bg_####.png");
    let run = drape(&["check", scene_file.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let plate_line = stdout.lines().find(|line| line.trim_start().starts_with("plate")).unwrap();
    assert!(
        plate_line.contains("the 3 files the timeline shows read (frame 0: PNG 8 × 6 px)"),
        "frames 0..120 show files 0, 1 and 3, not 500: {plate_line}"
    );
    std::fs::write(dir.path().join("plates/bg_0003.png"), &whole[..whole.len() - 20]).unwrap();
    std::fs::write(dir.path().join("plates/bg_0500.png"), b"no frame shows this").unwrap();
    let run = drape(&["check", scene_file.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    let expected = format!(
        "error: {}:{at}: plate: cannot use \"plates/bg_0003.png\" (shown at frame 3): the PNG is cut short",
        scene_file.display()
    );
    assert!(!run.status.success() && stderr.starts_with(&expected), "{stderr}\nexpected {expected}");
}

/// A scene named without a folder, run in its own folder (`drape render
/// shot.ron`), finds a plate sequence beside it as it does by a full path.
#[test]
fn a_plate_sequence_beside_a_scene_named_bare_is_found() {
    let dir = tempfile::tempdir().unwrap();
    for number in [1, 2, 3] {
        std::fs::write(dir.path().join(format!("bg_{number:04}.png")), png_bytes(8, 6)).unwrap();
    }
    curtain_with_plate(dir.path(), "bg_####.png");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_drape"))
        .args(["check", "curtain.ron"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("PNG 8 × 6 px"), "{stdout}");
}
