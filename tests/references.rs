//! References: glTF files read into rigs and posed on the scene's clock.
//!
//! A small glTF is written here by code (a parent chain, a CUBICSPLINE and
//! a STEP channel, a two-joint skin with a morph target) and its poses are
//! compared with values worked out by hand; the bundled walker
//! (`assets/walker.glb`, made by `assets/make_walker.py`) is checked for
//! what a character must do: stand in its bind pose, loop its walk. Files
//! that are missing, malformed or name what they lack are positioned errors.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "support/winding.rs"]
mod winding;

use drape::animate::references_at::reference_at;
use drape::scene::{self, read_rig};
use drape::world::rig::Rig;
use glam::{DMat4, DQuat, DVec3};
use serde_json::json;
use winding::winding_number;

/// Binary data and the accessors over it, for writing a .gltf with a .bin.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<serde_json::Value>,
    accessors: Vec<serde_json::Value>,
}

impl Buffer {
    /// Adds `values` (f32) as an accessor of `kind` ("SCALAR", "VEC3", …)
    /// and returns its index; `min_max` for POSITION and inputs.
    fn floats(&mut self, values: &[f32], kind: &str, width: usize, min_max: bool) -> usize {
        let offset = self.bytes.len();
        values.iter().for_each(|v| self.bytes.extend_from_slice(&v.to_le_bytes()));
        self.views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": values.len() * 4}));
        let mut accessor = json!({
            "bufferView": self.views.len() - 1, "componentType": 5126, "count": values.len() / width, "type": kind
        });
        if min_max {
            let column = |c: usize| values.iter().skip(c).step_by(width).copied();
            let min: Vec<f32> = (0..width).map(|c| column(c).fold(f32::INFINITY, f32::min)).collect();
            let max: Vec<f32> = (0..width).map(|c| column(c).fold(f32::NEG_INFINITY, f32::max)).collect();
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Adds `values` as unsigned bytes (JOINTS_0) of `kind`.
    fn bytes(&mut self, values: &[u8], kind: &str, width: usize) -> usize {
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(values);
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": values.len()}));
        self.accessors.push(json!({
            "bufferView": self.views.len() - 1, "componentType": 5121, "count": values.len() / width, "type": kind
        }));
        self.accessors.len() - 1
    }
}

/// A glTF with: `arm` at (0, 1, 0) turned 90° about Y; its child `hand` 0.5
/// along x, whose translation a CUBICSPLINE moves; a triangle skinned to
/// both, with one morph target; `arm`'s scale keyed STEP. Written to
/// `folder/rig.gltf` + `rig.bin`.
fn write_test_gltf(folder: &Path) -> PathBuf {
    let mut buffer = Buffer::default();
    let positions = buffer.floats(&[0.0, 1.0, 0.0, 0.0, 1.0, -0.5, 0.0, 1.0, 0.5], "VEC3", 3, true);
    let joints = buffer.bytes(&[0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0], "VEC4", 4);
    let weights = buffer.floats(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0], "VEC4", 4, false);
    let morph = buffer.floats(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.2, 0.0], "VEC3", 3, true);
    // Bind: arm's world is T(0, 1, 0)·R_y(90°), hand's that times T(0.5, 0, 0).
    let arm_world = DMat4::from_rotation_translation(DQuat::from_rotation_y(90f64.to_radians()), DVec3::Y);
    let hand_world = arm_world * DMat4::from_translation(DVec3::new(0.5, 0.0, 0.0));
    let inverse_bind: Vec<f32> =
        [arm_world.inverse(), hand_world.inverse()].iter().flat_map(|m| m.to_cols_array()).map(|v| v as f32).collect();
    let inverse_bind = buffer.floats(&inverse_bind, "MAT4", 16, false);
    let times = buffer.floats(&[0.0, 1.0], "SCALAR", 1, true);
    // CUBICSPLINE: (in-tangent, value, out-tangent) per key.
    let cubic = [0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0];
    let cubic = buffer.floats(&cubic, "VEC3", 3, false);
    let step = buffer.floats(&[1.0, 1.0, 1.0, 2.0, 2.0, 2.0], "VEC3", 3, false);
    let morph_weights = buffer.floats(&[0.0, 1.0], "SCALAR", 1, false);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let gltf = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 2]}],
        "nodes": [
            {"name": "arm", "translation": [0.0, 1.0, 0.0], "rotation": [0.0, s, 0.0, s], "children": [1]},
            {"name": "hand", "translation": [0.5, 0.0, 0.0]},
            {"name": "skinned", "mesh": 0, "skin": 0}
        ],
        "meshes": [{"name": "tri", "weights": [0.0], "primitives": [{
            "attributes": {"POSITION": positions, "JOINTS_0": joints, "WEIGHTS_0": weights},
            "targets": [{"POSITION": morph}],
            "material": 0
        }]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 0.125, 1.0]}}],
        "skins": [{"joints": [0, 1], "inverseBindMatrices": inverse_bind}],
        "animations": [{"name": "reach", "samplers": [
            {"input": times, "output": cubic, "interpolation": "CUBICSPLINE"},
            {"input": times, "output": step, "interpolation": "STEP"},
            {"input": times, "output": morph_weights, "interpolation": "LINEAR"}
        ], "channels": [
            {"sampler": 0, "target": {"node": 1, "path": "translation"}},
            {"sampler": 1, "target": {"node": 0, "path": "scale"}},
            {"sampler": 2, "target": {"node": 2, "path": "weights"}}
        ]}],
        "buffers": [{"uri": "rig.bin", "byteLength": buffer.bytes.len()}],
        "bufferViews": buffer.views,
        "accessors": buffer.accessors,
    });
    std::fs::write(folder.join("rig.bin"), &buffer.bytes).unwrap();
    let path = folder.join("rig.gltf");
    std::fs::write(&path, serde_json::to_string_pretty(&gltf).unwrap()).unwrap();
    path
}

