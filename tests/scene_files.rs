//! Scene files on disk: malformed fixtures with their exact messages, the
//! reference scene, round trips, atomic saves, the shipped `scenes/`, and
//! fuzzing of the parser (it must never panic).

use std::fs;
use std::path::{Path, PathBuf};

use drape::scene::{
    self, Cloth, ClothTexture, Collider, Ease, Follow, Key, Layer, LoadedRig, Param, ParamKey, ParamValue, Pin,
    Placement, Plate, Reference, RelaxSettings, Scene, SceneError, ShotCamera, Timeline, View, WaveAxis,
};
use proptest::prelude::*;

const MALFORMED_DIR: &str = "tests/data/malformed";
const VALID_FULL: &str = "tests/data/valid_full.ron";

/// Every malformed fixture and the exact message `scene::load` gives for it.
const MALFORMED: &[(&str, &str)] = &[
    (
        "plate_pattern.ron",
        "tests/data/malformed/plate_pattern.ron:14:19: plate: \"plates/shot_##_bg_####.png\" has two runs of #: \
         one run stands for the frame number",
    ),
    (
        "plate_opacity.ron",
        "tests/data/malformed/plate_opacity.ron:14:50: plate: opacity is 1.5: it must be between 0 and 1",
    ),
    (
        "collider_field.ron",
        "tests/data/malformed/collider_field.ron:12:69: unknown field `radious` in Sphere collider \
         (expected one of: name, enabled, thickness, center, radius)",
    ),
    (
        "collider_keys.ron",
        "tests/data/malformed/collider_keys.ron:14:71: Sphere collider \"ball\": center y at frame 24 \
         must be a finite number, not inf",
    ),
    (
        "collider_kind.ron",
        "tests/data/malformed/collider_kind.ron:12:9: unknown collider `Torus` \
         (expected one of: Ground, Box, Cylinder, Sphere, Capsule, Mesh)",
    ),
    (
        "collider_size.ron",
        "tests/data/malformed/collider_size.ron:12:67: Box collider \"table\": size y is 0: \
         it must be greater than 0 and at most 1e4",
    ),
    (
        "placement_far.ron",
        "tests/data/malformed/placement_far.ron:9:33: placement center in the key at frame 0 is (0, 20000, 0), \
         too far out: each component must be within ±10 000 m",
    ),
    (
        "collider_mesh_missing.ron",
        "tests/data/malformed/collider_mesh_missing.ron:9:36: Mesh collider \"chair\": cannot use \"../meshes/chair.obj\": \
         there is no such file (tests/data/malformed/../meshes/chair.obj)",
    ),
    (
        "collider_mesh_broken.ron",
        "tests/data/malformed/collider_mesh_broken.ron:9:36: Mesh collider \"chair\": cannot use \"../meshes/broken.obj\": \
         not a readable OBJ file (face vertex index out of bounds)",
    ),
    ("syntax_error.ron", "tests/data/malformed/syntax_error.ron:2:15: expected a comma before `cloth`"),
    (
        "unclosed_bracket.ron",
        "tests/data/malformed/unclosed_bracket.ron:5:1: `)` does not close the `[` at 4:11: is a `]` missing?",
    ),
    (
        "unknown_field.ron",
        "tests/data/malformed/unknown_field.ron:12:13: unknown field `elastisity` in key \
         (expected one of: frame, pins, placement, elasticity, stiffness, relax, ease, inbetween_relax, thickness, \
         friction)",
    ),
    (
        "unknown_ease.ron",
        "tests/data/malformed/unknown_ease.ron:12:19: unknown ease `Smooth` (expected one of: \
         Linear, Step, EaseIn, EaseOut, EaseInOut, Bezier, Back, Elastic, Bounce)",
    ),
    (
        "unknown_texture.ron",
        "tests/data/malformed/unknown_texture.ron:4:56: unknown cloth texture `Velvet` \
         (expected one of: Plain, Carpet, Checker)",
    ),
    (
        "view_pitch.ron",
        "tests/data/malformed/view_pitch.ron:14:63: view pitch 90° is out of range: \
         it must be between -89° and 89°",
    ),
    ("wrong_type.ron", "tests/data/malformed/wrong_type.ron:12:24: expected a number, found `\"high\"`"),
    (
        "negative_grid.ron",
        "tests/data/malformed/negative_grid.ron:4:38: the number -3 is out of range here: \
         this field cannot be negative",
    ),
    ("missing_keys.ron", "tests/data/malformed/missing_keys.ron:6:1: missing field `keys` in the scene"),
    ("missing_cloth_grid.ron", "tests/data/malformed/missing_cloth_grid.ron:4:29: missing field `grid` in cloth"),
    (
        "empty_keys.ron",
        "tests/data/malformed/empty_keys.ron:5:11: the scene has no keys: it needs at least one key with pins",
    ),
    (
        "key_without_pins.ron",
        "tests/data/malformed/key_without_pins.ron:8:19: key at frame 0 has no pins and no collider \
         holds the cloth up: it needs at least one pin, or an enabled collider under its placement",
    ),
    (
        "pin_outside_grid.ron",
        "tests/data/malformed/pin_outside_grid.ron:10:24: pin (40, 3) is outside the 33 × 25 grid",
    ),
    (
        "duplicate_pin.ron",
        "tests/data/malformed/duplicate_pin.ron:10:24: pin (0, 0) is pinned twice in the key at frame 0",
    ),
    (
        "pin_too_far.ron",
        "tests/data/malformed/pin_too_far.ron:8:40: pin (0, 0) in the key at frame 0 is at (0, 20000, 0), \
         too far out: each coordinate must be within ±10 000 m",
    ),
    (
        "nan_elasticity.ron",
        "tests/data/malformed/nan_elasticity.ron:12:25: elasticity in the key at frame 0 \
         must be a finite number, not NaN",
    ),
    (
        "elasticity_below_one.ron",
        "tests/data/malformed/elasticity_below_one.ron:12:25: elasticity 0.5 in the key at frame 0 \
         is out of range: it must be between 1 (the fabric's own length) and 10",
    ),
    (
        "stiffness_above_one.ron",
        "tests/data/malformed/stiffness_above_one.ron:12:24: stiffness 2 in the key at frame 0 \
         is out of range: it must be between 0 (limp) and 1 (stiff)",
    ),
    (
        "too_many_iterations.ron",
        "tests/data/malformed/too_many_iterations.ron:12:33: relax iterations 1 000 000 \
         in the key at frame 0 is above the limit of 100 000",
    ),
    (
        "zero_tolerance.ron",
        "tests/data/malformed/zero_tolerance.ron:12:32: relax tolerance 0 in the key at frame 0 \
         is out of range: it must be greater than 0 and at most 1",
    ),
    (
        "grid_too_large.ron",
        "tests/data/malformed/grid_too_large.ron:4:37: grid 2000 × 2000 has 4 000 000 points; \
         the limit is 262 144 (512 × 512)",
    ),
    (
        "too_many_keys.ron",
        "tests/data/malformed/too_many_keys.ron:25:9: the scene has 17 keys on a 512 × 512 grid; at most 16 fit, \
         since keys × grid points may not pass 4 194 304: use fewer keys or a coarser grid",
    ),
    ("too_many_layers.ron", "tests/data/malformed/too_many_layers.ron:48:9: the scene has 33 layers; the limit is 32"),
    (
        "camera_picture_too_large.ron",
        "tests/data/malformed/camera_picture_too_large.ron:15:78: camera: image_size 8192 × 4320 \
         must be 1 to 4096 pixels a side",
    ),
    (
        "grid_too_small.ron",
        "tests/data/malformed/grid_too_small.ron:4:37: grid 1 × 5 is too small: \
         the cloth needs at least 2 points along each side",
    ),
    (
        "negative_size.ron",
        "tests/data/malformed/negative_size.ron:4:20: cloth width must be greater than 0 m (it is -2 m)",
    ),
    (
        "negative_stretch_limit.ron",
        "tests/data/malformed/negative_stretch_limit.ron:4:62: stretch limit -0.1 is out of range: \
         it must be between 0 (off) and 10 (edges up to 11× their rest length)",
    ),
    (
        "version_2.ron",
        "tests/data/malformed/version_2.ron:2:14: unsupported scene version 2 (this Drape reads version 1)",
    ),
    (
        "zero_fps.ron",
        "tests/data/malformed/zero_fps.ron:14:21: fps 0 is out of range: \
         it must be greater than 0 and at most 1000",
    ),
    (
        "timeline_backwards.ron",
        "tests/data/malformed/timeline_backwards.ron:14:44: the timeline ends at frame 50 \
         before it starts at frame 100: end must not be before start",
    ),
    (
        "timeline_too_long.ron",
        "tests/data/malformed/timeline_too_long.ron:14:42: timeline end 2 147 483 647 is out of range: \
         it must be within ±100 000 frames",
    ),
    (
        "key_frame_too_far.ron",
        "tests/data/malformed/key_frame_too_far.ron:14:20: key frame -2 000 000 000 is out of range: \
         it must be within ±100 000 frames",
    ),
    (
        "param_key_frame_too_far.ron",
        "tests/data/malformed/param_key_frame_too_far.ron:16:57: Sway layer 1: magnitude key frame 2 000 000 000 \
         is out of range: it must be within ±100 000 frames",
    ),
    (
        "keys_out_of_order.ron",
        "tests/data/malformed/keys_out_of_order.ron:6:17: key at frame 10 comes after \
         the key at frame 20: keys must be in increasing frame order",
    ),
    (
        "duplicate_key_frame.ron",
        "tests/data/malformed/duplicate_key_frame.ron:6:17: two keys at frame 10: \
         each key needs a frame of its own",
    ),
    (
        "zero_sway_direction.ron",
        "tests/data/malformed/zero_sway_direction.ron:15:58: Sway layer \"breeze\": direction is zero: \
         give a direction to sway along",
    ),
    (
        "zero_wave_axis.ron",
        "tests/data/malformed/zero_wave_axis.ron:15:38: Wave layer 1: axis is zero: \
         give a direction to displace along",
    ),
    (
        "infinite_param_key.ron",
        "tests/data/malformed/infinite_param_key.ron:15:86: Wave layer \"ripple\": magnitude at frame 48 \
         must be a finite number, not inf",
    ),
    (
        "param_keys_out_of_order.ron",
        "tests/data/malformed/param_keys_out_of_order.ron:16:58: Sway layer 1: magnitude key at frame 10 \
         comes after the key at frame 30: keys must be in increasing frame order",
    ),
    (
        "bezier_x1.ron",
        "tests/data/malformed/bezier_x1.ron:12:26: ease of the key at frame 0: Bezier x1 = 1.5 \
         is out of range: x1 and x2 must be between 0 and 1",
    ),
    (
        "noise_zero_scale.ron",
        "tests/data/malformed/noise_zero_scale.ron:15:55: Gusts layer \"gusts\": scale is 0: it must be greater than 0 and at most 1e6",
    ),
    (
        "negative_falloff.ron",
        "tests/data/malformed/negative_falloff.ron:15:112: Sway layer 1: falloff at frame 24 is -2: it must be between 0 and 16",
    ),
    (
        "noise_octaves.ron",
        "tests/data/malformed/noise_octaves.ron:15:70: Gusts layer 1: octaves is 9: it must be between 1 and 6",
    ),
    (
        "negative_lag.ron",
        "tests/data/malformed/negative_lag.ron:15:44: FollowThrough layer \"trail\": lag is -0.5: it must be between 0 and 60 seconds",
    ),
    (
        "absurd_magnitude.ron",
        "tests/data/malformed/absurd_magnitude.ron:15:26: Wave layer 1: magnitude is 1e30: it must be within ±1e6",
    ),
    (
        "inbetween_relax_too_many.ron",
        "tests/data/malformed/inbetween_relax_too_many.ron:12:30: inbetween_relax 5 000 in the key at frame 0 is above the limit of 1000 sweeps",
    ),
    (
        "control_characters.ron",
        "tests/data/malformed/control_characters.ron:6:12: expected `(`, found `\"\\u{1b}[2J\\0\\u{202e}gnp.exe\"`",
    ),
    ("not_utf8.ron", "tests/data/malformed/not_utf8.ron:3:17: the file is not UTF-8 text (invalid byte 0xE9)"),
    (
        "empty.ron",
        "tests/data/malformed/empty.ron: the file is empty: a scene starts with \
         `(version: 1, cloth: …, keys: […])`",
    ),
];

