//! Exported animation read back by readers Drape did not write: the `gltf`
//! crate for glTF, and small parsers here that follow the published PC2, MDD,
//! USD text and OBJ layouts (not the exporters' code). Every vertex of every
//! frame must equal `evaluate` at that frame. When Node with the Khronos glTF
//! validator, or Python with Pixar's USD library, is installed (see
//! `.ci/run`), the files also go through them; `DRAPE_REQUIRE_TOOLS=1` makes
//! their absence a failure.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::process::Command;

use drape::animate::{Stage, evaluate, frame_time_secs};
use drape::export::{AnimationFormat, ExportError, ExportOptions, export_animation, export_animation_with};
use drape::mesh::Mesh;
use drape::scene::{self, ClothTexture, Scene};
use glam::Vec3;

/// The largest difference allowed between a read-back vertex and `evaluate`'s (metres).
const TOLERANCE_M: f32 = 1e-6;

fn load(name: &str) -> Scene {
    scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)).unwrap()
}

/// The magic carpet (textured, five keys) over its first second.
fn carpet() -> (Scene, std::ops::RangeInclusive<i32>) {
    (load("magic_carpet.ron"), 0..=24)
}

/// The flag (plain cloth, three layers) over a stretch in the middle of its timeline.
fn flag() -> (Scene, std::ops::RangeInclusive<i32>) {
    (load("flag.ron"), 40..=52)
}

fn reference(scene: &Scene, frame: i32) -> Mesh {
    evaluate(scene, frame_time_secs(&scene.timeline, f64::from(frame)))
}

fn export(scene: &Scene, frames: std::ops::RangeInclusive<i32>, output: &Path) {
    let format = AnimationFormat::from_extension(output).unwrap();
    export_animation(scene, frames, output, format, &mut |_, _| true).unwrap();
}

fn assert_points_match(what: &str, got: &[Vec3], want: &[Vec3], tolerance: f32) {
    assert_eq!(got.len(), want.len(), "{what}: vertex count");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let error = (*g - *w).abs().max_element();
        assert!(error <= tolerance, "{what}: vertex {k} is {g} instead of {w} (off by {error:e})");
    }
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    names
}

// ---------------------------------------------------------------- OBJ reader

/// The `v` and `vn` lines of an OBJ, and its face count.
fn read_obj(path: &Path) -> (Vec<Vec3>, Vec<Vec3>, usize) {
    let text = fs::read_to_string(path).unwrap();
    let vec3 = |line: &str| {
        let c: Vec<f32> = line.split_whitespace().skip(1).map(|t| t.parse().unwrap()).collect();
        Vec3::new(c[0], c[1], c[2])
    };
    let positions = text.lines().filter(|l| l.starts_with("v ")).map(vec3).collect();
    let normals = text.lines().filter(|l| l.starts_with("vn ")).map(vec3).collect();
    let faces = text.lines().filter(|l| l.starts_with("f ")).count();
    (positions, normals, faces)
}

// ------------------------------------------------------- PC2 and MDD readers

struct PointCache {
    points: usize,
    /// PC2: start frame and sample rate.
    start_frame: f32,
    sample_rate: f32,
    /// MDD: each frame's time in seconds.
    times_secs: Vec<f32>,
    frames: Vec<Vec<Vec3>>,
}

/// PC2 as 3ds Max defines it: "POINTCACHE2\0", then little-endian i32
/// version, i32 numPoints, f32 startFrame, f32 sampleRate, i32 numSamples,
/// then numSamples × numPoints × (f32 x, y, z).
fn read_pc2(bytes: &[u8]) -> PointCache {
    assert_eq!(&bytes[..12], b"POINTCACHE2\0", "PC2 signature");
    let i32_at = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let f32_at = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!(i32_at(12), 1, "PC2 version");
    let points = i32_at(16) as usize;
    let samples = i32_at(28) as usize;
    assert_eq!(bytes.len(), 32 + samples * points * 12, "PC2 size for {samples} samples of {points} points");
    let frames = (0..samples)
        .map(|s| {
            (0..points)
                .map(|p| {
                    let at = 32 + (s * points + p) * 12;
                    Vec3::new(f32_at(at), f32_at(at + 4), f32_at(at + 8))
                })
                .collect()
        })
        .collect();
    PointCache { points, start_frame: f32_at(20), sample_rate: f32_at(24), times_secs: Vec::new(), frames }
}

/// MDD as LightWave defines it: big-endian i32 totalFrames, i32 numPoints,
/// f32 times[totalFrames] (seconds), then totalFrames × numPoints × (f32 x, y, z).
fn read_mdd(bytes: &[u8]) -> PointCache {
    let i32_at = |at: usize| i32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    let f32_at = |at: usize| f32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    let (frame_count, points) = (i32_at(0) as usize, i32_at(4) as usize);
    let data = 8 + frame_count * 4;
    assert_eq!(bytes.len(), data + frame_count * points * 12, "MDD size for {frame_count} frames of {points} points");
    let times_secs = (0..frame_count).map(|f| f32_at(8 + f * 4)).collect();
    let frames = (0..frame_count)
        .map(|f| {
            (0..points)
                .map(|p| {
                    let at = data + (f * points + p) * 12;
                    Vec3::new(f32_at(at), f32_at(at + 4), f32_at(at + 8))
                })
                .collect()
        })
        .collect();
    PointCache { points, start_frame: f32::NAN, sample_rate: f32::NAN, times_secs, frames }
}

#[test]
fn pc2_holds_every_frame_of_evaluate_with_the_base_mesh_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, frames) in [carpet(), flag()] {
        let output = dir.path().join("cloth.pc2");
        export(&scene, frames.clone(), &output);
        let cache = read_pc2(&fs::read(&output).unwrap());
        assert_eq!(cache.points, scene.cloth.cols() * scene.cloth.rows());
        assert_eq!(cache.start_frame, *frames.start() as f32);
        assert_eq!(cache.sample_rate, 1.0);
        assert_eq!(cache.frames.len(), frames.clone().count());
        for (frame, points) in frames.clone().zip(&cache.frames) {
            assert_points_match(
                &format!("PC2 frame {frame}"),
                points,
                &reference(&scene, frame).positions,
                TOLERANCE_M,
            );
        }
        let (base, normals, faces) = read_obj(&dir.path().join("cloth.obj"));
        let first = reference(&scene, *frames.start());
        assert_points_match("base OBJ", &base, &first.positions, TOLERANCE_M);
        assert_points_match("base OBJ normals", &normals, &first.normals, 1e-6);
        assert_eq!(faces, first.triangle_count());
    }
}

#[test]
fn mdd_holds_every_frame_of_evaluate_at_its_time() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, frames) in [carpet(), flag()] {
        let output = dir.path().join("cloth.mdd");
        export(&scene, frames.clone(), &output);
        let cache = read_mdd(&fs::read(&output).unwrap());
        assert_eq!(cache.points, scene.cloth.cols() * scene.cloth.rows());
        assert_eq!(cache.frames.len(), frames.clone().count());
        for (k, frame) in frames.clone().enumerate() {
            let want_secs = f64::from(frame) / scene.timeline.fps;
            assert!((f64::from(cache.times_secs[k]) - want_secs).abs() < 1e-6, "MDD time of frame {frame}");
            let what = format!("MDD frame {frame}");
            assert_points_match(&what, &cache.frames[k], &reference(&scene, frame).positions, TOLERANCE_M);
        }
        assert_eq!(read_obj(&dir.path().join("cloth.obj")).0.len(), cache.points, "base OBJ beside the MDD");
    }
}

