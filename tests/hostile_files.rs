//! Files made to hang or exhaust a reader: glTF node loops and diamonds,
//! accessors that claim more than their buffers hold, buffers that point at
//! devices, and paths that are FIFOs. Each is a positioned error from
//! `drape check`, at once; a reader that loops or blocks fails the test at
//! its deadline instead of hanging the suite.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// Longer than any of these checks takes by orders of magnitude: reaching it means a hang.
const HANG_DEADLINE: Duration = Duration::from_secs(120);

/// `drape check FILE`: whether it passed and what it printed, or a panic when it
/// has not finished by the deadline (the child is killed first).
fn drape_check(path: &Path) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_drape"))
        .arg("check")
        .arg(path)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > HANG_DEADLINE {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("drape check {} did not finish within {HANG_DEADLINE:?}", path.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success() || output.status.code() == Some(1), "{:?}: {text}", output.status);
    (output.status.success(), text)
}

/// A scene in `dir` whose only reference (or mesh collider) is `file`.
fn scene_naming(dir: &Path, file: &str, as_collider: bool) -> PathBuf {
    let named = if as_collider {
        format!("colliders: [Mesh((file: {file:?}))]")
    } else {
        format!("references: [(file: {file:?})]")
    };
    let text = format!(
        "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)),\n keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 2.0, 0.0))])],\n {named})"
    );
    let path = dir.join("scene.ron");
    std::fs::write(&path, text).unwrap();
    path
}

/// Checks the scene naming `file` both ways and returns each message, asserting
/// each is an error at the file's place in the scene (line 3).
fn refused_both_ways(dir: &Path, file: &str) -> [String; 2] {
    [false, true].map(|as_collider| {
        let (ok, message) = drape_check(&scene_naming(dir, file, as_collider));
        assert!(!ok, "{message}");
        let what = if as_collider { "collider 1" } else { "reference 1" };
        assert!(message.contains("scene.ron:3:"), "{message}");
        assert!(message.contains(&format!("{what}: cannot use {file:?}: ")), "{message}");
        message
    })
}

/// One triangle's three positions as a little-endian buffer.
fn triangle_bytes() -> Vec<u8> {
    [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]].iter().flatten().flat_map(|v| v.to_le_bytes()).collect()
}

/// A `.gltf` whose nodes list `children`, node 0 carrying a one-triangle mesh
/// read from `tri.bin` beside it.
fn gltf_with_children(dir: &Path, name: &str, children: &[Vec<usize>]) -> String {
    std::fs::write(dir.join("tri.bin"), triangle_bytes()).unwrap();
    let nodes: Vec<Value> = children
        .iter()
        .enumerate()
        .map(|(i, c)| if i == 0 { json!({"children": c, "mesh": 0}) } else { json!({"children": c}) })
        .collect();
    let gltf = json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0.0, 0.0, 0.0], "max": [1.0, 0.0, 1.0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36, "uri": "tri.bin"}],
    });
    std::fs::write(dir.join(name), gltf.to_string()).unwrap();
    name.to_owned()
}

#[test]
fn a_gltf_node_cycle_is_an_error_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let file = gltf_with_children(dir.path(), "loop.gltf", &[vec![1], vec![0]]);
    for message in refused_both_ways(dir.path(), &file) {
        assert!(message.contains("node 0 is its own ancestor: glTF nodes form trees"), "{message}");
    }
}

#[test]
fn a_gltf_node_diamond_is_an_error_not_an_exponential_walk() {
    let dir = tempfile::tempdir().unwrap();
    // Sixty nodes, each listing the next twice: 2^60 paths from the root.
    let children: Vec<Vec<usize>> = (0..60).map(|i| if i < 59 { vec![i + 1, i + 1] } else { vec![] }).collect();
    let file = gltf_with_children(dir.path(), "diamond.gltf", &children);
    for message in refused_both_ways(dir.path(), &file) {
        assert!(message.contains("node 1 is listed as a child twice"), "{message}");
    }
}

/// The walker's GLB with its JSON chunk changed by `edit`.
fn edited_walker(dir: &Path, name: &str, edit: impl FnOnce(&mut Value)) -> String {
    let glb = std::fs::read("assets/walker.glb").unwrap();
    let json_length = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let mut document: Value = serde_json::from_slice(&glb[20..20 + json_length]).unwrap();
    edit(&mut document);
    let mut json_chunk = document.to_string().into_bytes();
    while !json_chunk.len().is_multiple_of(4) {
        json_chunk.push(b' ');
    }
    let rest = &glb[20 + json_length..];
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((12 + 8 + json_chunk.len() + rest.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json_chunk);
    out.extend_from_slice(rest);
    std::fs::write(dir.join(name), out).unwrap();
    name.to_owned()
}

#[test]
fn an_accessor_larger_than_its_buffer_view_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = edited_walker(dir.path(), "huge.glb", |document| {
        let position = document["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
        document["accessors"][position]["count"] = json!(1u64 << 31);
    });
    for message in refused_both_ways(dir.path(), &file) {
        assert!(message.contains("2147483648 elements of 12 bytes do not fit its buffer view"), "{message}");
    }
    // The walker itself still reads.
    let walker = std::fs::canonicalize("assets/walker.glb").unwrap();
    let (ok, message) = drape_check(&scene_naming(dir.path(), &walker.display().to_string(), false));
    assert!(ok, "{message}");
}

#[test]
fn a_buffer_that_is_a_device_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let gltf = json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}],
        "buffers": [{"byteLength": 1000, "uri": "/dev/zero"}],
    });
    std::fs::write(dir.path().join("zero.gltf"), gltf.to_string()).unwrap();
    for message in refused_both_ways(dir.path(), "zero.gltf") {
        assert!(
            message.contains("cannot read its buffer \"/dev/zero\": it is a device, not a regular file"),
            "{message}"
        );
    }
}