/// `drape check` on `path`.
fn drape_check(path: &Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_drape")).arg("check").arg(path).output().unwrap()
}

/// Control and bidi characters in a scene's name, or in the file's text a
/// message quotes, reach the terminal escaped (`\u{1b}`, `\0`, `\u{202e}`),
/// never as the characters that would move the cursor or turn the line
/// around.
#[test]
fn check_shows_control_and_bidi_characters_escaped() {
    let raw = ['\u{1b}', '\0', '\u{7}', '\u{202e}', '\u{2066}'];
    let dir = tempfile::tempdir().unwrap();
    let curtain = fs::read_to_string("scenes/curtain.ron").unwrap();
    let named = dir.path().join("named.ron");
    fs::write(&named, curtain.replace("\"Curtain\"", "\"Red\u{1b}[31m\0\u{7}\u{202e}txt\u{2066}.exe\"")).unwrap();
    let run = drape_check(&named);
    let stdout = String::from_utf8(run.stdout).unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let first = stdout.lines().next().unwrap_or_default();
    let escaped_name = "Red\\u{1b}[31m\\0\\u{7}\\u{202e}txt\\u{2066}.exe";
    assert_eq!(first, format!("{}: {escaped_name} — valid", named.display()));
    assert!(!stdout.contains(raw), "{stdout:?}");

    let fixture = Path::new(MALFORMED_DIR).join("control_characters.ron");
    let run = drape_check(&fixture);
    let stderr = String::from_utf8(run.stderr).unwrap();
    let (_, expected) = MALFORMED.iter().find(|(name, _)| *name == "control_characters.ron").unwrap();
    assert!(!run.status.success());
    assert_eq!(stderr, format!("error: {expected}\n"));
    assert!(!stderr.contains(raw), "{stderr:?}");
}