// ----------------------------------------------------------------- glTF

/// A glTF file read back through the `gltf` crate: the mesh at each keyframe
/// (base + the target whose weight is 1), the key times and interpolation.
struct GltfAnimation {
    node_name: String,
    mesh_name: String,
    frames_positions: Vec<Vec<Vec3>>,
    frames_normals: Vec<Vec<Vec3>>,
    uvs: Vec<[f32; 2]>,
    indices: Vec<u32>,
    times_secs: Vec<f32>,
    interpolation: gltf::animation::Interpolation,
    double_sided: bool,
    base_color: [f32; 4],
    texture_png: Option<Vec<u8>>,
    fps: f64,
}

fn read_gltf(path: &Path) -> GltfAnimation {
    let bytes = fs::read(path).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let dir = path.parent().unwrap();
    let buffers: Vec<Vec<u8>> = gltf
        .buffers()
        .map(|buffer| match buffer.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().expect("a GLB BIN chunk"),
            gltf::buffer::Source::Uri(uri) => fs::read(dir.join(percent_decoded(uri))).unwrap(),
        })
        .collect();
    let get = |buffer: gltf::Buffer| buffers.get(buffer.index()).map(Vec::as_slice);

    let node = gltf.nodes().next().expect("a node");
    let mesh = node.mesh().expect("the node has the mesh");
    let primitive = mesh.primitives().next().unwrap();
    assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
    let reader = primitive.reader(get);
    let base: Vec<Vec3> = reader.read_positions().unwrap().map(Vec3::from).collect();
    let base_normals: Vec<Vec3> = reader.read_normals().unwrap().map(Vec3::from).collect();
    let uvs = reader.read_tex_coords(0).unwrap().into_f32().collect();
    let indices = reader.read_indices().unwrap().into_u32().collect();
    let targets: Vec<(Vec<Vec3>, Vec<Vec3>)> = reader
        .read_morph_targets()
        .map(|(positions, normals, _)| {
            (positions.unwrap().map(Vec3::from).collect(), normals.unwrap().map(Vec3::from).collect())
        })
        .collect();

    let animation = gltf.animations().next().expect("an animation");
    let channel = animation.channels().next().unwrap();
    assert_eq!(channel.target().property(), gltf::animation::Property::MorphTargetWeights);
    assert_eq!(channel.target().node().index(), node.index());
    let channel_reader = channel.reader(get);
    let times_secs: Vec<f32> = channel_reader.read_inputs().unwrap().collect();
    let weights: Vec<f32> = match channel_reader.read_outputs().unwrap() {
        gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
        _ => panic!("the channel animates weights"),
    };
    assert_eq!(weights.len(), times_secs.len() * targets.len(), "one weight per target per keyframe");
    // At each keyframe the mesh is the base plus the targets scaled by their weights.
    let (mut frames_positions, mut frames_normals) = (Vec::new(), Vec::new());
    for key_weights in weights.chunks(targets.len()) {
        let mut positions = base.clone();
        let mut normals = base_normals.clone();
        for ((target_positions, target_normals), weight) in targets.iter().zip(key_weights) {
            if *weight != 0.0 {
                positions.iter_mut().zip(target_positions).for_each(|(p, d)| *p += *weight * *d);
                normals.iter_mut().zip(target_normals).for_each(|(n, d)| *n += *weight * *d);
            }
        }
        frames_positions.push(positions);
        frames_normals.push(normals);
    }

    let material = primitive.material();
    let pbr = material.pbr_metallic_roughness();
    let texture_png = pbr.base_color_texture().map(|info| match info.texture().source().source() {
        gltf::image::Source::View { view, mime_type } => {
            assert_eq!(mime_type, "image/png");
            buffers[view.buffer().index()][view.offset()..view.offset() + view.length()].to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => fs::read(dir.join(percent_decoded(uri))).unwrap(),
    });
    let json: serde_json::Value = match gltf::Glb::from_slice(&bytes) {
        Ok(glb) => serde_json::from_slice(&glb.json).unwrap(),
        Err(_) => serde_json::from_slice(&bytes).unwrap(),
    };
    GltfAnimation {
        node_name: node.name().unwrap_or_default().to_string(),
        mesh_name: mesh.name().unwrap_or_default().to_string(),
        frames_positions,
        frames_normals,
        uvs,
        indices,
        times_secs,
        interpolation: channel.sampler().interpolation(),
        double_sided: material.double_sided(),
        base_color: pbr.base_color_factor(),
        texture_png,
        fps: json["asset"]["extras"]["fps"].as_f64().unwrap(),
    }
}

/// A relative URI's path: `%XX` escapes decoded (RFC 3986).
fn percent_decoded(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' {
            out.push(u8::from_str_radix(&uri[k + 1..k + 3], 16).unwrap());
            k += 3;
        } else {
            out.push(bytes[k]);
            k += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

fn check_gltf(scene: &Scene, frames: std::ops::RangeInclusive<i32>, path: &Path) {
    let read = read_gltf(path);
    assert_eq!(read.node_name, scene.name);
    assert_eq!(read.mesh_name, scene.name);
    assert_eq!(read.frames_positions.len(), frames.clone().count(), "one keyframe per frame");
    assert_eq!(read.interpolation, gltf::animation::Interpolation::Linear);
    assert_eq!(read.fps, scene.timeline.fps);
    for (k, frame) in frames.clone().enumerate() {
        let want = reference(scene, frame);
        let want_secs = (f64::from(frame - *frames.start()) / scene.timeline.fps) as f32;
        assert_eq!(read.times_secs[k], want_secs, "key time of frame {frame}");
        assert_points_match(&format!("glTF frame {frame}"), &read.frames_positions[k], &want.positions, TOLERANCE_M);
        assert_points_match(&format!("glTF normals {frame}"), &read.frames_normals[k], &want.normals, 1e-6);
        if k == 0 {
            assert_eq!(read.indices, want.indices);
            assert_eq!(read.uvs, want.uvs.iter().map(|uv| uv.to_array()).collect::<Vec<_>>());
        }
    }
    assert!(read.double_sided);
    let asset = match scene.cloth.texture {
        ClothTexture::Plain => None,
        ClothTexture::Carpet => Some("carpet.png"),
        ClothTexture::Checker => Some("checker.png"),
    };
    match asset {
        Some(asset) => {
            let png = fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets").join(asset)).unwrap();
            assert_eq!(read.texture_png.as_deref(), Some(&png[..]), "the scene's texture");
            assert_eq!(read.base_color, [1.0; 4]);
        }
        None => {
            assert!(read.texture_png.is_none(), "a plain cloth has no texture");
            assert_eq!(read.base_color[3], 1.0);
        }
    }
}

#[test]
fn glb_morph_animation_reproduces_evaluate_at_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, frames) in [carpet(), flag()] {
        let output = dir.path().join("cloth.glb");
        export(&scene, frames.clone(), &output);
        check_gltf(&scene, frames, &output);
    }
    assert_eq!(files_in(dir.path()), ["cloth.glb"], "a GLB is one file");
}