#[test]
fn a_buffer_shorter_than_declared_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = gltf_with_children(dir.path(), "short.gltf", &[vec![]]);
    std::fs::write(dir.path().join("tri.bin"), &triangle_bytes()[..20]).unwrap();
    for message in refused_both_ways(dir.path(), &file) {
        assert!(message.contains("it holds 20 bytes, fewer than the 36 declared"), "{message}");
    }
}

#[cfg(unix)]
fn make_fifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success());
}

#[cfg(unix)]
#[test]
fn fifos_are_refused_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    make_fifo(&dir.path().join("pipe.glb"));
    for message in refused_both_ways(dir.path(), "pipe.glb") {
        assert!(message.contains("it is a named pipe (FIFO), not a regular file"), "{message}");
    }
    let scene = dir.path().join("pipe.ron");
    make_fifo(&scene);
    let (ok, message) = drape_check(&scene);
    assert!(!ok);
    assert!(message.contains("it is a named pipe (FIFO), not a regular file"), "{message}");
    let (ok, message) = drape_check(dir.path());
    assert!(!ok);
    assert!(message.contains("it is a folder, not a regular file"), "{message}");
}

#[test]
fn a_gltf_tree_still_reads_both_ways() {
    let dir = tempfile::tempdir().unwrap();
    let file = gltf_with_children(dir.path(), "tree.gltf", &[vec![1, 2], vec![], vec![]]);
    for as_collider in [false, true] {
        let (ok, message) = drape_check(&scene_naming(dir.path(), &file, as_collider));
        assert!(ok, "{message}");
    }
}

/// Runs `drape check FILE` and returns whether it passed, its stderr and its
/// peak resident memory in megabytes (`wait4`'s rusage, the figure
/// `/usr/bin/time -v` prints).
#[cfg(unix)]
// The child is reaped by `wait4`, which also gives its rusage.
#[allow(clippy::zombie_processes)]
fn check_measuring_memory(path: &Path) -> (bool, String, u64) {
    let child = Command::new(env!("CARGO_BIN_EXE_drape"))
        .arg("check")
        .arg(path)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(path.with_extension("stderr")).unwrap())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: all-zero is a valid rusage, which wait4 then fills in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child, not waited for yet; both pointers are valid.
    let waited = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(waited, child.id() as libc::pid_t, "wait4 failed");
    let passed = libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0;
    let text = std::fs::read_to_string(path.with_extension("stderr")).unwrap();
    (passed, text, usage.ru_maxrss as u64 / 1024)
}

/// `body` repeated until the scene text passes `bytes`, between `head` and `tail`.
fn large_scene(dir: &Path, name: &str, head: &str, body: &str, tail: &str, bytes: usize) -> PathBuf {
    let mut text = String::with_capacity(bytes + head.len() + tail.len() + body.len());
    text.push_str(head);
    while text.len() < bytes {
        text.push_str(body);
    }
    text.push_str(tail);
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const LARGE_SCENE_BYTES: usize = 60 << 20;

/// A scene file near the size limit takes memory a small multiple of its
/// size, whatever it holds: never the 1–2.5 GB that 60 MB of pins, comments
/// or parameter keys once took.
#[cfg(unix)]
#[test]
fn memory_grows_with_a_scene_files_size_only() {
    let dir = tempfile::tempdir().unwrap();
    let head = "(version: 1, cloth: (size: (1.0, 1.0), grid: (65, 65)),\n keys: [(frame: 0, pins: [";
    let pins =
        large_scene(dir.path(), "pins.ron", head, "(grid: (0, 0), pos: (0.0, 1.0, 0.0)),", "])])\n", LARGE_SCENE_BYTES);
    let (passed, message, pins_mb) = check_measuring_memory(&pins);
    assert!(!passed);
    assert!(message.contains("pins; the limit is 4 096 pins per key"), "{message}");

    let minimal = "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)),\n keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])])\n";
    let comments = large_scene(
        dir.path(),
        "comments.ron",
        "",
        "// a line of comment that says nothing\n",
        minimal,
        LARGE_SCENE_BYTES,
    );
    let (passed, message, comments_mb) = check_measuring_memory(&comments);
    assert!(passed, "{message}");

    // Layers with a parameter key at every frame of the timeline.
    let head = "(version: 1, cloth: (size: (1.0, 1.0), grid: (5, 5)), timeline: (start: 0, end: 100000),\n \
                keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])],\n layers: [";
    let layer: String = format!(
        "Sway((magnitude: [{}], direction: (1.0, 0.0, 0.0))),",
        (0..100_000).map(|frame| format!("(frame: {frame}, value: 1.0),")).collect::<String>()
    );
    let keys = large_scene(dir.path(), "keys.ron", head, &layer, "])\n", LARGE_SCENE_BYTES);
    let (_, _, keys_mb) = check_measuring_memory(&keys);

    let file_mb = (LARGE_SCENE_BYTES >> 20) as u64;
    for (what, mb) in [("pins", pins_mb), ("comments", comments_mb), ("parameter keys", keys_mb)] {
        assert!(mb < 8 * file_mb, "a {file_mb} MB scene of {what} took {mb} MB");
    }
}