#[test]
fn every_malformed_file_gives_its_exact_message() {
    let mut failures = Vec::new();
    for (name, expected) in MALFORMED {
        let path = Path::new(MALFORMED_DIR).join(name);
        match scene::load(&path) {
            Ok(_) => failures.push(format!("{name}: loaded without an error\n  expected: {expected}")),
            Err(error) if error.to_string() != *expected => {
                failures.push(format!("{name}:\n  expected: {expected}\n  got:      {error}"));
            }
            Err(_) => {}
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_malformed_fixture_is_in_the_table() {
    let listed: Vec<&str> = MALFORMED.iter().map(|(name, _)| *name).collect();
    let missing: Vec<PathBuf> = ron_files(Path::new(MALFORMED_DIR))
        .into_iter()
        .filter(|path| !listed.iter().any(|name| path.ends_with(name)))
        .collect();
    assert!(missing.is_empty(), "fixtures without an expected message: {missing:?}");
}

#[test]
fn a_missing_file_says_which_path_and_why() {
    let error = scene::load(Path::new("tests/data/no_such_scene.ron")).unwrap_err();
    assert!(matches!(error, SceneError::Read { .. }));
    assert_eq!(error.to_string(), "cannot read tests/data/no_such_scene.ron: No such file or directory");
}

fn ron_files(dir: &Path) -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "ron"))
        .collect();
    paths.sort();
    paths
}