#[test]
fn gltf_with_its_bin_and_texture_beside_it_reproduces_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, frames) = carpet();
    let output = dir.path().join("magic carpet.gltf");
    export(&scene, frames.clone(), &output);
    assert_eq!(files_in(dir.path()), ["magic carpet.bin", "magic carpet.gltf", "magic carpet_texture.png"]);
    check_gltf(&scene, frames, &output);

    let (scene, frames) = flag();
    let output = dir.path().join("flag.gltf");
    export(&scene, frames.clone(), &output);
    assert!(!dir.path().join("flag_texture.png").exists(), "no texture file for a plain cloth");
    check_gltf(&scene, frames, &output);
}

/// A directory with the Khronos validator's npm package, and Node to run it.
fn gltf_validator() -> Option<PathBuf> {
    let dir = match std::env::var_os("DRAPE_GLTF_VALIDATOR") {
        Some(dir) => PathBuf::from(dir),
        None => {
            PathBuf::from(std::env::var_os("HOME")?).join(".cache/drape/gltf-validator/node_modules/gltf-validator")
        }
    };
    let node = Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success());
    (node && dir.join("package.json").is_file()).then_some(dir)
}

fn tool_missing(what: &str) {
    let message = format!("{what}; see .ci/run for how to install it");
    if std::env::var_os("DRAPE_REQUIRE_TOOLS").is_some_and(|v| v == "1") {
        panic!("{message} (DRAPE_REQUIRE_TOOLS=1)");
    }
    println!("SKIPPED: {message}");
    eprintln!("SKIPPED: {message}");
}

#[test]
fn khronos_gltf_validator_reports_no_errors() {
    let Some(validator) = gltf_validator() else {
        return tool_missing(
            "the Khronos glTF validator was not run: no `node`, or no gltf-validator package under \
             ~/.cache/drape/gltf-validator (or $DRAPE_GLTF_VALIDATOR)",
        );
    };
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for (scene, frames, name) in [(carpet().0, 0..=120, "carpet"), (flag().0, 0..=30, "flag")] {
        for extension in ["glb", "gltf"] {
            let output = dir.path().join(format!("{name}.{extension}"));
            export(&scene, frames.clone(), &output);
            files.push(output);
        }
    }
    // A single frame is an animation with one keyframe.
    let output = dir.path().join("still.glb");
    export(&flag().0, 7..=7, &output);
    files.push(output);
    // A name with line breaks and a NUL is escaped in the JSON.
    for extension in ["glb", "gltf"] {
        let output = dir.path().join(format!("hostile.{extension}"));
        export(&hostile_flag(), 0..=3, &output);
        files.push(output);
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools/validate_gltf.cjs");
    let run = Command::new("node").arg(script).arg(&validator).args(&files).output().unwrap();
    let report = String::from_utf8_lossy(&run.stdout);
    println!("{report}");
    assert!(run.status.success(), "the glTF validator found errors:\n{report}{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(report.matches(": 0 errors").count(), files.len(), "{report}");
}

// ------------------------------------------------------------------- USD

/// What a small reader of USD's text format finds in the export: the layer's
/// metadata and the Mesh's attributes.
struct Usda {
    metadata: Vec<(String, String)>,
    /// `points.timeSamples` / `normals.timeSamples`: (time code, values).
    points: Vec<(f64, Vec<Vec3>)>,
    normals: Vec<(f64, Vec<Vec3>)>,
    face_vertex_counts: Vec<i64>,
    face_vertex_indices: Vec<i64>,
    st: Vec<(f32, f32)>,
    /// Every statement (declaration and value), its lines joined by spaces.
    declarations: Vec<String>,
}

impl Usda {
    /// A metadata value, without the quotes of a string or token.
    fn metadata(&self, key: &str) -> &str {
        self.metadata_literal(key).trim_matches('"')
    }

    /// A metadata value as written, quotes and escapes included.
    fn metadata_literal(&self, key: &str) -> &str {
        &self.metadata.iter().find(|(k, _)| k == key).unwrap_or_else(|| panic!("no {key} in the layer")).1
    }
}

/// The tuples `(a, b, …)` of a USD array value `[(…), (…)]` as lists of numbers.
fn tuples(text: &str) -> Vec<Vec<f32>> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find('(') {
        let close = rest[open..].find(')').unwrap() + open;
        out.push(rest[open + 1..close].split(',').map(|n| n.trim().parse().unwrap()).collect());
        rest = &rest[close + 1..];
    }
    out
}

fn scalars(text: &str) -> Vec<i64> {
    let inner = text.trim().trim_start_matches('[').trim_end_matches(']');
    inner.split(',').filter(|s| !s.trim().is_empty()).map(|n| n.trim().parse().unwrap()).collect()
}

/// Reads a USD text layer: the header's `key = value` metadata, and in the
/// prims, attributes `type name = value` and `type name.timeSamples = { t: value, … }`.
/// Values and samples may span lines; the reader collects text until the
/// brackets balance.
fn read_usda(text: &str) -> Usda {
    assert!(text.starts_with("#usda 1.0\n"), "a USD text layer starts with #usda 1.0");
    let mut usda = Usda {
        metadata: Vec::new(),
        points: Vec::new(),
        normals: Vec::new(),
        face_vertex_counts: Vec::new(),
        face_vertex_indices: Vec::new(),
        st: Vec::new(),
        declarations: Vec::new(),
    };
    let mut lines = text.lines().skip(1).peekable();
    // The layer's metadata: `(` … `)` before the first prim.
    while let Some(line) = lines.next() {
        if line.trim() == "(" {
            for line in lines.by_ref() {
                if line.trim() == ")" {
                    break;
                }
                let (key, value) = line.split_once('=').unwrap();
                usda.metadata.push((key.trim().to_string(), value.trim().to_string()));
            }
            break;
        }
    }
    // Join each statement's lines until its brackets and braces balance.
    let mut statement = String::new();
    let mut depth = 0i32;
    for line in lines {
        // A prim's own braces open and close its body; they are not part of a statement.
        if depth == 0 && matches!(line.trim(), "{" | "}") {
            continue;
        }
        for c in line.chars() {
            match c {
                '[' | '{' | '(' => depth += 1,
                ']' | '}' | ')' => depth -= 1,
                _ => {}
            }
        }
        statement.push_str(line.trim());
        statement.push(' ');
        if depth > 0 {
            continue;
        }
        let s = std::mem::take(&mut statement);
        let s = s.trim();
        if !s.is_empty() {
            usda.declarations.push(s.to_string());
        }
        if let Some((declaration, value)) = s.split_once(" = ") {
            let samples = |value: &str| -> Vec<(f64, Vec<Vec3>)> {
                let body = value.trim().trim_start_matches('{').trim_end_matches('}');
                body.split("],")
                    .filter(|sample| !sample.trim().is_empty())
                    .map(|sample| {
                        let (time, values) = sample.split_once(':').unwrap();
                        let points = tuples(values).into_iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect();
                        (time.trim().parse().unwrap(), points)
                    })
                    .collect()
            };
            match declaration {
                "point3f[] points.timeSamples" => usda.points = samples(value),
                "normal3f[] normals.timeSamples" => usda.normals = samples(value),
                "int[] faceVertexCounts" => usda.face_vertex_counts = scalars(value),
                "int[] faceVertexIndices" => usda.face_vertex_indices = scalars(value),
                "texCoord2f[] primvars:st" => {
                    let array = value.split(']').next().unwrap();
                    usda.st = tuples(array).into_iter().map(|c| (c[0], c[1])).collect();
                }
                _ => {}
            }
        }
    }
    usda
}

#[test]
fn usda_time_samples_hold_every_frame_of_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, frames) in [carpet(), flag()] {
        let output = dir.path().join("cloth.usda");
        export(&scene, frames.clone(), &output);
        let usda = read_usda(&fs::read_to_string(&output).unwrap());
        assert_eq!(usda.metadata("upAxis"), "Y");
        assert_eq!(usda.metadata("metersPerUnit"), "1");
        let fps: f64 = usda.metadata("timeCodesPerSecond").parse().unwrap();
        assert_eq!(fps, scene.timeline.fps);
        assert_eq!(usda.metadata("framesPerSecond").parse::<f64>().unwrap(), scene.timeline.fps);
        assert_eq!(usda.metadata("startTimeCode"), frames.start().to_string());
        assert_eq!(usda.metadata("endTimeCode"), frames.end().to_string());
        assert_eq!(usda.points.len(), frames.clone().count(), "one points sample per frame");
        assert_eq!(usda.normals.len(), frames.clone().count(), "one normals sample per frame");
        for (k, frame) in frames.clone().enumerate() {
            let want = reference(&scene, frame);
            assert_eq!(usda.points[k].0, f64::from(frame), "time code of frame {frame}");
            assert_eq!(usda.normals[k].0, f64::from(frame));
            assert_points_match(&format!("USD frame {frame}"), &usda.points[k].1, &want.positions, TOLERANCE_M);
            assert_points_match(&format!("USD normals {frame}"), &usda.normals[k].1, &want.normals, 1e-6);
            if k == 0 {
                assert_eq!(usda.face_vertex_counts, vec![3; want.triangle_count()]);
                let indices: Vec<i64> = want.indices.iter().map(|&i| i64::from(i)).collect();
                assert_eq!(usda.face_vertex_indices, indices);
                let st: Vec<(f32, f32)> = want.uvs.iter().map(|uv| (uv.x, 1.0 - uv.y)).collect();
                assert_eq!(usda.st, st, "st has v up");
            }
        }
        for declaration in [
            "uniform token orientation = \"rightHanded\"",
            "uniform bool doubleSided = 1",
            "normal3f[] normals ( interpolation = \"vertex\" )",
            "texCoord2f[] primvars:st = [",
            "float3[] extent.timeSamples = {",
        ] {
            assert!(
                usda.declarations.iter().any(|d| d.starts_with(declaration)),
                "no `{declaration}` in {:?}",
                usda.declarations
            );
        }
    }
}