fn origin(rig: &Rig, node: &str, t_secs: f64) -> DVec3 {
    let pose = rig.pose(Some(0), t_secs);
    pose.world_from_node[rig.node_named(node).unwrap()].transform_point3(DVec3::ZERO)
}

#[test]
fn a_written_gltf_poses_as_worked_out_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let rig = read_rig(&write_test_gltf(dir.path())).unwrap();
    assert_eq!(rig.nodes().iter().map(|n| n.name.as_str()).collect::<Vec<_>>(), ["arm", "hand", "skinned"]);
    assert_eq!(rig.nodes()[1].parent, Some(0));
    assert_eq!(rig.meshes()[0].color, [0.5, 0.25, 0.125, 1.0]);
    assert_eq!(rig.clips()[0].span_secs(), (0.0, 1.0));
    // The hand's translation at t = 0.5: Hermite with td = 1 from 0.5 (out-tangent
    // 1) to 1.5 (in-tangent 0): 0.5·0.5 + 0.125·1 + 0.5·1.5 = 1.125 along the
    // arm's x, which the arm's 90° about Y turns to −z; the STEP scale is still 1.
    let hand = origin(&rig, "hand", 0.5);
    assert!(hand.abs_diff_eq(DVec3::new(0.0, 1.0, -1.125), 1e-6), "{hand}");
    // At 1 s: 1.5 along x, and the arm's STEP scale is 2: −3 along z.
    let hand = origin(&rig, "hand", 1.0);
    assert!(hand.abs_diff_eq(DVec3::new(0.0, 1.0, -3.0), 1e-6), "{hand}");

    let mut skinned = Vec::new();
    rig.posed_positions(0, &rig.rest_pose(), &mut skinned);
    for (posed, bind) in skinned.iter().zip(&rig.meshes()[0].positions) {
        assert!(posed.abs_diff_eq(*bind, 1e-6), "the bind pose moves {bind} to {posed}");
    }
    rig.posed_positions(0, &rig.pose(Some(0), 1.0), &mut skinned);
    // Vertex 0, on the arm at its origin (0, 1, 0): the arm is still there.
    assert!(skinned[0].abs_diff_eq(DVec3::new(0.0, 1.0, 0.0), 1e-6), "{}", skinned[0]);
    // Vertex 1, on the hand where the hand was bound: wherever the hand now is.
    assert!(skinned[1].abs_diff_eq(DVec3::new(0.0, 1.0, -3.0), 1e-6), "{}", skinned[1]);
    // Vertex 2, (0, 1, 0.5) morphed by +0.2 y at weight 1, half arm and half
    // hand. In the arm's bind frame it is at (−0.5, 0.2, 0); the arm scaled
    // by 2 puts it at (−1, 0.4, 0) → world (0, 1.4, 1). In the hand's frame
    // it is at (−1, 0.2, 0); the hand now 1.5 along the arm, scaled 2 with
    // it: (1.5 − 1)·2 = 1 along the arm's x, 0.4 up → world (0, 1.4, −1).
    // Half each: (0, 1.4, 0).
    assert!(skinned[2].abs_diff_eq(DVec3::new(0.0, 1.4, 0.0), 1e-6), "{}", skinned[2]);
}

fn walker() -> Rig {
    read_rig(Path::new("assets/walker.glb")).unwrap()
}

