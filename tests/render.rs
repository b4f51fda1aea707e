//! The renderer on a real (software) GPU: golden images of every example
//! scene, overlays and ghosts, a projection check, and naga validation of the
//! shaders. `WGPU_BACKEND=gl` runs them on llvmpipe, `=vulkan` on lavapipe;
//! unset, Vulkan is tried first. Set `DRAPE_UPDATE_GOLDEN=1` to rewrite the
//! expected pictures after a deliberate change (and look at them).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use drape::animate::{Evaluator, frame_time_secs};
use drape::export::write_png;
use drape::image::RgbaImage;
use drape::mesh::Mesh;
use drape::picture::{SceneOverlays, SceneRenderer, render_scene_frame};
use drape::render::headless::render_mesh;
use drape::render::overlay::colors;
use drape::render::pipelines::SHADER_SOURCES;
use drape::render::{FrameInput, Ghost, GpuContext, OrbitCamera, Overlay, PinState, RenderOptions, Solids};
use drape::scene::{self, ClothTexture};

const GOLDEN_SIZE: (u32, u32) = (320, 180);

fn context() -> GpuContext {
    static CONTEXT: OnceLock<GpuContext> = OnceLock::new();
    CONTEXT.get_or_init(|| GpuContext::headless().unwrap_or_else(|error| panic!("{error}"))).clone()
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// sRGB byte to CIELAB (D65), for a colour difference that follows what the eye sees.
fn lab(rgb: [u8; 3]) -> [f32; 3] {
    let linear = rgb.map(|v| {
        let v = v as f32 / 255.0;
        if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
    });
    let [r, g, b] = linear;
    let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
    let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
    let f = |t: f32| if t > 0.008856 { t.cbrt() } else { 7.787 * t + 16.0 / 116.0 };
    let (fx, fy, fz) = (f(x), f(y), f(z));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

fn delta_e(a: [u8; 4], b: [u8; 4]) -> f32 {
    let (la, lb) = (lab([a[0], a[1], a[2]]), lab([b[0], b[1], b[2]]));
    ((la[0] - lb[0]).powi(2) + (la[1] - lb[1]).powi(2) + (la[2] - lb[2]).powi(2)).sqrt()
}

/// The tolerance, and why:
/// - A pixel "differs" when its CIE76 ΔE exceeds 8: about where two flat patches
///   side by side look different to most viewers. Shading changes from a
///   different light, normal or texture lookup exceed it over whole regions.
/// - Up to 0.5% of the pixels may differ: on a 320×180 picture that is a
///   one-pixel band along about 290 px of silhouette or overlay edge, which is
///   what rasterisers legitimately disagree on (sample positions, the last bit
///   of interpolation, MSAA resolve). Moving the cloth by one pixel changes far more.
/// - The mean ΔE over the picture stays under 1: no global tint or exposure shift.
///
/// llvmpipe through GL and through Vulkan (lavapipe) agree to within 1/255 on
/// every pixel here; the slack is for other Mesa and LLVM versions.
const DIFFERING_DELTA_E: f32 = 8.0;
const MAX_DIFFERING_FRACTION: f64 = 0.005;
const MAX_MEAN_DELTA_E: f64 = 1.0;

/// Compares `actual` with `tests/golden/<name>.png`; on failure writes
/// `<name>.actual.png` and `<name>.diff.png` beside it and panics with the figures.
fn assert_matches_golden(name: &str, actual: &RgbaImage) {
    let expected_path = golden_dir().join(format!("{name}.png"));
    if std::env::var_os("DRAPE_UPDATE_GOLDEN").is_some() {
        std::fs::create_dir_all(golden_dir()).unwrap();
        // Best compression: these files live in the repository.
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, actual.width, actual.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_compression(png::Compression::High);
        encoder.write_header().unwrap().write_image_data(&actual.pixels).unwrap();
        std::fs::write(&expected_path, bytes).unwrap();
        return;
    }
    let bytes = std::fs::read(&expected_path)
        .unwrap_or_else(|e| panic!("{}: {e} (DRAPE_UPDATE_GOLDEN=1 creates it)", expected_path.display()));
    let expected = RgbaImage::decode_png(&bytes).unwrap();
    assert_eq!((expected.width, expected.height), (actual.width, actual.height), "{name}: size differs");
    let mut diff = RgbaImage::new(actual.width, actual.height);
    let (mut differing, mut sum) = (0usize, 0f64);
    for y in 0..actual.height {
        for x in 0..actual.width {
            let (a, e) = (actual.pixel(x, y), expected.pixel(x, y));
            let de = delta_e(a, e);
            sum += de as f64;
            let at = ((y * actual.width + x) * 4) as usize;
            // Differing pixels in red over a faded copy of the expected picture.
            let faded = (e[0] as u32 + e[1] as u32 + e[2] as u32) / 12;
            let px = if de > DIFFERING_DELTA_E {
                differing += 1;
                [255, 0, 0, 255]
            } else {
                [faded as u8, faded as u8, faded as u8, 255]
            };
            diff.pixels[at..at + 4].copy_from_slice(&px);
        }
    }
    let count = (actual.width * actual.height) as f64;
    let fraction = differing as f64 / count;
    let mean = sum / count;
    if fraction > MAX_DIFFERING_FRACTION || mean > MAX_MEAN_DELTA_E {
        for (suffix, image) in [("actual", actual), ("diff", &diff)] {
            let mut bytes = Vec::new();
            write_png(image, &mut bytes).unwrap();
            std::fs::write(golden_dir().join(format!("{name}.{suffix}.png")), bytes).unwrap();
        }
        panic!(
            "{name}: {:.3}% of pixels differ by ΔE > {DIFFERING_DELTA_E} (allowed {:.3}%), mean ΔE {mean:.3} \
             (allowed {MAX_MEAN_DELTA_E}); wrote {name}.actual.png and {name}.diff.png in {}",
            fraction * 100.0,
            MAX_DIFFERING_FRACTION * 100.0,
            golden_dir().display()
        );
    }
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(format!("{name}.ron"))
}

fn render_scene(name: &str, frames: &[i32], overlays: SceneOverlays) -> Vec<RgbaImage> {
    let scene = scene::load(&scene_path(name)).unwrap();
    let mut renderer = SceneRenderer::new(context(), &scene, GOLDEN_SIZE, overlays);
    frames.iter().map(|&f| renderer.render_frame(&scene, f as f64).unwrap()).collect()
}

/// (scene, frames): rest poses, and frames where in-betweens and layers show.
const GOLDEN_FRAMES: [(&str, &[i32]); 12] = [
    ("curtain", &[0]),
    ("tablecloth", &[0]),
    ("tent", &[0]),
    ("corner", &[0]),
    ("flag", &[0, 60]),
    ("tablecloth_pull", &[0, 30]),
    ("round_table", &[0, 36]),
    ("cape_on_shoulders", &[0, 7]),
    ("cape", &[0, 9]),
    ("swing", &[12]),
    ("magic_carpet", &[0, 36, 100]),
    ("magic_carpet_tutorial", &[24, 96]),
];

#[test]
fn every_example_scene_matches_its_golden_images() {
    let mut failures = Vec::new();
    for (name, frames) in GOLDEN_FRAMES {
        let images = render_scene(name, frames, SceneOverlays::default());
        for (frame, image) in frames.iter().zip(&images) {
            let golden = format!("{name}_f{frame:04}");
            if let Err(panic) = std::panic::catch_unwind(|| assert_matches_golden(&golden, image)) {
                failures.push(panic.downcast_ref::<String>().cloned().unwrap_or_default());
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_scene_in_the_folder_has_golden_images() {
    for entry in std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        assert!(GOLDEN_FRAMES.iter().any(|(name, _)| *name == stem), "scenes/{stem}.ron has no golden image");
    }
}

#[test]
fn overlays_match_their_golden_image() {
    let overlays =
        SceneOverlays { wireframe: true, pins: true, catenaries: true, triangulation: false, ..Default::default() };
    let image = render_scene("tent", &[0], overlays).remove(0);
    assert_matches_golden("tent_overlays_f0000", &image);
    // The triangulation alone, through the one-call API on a scene frame.
    let scene = scene::load(&scene_path("tent")).unwrap();
    let overlays = SceneOverlays { triangulation: true, pins: true, ..SceneOverlays::default() };
    let image = render_scene_frame(Some(&context()), &scene, 0.0, GOLDEN_SIZE, overlays).unwrap();
    assert_matches_golden("tent_triangulation_f0000", &image);
}

fn carpet_mesh(frame: i32) -> (Mesh, scene::Scene) {
    let scene = scene::load(&scene_path("magic_carpet")).unwrap();
    let mesh = Evaluator::new().evaluate(&scene, frame_time_secs(&scene.timeline, frame as f64));
    (mesh, scene)
}

#[test]
fn textures_and_ghosts_match_their_golden_image() {
    let (mesh, scene) = carpet_mesh(40);
    let before = Evaluator::new().evaluate(&scene, frame_time_secs(&scene.timeline, 34.0));
    let after = Evaluator::new().evaluate(&scene, frame_time_secs(&scene.timeline, 46.0));
    let ghosts = [
        Ghost { mesh: &before, tint: [0.9, 0.25, 0.15], opacity: 0.35 },
        Ghost { mesh: &after, tint: [0.15, 0.55, 0.9], opacity: 0.35 },
    ];
    let (lo, hi) =
        drape::render::camera::bounds(&[before.positions.clone(), after.positions.clone()].concat()).unwrap();
    let camera = OrbitCamera::framing(lo, hi, 16.0 / 9.0);
    for texture in [ClothTexture::Carpet, ClothTexture::Checker] {
        let options = RenderOptions::default().with_texture(texture);
        let overlay = Overlay::default();
        let input = FrameInput {
            mesh: &mesh,
            camera: &camera,
            options: &options,
            ghosts: &ghosts,
            overlay: &overlay,
            solids: &[],
        };
        let image = render_mesh(Some(&context()), input, GOLDEN_SIZE).unwrap();
        assert_matches_golden(&format!("magic_carpet_{texture:?}_ghosts_f0040").to_lowercase(), &image);
    }
}

#[test]
fn a_pin_is_drawn_on_the_pixel_it_projects_to() {
    // Scenes whose pins are all in plain view from the default camera.
    for name in ["curtain", "tablecloth", "magic_carpet"] {
        assert_pins_project_onto_their_dots(name);
    }
}

fn assert_pins_project_onto_their_dots(name: &str) {
    let scene = scene::load(&scene_path(name)).unwrap();
    let mesh = Evaluator::new().evaluate(&scene, 0.0);
    let (lo, hi) = drape::render::camera::bounds(&mesh.positions).unwrap();
    let camera = OrbitCamera::framing(lo, hi, 4.0 / 3.0);
    let size = (400, 300);
    let options = RenderOptions::default();
    for pin in &scene.keys[0].pins {
        let grid = (pin.grid.0 as usize, pin.grid.1 as usize);
        let mut overlay = Overlay::default();
        overlay.add_pins(&mesh, [(grid, PinState::Normal)]);
        let input =
            FrameInput { mesh: &mesh, camera: &camera, options: &options, ghosts: &[], overlay: &overlay, solids: &[] };
        let image = render_mesh(Some(&context()), input, size).unwrap();
        let world = mesh.positions[grid.1 * mesh.cols + grid.0];
        let pixel = camera.project(world, size).expect("the pin is in front of the camera");
        let (x, y) = (pixel.x.floor() as u32, pixel.y.floor() as u32);
        let drawn = image.pixel(x, y);
        let pin_srgb = colors::PIN.map(|c| if c <= 0.0031308 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 });
        let expected = [0, 1, 2].map(|c| (pin_srgb[c] * 255.0).round() as i32);
        for c in 0..3 {
            assert!(
                (drawn[c] as i32 - expected[c]).abs() <= 2,
                "{name}: pin {grid:?} at {world} projects to ({x}, {y}) where the picture has {drawn:?}, \
                 not the pin's {expected:?}"
            );
        }
    }
}

#[test]
fn every_shader_passes_naga_validation() {
    let mut validated = Vec::new();
    for (name, source) in SHADER_SOURCES {
        let module =
            naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        validated.push(name.to_string());
    }
    let compose = drape::render::compose::COMPOSE_SHADER;
    let module = naga::front::wgsl::parse_str(compose).unwrap_or_else(|e| panic!("{}", e.emit_to_string(compose)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default())
        .validate(&module)
        .unwrap_or_else(|e| panic!("compose.wgsl: {}", e.emit_to_string(compose)));
    validated.push("compose.wgsl".to_string());
    // Every file in shaders/ is compiled (frame.wgsl as the prefix of all the others).
    for entry in std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders")).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().to_string();
        assert!(file == "frame.wgsl" || validated.contains(&file), "shaders/{file} is not in SHADER_SOURCES");
    }
}

#[test]
fn a_missing_driver_is_an_error_that_says_what_was_tried_and_what_to_install() {
    let scene = scene_path("curtain");
    let out = std::env::temp_dir().join("drape_no_driver.png");
    // Vulkan with no driver to load: the adapter search fails for real.
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_drape"))
        .args(["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .env("WGPU_BACKEND", "vulkan")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no GPU adapter found. Tried: Vulkan (lavapipe on Mesa)"), "{stderr}");
    assert!(stderr.contains("apt-get install mesa-vulkan-drivers"), "{stderr}");
    assert!(!out.exists());
}

fn drape(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_drape")).args(args).output().unwrap()
}

#[test]
fn render_writes_a_gif_with_every_frame_at_the_scene_fps() {
    let dir = tempfile::tempdir().unwrap();
    let gif_path = dir.path().join("carpet.gif");
    let scene = scene_path("magic_carpet");
    let run = drape(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        gif_path.to_str().unwrap(),
        "--frames",
        "10..21",
        "--size",
        "96x54",
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("frames 10..21, 12 frames at 96×54") && stdout.contains("frames/s"), "{stdout}");
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(std::fs::File::open(&gif_path).unwrap()).unwrap();
    assert_eq!((decoder.width(), decoder.height()), (96, 54));
    let mut delays_cs = Vec::new();
    let mut first_pixels = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        delays_cs.push(frame.delay as u32);
        first_pixels.push(frame.buffer.to_vec());
    }
    assert_eq!(delays_cs.len(), 12);
    // 24 fps: 12 frames last half a second.
    assert_eq!(delays_cs.iter().sum::<u32>(), 50);
    // The cloth moves: consecutive frames differ.
    assert!(first_pixels.windows(2).all(|w| w[0] != w[1]));
}

#[test]
fn render_writes_a_numbered_png_sequence_and_one_png() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("flag");
    let seq = dir.path().join("seq");
    let run =
        drape(&["render", scene.to_str().unwrap(), "-o", seq.to_str().unwrap(), "--frames", "0..3", "--size", "64x48"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let mut names: Vec<String> =
        std::fs::read_dir(&seq).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    names.sort();
    assert_eq!(names, ["flag_0000.png", "flag_0001.png", "flag_0002.png", "flag_0003.png"]);
    let frame_2 = RgbaImage::decode_png(&std::fs::read(seq.join("flag_0002.png")).unwrap()).unwrap();
    assert_eq!((frame_2.width, frame_2.height), (64, 48));

    // A single frame matches the same frame of the sequence exactly.
    let one = dir.path().join("one.png");
    let run =
        drape(&["render", scene.to_str().unwrap(), "-o", one.to_str().unwrap(), "--frame", "2", "--size", "64x48"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(RgbaImage::decode_png(&std::fs::read(&one).unwrap()).unwrap(), frame_2);
}

#[test]
fn render_refuses_bad_requests_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("flag");
    let scene = scene.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (&["-o", "x.jpg"], "cannot render to .jpg"),
        (&["-o", "x.png", "--frames", "0..3"], "names a PNG file"),
        (&["-o", "x.png", "--size", "0x10"], "not a side of 1 to 4096 pixels"),
        (&["-o", "noext"], "has no extension"),
    ];
    for (args, message) in cases {
        // The argument after -o is a file name in the temporary directory.
        let out_args: Vec<String> = args
            .iter()
            .enumerate()
            .map(|(k, a)| if k == 1 { dir.path().join(a).display().to_string() } else { a.to_string() })
            .collect();
        let mut all = vec!["render", scene];
        all.extend(out_args.iter().map(String::as_str));
        let run = drape(&all);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success() && stderr.contains(message), "{args:?}: {stderr}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing is written on a refused request");
}

#[test]
fn a_pin_behind_the_cloth_shows_faintly() {
    let scene = scene::load(&scene_path("tent")).unwrap();
    let mesh = Evaluator::new().evaluate(&scene, 0.0);
    let (lo, hi) = drape::render::camera::bounds(&mesh.positions).unwrap();
    let camera = OrbitCamera::framing(lo, hi, 4.0 / 3.0);
    let size = (400, 300);
    let options = RenderOptions::default();
    // Grid (0, 0) is the back-left corner, on the ground behind the tent from the default view.
    let back = mesh.positions[0];
    let pixel = camera.project(back, size).unwrap();
    let (x, y) = (pixel.x as u32, pixel.y as u32);
    let mut with_pin = Overlay::default();
    with_pin.add_pins(&mesh, [((0, 0), PinState::Normal)]);
    let picture = |overlay: &Overlay| {
        let input = FrameInput { mesh: &mesh, camera: &camera, options: &options, ghosts: &[], overlay, solids: &[] };
        render_mesh(Some(&context()), input, size).unwrap().pixel(x, y)
    };
    let (without, with) = (picture(&Overlay::default()), picture(&with_pin));
    // Redder than the cloth alone, but far from the full red dot.
    assert!(with[0] as i32 - with[1] as i32 > without[0] as i32 - without[1] as i32 + 20, "{without:?} → {with:?}");
    assert!(with[1] > 100, "the hidden pin is drawn at full strength: {with:?}");
}

/// One renderer drawing frame after frame (as the viewport does) writes the
/// colliders again only when they change: a ball moved, then hidden, draws
/// exactly as a fresh renderer draws it.
#[test]
fn a_renderer_kept_between_frames_draws_changed_solids_as_a_fresh_one() {
    use drape::render::{OffscreenTarget, Renderer, readback::read_texture};
    let (mesh, scene) = carpet_mesh(0);
    let (lo, hi) = drape::render::camera::bounds(&mesh.positions).unwrap();
    let camera = OrbitCamera::framing(lo, hi - glam::Vec3::Y * 0.5, 4.0 / 3.0);
    let options = RenderOptions::default();
    let overlay = Overlay::default();
    let ball = |x: f64| {
        let mut with_ball = scene.clone();
        with_ball.colliders = ron::from_str(&format!("[Sphere((center: ({x}, 0.6, -0.8), radius: 0.3))]")).unwrap();
        drape::picture::collider_solids(&with_ball, 0.0, 1.0)
    };
    // Sets of solids, as colliders and referenced files give them: two sets at the end.
    let frames =
        [vec![ball(-0.3)], vec![ball(-0.3)], vec![ball(0.4)], vec![], vec![ball(0.4)], vec![ball(-0.3), ball(0.4)]];
    let context = context();
    let size = (320, 240);
    let mut kept = Renderer::new(&context.device, &context.queue);
    let target = OffscreenTarget::new(&context.device, size);
    for (index, solids) in frames.iter().enumerate() {
        let input =
            FrameInput { mesh: &mesh, camera: &camera, options: &options, ghosts: &[], overlay: &overlay, solids };
        kept.render(&context.device, &context.queue, &target, input);
        let drawn = read_texture(&context.device, &context.queue, target.resolved()).unwrap();
        let fresh = render_mesh(Some(&context), input, size).unwrap();
        assert!(drawn == fresh, "frame {index}: the kept renderer drew something else");
    }
    let picture = |solids: &[Solids]| {
        let input =
            FrameInput { mesh: &mesh, camera: &camera, options: &options, ghosts: &[], overlay: &overlay, solids };
        render_mesh(Some(&context), input, size).unwrap()
    };
    assert!(picture(&frames[0]) != picture(&frames[2]), "the ball is in view and moved");
}

/// A reference's base-colour texture is drawn: a quad facing the camera
/// with a two-pixel texture (left red, right green) written here as a
/// `.gltf` with its `.bin` and `.png` beside it, seen through a saved view.
/// Untextured, both halves would be the same (white) base colour.
#[test]
fn a_referenced_mesh_is_drawn_with_its_texture() {
    let dir = tempfile::tempdir().unwrap();
    let floats = |values: &[f32]| values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>();
    let mut bin = floats(&[-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 2.0, 0.0, -1.0, 2.0, 0.0]);
    bin.extend(floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]));
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.path().join("quad.bin"), &bin).unwrap();
    let texture = RgbaImage { width: 2, height: 1, pixels: vec![230, 20, 20, 255, 20, 230, 20, 255] };
    let mut png = Vec::new();
    write_png(&texture, &mut png).unwrap();
    std::fs::write(dir.path().join("quad.png"), png).unwrap();
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0, "sampler": 0}], "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"uri": "quad.png"}],
        "buffers": [{"uri": "quad.bin", "byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, 0.0, 0.0], "max": [1.0, 2.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    std::fs::write(dir.path().join("quad.gltf"), gltf.to_string()).unwrap();
    // The cloth hangs in view beside the quad, so the saved view stays as it is.
    let text = "(version: 1, cloth: (size: (0.1, 0.1), grid: (3, 3)), \
                keys: [(frame: 0, pins: [(grid: (0, 0), pos: (1.3, 0.4, 0.5))])], \
                references: [(name: \"quad\", file: \"quad.gltf\")], \
                view: (target: (0.0, 1.0, 0.0), yaw_deg: 0.0, pitch_deg: 0.0, distance_m: 4.0, fov_y_deg: 35.0))";
    std::fs::write(dir.path().join("quad.ron"), text).unwrap();
    let scene = scene::load(&dir.path().join("quad.ron")).unwrap();
    let image = render_scene_frame(Some(&context()), &scene, 0.0, (320, 240), SceneOverlays::default()).unwrap();
    let pixel = |x: u32, y: u32| {
        let at = ((y * image.width + x) * 4) as usize;
        [image.pixels[at], image.pixels[at + 1], image.pixels[at + 2]].map(f32::from)
    };
    // 0.5 m either side of the middle, 4 m away: about 48 px either side of 160.
    let (left, right) = (pixel(112, 120), pixel(208, 120));
    assert!(left[0] > 2.0 * left[1] && left[0] > 2.0 * left[2], "the left half is red: {left:?}");
    assert!(right[1] > 2.0 * right[0] && right[1] > 2.0 * right[2], "the right half is green: {right:?}");
}

/// A scene's shot camera is what `drape render` looks through, at its
/// image size unless --size says otherwise; `--camera shot` on a scene
/// without one is refused; `--camera view` looks through the framing view.
#[test]
fn render_looks_through_the_shot_camera_at_its_image_size() {
    let dir = tempfile::tempdir().unwrap();
    let flag = std::fs::read_to_string(scene_path("flag")).unwrap();
    let end = flag.rfind(')').unwrap();
    let with_camera = format!(
        "{}    camera: (position: (0.0, 1.5, 6.0), target: (0.0, 1.5, 0.0), focal_length_mm: 50.0, image_size: (160, 90)),\n)",
        &flag[..end]
    );
    let scene = dir.path().join("flag.ron");
    std::fs::write(&scene, with_camera).unwrap();
    let shot = dir.path().join("shot.png");
    let run = drape(&["render", scene.to_str().unwrap(), "-o", shot.to_str().unwrap(), "--frame", "30"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let image = RgbaImage::decode_png(&std::fs::read(&shot).unwrap()).unwrap();
    assert_eq!((image.width, image.height), (160, 90), "the camera's image size");
    let view = dir.path().join("view.png");
    let args = ["render", scene.to_str().unwrap(), "-o", view.to_str().unwrap(), "--frame", "30", "--camera", "view"];
    let run = drape(&[&args[..], &["--size", "160x90"]].concat());
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let framed = RgbaImage::decode_png(&std::fs::read(&view).unwrap()).unwrap();
    assert!(framed.pixels != image.pixels, "the framing view is another picture");
    let plain = scene_path("flag");
    let out = dir.path().join("none.png");
    let run = drape(&["render", plain.to_str().unwrap(), "-o", out.to_str().unwrap(), "--camera", "shot"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && stderr.contains("the scene has no shot camera"), "{stderr}");
}

/// `--alpha`: the cloth alone over transparency. Away from the cloth every
/// pixel is alpha 0 (no ground, no background), inside it 255, its
/// anti-aliased rim in between; a GIF with alpha is refused.
#[test]
fn an_alpha_render_is_transparent_off_the_cloth_and_opaque_on_it() {
    let scene = scene::load(&scene_path("flag")).unwrap();
    let overlays = SceneOverlays { alpha: true, ..SceneOverlays::default() };
    let mut renderer = SceneRenderer::new(context(), &scene, GOLDEN_SIZE, overlays);
    let image = renderer.render_frame(&scene, 30.0).unwrap();
    let alpha = |x: u32, y: u32| image.pixel(x, y)[3];
    // Projected cloth points: every grid point's pixel lies on the cloth.
    let (cols, rows) = (scene.cloth.cols(), scene.cloth.rows());
    let mesh = renderer.mesh().clone();
    let camera = *renderer.camera();
    for j in 1..rows - 1 {
        for i in 1..cols - 1 {
            let at = camera.project(mesh.positions[j * cols + i], GOLDEN_SIZE).unwrap();
            let (x, y) = (at.x as u32, at.y as u32);
            assert_eq!(alpha(x, y), 255, "inside the cloth at grid ({i}, {j}), pixel ({x}, {y})");
        }
    }
    // The ground and the background are gone: the bottom rows and the corners are clear.
    for x in 0..GOLDEN_SIZE.0 {
        for y in [0, GOLDEN_SIZE.1 - 1] {
            assert_eq!(alpha(x, y), 0, "pixel ({x}, {y}) is off the cloth");
        }
    }
    let rim = image.pixels.chunks_exact(4).filter(|p| p[3] > 0 && p[3] < 255).count();
    assert!(rim > 0, "the cloth's edge is anti-aliased");
    assert!(image.pixels.chunks_exact(4).all(|p| p[3] > 0 || p[..3] == [0, 0, 0]), "transparent is transparent black");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("flag.gif");
    let run = drape(&["render", scene_path("flag").to_str().unwrap(), "-o", out.to_str().unwrap(), "--alpha"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && stderr.contains("a GIF has no alpha channel"), "{stderr}");
}

/// The toon style on the magic carpet and the flag, at the frames the other
/// goldens use: flat tone bands, the texture kept, ink on the border,
/// silhouette and creases, in the scenes' default toon settings.
#[test]
fn the_toon_style_matches_its_golden_images() {
    let overlays = SceneOverlays { toon: true, ..SceneOverlays::default() };
    for (name, frame) in [("magic_carpet", 36), ("flag", 60)] {
        let image = render_scene(name, &[frame], overlays).remove(0);
        assert_matches_golden(&format!("{name}_toon_f{frame:04}"), &image);
    }
}

/// A sheet folded back on itself (a taco seen from the front): the ink of
/// the border hidden behind the front half is hidden, the front half's own
/// border and the fold (a silhouette) are drawn on the visible surface.
#[test]
fn toon_ink_behind_the_cloth_is_hidden_and_on_it_is_drawn() {
    let (cols, rows) = (9, 9);
    let positions: Vec<glam::DVec3> = (0..rows)
        .flat_map(|j| (0..cols).map(move |i| (i, j)))
        .map(|(i, j)| {
            let x = i as f64 / 8.0 - 0.5;
            // Down the front to the fold at row 4, then back up behind it.
            if j <= 4 {
                glam::DVec3::new(x, 1.0 - j as f64 * 0.125, 0.0)
            } else {
                glam::DVec3::new(x, 0.5 + (j - 4) as f64 * 0.1, -0.15)
            }
        })
        .collect();
    let mesh = Mesh::from_grid(cols, rows, &positions);
    let camera =
        OrbitCamera { target: glam::Vec3::new(0.0, 0.75, 0.0), yaw_deg: 0.0, pitch_deg: 0.0, ..OrbitCamera::default() };
    let options = RenderOptions {
        style: drape::render::Style::Toon(drape::render::ToonLook::default()),
        ground: None,
        ..RenderOptions::default()
    };
    let size = (400, 300);
    let overlay = Overlay::default();
    let input =
        FrameInput { mesh: &mesh, camera: &camera, options: &options, ghosts: &[], overlay: &overlay, solids: &[] };
    let image = render_mesh(Some(&context()), input, size).unwrap();
    let brightness = |world: glam::Vec3| {
        let at = camera.project(world, size).unwrap();
        let [r, g, b, _] = image.pixel(at.x as u32, at.y as u32);
        (r as u32 + g as u32 + b as u32) / 3
    };
    let behind = brightness(glam::Vec3::new(0.0, 0.9, -0.15));
    assert!(behind > 80, "the hidden border shows through: brightness {behind}");
    let top = brightness(glam::Vec3::new(0.0, 1.0, 0.0));
    assert!(top < 40, "the front's top border is inked: brightness {top}");
    let fold = brightness(glam::Vec3::new(0.1, 0.5, 0.0));
    assert!(fold < 40, "the fold is inked: brightness {fold}");
    let side = brightness(glam::Vec3::new(-0.5, 0.75, 0.0));
    assert!(side < 40, "the front's side border is inked: brightness {side}");
}

/// `drape render --style toon` draws otherwise than lit, with `--alpha`
/// too (ink opaque, transparent off the cloth); an unknown style is refused.
#[test]
fn render_draws_the_toon_style_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("flag");
    let render = |extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let args =
            ["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "--frame", "60", "--size", "160x90"];
        let run = drape(&[&args[..], extra].concat());
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        RgbaImage::decode_png(&std::fs::read(&out).unwrap()).unwrap()
    };
    let lit = render(&["--style", "lit"], "lit.png");
    let toon = render(&["--style", "toon"], "toon.png");
    assert_eq!(lit, render(&[], "default.png"), "lit is the default");
    let differing = lit.pixels.chunks_exact(4).zip(toon.pixels.chunks_exact(4)).filter(|(a, b)| a != b).count();
    assert!(differing > 1000, "only {differing} pixels differ");
    let alpha = render(&["--style", "toon", "--alpha"], "alpha.png");
    assert_eq!(alpha.pixel(0, 0)[3], 0, "off the cloth is transparent");
    let ink = alpha.pixels.chunks_exact(4).filter(|p| p[3] == 255 && p[0] < 40 && p[1] < 40 && p[2] < 40).count();
    assert!(ink > 100, "opaque ink round the flag: {ink} pixels");
    let out = dir.path().join("x.png");
    let run = drape(&["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "--style", "sketch"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && stderr.contains("sketch"), "{stderr}");
}