/// A Python with Pixar's USD library (`pip install usd-core`).
fn usd_python() -> Option<PathBuf> {
    let python = match std::env::var_os("DRAPE_USD_PYTHON") {
        Some(python) => PathBuf::from(python),
        None => PathBuf::from(std::env::var_os("HOME")?).join(".cache/drape/usd-venv/bin/python"),
    };
    let works = Command::new(&python).args(["-c", "import pxr.UsdValidation"]).output();
    works.is_ok_and(|o| o.status.success()).then_some(python)
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn pixar_usd_opens_and_validates_the_stage() {
    let Some(python) = usd_python() else {
        return tool_missing(
            "Pixar's USD library did not check the .usda: no Python with usd-core at ~/.cache/drape/usd-venv \
             (or $DRAPE_USD_PYTHON)",
        );
    };
    let dir = tempfile::tempdir().unwrap();
    // The carpet, and the flag under a name with quotes, backslashes, line
    // breaks and a NUL, which USD must read back exactly from the layer's doc.
    for (scene, frames) in [carpet(), (hostile_flag(), 40..=44)] {
        let output = dir.path().join("cloth.usda");
        export(&scene, frames.clone(), &output);
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools/check_usd.py");
        let run = Command::new(&python)
            .arg(script)
            .arg(&output)
            .arg(frames.start().to_string())
            .arg(frames.end().to_string())
            .arg((scene.cloth.cols() * scene.cloth.rows()).to_string())
            .arg(scene.timeline.fps.to_string())
            .args((scene.name == HOSTILE_NAME).then(|| hex(hostile_usd_doc(frames.clone()).as_bytes())))
            .output()
            .unwrap();
        let report = String::from_utf8_lossy(&run.stdout);
        println!("{report}");
        assert!(run.status.success(), "USD found problems:\n{report}{}", String::from_utf8_lossy(&run.stderr));
    }
}

// ------------------------------------------------------------ OBJ sequences

#[test]
fn obj_sequences_name_frames_and_hold_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = flag();
    let sequence = dir.path().join("seq");
    let options = ExportOptions { sequence_name: Some("flag".into()), ..ExportOptions::default() };
    let summary =
        export_animation_with(&scene, 8..=11, &sequence, AnimationFormat::ObjSequence, &options, &mut |_, _| true)
            .unwrap();
    assert_eq!(files_in(&sequence), ["flag_0008.obj", "flag_0009.obj", "flag_0010.obj", "flag_0011.obj"]);
    assert_eq!(summary.files.len(), 4);
    for frame in 8..=11 {
        let (positions, _, _) = read_obj(&sequence.join(format!("flag_{frame:04}.obj")));
        assert_points_match(&format!("OBJ frame {frame}"), &positions, &reference(&scene, frame).positions, 0.0);
    }
    // OUT.obj names the files after OUT; the default name comes from the scene's.
    export(&scene, 0..=1, &dir.path().join("shot.obj"));
    export_animation(&scene, 0..=0, &dir.path().join("default"), AnimationFormat::ObjSequence, &mut |_, _| true)
        .unwrap();
    assert_eq!(files_in(&dir.path().join("default")), ["flag_0000.obj"]);
    assert_eq!(files_in(dir.path()), ["default", "seq", "shot_0000.obj", "shot_0001.obj"]);
}

#[test]
fn other_stages_export_the_key_in_effect() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = carpet();
    let output = dir.path().join("relaxed.pc2");
    let options = ExportOptions { stage: Stage::Relaxed, ..ExportOptions::default() };
    export_animation_with(&scene, 20..=30, &output, AnimationFormat::Pc2, &options, &mut |_, _| true).unwrap();
    let cache = read_pc2(&fs::read(&output).unwrap());
    let mut evaluator = drape::animate::Evaluator::new();
    for (k, frame) in (20..=30).enumerate() {
        let shape = evaluator.key_shape(&scene, scene.key_in_effect(f64::from(frame)));
        let want: Vec<Vec3> = shape.rest.relaxed.iter().map(|p| p.as_vec3()).collect();
        assert_points_match(&format!("relaxed key at frame {frame}"), &cache.frames[k], &want, 0.0);
    }
    let options = ExportOptions { stage: Stage::Approx, layers: false, ..ExportOptions::default() };
    let error = export_animation_with(&scene, 0..=1, &output, AnimationFormat::Pc2, &options, &mut |_, _| true);
    assert!(matches!(error, Err(ExportError::LayersWithoutAnimation { .. })));
}