#[test]
fn the_walker_stands_in_its_bind_pose_and_loops_its_walk() {
    let rig = walker();
    assert_eq!(rig.clips().len(), 1);
    assert_eq!(rig.clips()[0].name, "Walk");
    assert_eq!(rig.clips()[0].span_secs(), (0.0, 1.0));
    assert_eq!(rig.skins()[0].joints.len(), 19);
    assert!((9_000..=11_000).contains(&rig.vertex_count()), "{}", rig.vertex_count());
    let (mut bind, mut start, mut end) = (Vec::new(), Vec::new(), Vec::new());
    rig.posed_positions(0, &rig.rest_pose(), &mut bind);
    let most_moved = bind.iter().zip(&rig.meshes()[0].positions).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
    assert!(most_moved < 1e-5, "the bind pose moves a vertex by {most_moved} m");
    rig.posed_positions(0, &rig.pose(Some(0), 0.0), &mut start);
    rig.posed_positions(0, &rig.pose(Some(0), 1.0), &mut end);
    let seam = start.iter().zip(&end).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
    assert!(seam < 1e-6, "the walk's last pose is {seam} m from its first");
    // Mid-stride the feet are apart and nothing sinks through the floor.
    let mut mid = Vec::new();
    rig.posed_positions(0, &rig.pose(Some(0), 0.25), &mut mid);
    let lowest = mid.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let (front, back) = mid.iter().fold((f64::NEG_INFINITY, f64::INFINITY), |(f, b), p| (f.max(p.z), b.min(p.z)));
    assert!(lowest > -0.01, "a foot sinks to {lowest} m");
    assert!(front - back > 0.7, "mid-stride spans only {} m front to back", front - back);
}

/// A scene with the walker placed at (1, 0, 0), half speed, repeated,
/// starting at frame 12, with `extra` added to the reference.
fn walker_scene(extra: &str) -> String {
    let assets = std::fs::canonicalize("assets").unwrap();
    format!(
        "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)), timeline: (fps: 24.0, start: 0, end: 48), \
         keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 2.0, 0.0))])], \
         references: [(name: \"hero\", file: {:?}, center: (1.0, 0.0, 0.0), speed: 0.5, repeat: true, \
         start_frame: 12{extra})])",
        assets.join("walker.glb").display().to_string()
    )
}

fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("scene.ron");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_reference_plays_on_the_scene_clock_where_it_is_placed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene::load(&write_scene(dir.path(), &walker_scene(""))).unwrap();
    let rig = walker();
    let head = rig.node_named("head").unwrap();
    // Frame 12 + 24 = 0.5 s of the clip at half speed; frame 12 + 48 + 24 repeats it.
    let at = |frame: f64| reference_at(&scene, 0, frame).unwrap().scene_from_node(head).unwrap().w_axis.truncate();
    let file = rig.pose(Some(0), 0.5).world_from_node[head].w_axis.truncate();
    assert!(at(36.0).abs_diff_eq(file + DVec3::X, 1e-9), "{} vs {}", at(36.0), file + DVec3::X);
    assert!(at(84.0).abs_diff_eq(at(36.0), 1e-9), "the walk repeats every 48 frames at half speed");
    assert!(!at(30.0).abs_diff_eq(at(36.0), 1e-6), "the head moves while the walk plays");
}

fn drape_check(path: &Path) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_drape")).arg("check").arg(path).output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success() || output.status.code() == Some(1), "{text}");
    (output.status.success(), text)
}

#[test]
fn check_says_what_a_reference_holds() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, text) = drape_check(&write_scene(dir.path(), &walker_scene("")));
    assert!(ok, "{text}");
    assert!(text.contains("references 1"), "{text}");
    assert!(text.contains("reference \"hero\""), "{text}");
    assert!(text.contains("19 joints"), "{text}");
    assert!(text.contains("animation \"Walk\" 0–1 s (48 frames at speed 0.5) from frame 12, repeated"), "{text}");
}

#[test]
fn missing_malformed_or_mismatched_references_are_positioned_errors() {
    let dir = tempfile::tempdir().unwrap();
    let text = walker_scene("").replace("walker.glb", "nobody.glb");
    let (ok, message) = drape_check(&write_scene(dir.path(), &text));
    assert!(!ok);
    let column = text.find("file:").unwrap() + "file: ".len() + 1;
    assert!(message.contains(&format!("scene.ron:1:{column}: reference \"hero\": cannot use")), "{message}");
    assert!(message.contains("there is no such file"), "{message}");

    std::fs::write(dir.path().join("broken.glb"), b"glTF\x02\x00\x00\x00garbage").unwrap();
    let text = "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)),\n keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 2.0, 0.0))])],\n references: [\n  (file: \"broken.glb\")])";
    let (ok, message) = drape_check(&write_scene(dir.path(), text));
    assert!(!ok);
    assert!(
        message.contains("scene.ron:4:10: reference 1: cannot use \"broken.glb\": not a readable glTF file"),
        "{message}"
    );

    let (ok, message) = drape_check(&write_scene(dir.path(), &walker_scene(", animation: \"Run\"")));
    assert!(!ok);
    assert!(message.contains("has no animation \"Run\" (it has \"Walk\")"), "{message}");

    let (ok, message) =
        drape_check(&write_scene(dir.path(), &walker_scene(", speed: 0.0").replace("speed: 0.5, ", "")));
    assert!(!ok);
    assert!(message.contains("reference \"hero\": speed 0 must be greater than 0"), "{message}");

    let text = walker_scene("").replace("walker.glb", "walker.fbx");
    let (ok, message) = drape_check(&write_scene(dir.path(), &text));
    assert!(!ok);
    assert!(message.contains("is not a glTF file"), "{message}");
}