/// Every scene shipped in `scenes/` loads and validates.
#[test]
fn every_scene_in_the_scenes_directory_loads() {
    let dir = Path::new("scenes");
    if !dir.is_dir() {
        return;
    }
    let paths = ron_files(dir);
    assert!(!paths.is_empty(), "scenes/ exists but holds no .ron scene");
    let failures: Vec<String> =
        paths.iter().filter_map(|path| scene::load(path).err()).map(|e| e.to_string()).collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The reference scene, its mesh files named by absolute paths so that a
/// copy saved anywhere still finds them.
fn reference() -> Scene {
    let mut scene = scene::load(Path::new(VALID_FULL)).unwrap_or_else(|e| panic!("{e}"));
    for collider in &mut scene.colliders {
        if let Collider::Mesh(mesh) = collider {
            let folder = Path::new(VALID_FULL).parent().unwrap_or(Path::new(""));
            mesh.file = fs::canonicalize(folder.join(&mesh.file)).unwrap().display().to_string();
        }
    }
    scene
}

fn eases(scene: &Scene) -> Vec<Ease> {
    let mut eases: Vec<Ease> = scene.keys.iter().map(|k| k.ease).collect();
    let params: Vec<&Param> =
        scene.layers.iter().flat_map(|layer| layer.params().iter().filter_map(|spec| spec.number(layer))).collect();
    for param in params {
        if let Param::Keys(keys) = param {
            eases.extend(keys.iter().map(|k| k.ease));
        }
    }
    eases
}

#[test]
fn the_reference_scene_exercises_every_variant() {
    let scene = reference();
    let eases = eases(&scene);
    for variant in ["Linear", "Step", "EaseIn", "EaseOut", "EaseInOut", "Bezier", "Back", "Elastic", "Bounce"] {
        assert!(
            eases.iter().any(|e| format!("{e:?}").split('(').next() == Some(variant)),
            "no {variant} ease in {VALID_FULL}"
        );
    }
    let axes: Vec<WaveAxis> =
        scene.layers.iter().filter_map(|l| if let Layer::Wave(w) = l { Some(w.axis) } else { None }).collect();
    assert!(axes.contains(&WaveAxis::Normal));
    assert!(axes.iter().any(|a| matches!(a, WaveAxis::Fixed(_))));
    assert!(scene.layers.iter().any(|l| matches!(l, Layer::Sway(s) if !s.enabled)));
    for kind in ["Sway", "Wave", "Gusts", "FollowThrough"] {
        assert!(scene.layers.iter().any(|l| l.kind() == kind), "no {kind} layer in {VALID_FULL}");
    }
    for kind in Collider::KINDS {
        assert!(scene.colliders.iter().any(|c| c.kind() == *kind), "no {kind} collider in {VALID_FULL}");
    }
    assert!(scene.colliders.iter().any(|c| !c.enabled()) && scene.colliders.iter().any(|c| c.thickness().is_some()));
    assert_eq!(scene.keys[0].inbetween_relax, 20);
    assert_eq!(scene.keys[1].inbetween_relax, 0, "the default");
    // Defaults fill what the file leaves out (the third key, the first Sway).
    assert_eq!(scene.keys[2].elasticity, 1.0);
    assert_eq!(scene.keys[2].stiffness, 0.2);
    assert_eq!(scene.keys[2].relax, RelaxSettings { iterations: 40_000, tolerance: 1e-5 });
    let Layer::Sway(breeze) = &scene.layers[0] else { panic!("first layer is the breeze Sway") };
    assert!(breeze.enabled);
    assert_eq!(breeze.weight, Param::Constant(1.0));
    assert_eq!(breeze.falloff, Param::Constant(1.0));
    assert_eq!(breeze.frequency, Param::Constant(0.0));
}

#[test]
fn a_minimal_scene_gets_the_documented_defaults() {
    let text = "(version: 1, cloth: (size: (1.0, 1.0), grid: (2, 2)), \
                keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])])";
    let scene = scene::parse(text, "minimal").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.name, "");
    assert_eq!(scene.timeline, Timeline { fps: 24.0, start: 0, end: 120 });
    assert_eq!(scene.cloth.stretch_limit, 0.1);
    assert_eq!(scene.keys[0].elasticity, 1.0);
    assert_eq!(scene.keys[0].stiffness, 0.2);
    assert_eq!(scene.keys[0].relax, RelaxSettings::default());
    assert_eq!(scene.keys[0].ease, Ease::EaseInOut);
    assert_eq!(scene.keys[0].inbetween_relax, 0);
    assert!(scene.layers.is_empty());
    let layers = "(version: 1, cloth: (size: (1.0, 1.0), grid: (2, 2)), \
                  keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])], \
                  layers: [Gusts((amplitude: 0.1, direction: (1.0, 0.0, 0.0))), FollowThrough(())])";
    let scene = scene::parse(layers, "layers").unwrap_or_else(|e| panic!("{e}"));
    let Layer::Gusts(gusts) = &scene.layers[0] else { panic!("a Gusts layer") };
    assert_eq!(
        (gusts.scale.clone(), gusts.speed.clone(), gusts.turbulence.clone()),
        (0.5.into(), 1.0.into(), 0.3.into())
    );
    assert_eq!((gusts.octaves, gusts.seed, gusts.enabled), (2, 0, true));
    let Layer::FollowThrough(follow) = &scene.layers[1] else { panic!("a FollowThrough layer") };
    assert_eq!(
        (follow.lag.clone(), follow.falloff.clone(), follow.weight.clone()),
        (0.25.into(), 1.0.into(), 1.0.into())
    );
}