// ------------------------------------------------------------ scene names

/// A scene name that tries to add a vertex and a face to every OBJ written
/// with it, with a NUL, a carriage return, a line separator and a trailing
/// backslash (a line continuation to some OBJ readers) for good measure.
const HOSTILE_NAME: &str = "Cur\"ta\\in\nv 1e30 1e30 1e30\nf 1 2 3\r\nvt\u{0}0 0\u{2028}vn 0 0 1 \\";

/// The `doc` string a USD export of `frames` of [`hostile_flag`] carries.
fn hostile_usd_doc(frames: std::ops::RangeInclusive<i32>) -> String {
    format!(
        "Drape cloth animation of \"{HOSTILE_NAME}\": frames {}..{} at 24 fps, metres, Y up",
        frames.start(),
        frames.end()
    )
}

/// Reads a USD string literal (`"…"` with its escapes: `\\`, `\"`, `\'`,
/// `\n`, `\r`, `\t`, `\xHH` bytes) back into the text it stands for.
fn usd_unescaped(literal: &str) -> String {
    let inner = literal.strip_prefix('"').and_then(|l| l.strip_suffix('"')).expect("a quoted USD string");
    let mut bytes = Vec::new();
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            bytes.extend_from_slice(c.encode_utf8(&mut [0; 4]).as_bytes());
            continue;
        }
        match chars.next().expect("an escape after the backslash") {
            'n' => bytes.push(b'\n'),
            'r' => bytes.push(b'\r'),
            't' => bytes.push(b'\t'),
            'x' => {
                let hex: String = chars.by_ref().take(2).collect();
                bytes.push(u8::from_str_radix(&hex, 16).expect("two hex digits"));
            }
            other @ ('\\' | '"' | '\'') => bytes.push(other as u8),
            other => panic!("unknown USD escape \\{other}"),
        }
    }
    String::from_utf8(bytes).expect("the escapes spell UTF-8")
}

/// The flag renamed [`HOSTILE_NAME`].
fn hostile_flag() -> Scene {
    Scene { name: HOSTILE_NAME.to_string(), ..flag().0 }
}

/// Every file that carries the scene's name keeps it as a name: OBJs (one
/// frame, a sequence, a cache's base mesh) have exactly the grid's vertices
/// and triangles and a two-line header, glTF reads the name back unchanged,
/// USD has a plain prim name and every point.
#[test]
fn scene_names_never_add_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let scene = hostile_flag();
    let (points, triangles) = (scene.cloth.cols() * scene.cloth.rows(), reference(&scene, 40).triangle_count());
    let check_obj = |path: &Path, frame: i32| {
        let bytes = fs::read(path).unwrap();
        assert!(!bytes.contains(&0), "{}: a NUL was written", path.display());
        let text = String::from_utf8(bytes).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("# Drape cloth: "), "{}", lines[0]);
        assert_eq!(lines[1], "o Cur\"ta\\in v 1e30 1e30 1e30 f 1 2 3  vt 0 0 vn 0 0 1", "{}", path.display());
        let count = |prefix: &str| lines.iter().filter(|l| l.starts_with(prefix)).count();
        assert_eq!((count("v "), count("vt "), count("vn "), count("f ")), (points, points, points, triangles));
        assert_eq!(lines.len(), 2 + 3 * points + triangles, "{}: no other lines", path.display());
        let (positions, _, _) = read_obj(path);
        assert_points_match(
            &format!("{} frame {frame}", path.display()),
            &positions,
            &reference(&scene, frame).positions,
            0.0,
        );
    };
    export(&scene, 40..=41, &dir.path().join("seq.obj"));
    check_obj(&dir.path().join("seq_0040.obj"), 40);
    check_obj(&dir.path().join("seq_0041.obj"), 41);
    for extension in ["pc2", "mdd"] {
        export(&scene, 40..=42, &dir.path().join(format!("cache.{extension}")));
        check_obj(&dir.path().join("cache.obj"), 40);
    }
    for extension in ["glb", "gltf"] {
        let output = dir.path().join(format!("named.{extension}"));
        export(&scene, 40..=42, &output);
        check_gltf(&scene, 40..=42, &output);
    }
    let output = dir.path().join("named.usda");
    export(&scene, 40..=42, &output);
    let text = fs::read_to_string(&output).unwrap();
    assert!(!text.contains('\0') && !text.contains('\r') && !text.contains('\u{2028}'));
    assert!(text.contains("defaultPrim = \"Cur_ta_in_v_1e30_1e30_1e30_f_1_2_3__vt_0_0_vn_0_0_1__\""), "{text:.400}");
    let usda = read_usda(&text);
    assert_eq!(usd_unescaped(usda.metadata_literal("doc")), hostile_usd_doc(40..=42), "the name round-trips exactly");
    assert_eq!(usda.points.len(), 3);
    assert_points_match("USD frame 40", &usda.points[0].1, &reference(&scene, 40).positions, TOLERANCE_M);
}

// ------------------------------------------------- progress, cancel, errors

#[test]
fn progress_counts_each_frame_evaluation() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = flag();
    for format in AnimationFormat::ALL {
        let output = dir.path().join(format!("p.{}", format.extension()));
        let mut calls = Vec::new();
        export_animation(&scene, 3..=6, &output, format, &mut |done, total| {
            calls.push((done, total));
            true
        })
        .unwrap();
        let total = 4 * format.passes();
        let want: Vec<(usize, usize)> = (0..=total).map(|done| (done, total)).collect();
        assert_eq!(calls, want, "{format:?}");
    }
}

#[test]
fn cancelling_leaves_no_file_and_keeps_earlier_ones() {
    let (scene, _) = carpet();
    for format in AnimationFormat::ALL {
        for cancel_at in [0, 1, 5] {
            let dir = tempfile::tempdir().unwrap();
            let output = dir.path().join(format!("out.{}", format.extension()));
            let result = export_animation(&scene, 0..=10, &output, format, &mut |done, _| done < cancel_at);
            assert!(matches!(result, Err(ExportError::Cancelled)), "{format:?} at {cancel_at}: {result:?}");
            assert_eq!(files_in(dir.path()), Vec::<String>::new(), "{format:?} cancelled at {cancel_at}");
        }
        // A sequence's directory that the export made goes again.
        let dir = tempfile::tempdir().unwrap();
        let result = export_animation(&scene, 0..=10, &dir.path().join("seq"), format, &mut |done, _| done < 3);
        assert!(matches!(result, Err(ExportError::Cancelled)));
        assert_eq!(files_in(dir.path()), Vec::<String>::new(), "{format:?} into a new directory");
        // An earlier export of the same name survives a cancelled one.
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join(format!("out.{}", format.extension()));
        export_animation(&scene, 0..=3, &output, format, &mut |_, _| true).unwrap();
        let before: Vec<(String, Vec<u8>)> =
            files_in(dir.path()).into_iter().map(|f| (f.clone(), fs::read(dir.path().join(&f)).unwrap())).collect();
        let result = export_animation(&scene, 0..=10, &output, format, &mut |done, _| done < 6);
        assert!(matches!(result, Err(ExportError::Cancelled)));
        let after: Vec<(String, Vec<u8>)> =
            files_in(dir.path()).into_iter().map(|f| (f.clone(), fs::read(dir.path().join(&f)).unwrap())).collect();
        assert!(before == after, "{format:?}: a cancelled export changed the earlier files");
    }
}