#[test]
fn a_rig_that_needs_an_extension_says_which() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("draco.gltf");
    let gltf = json!({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
                      "extensionsRequired": ["KHR_draco_mesh_compression"]});
    std::fs::write(&path, gltf.to_string()).unwrap();
    let error = read_rig(&path).unwrap_err();
    assert!(error.contains("KHR_draco_mesh_compression"), "{error}");
}

/// `scenes/cape.ron`: a cape attached to the walker's chest, the walker a collider.
fn cape() -> scene::Scene {
    scene::load(Path::new("scenes/cape.ron")).unwrap_or_else(|error| panic!("{error}"))
}

#[test]
fn the_capes_attached_pins_sit_on_their_attachments_at_every_frame() {
    use drape::animate::attachments::attachment_at;
    let scene = cape();
    let mut evaluator = drape::animate::Evaluator::new();
    let cols = scene.cloth.cols();
    let mut moved = 0.0f64;
    for frame in scene.timeline.start..=scene.timeline.end {
        let frame = f64::from(frame);
        let mesh = evaluator.evaluate_frame(&scene, frame);
        for pin in &scene.keys[0].pins {
            let attachment = pin.attach.as_ref().expect("every pin of the cape is attached");
            let at = attachment_at(&scene, attachment, frame).unwrap();
            let vertex = mesh.positions[pin.grid.1 as usize * cols + pin.grid.0 as usize].as_dvec3();
            assert!(vertex.distance(at) < 1e-6, "frame {frame}: pin {:?} is {} m off", pin.grid, vertex.distance(at));
            moved = moved.max(at.distance(DVec3::from(pin.pos)));
        }
    }
    assert!(moved > 0.01, "the walk should carry the seam (it moved at most {moved} m)");
}

#[test]
fn the_cape_stays_outside_the_walking_body() {
    let scene = cape();
    let thickness = scene.keys[0].thickness;
    let mut evaluator = drape::animate::Evaluator::new();
    let mut nearest = f64::INFINITY;
    for frame in scene.timeline.start..=scene.timeline.end {
        let frame = f64::from(frame);
        let mesh = evaluator.evaluate_frame(&scene, frame);
        let body = reference_at(&scene, 0, frame).unwrap().build_solid().unwrap();
        let triangles = body.triangles();
        for (k, p) in mesh.positions.iter().enumerate() {
            let distance = body.surface_point(p.as_dvec3()).distance;
            nearest = nearest.min(distance);
            assert!(
                distance >= thickness - 5e-4,
                "frame {frame}: vertex {k} at {p} is {:.2} mm from the body",
                distance * 1e3
            );
            if distance < NEAR_BODY_M {
                let winding = winding_number(&triangles, p.as_dvec3());
                assert!(winding < 0.5, "frame {frame}: vertex {k} at {p} is inside the body (winding {winding:.3})");
            }
        }
    }
    // The legs and the back do push on it: some vertex rests against the body.
    assert!(nearest < thickness + 2e-3, "the cape never comes near the body ({nearest} m)");
}

/// How near the body a point's side is also told by the winding number.
const NEAR_BODY_M: f64 = 0.03;

/// A second key at frame 60 stretched to elasticity 1.4, as an animator
/// tweaking the cape would add: its rest shape hangs behind the back, no
/// point and no place along an edge inside the walking body, nowhere
/// through itself, and settled.
#[test]
fn a_second_key_stretched_to_1_4_hangs_behind_the_back() {
    use drape::shape::Placement;
    use drape::shape::through::through_obstacles;
    use drape::world::ColliderShape;
    let mut scene = cape();
    scene.timeline.end = 96;
    let mut second = scene.keys[0].clone();
    second.frame = 60;
    second.elasticity = 1.4;
    scene.keys.push(second);
    let key = &scene.keys[1];
    let mut evaluator = drape::animate::Evaluator::new();
    let obstacles = evaluator.key_obstacles(&scene, key);
    assert!(!obstacles.is_empty(), "the walker is a collider");
    let shape = evaluator.key_shape(&scene, key);
    let rest = &shape.rest;
    let pinned: Vec<bool> = rest.placement.iter().map(|p| *p == Placement::Pin).collect();
    let through = through_obstacles(&rest.relaxed, (rest.grid.cols, rest.grid.rows), &pinned, &obstacles);
    assert_eq!(through, None);
    // The body the key was kept out of (placed as it is: no move, no scale).
    let Some(ColliderShape::Mesh { solid: body, .. }) = obstacles.first().map(|o| &o.shape) else {
        panic!("the walker is a mesh collider")
    };
    let triangles = body.triangles();
    let chest = winding_number(&triangles, DVec3::new(0.0, 1.2, 0.0));
    assert!((chest - 1.0).abs() < 1e-6, "the chest is inside the body: winding {chest}");
    for (k, p) in rest.relaxed.iter().enumerate() {
        if body.surface_point(*p).distance < NEAR_BODY_M {
            let winding = winding_number(&triangles, *p);
            assert!(winding < 0.5, "point {k} at {p} is inside the body (winding {winding:.3})");
        }
    }
    assert_eq!(shape.self_crossings(), 0);
    assert!(shape.settled(key.thickness), "{}", shape.verdict(key.thickness));
    // The pins are behind the neck (z −0.13 to −0.115): so is the cloth they hold.
    let count = rest.relaxed.len() as f64;
    let mean_z = rest.relaxed.iter().map(|p| p.z).sum::<f64>() / count;
    let in_front = rest.relaxed.iter().filter(|p| p.z > 0.0).count();
    assert!(mean_z < -0.12 && in_front == 0, "mean z {mean_z:.3} m, {in_front} points in front of z = 0");
}