/// Drape wrote the gusts layer as `Noise` before it was named `Gusts`:
/// such files still load, and are written back with the new name.
#[test]
fn a_gusts_layer_written_as_noise_still_loads() {
    let with = |kind: &str| {
        format!(
            "(version: 1, cloth: (size: (1.0, 1.0), grid: (2, 2)), \
             keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])], \
             layers: [{kind}((name: \"wind\", amplitude: 0.1, direction: (1.0, 0.0, 0.0), seed: 3))])"
        )
    };
    let old = scene::parse(&with("Noise"), "old.ron").unwrap_or_else(|e| panic!("{e}"));
    let new = scene::parse(&with("Gusts"), "new.ron").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(old, new);
    assert_eq!(old.layers[0].label(0), "Gusts layer \"wind\"");
    let text = scene::to_ron_string(&old);
    assert!(text.contains("Gusts((") && !text.contains("Noise"), "{text}");
}

#[test]
fn the_reference_scene_round_trips_through_text() {
    let scene = reference();
    let text = scene::to_ron_string(&scene);
    let mut back = scene::parse(&text, "round trip").unwrap_or_else(|e| panic!("{e}\n{text}"));
    // The text names the stool's file; its solid comes from reading it again.
    assert!(back != scene, "a mesh not read is not the mesh read");
    scene::read_meshes(&mut back, Path::new(VALID_FULL), &text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back, scene);
    assert_eq!(scene::to_ron_string(&back), text, "writing is stable");
    // Constants are plain numbers; animated values are lists of keys.
    assert!(text.contains("            magnitude: 0.2,\n"), "{text}");
    assert!(text.contains("            weight: 0.5,\n"), "{text}");
    assert!(text.contains("axis: Fixed((0.0, 1.0, 0.0)),"), "{text}");
    assert!(text.contains("ease: Bezier(0.25, 0.1, 0.25, 1.0),"), "{text}");
    assert!(text.contains("                (frame: 48, value: 0.05, ease: EaseIn),\n"), "{text}");
    assert!(text.lines().all(|line| line.chars().count() <= scene::MAX_LINE_CHARS), "{text}");
}

#[test]
fn save_then_load_gives_the_same_scene_and_leaves_no_temporary_files() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("curtain.ron");
    let mut scene = reference();
    scene::save(&scene, &path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene::load(&path).unwrap_or_else(|e| panic!("{e}")), scene);

    scene.name = "Overwritten".into();
    scene::save(&scene, &path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene::load(&path).unwrap_or_else(|e| panic!("{e}")).name, "Overwritten");

    let names: Vec<_> = fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, ["curtain.ron"]);
}

#[test]
fn saving_into_a_missing_directory_fails_and_creates_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("no_such_dir").join("x.ron");
    let error = scene::save(&reference(), &path).unwrap_err();
    assert!(matches!(error, SceneError::Write { .. }));
    assert_eq!(error.to_string(), format!("cannot write {}: No such file or directory", path.display()));
    assert!(!dir.path().join("no_such_dir").exists());
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// When the final rename fails (here: the target is a directory), nothing at
/// the target changes and the temporary file is removed.
#[test]
fn a_failed_rename_keeps_the_target_and_removes_the_temporary_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let target = dir.path().join("taken.ron");
    fs::create_dir(&target).unwrap();
    fs::write(target.join("inside"), "keep me").unwrap();
    let error = scene::save(&reference(), &target).unwrap_err();
    assert!(matches!(error, SceneError::Write { .. }), "{error}");
    assert!(error.to_string().starts_with(&format!("cannot write {}: ", target.display())));
    assert_eq!(fs::read_to_string(target.join("inside")).unwrap(), "keep me");
    assert_eq!(entries(dir.path()), ["taken.ron"]);
}