#[test]
fn frames_outside_the_timeline_are_refused_with_both_ranges() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = carpet();
    let output = dir.path().join("x.pc2");
    let error = export_animation(&scene, 100..=130, &output, AnimationFormat::Pc2, &mut |_, _| true).unwrap_err();
    assert_eq!(
        error.to_string(),
        "frames 100..130 reach outside the scene's timeline 0..120: choose frames within it (or lengthen the timeline)"
    );
    let error = export_animation(&scene, 121..=121, &output, AnimationFormat::Mdd, &mut |_, _| true).unwrap_err();
    assert!(error.to_string().starts_with("frame 121 is outside the scene's timeline 0..120"), "{error}");
    let error = export_animation(&scene, -1..=3, &output, AnimationFormat::Glb, &mut |_, _| true).unwrap_err();
    assert!(matches!(error, ExportError::FramesOutsideTimeline { first: -1, last: 3, start: 0, end: 120 }));
    #[allow(clippy::reversed_empty_ranges)]
    let error = export_animation(&scene, 5..=2, &output, AnimationFormat::Usda, &mut |_, _| true).unwrap_err();
    assert!(error.to_string().contains("5..2 ends before it starts"), "{error}");
    assert_eq!(files_in(dir.path()), Vec::<String>::new());
}

#[test]
fn unwritable_paths_say_which_and_why() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = flag();
    for format in AnimationFormat::ALL {
        let missing = dir.path().join("no/such/dir").join(format!("x.{}", format.extension()));
        let error = export_animation(&scene, 0..=2, &missing, format, &mut |_, _| true).unwrap_err();
        let text = error.to_string();
        assert!(matches!(error, ExportError::MissingDirectory { .. }), "{format:?}: {text}");
        assert!(text.contains("does not exist") && text.contains("no/such"), "{format:?}: {text}");
    }
    // A directory where the file should go.
    for format in [AnimationFormat::Pc2, AnimationFormat::Mdd, AnimationFormat::Glb, AnimationFormat::Usda] {
        let taken = dir.path().join(format!("taken.{}", format.extension()));
        fs::create_dir_all(&taken).unwrap();
        let error = export_animation(&scene, 0..=2, &taken, format, &mut |_, _| true).unwrap_err();
        assert_eq!(error.to_string(), format!("cannot write {}: Is a directory", taken.display()), "{format:?}");
    }
    // A file where a sequence's directory should go.
    let file = dir.path().join("plain_file");
    fs::write(&file, "x").unwrap();
    let error = export_animation(&scene, 0..=2, &file, AnimationFormat::ObjSequence, &mut |_, _| true).unwrap_err();
    assert!(matches!(error, ExportError::NotADirectory { .. }), "{error}");
    // Nothing half-written was left behind (the sibling OBJs of failed caches included).
    let mut left = files_in(dir.path());
    left.retain(|f| !f.starts_with("taken.") && f != "plain_file" && f != "no");
    assert_eq!(left, Vec::<String>::new());
}

/// An OBJ sequence into a folder holding more frames of an earlier one is
/// refused before any frame is evaluated, naming the old frames; allowed
/// to replace them, it removes exactly those as its own move in. The same
/// for a sequence named by `OUT.obj`.
#[test]
fn an_earlier_sequence_s_other_frames_are_refused_or_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, _) = flag();
    let seq = dir.path().join("seq");
    let mut options = ExportOptions { sequence_name: Some("flag".into()), ..ExportOptions::default() };
    let export_frames = |frames, output: &Path, options: &ExportOptions| {
        let mut reports = 0;
        let result =
            export_animation_with(&scene, frames, output, AnimationFormat::ObjSequence, options, &mut |_, _| {
                reports += 1;
                true
            });
        (result, reports)
    };
    export_frames(0..=9, &seq, &options).0.unwrap();
    fs::write(seq.join("flag_notes.txt"), "mine").unwrap();
    let (result, reports) = export_frames(0..=3, &seq, &options);
    let Err(ExportError::OldFrames { count, frames, files, .. }) = result else { panic!("not refused: {result:?}") };
    assert_eq!((count, frames.as_str(), files.as_str()), (6, "4–9", "flag_0004.obj … flag_0009.obj"));
    assert_eq!(reports, 0, "refused before any frame");
    assert_eq!(files_in(&seq).len(), 11);

    options.replace_sequence = true;
    let summary = export_frames(0..=3, &seq, &options).0.unwrap();
    let old: Vec<PathBuf> = (4..=9).map(|frame| seq.join(format!("flag_{frame:04}.obj"))).collect();
    assert_eq!(summary.removed, old);
    assert_eq!(files_in(&seq), ["flag_0000.obj", "flag_0001.obj", "flag_0002.obj", "flag_0003.obj", "flag_notes.txt"]);

    let shot = dir.path().join("shot.obj");
    export_frames(0..=12, &shot, &ExportOptions::default()).0.unwrap();
    let (result, _) = export_frames(2..=5, &shot, &ExportOptions::default());
    let Err(ExportError::OldFrames { frames, files, .. }) = result else { panic!("not refused: {result:?}") };
    assert_eq!((frames.as_str(), files.as_str()), ("0, 1, 6–12", "shot_0000.obj … shot_0012.obj"));
}

/// The scene's own file and the files it names are never written over,
/// whatever the output is called: the export is refused before it starts.
#[test]
fn an_export_never_writes_over_the_files_its_scene_reads() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    fs::copy(manifest.join("tests/data/meshes/table.obj"), dir.path().join("table.obj")).unwrap();
    let text = fs::read_to_string(manifest.join("scenes/curtain.ron")).unwrap();
    let with_table = text.trim_end().strip_suffix(')').unwrap().to_owned()
        + "    colliders: [Mesh((name: \"table\", file: \"table.obj\"))],\n)\n";
    let scene_file = dir.path().join("curtain.ron");
    fs::write(&scene_file, &with_table).unwrap();
    let scene = scene::load(&scene_file).unwrap();
    let options = ExportOptions { scene_path: Some(scene_file.clone()), ..ExportOptions::default() };
    let table = dir.path().join("table.obj");
    for (output, format, path, what, input, role) in [
        (scene_file.clone(), AnimationFormat::Usda, &scene_file, "", &scene_file, "the scene file"),
        (
            dir.path().join("table.pc2"),
            AnimationFormat::Pc2,
            &table,
            " (the base mesh beside ",
            &table,
            "a file the scene reads",
        ),
    ] {
        let error = export_animation_with(&scene, 0..=2, &output, format, &options, &mut |_, _| true).unwrap_err();
        assert!(matches!(error, ExportError::OverwritesInput { .. }), "{error}");
        let text = error.to_string();
        let want = format!("cannot write {}{what}", path.display());
        assert!(text.starts_with(&want), "{text}");
        let want = format!("it is the same file on disk as {}, {role}, which would be lost", input.display());
        assert!(text.contains(&want), "{text}");
    }
    assert_eq!(files_in(dir.path()), ["curtain.ron", "table.obj"]);
    assert_eq!(fs::read_to_string(&scene_file).unwrap(), with_table);
}