#[test]
fn a_cloth_following_a_node_is_carried_as_the_node_moves() {
    let dir = tempfile::tempdir().unwrap();
    write_test_gltf(dir.path());
    let text = "(version: 1, cloth: (size: (0.4, 0.4), grid: (5, 5)), timeline: (fps: 24.0, start: 0, end: 48), \
                keys: [(frame: 0, pins: [(grid: (0, 0), pos: (-0.2, 1.0, -0.5)), (grid: (4, 0), pos: (0.2, 1.0, -0.5))])], \
                references: [(name: \"rig\", file: \"rig.gltf\")], follow: (reference: \"rig\", node: \"hand\"))";
    let scene = scene::load(&write_scene(dir.path(), text)).unwrap();
    let mut evaluator = drape::animate::Evaluator::new();
    let rest = evaluator.key_shape(&scene, &scene.keys[0]).positions.clone();
    let at_key = evaluator.evaluate_frame(&scene, 0.0);
    // No layers: on its key's frame the cloth is the key's rest shape.
    for (p, q) in at_key.positions.iter().zip(&rest) {
        assert!(p.distance(*q) < 1e-6, "{p} vs {q}");
    }
    // Frame 12 is 0.5 s: the hand has moved from 0.5 to 1.125 along the arm,
    // which points along −z; its turn and scale are unchanged.
    let moved = evaluator.evaluate_frame(&scene, 12.0);
    for (p, q) in moved.positions.iter().zip(&rest) {
        let expected = *q + glam::Vec3::new(0.0, 0.0, -0.625);
        assert!(p.distance(expected) < 1e-5, "{p} vs {expected}");
    }
    let wrong = text.replace("node: \"hand\"", "node: \"foot\"");
    let (ok, message) = drape_check(&write_scene(dir.path(), &wrong));
    assert!(!ok);
    assert!(message.contains("the cloth follows node \"foot\" of \"rig.gltf\", which has no such node"), "{message}");
    let wrong = text.replace("reference: \"rig\", node", "reference: \"hero\", node");
    let (ok, message) = drape_check(&write_scene(dir.path(), &wrong));
    assert!(!ok);
    assert!(message.contains("the cloth follows reference \"hero\", but no reference has that name"), "{message}");
}