/// Saving through a symlink replaces the file it points to; the link stays.
#[cfg(unix)]
#[test]
fn saving_through_a_symlink_keeps_the_link_and_replaces_its_target() {
    let dir = tempfile::tempdir().expect("temp dir");
    fs::create_dir(dir.path().join("shots")).unwrap();
    let target = dir.path().join("shots/curtain.ron");
    fs::write(&target, "old").unwrap();
    let link = dir.path().join("curtain.ron");
    std::os::unix::fs::symlink("shots/curtain.ron", &link).unwrap();
    scene::save(&reference(), &link).unwrap_or_else(|e| panic!("{e}"));
    assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
    assert_eq!(scene::load(&target).unwrap_or_else(|e| panic!("{e}")), reference());
    assert_eq!(entries(dir.path()), ["curtain.ron", "shots"]);
    assert_eq!(entries(&dir.path().join("shots")), ["curtain.ron"]);
}

/// Scene files over 64 MiB are refused with the file's name, without
/// reading them whole: a sparse file by its size, an endless device as soon
/// as it passes the limit.
#[test]
fn files_too_large_for_a_scene_are_refused_promptly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let huge = dir.path().join("huge.ron");
    fs::File::create(&huge).unwrap().set_len(scene::MAX_SCENE_FILE_BYTES + 1).unwrap();
    let error = scene::load(&huge).unwrap_err();
    assert!(matches!(error, SceneError::TooLarge { .. }), "{error}");
    assert_eq!(error.to_string(), format!("{} is too large for a scene file: over 64 MiB", huge.display()));
    // A file exactly at a limit is read whole; one byte more is refused.
    let small = dir.path().join("small.ron");
    fs::write(&small, "0123456789").unwrap();
    assert_eq!(scene::read_capped(&small, 10).unwrap(), b"0123456789");
    assert!(matches!(scene::read_capped(&small, 9), Err(SceneError::TooLarge { limit_bytes: 9, .. })));
    // A device is refused before any byte is read, whatever it would give.
    if Path::new("/dev/zero").exists() {
        let error = scene::load(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(error.to_string(), "cannot read /dev/zero: it is a device, not a regular file");
    }
}

// ---- Property tests -------------------------------------------------------

/// Characters that make up RON, to reach deeper into the parser than random Unicode.
const RON_ALPHABET: &str = "[(){}\\[\\],:\"'/*#!rbaeEinfNtuxsv0-9_.+\\- \n\t]{0,300}";

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0..10.0f64,
        proptest::num::f64::NORMAL | proptest::num::f64::SUBNORMAL | proptest::num::f64::ZERO,
        Just(1.0),
        Just(0.0),
    ]
}

fn ease() -> impl Strategy<Value = Ease> {
    prop_oneof![
        Just(Ease::Linear),
        Just(Ease::Step),
        Just(Ease::EaseIn),
        Just(Ease::EaseOut),
        Just(Ease::EaseInOut),
        Just(Ease::Back),
        Just(Ease::Elastic),
        Just(Ease::Bounce),
        (finite(), finite(), finite(), finite()).prop_map(|(a, b, c, d)| Ease::Bezier(a, b, c, d)),
    ]
}

fn param() -> impl Strategy<Value = Param> {
    prop_oneof![
        finite().prop_map(Param::Constant),
        proptest::collection::vec(
            (any::<i32>(), finite(), ease()).prop_map(|(frame, value, ease)| ParamKey { frame, value, ease }),
            0..4
        )
        .prop_map(Param::Keys),
    ]
}

fn vec3() -> impl Strategy<Value = (f64, f64, f64)> {
    (finite(), finite(), finite())
}

/// A layer of any kind with random values in every field its schema lists
/// (driven by the schema, so a new parameter is covered without a change here).
fn layer() -> impl Strategy<Value = Layer> {
    let axis = prop_oneof![Just(WaveAxis::Normal), vec3().prop_map(WaveAxis::Fixed)];
    let values = proptest::collection::vec((param(), vec3(), axis, any::<u32>()), 16);
    (proptest::sample::select(Layer::KINDS), any::<String>(), any::<bool>(), values).prop_map(
        |(kind, name, enabled, values)| {
            let mut layer = Layer::with_start_values(kind).expect("one of Layer::KINDS");
            assert!(layer.params().len() <= values.len(), "more values for {kind}");
            *layer.name_mut() = name;
            *layer.enabled_mut() = enabled;
            for (spec, (number, vector, axis, count)) in layer.params().iter().zip(values) {
                match spec.value {
                    ParamValue::Number(n) => *n.access.get_mut(&mut layer).expect("its own field") = number,
                    ParamValue::Direction(d) => *d.access.get_mut(&mut layer).expect("its own field") = vector,
                    ParamValue::Axis(a) => *a.access.get_mut(&mut layer).expect("its own field") = axis,
                    ParamValue::Count(c) => *c.access.get_mut(&mut layer).expect("its own field") = count,
                }
            }
            layer
        },
    )
}