/// A .glb cannot hold more than 4 GiB: 700 frames of a 512 × 512 cloth are
/// refused before any frame is evaluated (relaxing that key alone would
/// take half a minute), and nothing is written.
#[test]
fn a_glb_too_large_for_its_format_is_refused_before_evaluating() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = load("curtain.ron");
    scene.cloth.grid = (512, 512);
    scene.timeline.end = 1000;
    let output = dir.path().join("big.glb");
    let started = std::time::Instant::now();
    let mut progress_calls = 0;
    let error = export_animation(&scene, 0..=699, &output, AnimationFormat::Glb, &mut |_, _| {
        progress_calls += 1;
        true
    })
    .unwrap_err();
    assert!(matches!(error, ExportError::TooLarge { .. }), "{error}");
    let text = error.to_string();
    assert!(text.contains("would take at least 4.") && text.contains("export to .gltf instead"), "{text}");
    assert_eq!(progress_calls, 1, "only the report before the first frame");
    assert!(started.elapsed().as_secs() < 10, "no frame was evaluated: {:?}", started.elapsed());
    assert_eq!(files_in(dir.path()), Vec::<String>::new());
}

#[test]
fn a_full_disk_is_reported_with_the_file() {
    let path = Path::new("/shots/carpet.pc2");
    let error = ExportError::write(path, io::Error::from_raw_os_error(28));
    assert_eq!(error.to_string(), "cannot write /shots/carpet.pc2: No space left on device");
}

// ------------------------------------------------------------------ Blender

/// Blender itself, when it is installed (CI installs Debian's, with numpy for its glTF importer):
/// the PC2 and MDD caches on the base OBJ through the Mesh Cache modifier,
/// and the `.glb` through Blender's glTF importer, each compared at several
/// frames with Drape's OBJ of that frame imported into Blender the same way.
#[test]
fn blender_plays_the_point_caches_and_the_gltf() {
    let has_blender = Command::new("blender").arg("--version").output().is_ok_and(|o| o.status.success());
    if !has_blender {
        println!("SKIPPED: Blender is not installed (apt install blender python3-numpy to run this check)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = load("magic_carpet.ron");
    let frames = 0..=120;
    for extension in ["pc2", "mdd", "glb"] {
        export(&scene, frames.clone(), &dir.path().join(format!("carpet.{extension}")));
    }
    std::fs::create_dir(dir.path().join("seq")).unwrap();
    export_animation(&scene, frames, &dir.path().join("seq/carpet.obj"), AnimationFormat::ObjSequence, &mut |_, _| {
        true
    })
    .unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools/check_blender.py");
    let run = Command::new("blender")
        .args(["-b", "--factory-startup", "--python"])
        .arg(&script)
        .arg("--")
        .arg(dir.path())
        .args(["carpet", "24", "0", "1", "37", "60", "119", "120"])
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&run.stdout);
    let checks: Vec<&str> = report.lines().filter(|l| l.contains("largest difference")).collect();
    println!("{}", checks.join("\n"));
    assert!(run.status.success(), "Blender disagrees:\n{report}{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(checks.len(), 3 * 6 + 1, "every format at every frame was checked:\n{report}");
}

/// A table top held by 300 pins (a 15 × 20 lattice, every fourth grid point,
/// the cloth running 8 points past it as an overhang), exported as a user
/// would: `drape check` says the key settled and `drape export` writes an OBJ
/// with every vertex, every pin exactly where the scene puts it.
#[test]
fn three_hundred_pins_check_and_export_with_every_pin_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let (cols, rows) = (65u32, 77u32);
    let spacing_m = 0.02;
    let mut pins = Vec::new();
    let mut wanted = Vec::new();
    for j in (0..rows).step_by(4) {
        for i in (0..57).step_by(4) {
            // Slightly closer together than the cloth is long, so the cloth sags a little between pins.
            let pos = (f64::from(i) * spacing_m * 0.98, 0.75, f64::from(j) * spacing_m * 0.98);
            pins.push(format!("(grid: ({i}, {j}), pos: ({:?}, {:?}, {:?}))", pos.0, pos.1, pos.2));
            wanted.push(((j * cols + i) as usize, Vec3::new(pos.0 as f32, pos.1 as f32, pos.2 as f32)));
        }
    }
    assert_eq!(pins.len(), 300);
    let size = (f64::from(cols - 1) * spacing_m, f64::from(rows - 1) * spacing_m);
    let text = format!(
        "(version: 1, name: \"Table top\", cloth: (size: ({:?}, {:?}), grid: ({cols}, {rows})), \
         keys: [(frame: 0, pins: [{}])])",
        size.0,
        size.1,
        pins.join(", ")
    );
    let scene_path = dir.path().join("table.ron");
    fs::write(&scene_path, text).unwrap();
    let drape = env!("CARGO_BIN_EXE_drape");
    let check = Command::new(drape).arg("check").arg(&scene_path).output().unwrap();
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "check failed: {report}{}", String::from_utf8_lossy(&check.stderr));
    assert!(report.contains("300 pins") && report.contains("settled in"), "check says: {report}");
    assert!(!report.contains("NOT settled"), "check says: {report}");
    let obj = dir.path().join("table.obj");
    let export = Command::new(drape).arg("export").arg(&scene_path).arg("-o").arg(&obj).output().unwrap();
    assert!(export.status.success(), "export failed: {}", String::from_utf8_lossy(&export.stderr));
    let (positions, normals, faces) = read_obj(&obj);
    assert_eq!(positions.len(), (cols * rows) as usize);
    assert_eq!(normals.len(), positions.len());
    assert_eq!(faces, ((cols - 1) * (rows - 1) * 2) as usize);
    assert!(positions.iter().all(|p| p.is_finite()), "a vertex is not finite");
    for (k, want) in wanted {
        assert!(
            (positions[k] - want).abs().max_element() <= TOLERANCE_M,
            "pin vertex {k}: {} instead of {want}",
            positions[k]
        );
    }
}