/// Blender itself, when it is installed (not in CI: it is a large package):
/// `tests/tools/blender_rig.py` builds a skinned tube on a three-bone chain
/// with Bezier-keyed bones and a keyed shape key, exports it with Blender's
/// own glTF exporter, and writes where Blender shows its bones and vertices
/// at several frames; Drape plays the file as a reference and must put
/// every bone's head and every vertex within 0.1 mm of Blender's.
#[test]
fn a_gltf_exported_by_blender_plays_as_blender_shows_it() {
    let has_blender = Command::new("blender").arg("--version").output().is_ok_and(|o| o.status.success());
    if !has_blender {
        println!("SKIPPED: Blender is not installed (apt install blender to run this check)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let frames = [0, 7, 16, 25, 33, 40, 48];
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools/blender_rig.py");
    let run = Command::new("blender")
        .args(["-b", "--factory-startup", "--python"])
        .arg(&script)
        .arg("--")
        .arg(dir.path())
        .args(frames.map(|f| f.to_string()))
        .output()
        .unwrap();
    assert!(run.status.success(), "Blender failed:\n{}", String::from_utf8_lossy(&run.stderr));
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("blender.json")).unwrap()).unwrap();
    let fps = report["fps"].as_f64().unwrap();
    let text = format!(
        "(version: 1, cloth: (size: (1.0, 1.0), grid: (3, 3)), timeline: (fps: {fps:?}, start: 0, end: 48), \
         keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 3.0, 0.0))])], \
         references: [(name: \"tube\", file: \"rig.glb\")])"
    );
    let scene = scene::load(&write_scene(dir.path(), &text)).unwrap();
    let rig = scene.references[0].rig.0.clone().unwrap();
    assert_eq!(rig.clips().len(), 2, "Blender exports the bones' action and the shape key's as two animations");
    let point =
        |v: &serde_json::Value| DVec3::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap());
    for shown in report["frames"].as_array().unwrap() {
        let frame = shown["frame"].as_f64().unwrap();
        let posed = reference_at(&scene, 0, frame).unwrap();
        for (name, bone) in shown["bones"].as_object().unwrap() {
            let node = rig.node_named(name).unwrap_or_else(|| panic!("no node {name}"));
            let head = posed.scene_from_node(node).unwrap().transform_point3(DVec3::ZERO);
            let blender = point(&bone["head"]);
            assert!(head.distance(blender) < 1e-4, "frame {frame}: bone {name} at {head}, Blender {blender}");
        }
        let drape: Vec<DVec3> = posed.meshes().into_iter().flat_map(|m| m.positions).collect();
        let blender: Vec<DVec3> = shown["vertices"].as_array().unwrap().iter().map(point).collect();
        let nearest = |p: &DVec3, among: &[DVec3]| among.iter().map(|q| p.distance(*q)).fold(f64::INFINITY, f64::min);
        let worst = blender.iter().map(|p| nearest(p, &drape)).chain(drape.iter().map(|p| nearest(p, &blender)));
        let worst = worst.fold(0.0, f64::max);
        assert!(worst < 1e-4, "frame {frame}: a vertex is {worst} m from Blender's");
    }
}

// --- A reference's camera as the shot camera ------------------------------------------
//
// `assets/layout_camera.glb` (made by `assets/make_layout_camera.py`): a node
// "dolly" moved from x = −1 to +1 over 1 s carries "ShotCam" (1.5 m up, 4 m
// back, tilted 10° down; yfov 0.5 rad, 16:9, znear 0.1) and "Dutch" (the same
// place, rolled 15°); "Plan" is orthographic.

fn layout_camera_file() -> PathBuf {
    std::fs::canonicalize("assets/layout_camera.glb").unwrap()
}

/// A scene with the layout file as reference "layout", placed at (0, 0, 1)
/// and turned 90° about Y, and `camera` as its shot camera.
fn layout_scene(camera: &str) -> String {
    format!(
        "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)), timeline: (fps: 24.0, start: 0, end: 24),\n \
         keys: [(frame: 0, pins: [(grid: (0, 0), pos: (-0.5, 1.5, 0.0)), (grid: (4, 0), pos: (0.5, 1.5, 0.0))])],\n \
         references: [(name: \"layout\", file: {:?}, center: (0.0, 0.0, 1.0), rotation_deg: (0.0, 90.0, 0.0))],\n \
         camera: {camera},\n)",
        layout_camera_file().display().to_string()
    )
}

const FOLLOW_SHOT_CAM: &str =
    "(from_reference: (reference: \"layout\", camera: \"ShotCam\"), image_size: (1280, 720), sensor_width_mm: 36.0)";

#[test]
fn a_layout_files_cameras_are_read_with_their_nodes() {
    use drape::world::rig::Projection;
    let rig = read_rig(&layout_camera_file()).unwrap();
    let names: Vec<&str> = rig.cameras().iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["ShotCam", "Dutch", "Plan"], "named as their nodes, in the file's node order");
    let shot = rig.camera_named("ShotCam").unwrap();
    assert_eq!(shot.node, rig.node_named("ShotCam").unwrap());
    let Projection::Perspective { yfov_rad, aspect_ratio, znear } = shot.projection else { panic!("{shot:?}") };
    assert_eq!(yfov_rad, 0.5);
    assert!((aspect_ratio.unwrap() - 16.0 / 9.0).abs() < 1e-6 && (znear - 0.1).abs() < 1e-6);
    let dutch = rig.camera_named("Dutch").unwrap();
    assert!(matches!(dutch.projection, Projection::Perspective { aspect_ratio: None, .. }));
    assert_eq!(rig.camera_named("Plan").unwrap().projection, Projection::Orthographic);
    assert!(rig.camera_named("ShotCamLens").is_none(), "a camera goes by its node's name");
}