fn key() -> impl Strategy<Value = Key> {
    let pin = ((any::<u32>(), any::<u32>()), vec3()).prop_map(|(grid, pos)| Pin::at(grid, pos));
    (
        any::<i32>(),
        proptest::collection::vec(pin, 0..4),
        finite(),
        finite(),
        (any::<u32>(), finite()),
        ease(),
        (any::<u32>(), finite(), finite()),
        proptest::option::of((vec3(), vec3())),
    )
        .prop_map(
            |(
                frame,
                pins,
                elasticity,
                stiffness,
                (iterations, tolerance),
                ease,
                (inbetween_relax, thickness, friction),
                placement,
            )| Key {
                frame,
                pins,
                elasticity,
                stiffness,
                relax: RelaxSettings { iterations, tolerance },
                ease,
                inbetween_relax,
                thickness,
                friction,
                placement: placement.map(|(center, rotation_deg)| Placement { center, rotation_deg }),
            },
        )
}

fn any_scene() -> impl Strategy<Value = Scene> {
    (
        any::<u32>(),
        any::<String>(),
        ((finite(), finite()), (any::<u32>(), any::<u32>())),
        (finite(), any::<i32>(), any::<i32>()),
        proptest::collection::vec(key(), 0..3),
        proptest::collection::vec(layer(), 0..3),
        (
            proptest::option::of(view()),
            0..3u8,
            proptest::collection::vec(collider(), 0..3),
            proptest::collection::vec(glb_reference(), 0..3),
            proptest::option::of(shot_camera()),
            proptest::option::of((any::<String>(), any::<String>())),
            proptest::option::of((any::<String>(), any::<i32>(), param())),
        ),
    )
        .prop_map(
            |(
                version,
                name,
                (size, grid),
                (fps, start, end),
                keys,
                layers,
                (view, texture, colliders, references, camera, follow, plate),
            )| {
                Scene {
                    version,
                    name,
                    cloth: Cloth {
                        texture: [ClothTexture::Plain, ClothTexture::Carpet, ClothTexture::Checker][texture as usize],
                        ..Cloth::new(size, grid)
                    },
                    timeline: Timeline { fps, start, end },
                    keys,
                    layers,
                    colliders,
                    references,
                    follow: follow.map(|(reference, node)| Follow { reference, node }),
                    camera,
                    plate: plate.map(|(file, frame_offset, opacity)| Plate { file, frame_offset, opacity }),
                    view,
                }
            },
        )
}

/// A shot camera with every number drawn, keyed or not.
fn shot_camera() -> impl Strategy<Value = ShotCamera> {
    (proptest::collection::vec(param(), 8), (any::<u32>(), any::<u32>())).prop_map(|(values, image_size)| {
        let [px, py, pz, tx, ty, tz, focal_length_mm, sensor_width_mm] =
            <[Param; 8]>::try_from(values).expect("eight numbers");
        ShotCamera {
            from_reference: None,
            position: (px, py, pz),
            target: (tx, ty, tz),
            focal_length_mm,
            sensor_width_mm,
            image_size,
        }
    })
}

/// A collider of any kind with every number, its name, switch and thickness drawn.
fn collider() -> impl Strategy<Value = Collider> {
    (
        0..Collider::KINDS.len(),
        any::<String>(),
        any::<bool>(),
        proptest::option::of(param()),
        proptest::collection::vec(param(), 10),
    )
        .prop_map(|(kind, name, enabled, thickness, values)| {
            let mut collider = Collider::with_start_values(Collider::KINDS[kind]).expect("a listed kind");
            *collider.name_mut() = name;
            *collider.enabled_mut() = enabled;
            *collider.thickness_mut() = thickness;
            for (number, value) in collider.numbers().into_iter().zip(values) {
                *collider.param_mut(number).expect("its own number") = value;
            }
            collider
        })
}

fn glb_reference() -> impl Strategy<Value = Reference> {
    (
        (any::<String>(), any::<String>(), proptest::option::of(any::<String>()), any::<i32>(), finite()),
        (any::<bool>(), any::<bool>(), any::<bool>(), proptest::option::of(param())),
        proptest::collection::vec(param(), 7),
    )
        .prop_map(
            |((name, file, animation, start_frame, speed), (repeat, visible, collider, thickness), values)| {
                let [cx, cy, cz, rx, ry, rz, scale] = <[Param; 7]>::try_from(values).expect("seven numbers");
                Reference {
                    name,
                    file,
                    animation,
                    start_frame,
                    speed,
                    repeat,
                    center: (cx, cy, cz),
                    rotation_deg: (rx, ry, rz),
                    scale,
                    visible,
                    collider,
                    thickness,
                    rig: LoadedRig::default(),
                }
            },
        )
}