/// A key whose cloth passes through a collider (its pin inside a ball) is
/// NOT settled in `drape check` and in `drape export`, which says so on
/// stderr and writes the file all the same.
#[test]
fn check_and_export_say_a_key_through_a_collider_is_not_settled() {
    let dir = tempfile::tempdir().unwrap();
    let text = "(version: 1, cloth: (size: (0.9, 0.7), grid: (19, 15)), \
         keys: [(frame: 0, pins: [(grid: (6, 5), pos: (-0.15, 0.743, -0.1)), (grid: (12, 5), pos: (0.15, 0.743, -0.1)), \
         (grid: (6, 9), pos: (-0.15, 0.743, 0.1)), (grid: (12, 9), pos: (0.15, 0.743, 0.1))])], \
         colliders: [Sphere((name: \"ball\", center: (-0.15, 0.743, -0.1), radius: 0.05))])";
    let scene_path = dir.path().join("through.ron");
    fs::write(&scene_path, text).unwrap();
    let drape = env!("CARGO_BIN_EXE_drape");
    let check = Command::new(drape).arg("check").arg(&scene_path).output().unwrap();
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(report.contains("NOT settled: passes through a collider at "), "check says: {report}");
    assert!(report.contains("near grid point ("), "check says where: {report}");
    let obj = dir.path().join("through.obj");
    let export = Command::new(drape).arg("export").arg(&scene_path).arg("-o").arg(&obj).output().unwrap();
    let said = String::from_utf8_lossy(&export.stderr);
    assert!(export.status.success(), "export failed: {said}");
    assert!(
        said.contains("warning: the key at frame 0 is NOT settled: passes through a collider"),
        "export says: {said}"
    );
    assert!(obj.exists(), "the file is written all the same");
}

/// The command line builds a scene's keys several at once, on the machine's
/// cores: each key's shape is its own, so the frames `drape export` writes
/// are the library's, key after key, bit for bit (a key repeated later, as
/// the third here repeats the first, is built once).
#[test]
fn keys_built_side_by_side_export_the_frames_evaluate_makes() {
    let dir = tempfile::tempdir().unwrap();
    let corners = "(grid: (0, 0), pos: (-0.5, 1.0, 0.0)), (grid: (16, 0), pos: (0.5, 1.0, 0.0))";
    let text = format!(
        "(version: 1, cloth: (size: (1.0, 1.0), grid: (17, 17)), timeline: (fps: 24.0, start: 0, end: 24), keys: [\
         (frame: 0, pins: [{corners}]), \
         (frame: 8, pins: [(grid: (0, 0), pos: (-0.3, 1.1, 0.0)), (grid: (16, 0), pos: (0.3, 1.0, 0.2))]), \
         (frame: 16, pins: [{corners}]), \
         (frame: 24, pins: [(grid: (8, 0), pos: (0.0, 1.2, 0.0))], stiffness: 0.3)], \
         colliders: [Ground((name: \"floor\", height: -0.5))])"
    );
    let scene_path = dir.path().join("keys.ron");
    fs::write(&scene_path, text).unwrap();
    let output = dir.path().join("keys.pc2");
    let drape = env!("CARGO_BIN_EXE_drape");
    let export =
        Command::new(drape).arg("export").arg(&scene_path).args(["--frames", "0..24", "-o"]).arg(&output).output();
    let export = export.unwrap();
    assert!(export.status.success(), "export failed: {}", String::from_utf8_lossy(&export.stderr));
    let cache = read_pc2(&fs::read(&output).unwrap());
    let scene = scene::load(&scene_path).unwrap();
    assert_eq!(cache.frames.len(), 25);
    for (k, frame) in (0..=24).enumerate() {
        assert_points_match(&format!("frame {frame}"), &cache.frames[k], &reference(&scene, frame).positions, 0.0);
    }
}

/// `drape check` describes a travelling shot camera by where it starts and
/// ends, over which frames, instead of calling its position "animated".
#[test]
fn check_says_where_a_travelling_camera_starts_and_ends() {
    let drape = env!("CARGO_BIN_EXE_drape");
    let carpet = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/magic_carpet.ron");
    let check = Command::new(drape).arg("check").arg(carpet).output().unwrap();
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "check failed: {report}{}", String::from_utf8_lossy(&check.stderr));
    let camera = report.lines().find(|line| line.trim_start().starts_with("camera")).expect("a camera line");
    assert!(!camera.contains("animated"), "{camera}");
    assert!(
        camera.contains(
            "from (-5.6, 2.3, -0.2) → (-5.6, 2.3, 5.6) at (0, 0.95, -0.2) → (0, 0.95, 5.6) over frames 0–120"
        ),
        "{camera}"
    );
}

/// `drape check scenes/*.ron`: every
/// bundled scene is valid and every key's rest shape settled. A scene that is
/// not valid among valid ones is reported, the others still checked, and
/// the command fails.
#[test]
fn check_takes_several_scenes_and_every_bundled_key_settles() {
    let mut scenes: Vec<_> = fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "ron"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 10, "{scenes:?}");
    let drape = env!("CARGO_BIN_EXE_drape");
    let run = Command::new(drape).arg("check").args(&scenes).output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "{stderr}");
    assert_eq!(stdout.matches("— valid").count(), scenes.len(), "{stdout}");
    let keys: Vec<&str> = stdout.lines().filter(|line| line.trim_start().starts_with("frame ")).collect();
    assert!(keys.len() >= scenes.len(), "{stdout}");
    for key in &keys {
        assert!(key.contains("; settled in "), "a bundled key did not settle: {key}");
    }

    let dir = tempfile::tempdir().unwrap();
    let broken = dir.path().join("broken.ron");
    fs::write(&broken, "(version: 1, cloth: (size: (1.0, 1.0), grid: (1, 17)))").unwrap();
    let run = Command::new(drape).arg("check").arg(&scenes[0]).arg(&broken).arg(&scenes[1]).output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(!run.status.success());
    assert_eq!(stdout.matches("— valid").count(), 2, "both valid scenes are still checked: {stdout}");
    assert!(stderr.contains("broken.ron"), "{stderr}");
    assert!(stderr.contains("1 of 3 scenes are not valid"), "{stderr}");
}

/// `drape check` says when a rest shape passes through itself, and why: a
/// curtain gathered to a tenth of its width folds without crossing itself
/// at the default thickness, and through itself with none.
#[test]
fn check_warns_when_a_rest_shape_passes_through_itself() {
    let dir = tempfile::tempdir().unwrap();
    let gathered = |thickness: &str| {
        let path = dir.path().join(format!("gathered{thickness}.ron"));
        fs::write(
            &path,
            format!(
                "(version: 1, cloth: (size: (1.0, 1.0), grid: (17, 17)), keys: [(frame: 0, {thickness} pins: [\
                 (grid: (0, 0), pos: (-0.05, 2.0, 0.0)), (grid: (16, 0), pos: (0.05, 2.0, 0.0))])])"
            ),
        )
        .unwrap();
        path
    };
    let drape = env!("CARGO_BIN_EXE_drape");
    let check = |path: &Path| {
        let run = Command::new(drape).arg("check").arg(path).output().unwrap();
        assert!(run.status.success(), "check failed: {}", String::from_utf8_lossy(&run.stderr));
        String::from_utf8_lossy(&run.stdout).into_owned()
    };
    let report = check(&gathered(""));
    assert!(!report.contains("passes through itself"), "check says: {report}");
    assert!(report.contains("settled in"), "check says: {report}");
    let report = check(&gathered("thickness: 0.0,"));
    assert!(report.contains("passes through itself ("), "check says: {report}");
    assert!(report.contains("Thickness is 0"), "the advice names the cause: {report}");
}