#[test]
fn a_reference_camera_is_posed_with_the_references_clock_and_placement() {
    use drape::animate::references_at::reference_camera_at;
    let dir = tempfile::tempdir().unwrap();
    let scene = scene::load(&write_scene(dir.path(), &layout_scene(FOLLOW_SHOT_CAM))).unwrap();
    let from = scene.camera.as_ref().unwrap().from_reference.clone().unwrap();
    // Frame 6 of 24 fps: 0.25 s, the dolly at x = −0.5, so in the file the
    // camera stands at (−0.5, 1.5, 4) and looks along (0, −sin 10°, −cos 10°).
    // Turned 90° about Y ((x, y, z) → (z, y, −x)) and moved by (0, 0, 1):
    let (sin, cos) = 10f64.to_radians().sin_cos();
    let posed = reference_camera_at(&scene, &from, 6.0).unwrap();
    assert!(posed.pose.eye.abs_diff_eq(DVec3::new(4.0, 1.5, 1.5), 1e-6), "{}", posed.pose.eye);
    assert!(posed.pose.forward.abs_diff_eq(DVec3::new(-cos, -sin, 0.0), 1e-6), "{}", posed.pose.forward);
    assert!(posed.pose.roll_deg().abs() < 1e-4, "a tilt is no roll");
    let end = reference_camera_at(&scene, &from, 24.0).unwrap();
    assert!(end.pose.eye.abs_diff_eq(DVec3::new(4.0, 1.5, -0.0), 1e-6), "the dolly's end: {}", end.pose.eye);

    // As the renderer's camera: there, aimed down the same line, seeing
    // yfov 0.5 rad across a 16:9 picture's height.
    let view = drape::picture::scene_shot_camera_at(&scene, 6.0, (1280, 720)).unwrap();
    assert!(view.eye().as_dvec3().abs_diff_eq(DVec3::new(4.0, 1.5, 1.5), 1e-5), "{}", view.eye());
    assert!(view.backward().as_dvec3().abs_diff_eq(DVec3::new(cos, sin, 0.0), 1e-5), "{}", view.backward());
    assert!((f64::from(view.fov_y_deg) - 0.5f64.to_degrees()).abs() < 1e-4, "{}", view.fov_y_deg);
    // Its focal length: hfov = 2·atan(tan(0.25)·16/9), focal = 18 / tan(hfov/2).
    let look = drape::picture::shot_look_at(&scene, scene.camera.as_ref().unwrap(), 6.0);
    let expected = 36.0 / (2.0 * 0.25f64.tan() * 16.0 / 9.0);
    assert!((look.focal_length_mm - expected).abs() < 1e-9, "{} vs {expected}", look.focal_length_mm);
    assert!((expected - 39.653).abs() < 1e-3, "{expected}");
}

#[test]
fn check_names_the_reference_camera_and_its_roll() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, text) = drape_check(&write_scene(dir.path(), &layout_scene(FOLLOW_SHOT_CAM)));
    assert!(ok, "{text}");
    assert!(
        text.contains("camera    ShotCam of reference \"layout\", yfov 28.6° (39.65 mm on a 36 mm sensor"),
        "{text}"
    );
    assert!(text.contains("1280 × 720 px, level"), "{text}");
    let dutch = FOLLOW_SHOT_CAM.replace("ShotCam", "Dutch").replace("720", "960");
    let (ok, text) = drape_check(&write_scene(dir.path(), &layout_scene(&dutch)));
    assert!(ok, "{text}");
    assert!(text.contains("rolls up to 15.0°, shown level (Drape's camera cannot roll)"), "{text}");
    let squarer = FOLLOW_SHOT_CAM.replace("720", "960");
    let (_, text) = drape_check(&write_scene(dir.path(), &layout_scene(&squarer)));
    assert!(text.contains("the file's aspect ratio 1.778 differs"), "{text}");
}

#[test]
fn a_camera_naming_what_is_not_there_says_what_is() {
    let dir = tempfile::tempdir().unwrap();
    let message = |camera: &str| {
        let text = layout_scene(camera);
        let (ok, message) = drape_check(&write_scene(dir.path(), &text));
        assert!(!ok, "{message}");
        (text, message)
    };
    let (text, error) = message(&FOLLOW_SHOT_CAM.replace("\"layout\"", "\"set\""));
    let line = text.lines().position(|l| l.contains("camera:")).unwrap() + 1;
    assert!(error.contains(&format!("scene.ron:{line}:")), "{error}");
    assert!(
        error.contains(
            "camera: from_reference names reference \"set\", but no reference has that name (the scene has \"layout\")"
        ),
        "{error}"
    );
    let (text, error) = message(&FOLLOW_SHOT_CAM.replace("ShotCam", "Crane"));
    let column = text.lines().nth(line - 1).unwrap().find("\"Crane\"").unwrap() + 1;
    assert!(error.contains(&format!("scene.ron:{line}:{column}:")), "{error}");
    assert!(error.contains("names camera \"Crane\""), "{error}");
    assert!(error.contains("which has no such camera (it has \"ShotCam\", \"Dutch\")"), "{error}");
    let (_, error) = message(&FOLLOW_SHOT_CAM.replace("ShotCam", "Plan"));
    assert!(error.contains("\"Plan\"") && error.contains("which is orthographic"), "{error}");
    let (_, error) = message("(image_size: (1280, 720))");
    assert!(error.contains("camera: `position` and `target` are missing"), "{error}");
    assert!(error.contains("from_reference"), "{error}");
}