fn view() -> impl Strategy<Value = View> {
    let frame = proptest::option::of(-100_000i32..100_000);
    let flags = (any::<bool>(), any::<bool>());
    ((finite(), finite(), finite()), finite(), finite(), finite(), finite(), frame, flags).prop_map(
        |(target, yaw_deg, pitch_deg, distance_m, fov_y_deg, frame, (follow, through_camera))| View {
            target,
            yaw_deg,
            pitch_deg,
            distance_m,
            fov_y_deg,
            frame,
            follow,
            through_camera,
        },
    )
}

/// One edit of a byte string: delete, insert, overwrite or duplicate a span.
#[derive(Clone, Debug)]
enum Mutation {
    Delete { at: usize, len: usize },
    Insert { at: usize, bytes: Vec<u8> },
    Overwrite { at: usize, bytes: Vec<u8> },
    Duplicate { at: usize, len: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let snippet = prop_oneof![
        proptest::collection::vec(any::<u8>(), 1..4),
        proptest::sample::select(vec![
            "NaN",
            "inf",
            "-inf",
            "-1",
            "1e309",
            "99999999999",
            "4294967296",
            "(",
            ")",
            "[",
            "]",
            ",",
            ":",
            "\"",
            "//",
            "/*",
            "Bezier(",
            "Fixed((",
            "Sway((",
            "r#",
            "'",
            "0x",
            "_",
            "é",
            "\u{feff}",
        ])
        .prop_map(|s: &str| s.as_bytes().to_vec()),
    ];
    prop_oneof![
        (any::<usize>(), 1..40usize).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), snippet.clone()).prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        (any::<usize>(), snippet).prop_map(|(at, bytes)| Mutation::Overwrite { at, bytes }),
        (any::<usize>(), 1..200usize).prop_map(|(at, len)| Mutation::Duplicate { at, len }),
    ]
}

fn apply(bytes: &mut Vec<u8>, mutation: &Mutation) {
    let at = |at: usize, bytes: &Vec<u8>| at % (bytes.len() + 1);
    match mutation {
        Mutation::Delete { at: a, len } => {
            let start = at(*a, bytes);
            let end = (start + len).min(bytes.len());
            bytes.drain(start..end);
        }
        Mutation::Insert { at: a, bytes: new } => {
            let start = at(*a, bytes);
            bytes.splice(start..start, new.iter().copied());
        }
        Mutation::Overwrite { at: a, bytes: new } => {
            let start = at(*a, bytes);
            let end = (start + new.len()).min(bytes.len());
            bytes.splice(start..end, new.iter().copied());
        }
        Mutation::Duplicate { at: a, len } => {
            let start = at(*a, bytes);
            let end = (start + len).min(bytes.len());
            let copy = bytes[start..end].to_vec();
            bytes.splice(end..end, copy);
        }
    }
}

/// A parse error always carries the label and, when it has a position, a
/// sensible one.
fn check_error(error: &SceneError, label: &str) {
    let text = error.to_string();
    assert!(text.starts_with(&format!("{label}:")), "{text}");
    if let Some(position) = error.position() {
        assert!(position.line >= 1 && position.col >= 1, "{text}");
    }
    assert!(!error.message().is_empty(), "{text}");
}

proptest! {
    #[test]
    fn parse_never_panics_on_any_text(text in any::<String>()) {
        if let Err(error) = scene::parse(&text, "fuzz.ron") {
            check_error(&error, "fuzz.ron");
        }
        let _ = scene::locate(&text, "keys[0].pins[1].grid");
    }

    #[test]
    fn parse_never_panics_on_ron_like_text(text in RON_ALPHABET) {
        if let Err(error) = scene::parse(&text, "fuzz.ron") {
            check_error(&error, "fuzz.ron");
        }
        let _ = scene::locate(&text, "layers[1].magnitude[0].value");
    }

    #[test]
    fn parse_never_panics_on_any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        if let Err(error) = scene::parse_bytes(&bytes, "fuzz.ron") {
            check_error(&error, "fuzz.ron");
        }
    }

    #[test]
    fn parse_never_panics_on_mutations_of_a_valid_scene(
        mutations in proptest::collection::vec(mutation(), 1..6)
    ) {
        let mut bytes = fs::read(VALID_FULL).expect("reference scene");
        for m in &mutations {
            apply(&mut bytes, m);
        }
        match scene::parse_bytes(&bytes, "mutant.ron") {
            Ok(scene) => prop_assert!(scene.validate().is_ok()),
            Err(error) => check_error(&error, "mutant.ron"),
        }
    }

    /// Any scene, valid or not, is written as text that reads back equal;
    /// valid scenes also pass `parse`.
    #[test]
    fn any_scene_round_trips_through_text(scene in any_scene()) {
        let text = scene::to_ron_string(&scene);
        let back: Scene = ron::from_str(&text).map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(&back, &scene);
        if scene.validate().is_ok() {
            prop_assert_eq!(scene::parse(&text, "generated.ron").map_err(|e| e.to_string()), Ok(scene));
        }
    }
}