#[test]
fn a_camera_following_a_reference_reads_back_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene::load(&write_scene(dir.path(), &layout_scene(FOLLOW_SHOT_CAM))).unwrap();
    let text = scene::to_ron_string(&scene);
    assert!(text.contains("from_reference: (reference: \"layout\", camera: \"ShotCam\")"), "{text}");
    let camera_text = &text[text.find("\n    camera:").unwrap_or_else(|| panic!("{text}"))..];
    assert!(!camera_text.contains("position") && !camera_text.contains("focal_length_mm"), "{text}");
    let again = scene::load(&write_scene(dir.path(), &text)).unwrap();
    assert_eq!(again.camera, scene.camera);
}

#[test]
fn drape_render_looks_through_the_reference_camera_as_it_dollies() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), &layout_scene(FOLLOW_SHOT_CAM));
    let render = |frame: &str| {
        let out = dir.path().join(format!("f{frame}.png"));
        let output = Command::new(env!("CARGO_BIN_EXE_drape"))
            .args(["render", &path.display().to_string(), "--frame", frame, "--size", "96x54", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        let image = drape::image::RgbaImage::decode_png(&std::fs::read(&out).unwrap()).unwrap();
        assert_eq!((image.width, image.height), (96, 54));
        image.pixels
    };
    let (start, end) = (render("0"), render("24"));
    let differing = start.chunks_exact(4).zip(end.chunks_exact(4)).filter(|(a, b)| a != b).count();
    assert!(differing > 96 * 54 / 20, "the dolly moves the picture: {differing} pixels differ");
}

/// View ▸ "Camera from layout · ShotCam" (a flat item, one per perspective
/// camera of the references) makes the shot camera follow it; "Camera from
/// view" and "Key camera at playhead" then do not apply, and "Detach camera
/// from reference" leaves a camera of its own.
#[test]
fn the_view_menu_offers_the_reference_cameras() {
    use drape::editor::DrapeApp;
    use eframe::egui;
    use eframe::egui::accesskit::Role;
    use egui_kittest::Harness;
    use egui_kittest::kittest::{NodeT as _, Queryable};

    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), &layout_scene("(position: (0.0, 1.5, 4.0), target: (0.0, 1.0, 0.0))"));
    let scene = scene::load(&path).unwrap();
    let (config, state) = (dir.path().join("config"), dir.path().join("state"));
    let mut harness = Harness::builder().with_size(egui::vec2(1100.0, 720.0)).wgpu().build_eframe(move |cc| {
        DrapeApp::new(scene, Some(path), cc.wgpu_render_state.as_ref()).with_file_dirs(Some(config), Some(state))
    });
    let settle = |harness: &mut Harness<'_, DrapeApp>| {
        for _ in 0..3 {
            assert!(harness.state_mut().wait_for_shapes(std::time::Duration::from_secs(120)));
            harness.run();
        }
    };
    settle(&mut harness);
    // A scene with a shot camera opens looking through it; "Camera from
    // view" takes the orbiting view, so the user leaves the camera first.
    if harness.state().looks_through_shot_camera() {
        harness.get_by_role_and_label(Role::Button, "Camera").click();
        harness.run_ok();
    }
    let open_view = |harness: &mut Harness<'_, DrapeApp>| {
        harness.get_by_role_and_label(Role::Button, "View").click();
        harness.run_ok();
    };
    open_view(&mut harness);
    assert!(harness.query_by_label("Camera from layout · Plan").is_none(), "an orthographic camera is not offered");
    assert!(!harness.get_by_label("Camera from view").accesskit_node().is_disabled());
    harness.get_by_label("Camera from layout · ShotCam").click();
    harness.run_ok();
    let camera = harness.state().scene().camera.clone().unwrap();
    let from = camera.from_reference.expect("it follows the reference's camera");
    assert_eq!((from.reference.as_str(), from.camera.as_str()), ("layout", "ShotCam"));

    open_view(&mut harness);
    assert!(harness.get_by_label("Camera from view").accesskit_node().is_disabled());
    assert!(harness.get_by_label("Key camera at playhead").accesskit_node().is_disabled());
    harness.get_by_label("Detach camera from reference").click();
    harness.run_ok();
    let camera = harness.state().scene().camera.clone().unwrap();
    assert_eq!(camera.from_reference, None);
    // Frame 0: the dolly at x = −1, the camera turned with the reference to (4, 1.5, 2).
    let position = drape::animate::track::sample_vec3(&camera.position, 0.0);
    assert!(position.abs_diff_eq(DVec3::new(4.0, 1.5, 2.0), 1e-6), "{position}");
    settle(&mut harness);
}
