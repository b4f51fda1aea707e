//! "Nothing blown up, nothing lost": the `drape` binary writing to special
//! files (no side file beside a device or FIFO), stdout and symlinks,
//! interrupted by signals or killed, leaving no temporary file behind and
//! removing only what it can prove it wrote; never writing over the scene
//! it reads, nor leaving an earlier sequence's frames among a new one's;
//! output names as long as a file name may be; hostile scene files (a name
//! that injects OBJ lines, an endless timeline, an endless file, too many
//! pins); bounded memory (a 1000-pin key) and exports refused up front past
//! their size limit unless --force; progress on a terminal only; and the
//! CLI's subcommands refusing the same things with the same messages.
//!
//! Every drape these tests start has SIGINT, SIGTERM and SIGHUP at their
//! default dispositions and can write at most [`CHILD_FILE_LIMIT_BYTES`]
//! into a file, however the tests themselves were started.

#![cfg(unix)]

use std::fs;
use std::io;
use std::os::unix::fs::FileTypeExt as _;
use std::os::unix::process::{CommandExt as _, ExitStatusExt as _};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use drape::scene::{self, Scene};

/// Most bytes a drape started by these tests may write into one file: a
/// runaway write (a forced export of hundreds of gigabytes whose interrupt
/// went unheard) fails instead of filling the disk.
const CHILD_FILE_LIMIT_BYTES: u64 = 256 << 20;

/// The `drape` binary Cargo built, or `$DRAPE_BIN` when set (a copy kept
/// aside where several checkouts share one target directory and overwrite
/// each other's `target/release/drape`), prepared by [`prepare_child`].
fn drape() -> Command {
    drape_with(CHILD_FILE_LIMIT_BYTES, libc::SIG_DFL)
}

/// [`drape`] with SIGINT set to `sigint` and files capped at `limit_bytes`.
fn drape_with(limit_bytes: u64, sigint: libc::sighandler_t) -> Command {
    let binary = std::env::var_os("DRAPE_BIN").unwrap_or_else(|| env!("CARGO_BIN_EXE_drape").into());
    let mut command = Command::new(binary);
    command.current_dir(env!("CARGO_MANIFEST_DIR"));
    // SAFETY: the hook only makes system calls (signal, getrlimit, setrlimit),
    // which are safe between fork and exec.
    unsafe { command.pre_exec(move || prepare_child(limit_bytes, sigint)) };
    command
}

/// Runs in the child before drape starts. Tests run as a background job
/// (`cargo test &` in a script) start with SIGINT ignored, and drape keeps
/// a signal ignored as a background process should, so a test that
/// interrupts drape sets the dispositions it means: `sigint`, and the
/// default for SIGTERM and SIGHUP. Files are capped at `limit_bytes`, with
/// SIGXFSZ ignored so that a write past the cap fails with EFBIG, which
/// drape reports (removing its temporaries), rather than killing it.
fn prepare_child(limit_bytes: u64, sigint: libc::sighandler_t) -> io::Result<()> {
    let set = |signal, disposition| {
        // SAFETY: signal(2) with a valid signal number and disposition.
        if unsafe { libc::signal(signal, disposition) } == libc::SIG_ERR {
            return Err(io::Error::last_os_error());
        }
        Ok(())
    };
    set(libc::SIGINT, sigint)?;
    set(libc::SIGTERM, libc::SIG_DFL)?;
    set(libc::SIGHUP, libc::SIG_DFL)?;
    set(libc::SIGXFSZ, libc::SIG_IGN)?;
    let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: getrlimit and setrlimit on a valid rlimit structure.
    unsafe {
        if libc::getrlimit(libc::RLIMIT_FSIZE, &mut limit) != 0 {
            return Err(io::Error::last_os_error());
        }
        limit.rlim_cur = limit.rlim_max.min(limit_bytes as libc::rlim_t);
        if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
            return Err(io::Error::last_os_error());
        }
    }
    Ok(())
}

fn run(args: &[&str]) -> Output {
    drape().args(args).output().expect("drape runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// The curtain (33 × 25 points, 32 × 24 × 2 triangles).
const CURTAIN_POINTS: usize = 33 * 25;
const CURTAIN_TRIANGLES: usize = 32 * 24 * 2;

/// The `v` and `f` lines of an OBJ.
fn obj_counts(text: &str) -> (usize, usize) {
    let count = |prefix: &str| text.lines().filter(|l| l.starts_with(prefix)).count();
    (count("v "), count("f "))
}

fn is_root() -> bool {
    // SAFETY: geteuid has no preconditions.
    unsafe { libc::geteuid() == 0 }
}

// ------------------------------------------------------------ special files

/// Exports the curtain's OBJ into the FIFO `fifo` while `cat` reads it;
/// returns what `cat` read.
fn export_through_fifo(fifo: &Path) -> String {
    let mut reader = Command::new("cat").arg(fifo).stdout(Stdio::piped()).spawn().unwrap();
    let export = run(&["export", "scenes/curtain.ron", "-o", fifo.to_str().unwrap(), "--format", "obj"]);
    let still_fifo = fs::symlink_metadata(fifo).is_ok_and(|m| m.file_type().is_fifo());
    if !export.status.success() || !still_fifo {
        // `cat` would wait for a writer forever.
        let _ = reader.kill();
        let _ = reader.wait();
        assert!(still_fifo, "the FIFO was replaced by a {:?}", fs::symlink_metadata(fifo).map(|m| m.file_type()));
        panic!("export into a FIFO failed: {}", stderr(&export));
    }
    let read = reader.wait_with_output().unwrap();
    String::from_utf8(read.stdout).unwrap()
}

#[test]
fn a_fifo_is_written_into_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.obj");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success(), "mkfifo failed");
    let text = export_through_fifo(&fifo);
    assert_eq!(obj_counts(&text), (CURTAIN_POINTS, CURTAIN_TRIANGLES), "the reader got the whole OBJ");
    assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(), "still a FIFO");
    assert_eq!(names_in(dir.path()), ["pipe.obj"], "no temporary file");
}

/// `/dev/null`'s twin made with mknod: it stays a character device. Needs
/// root (CAP_MKNOD); without it this says it did not run (the FIFO test above
/// covers the same path).
#[test]
fn a_device_is_written_into_not_replaced() {
    if !is_root() {
        println!("SKIPPED: a null device can only be made as root; the FIFO test covers special files");
        eprintln!("SKIPPED: a null device can only be made as root; the FIFO test covers special files");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let null = dir.path().join("null");
    let made = Command::new("mknod").arg(&null).args(["c", "1", "3"]).output().expect("mknod runs");
    if !made.status.success() {
        let why = String::from_utf8_lossy(&made.stderr);
        println!("SKIPPED: mknod failed even as root (no CAP_MKNOD in this container?): {why}");
        eprintln!("SKIPPED: mknod failed even as root (no CAP_MKNOD in this container?): {why}");
        return;
    }
    for format in ["obj", "usda", "pc2", "mdd", "glb"] {
        let args = ["--format", format, "--frames", "0..3"];
        let args = if format == "obj" { &args[..2] } else { &args[..] };
        let output = drape().args(["export", "scenes/curtain.ron", "-o"]).arg(&null).args(args).output().unwrap();
        assert!(output.status.success(), "{args:?}: {}", stderr(&output));
        let meta = fs::symlink_metadata(&null).unwrap();
        assert!(meta.file_type().is_char_device(), "{args:?}: the device was replaced by a {:?}", meta.file_type());
        if matches!(format, "pc2" | "mdd") {
            let stdout = String::from_utf8_lossy(&output.stdout);
            let note = format!(
                "  not written: the base mesh {}.obj: {} is not a regular file, and no file is made beside a device or FIFO\n",
                null.display(),
                null.display()
            );
            assert!(stdout.ends_with(&note), "{format}: {stdout}");
        }
    }
    // A .gltf cannot go without its .bin beside it: refused, nothing made.
    let output = drape().args(["export", "scenes/curtain.ron", "--format", "gltf", "-o"]).arg(&null).output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {} is not a regular file (a device or a FIFO): a .gltf needs its .bin beside it, which Drape \
             does not make next to a special file; write a .glb, which holds everything, instead\n",
            null.display()
        )
    );
    // Nor does an OBJ sequence go into one, which is not a directory.
    let output = drape().args(["export", "scenes/curtain.ron", "--frames", "0..2", "-o"]).arg(&null).output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("is not a directory: an OBJ sequence is written into a directory"));
    assert_eq!(names_in(dir.path()), ["null"], "no temporary file, no base mesh or .bin beside the device");
}

/// `-o /dev/stdout` pipes the file on: the summary goes to stderr, so
/// nothing but the file's bytes reaches stdout.
#[test]
fn an_export_to_stdout_keeps_the_summary_out_of_the_data() {
    let obj = run(&["export", "scenes/curtain.ron", "-o", "/dev/stdout", "--format", "obj"]);
    assert!(obj.status.success(), "{}", stderr(&obj));
    let text = String::from_utf8(obj.stdout.clone()).unwrap();
    assert_eq!(obj_counts(&text), (CURTAIN_POINTS, CURTAIN_TRIANGLES));
    assert!(text.lines().last().unwrap().starts_with("f "), "the OBJ ends with its last face");
    assert!(stderr(&obj).starts_with("wrote /dev/stdout ("), "{}", stderr(&obj));
    let pc2 = run(&["export", "scenes/curtain.ron", "-o", "/dev/stdout", "--format", "pc2", "--frames", "0..3"]);
    assert!(pc2.status.success(), "{}", stderr(&pc2));
    assert_eq!(pc2.stdout.len(), 32 + 4 * CURTAIN_POINTS * 12, "the cache and nothing else");
    assert!(stderr(&pc2).contains("not written: the base mesh /dev/stdout.obj"), "{}", stderr(&pc2));
}

/// A PC2 cache streamed into a named pipe arrives whole, and no base OBJ
/// appears beside the pipe (works without root, unlike the device above).
#[test]
fn a_point_cache_into_a_fifo_makes_no_file_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("cache.pc2");
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs").success());
    let reader = Command::new("cat").arg(&fifo).stdout(Stdio::piped()).spawn().unwrap();
    let export = drape().args(["export", "scenes/curtain.ron", "--frames", "0..3", "-o"]).arg(&fifo).output().unwrap();
    let read = reader.wait_with_output().unwrap();
    assert!(export.status.success(), "{}", stderr(&export));
    assert_eq!(read.stdout.len(), 32 + 4 * CURTAIN_POINTS * 12, "the header and four frames of every point");
    assert!(read.stdout.starts_with(b"POINTCACHE2\0"));
    assert!(String::from_utf8_lossy(&export.stdout).contains("not written: the base mesh"));
    assert_eq!(names_in(dir.path()), ["cache.pc2"], "no cache.obj beside the FIFO");

    // A sequence needs a directory: refused before anything opens the FIFO.
    let frames = dir.path().join("frames");
    assert!(Command::new("mkfifo").arg(&frames).status().expect("mkfifo runs").success());
    for command in ["export", "render"] {
        let output =
            drape().args([command, "scenes/curtain.ron", "--frames", "0..2", "-o"]).arg(&frames).output().unwrap();
        assert_eq!(output.status.code(), Some(1), "{command}");
        assert!(stderr(&output).contains(&format!("{} is not a directory", frames.display())), "{}", stderr(&output));
    }
    assert_eq!(names_in(dir.path()), ["cache.pc2", "frames"]);
}

#[test]
fn a_symlinked_output_keeps_the_link_and_replaces_its_target() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("shots")).unwrap();
    let target = dir.path().join("shots/curtain_v2.obj");
    fs::write(&target, "old").unwrap();
    let link = dir.path().join("curtain.obj");
    std::os::unix::fs::symlink("shots/curtain_v2.obj", &link).unwrap();
    let output = drape().args(["export", "scenes/curtain.ron", "-o"]).arg(&link).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
    assert_eq!(fs::read_link(&link).unwrap(), Path::new("shots/curtain_v2.obj"));
    let text = fs::read_to_string(&target).unwrap();
    assert_eq!(obj_counts(&text), (CURTAIN_POINTS, CURTAIN_TRIANGLES), "the target holds the new OBJ");
    assert_eq!(names_in(dir.path()), ["curtain.obj", "shots"]);
    assert_eq!(names_in(&dir.path().join("shots")), ["curtain_v2.obj"], "no temporary file beside the target");
}

// ------------------------------------------------------ hostile scene files

#[test]
fn a_scene_name_cannot_inject_obj_lines() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = scene::load(&scene_path("curtain.ron")).unwrap();
    scene.name = "Cur\nv 1e30 1e30 1e30\nf 1 2 3\0".into();
    let path = dir.path().join("hostile.ron");
    scene::save(&scene, &path).unwrap();
    let obj = dir.path().join("hostile.obj");
    let output = drape().args(["export"]).arg(&path).arg("-o").arg(&obj).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let bytes = fs::read(&obj).unwrap();
    assert!(!bytes.contains(&0), "no NUL in the OBJ");
    let text = String::from_utf8(bytes).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "# Drape cloth: 33 × 25 grid, vertex order j·cols + i");
    assert_eq!(lines[1], "o Cur v 1e30 1e30 1e30 f 1 2 3");
    assert_eq!(obj_counts(&text), (CURTAIN_POINTS, CURTAIN_TRIANGLES), "exactly the grid's vertices and faces");
    assert!(!text.contains("1e30 1e30 1e30\n"), "the injected vertex is not a line of its own");
}

/// Writes `scene` with `edit` applied to its text into `dir`.
fn scene_file(dir: &Path, name: &str, edit: impl FnOnce(String) -> String) -> PathBuf {
    let text = fs::read_to_string(scene_path("curtain.ron")).unwrap();
    let edited = edit(text.clone());
    assert_ne!(edited, text, "the edit for {name} changed nothing: has curtain.ron changed?");
    let path = dir.join(name);
    fs::write(&path, edited).unwrap();
    path
}

/// The bundled curtain's sweep cap, which the large-grid tests lower to keep
/// their rough rest shapes quick.
const CURTAIN_CAP: &str = "iterations: 2000";

#[test]
fn an_endless_timeline_is_a_positioned_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_file(dir.path(), "long.ron", |text| {
        let at = text.find("timeline:").expect("the curtain has a timeline");
        let end = at + text[at..].find(')').unwrap();
        format!("{}timeline: (fps: 24.0, start: 0, end: 2147483647{}", &text[..at], &text[end..])
    });
    let text = fs::read_to_string(&path).unwrap();
    let line = text[..text.find("2147483647").unwrap()].lines().count();
    let col = text.lines().nth(line - 1).unwrap().find("2147483647").unwrap() + 1;
    let want = format!(
        "error: {}:{line}:{col}: timeline end 2 147 483 647 is out of range: it must be within ±100 000 frames\n",
        path.display()
    );
    for args in [&["check"][..], &["export", "-o", "x.usda"][..]] {
        let output = drape().arg(args[0]).arg(&path).args(&args[1..]).current_dir(dir.path()).output().unwrap();
        assert_eq!(output.status.code(), Some(1), "{args:?}");
        assert_eq!(stderr(&output), want, "{args:?}");
    }
    assert_eq!(names_in(dir.path()), ["long.ron"]);
}

#[test]
fn an_endless_file_is_refused_promptly() {
    let mut child = drape().args(["check", "/dev/zero"]).stderr(Stdio::piped()).spawn().unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("`drape check /dev/zero` was still reading after 20 s");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(stderr(&output), "error: cannot read /dev/zero: it is a device, not a regular file\n");
}

#[test]
fn check_shortens_long_names_and_huge_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene: Scene = scene::load(&scene_path("flag.ron")).unwrap();
    scene.name = format!("Flag{}", "g".repeat(5_000_000));
    let drape::scene::Layer::Gusts(gusts) = &mut scene.layers[2] else { panic!("the flag's third layer is gusts") };
    gusts.direction = (1e150, 0.0, 0.0);
    gusts.name = "\u{1b}[2J".to_string() + &"gusts".repeat(100);
    let path = dir.path().join("flag.ron");
    scene::save(&scene, &path).unwrap();
    let output = drape().arg("check").arg(&path).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(text.len() < 10_000, "{} bytes of summary", text.len());
    let first = text.lines().next().unwrap();
    assert!(first.contains(": Flaggg") && first.contains("g… — valid"), "{first}");
    assert!(text.contains("direction (1e150, 0, 0)"), "{text}");
    assert!(!text.contains('\u{1b}'), "no terminal escape printed raw: {text}");
    assert!(text.contains("Gusts layer \"\\u{1b}[2Jgustsgusts"), "{text}");
    // Validation messages too: not 309 digits for a width of 1e308 m.
    scene.cloth.size.0 = 1e308;
    scene::save(&scene, &path).unwrap();
    let output = drape().arg("check").arg(&path).output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).ends_with(": cloth width 1e308 m is larger than the limit of 1000 m\n"),
        "{}",
        stderr(&output)
    );
}

// ------------------------------------------------- the same refusals as export

#[test]
fn render_refuses_frames_outside_the_timeline_as_export_does() {
    let dir = tempfile::tempdir().unwrap();
    let export =
        run(&["export", "scenes/curtain.ron", "-o", dir.path().join("x.obj").to_str().unwrap(), "--frame", "99999"]);
    let render =
        run(&["render", "scenes/curtain.ron", "-o", dir.path().join("x.png").to_str().unwrap(), "--frame", "99999"]);
    let want = "error: frame 99999 is outside the scene's timeline 0..120: choose frames within it \
                (or lengthen the timeline)\n";
    assert_eq!(stderr(&export), want);
    assert_eq!(stderr(&render), want);
    assert_eq!(render.status.code(), Some(1));
    let render = run(&[
        "render",
        "scenes/curtain.ron",
        "-o",
        dir.path().join("x.gif").to_str().unwrap(),
        "--frames",
        "100..130",
    ]);
    assert!(stderr(&render).starts_with("error: frames 100..130 reach outside the scene's timeline 0..120"));
    assert_eq!(names_in(dir.path()), Vec::<String>::new());
}

#[test]
fn render_refuses_a_sequence_into_missing_parents_as_export_does() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("no/such/frames");
    let export = drape().args(["export", "scenes/curtain.ron", "--frames", "0..2", "-o"]).arg(&out).output().unwrap();
    let render = drape().args(["render", "scenes/curtain.ron", "--frames", "0..2", "-o"]).arg(&out).output().unwrap();
    let want = format!(
        "error: cannot write {}: the directory {} does not exist\n",
        out.display(),
        out.parent().unwrap().display()
    );
    assert_eq!(stderr(&export), want);
    assert_eq!(stderr(&render), want);
    assert_eq!(names_in(dir.path()), Vec::<String>::new(), "no directory was made");
}

// ------------------------------------------------ outputs that lose files

/// Every file in `dir` with its bytes.
fn contents_of(dir: &Path) -> Vec<(String, Vec<u8>)> {
    names_in(dir).into_iter().map(|name| (name.clone(), fs::read(dir.join(&name)).unwrap())).collect()
}

/// A shorter sequence into the folder of a longer one would leave the old
/// frames after the new ones, which a `$F4` loader plays on: refused,
/// naming them, unless --replace-sequence, which removes exactly those.
#[test]
fn a_sequence_never_leaves_an_earlier_one_s_frames_among_its_own() {
    let dir = tempfile::tempdir().unwrap();
    fs::copy(scene_path("curtain.ron"), dir.path().join("curtain.ron")).unwrap();
    let in_dir = |args: &[&str]| drape().args(args).current_dir(dir.path()).output().unwrap();
    let seq = dir.path().join("seq");
    let first = in_dir(&["export", "curtain.ron", "--frames", "0..9", "-o", "seq/"]);
    assert!(first.status.success(), "{}", stderr(&first));
    // The user's files beside the frames, some named much like them.
    for name in ["notes.txt", "curtain_final.obj", "curtain_0004.obj.bak", "other_0005.obj", "curtain_012.obj"] {
        fs::write(seq.join(name), "the user's").unwrap();
    }
    let before = contents_of(&seq);

    let shorter = in_dir(&["export", "curtain.ron", "--frames", "0..3", "-o", "seq/"]);
    assert_eq!(shorter.status.code(), Some(1));
    assert_eq!(
        stderr(&shorter),
        "error: seq/ already holds 6 frames of a curtain_####.obj sequence that the new one does not replace \
         (frames 4–9: curtain_0004.obj … curtain_0009.obj): a loader would play them mixed with the new frames; \
         write the sequence into another folder, or replace the old one with --replace-sequence, which removes \
         exactly those files\n"
    );
    assert!(contents_of(&seq) == before, "nothing written or removed");
    let one_file = in_dir(&["export", "curtain.ron", "-o", "one.usda", "--replace-sequence"]);
    assert_eq!(one_file.status.code(), Some(1));
    assert!(stderr(&one_file).contains("--replace-sequence applies to an OBJ sequence"), "{}", stderr(&one_file));

    let replaced = in_dir(&["export", "curtain.ron", "--frames", "0..3", "-o", "seq/", "--replace-sequence"]);
    assert!(replaced.status.success(), "{}", stderr(&replaced));
    let summary = String::from_utf8_lossy(&replaced.stdout);
    assert!(summary.starts_with("wrote 4 files to seq ("), "{summary}");
    assert!(
        summary.ends_with("\n  removed 6 frames of the earlier sequence: curtain_0004.obj … curtain_0009.obj\n"),
        "{summary}"
    );
    let mut expected: Vec<String> = (0..4).map(|frame| format!("curtain_{frame:04}.obj")).collect();
    expected.extend(
        ["notes.txt", "curtain_final.obj", "curtain_0004.obj.bak", "other_0005.obj", "curtain_012.obj"]
            .map(String::from),
    );
    expected.sort();
    assert_eq!(names_in(&seq), expected);
    for (name, bytes) in &before {
        if !name.starts_with("curtain_00") || name.ends_with(".bak") {
            assert!(fs::read(seq.join(name)).unwrap() == *bytes, "{name} untouched");
        }
    }

    // The same for a PNG sequence.
    let render = |frames: &str, replace: bool| {
        let mut args = vec!["render", "curtain.ron", "--size", "32x24", "--frames", frames, "-o", "pictures"];
        args.extend(replace.then_some("--replace-sequence"));
        in_dir(&args)
    };
    let pictures = dir.path().join("pictures");
    assert!(render("0..4", false).status.success());
    let before = contents_of(&pictures);
    let shorter = render("0..1", false);
    assert_eq!(shorter.status.code(), Some(1));
    assert_eq!(
        stderr(&shorter),
        "error: pictures already holds 3 frames of a curtain_####.png sequence that the new one does not replace \
         (frames 2–4: curtain_0002.png … curtain_0004.png): a loader would play them mixed with the new frames; \
         write the sequence into another folder, or replace the old one with --replace-sequence, which removes \
         exactly those files\n"
    );
    assert!(contents_of(&pictures) == before, "nothing written or removed");
    let replaced = render("0..1", true);
    assert!(replaced.status.success(), "{}", stderr(&replaced));
    let summary = String::from_utf8_lossy(&replaced.stdout);
    assert!(
        summary.ends_with("\n  removed 3 frames of the earlier sequence: curtain_0002.png … curtain_0004.png\n"),
        "{summary}"
    );
    assert_eq!(names_in(&pictures), ["curtain_0000.png", "curtain_0001.png"]);
}

/// An output that is the scene file itself — by name, hard link or
/// symlink, or as a side file or a sequence's frame — is refused, and the
/// scene stays as it was.
#[test]
fn an_export_or_render_never_writes_over_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    let text = fs::read_to_string(scene_path("curtain.ron")).unwrap();
    for scene in ["self.ron", "cache.obj", "look.bin", "shot.png", "seq/s_0001.obj"] {
        fs::create_dir_all(dir.path().join(scene).parent().unwrap()).unwrap();
        fs::write(dir.path().join(scene), &text).unwrap();
    }
    fs::hard_link(dir.path().join("self.ron"), dir.path().join("linked.usda")).unwrap();
    std::os::unix::fs::symlink("self.ron", dir.path().join("pointer.obj")).unwrap();
    std::os::unix::fs::symlink("shot.png", dir.path().join("pointer.png")).unwrap();
    let names = names_in(dir.path());
    for (args, path, input) in [
        (vec!["export", "self.ron", "-o", "self.ron", "--format", "obj"], "self.ron", "self.ron"),
        (vec!["export", "self.ron", "-o", "self.ron", "--format", "pc2"], "self.ron", "self.ron"),
        (vec!["export", "self.ron", "-o", "linked.usda"], "linked.usda", "self.ron"),
        (vec!["export", "self.ron", "-o", "pointer.obj"], "pointer.obj", "self.ron"),
        (vec!["export", "cache.obj", "-o", "cache.pc2"], "cache.obj (the base mesh beside cache.pc2)", "cache.obj"),
        (vec!["export", "look.bin", "-o", "look.gltf"], "look.bin (the buffer beside look.gltf)", "look.bin"),
        (
            vec!["export", "seq/s_0001.obj", "--frames", "0..3", "-o", "seq/s.obj"],
            "seq/s_0001.obj (a frame of the sequence)",
            "seq/s_0001.obj",
        ),
        (vec!["render", "shot.png", "-o", "shot.png"], "shot.png", "shot.png"),
        (vec!["render", "shot.png", "-o", "pointer.png"], "pointer.png", "shot.png"),
    ] {
        let output = drape().args(&args).current_dir(dir.path()).output().unwrap();
        assert_eq!(output.status.code(), Some(1), "{args:?}: {}", stderr(&output));
        assert_eq!(
            stderr(&output),
            format!(
                "error: cannot write {path}: it is the same file on disk as {input}, the scene file, which would be \
                 lost: choose another output\n"
            ),
            "{args:?}"
        );
    }
    assert_eq!(names_in(dir.path()), names, "nothing written beside");
    for scene in ["self.ron", "cache.obj", "look.bin", "shot.png", "seq/s_0001.obj"] {
        assert_eq!(fs::read_to_string(dir.path().join(scene)).unwrap(), text, "{scene} is the scene still");
    }
    assert_eq!(names_in(&dir.path().join("seq")), ["s_0001.obj"]);
}

// ------------------------------------------------- bounds and size estimates

/// The curtain on the largest grid (512 × 512) over the longest timeline
/// (100 001 frames), relaxed for 20 sweeps only.
fn huge_curtain(dir: &Path) -> PathBuf {
    scene_file(dir, "big.ron", |text| {
        assert!(text.contains(CURTAIN_CAP), "curtain.ron's cap is not {CURTAIN_CAP}");
        text.replace("grid: (33, 25)", "grid: (512, 512)")
            .replace("timeline: (fps: 24.0, start: 0, end: 120)", "timeline: (fps: 24.0, start: 0, end: 100000)")
            // A rough rest shape: a second or so, not half a minute.
            .replace(CURTAIN_CAP, "iterations: 20")
    })
}

#[test]
fn an_export_past_the_size_limit_is_refused_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let big = huge_curtain(dir.path());
    let in_dir = |args: &[&str]| drape().args(args).current_dir(dir.path()).output().unwrap();
    let pc2 = in_dir(&["export", "big.ron", "-o", "x.pc2"]);
    assert_eq!(pc2.status.code(), Some(1));
    assert_eq!(
        stderr(&pc2),
        "error: the export (PC2 point cache of 262 144 points × 100 001 frames) would take about 293.0 GiB, \
         more than the 8.0 GiB limit: export fewer frames or a coarser grid, or pass --force to write it anyway\n"
    );
    let sequence = in_dir(&["export", "big.ron", "--frames", "0..100000", "-o", "frames"]);
    assert_eq!(sequence.status.code(), Some(1));
    assert!(
        stderr(&sequence).contains("the export (OBJ sequence of 262 144 points × 100 001 frames) would take about"),
        "{}",
        stderr(&sequence)
    );
    let gif = in_dir(&["render", "big.ron", "-o", "x.gif"]);
    assert_eq!(gif.status.code(), Some(1));
    assert!(
        stderr(&gif).ends_with(
            "(a GIF of 100 001 frames at 640×360, counted at a byte a pixel) would take about 21.6 GiB, more than \
             the 8.0 GiB limit: render fewer frames or smaller pictures, or pass --force to write it anyway\n"
        ),
        "{}",
        stderr(&gif)
    );
    // A PNG sequence is estimated from its first frame, rendered but not written.
    let pngs = in_dir(&["render", "big.ron", "--frames", "0..100000", "--size", "1920x1080", "-o", "frames"]);
    assert_eq!(pngs.status.code(), Some(1));
    let text = stderr(&pngs);
    assert!(text.starts_with("error: the render (a PNG sequence of 100 001 frames at 1920×1080, "), "{text}");
    assert!(text.contains(" each as the first frame is) would take about "), "{text}");
    assert!(text.contains("render fewer frames or smaller pictures, or pass --force"), "{text}");
    assert_eq!(names_in(dir.path()), ["big.ron"], "nothing written, no directory made");

    // A few frames of the same scene are small and go ahead.
    let few = in_dir(&["export", "big.ron", "--frames", "0..1", "-o", "few.pc2"]);
    assert!(few.status.success(), "{}", stderr(&few));
    assert_eq!(fs::metadata(dir.path().join("few.pc2")).unwrap().len(), 32 + 2 * 262_144 * 12);
    fs::remove_file(dir.path().join("few.pc2")).unwrap();
    fs::remove_file(dir.path().join("few.obj")).unwrap();

    // --force goes on: the write starts (then Ctrl+C ends it, leaving nothing).
    let child = start_writing(dir.path(), &["export", big.to_str().unwrap(), "-o", "x.pc2", "--force"]);
    send(&child, libc::SIGINT);
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", stderr(&output));
    assert_eq!(names_in(dir.path()), ["big.ron"]);
}

/// A key with `count` pins on a 65 × 65 cloth (at most 4225), one pin a
/// line, lying near a table top at y = 1 m with small pseudo-random bumps.
fn pinned_scene(dir: &Path, count: usize) -> PathBuf {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) as f64 / (1u64 << 31) as f64
    };
    let mut cells: Vec<(u32, u32)> = (0..65).flat_map(|j| (0..65).map(move |i| (i, j))).collect();
    for k in (1..cells.len()).rev() {
        cells.swap(k, (next() * (k + 1) as f64) as usize % (k + 1));
    }
    let mut text = String::from(
        "(\n    version: 1,\n    name: \"Pins\",\n    cloth: (size: (2.0, 2.0), grid: (65, 65)),\n    \
         timeline: (fps: 24.0, start: 0, end: 48),\n    keys: [\n        (\n            frame: 0,\n            pins: [\n",
    );
    for &(i, j) in cells.iter().cycle().take(count) {
        let (x, z) = (f64::from(i) / 32.0 - 1.0, f64::from(j) / 32.0 - 1.0);
        text +=
            &format!("                (grid: ({i}, {j}), pos: ({x:.4}, {:.4}, {z:.4})),\n", 1.0 + 0.1 * next() - 0.05);
    }
    text += "            ],\n        ),\n    ],\n)\n";
    let path = dir.join(format!("pins_{count}.ron"));
    fs::write(&path, text).unwrap();
    path
}

#[test]
fn too_many_pins_is_a_positioned_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = pinned_scene(dir.path(), 4097);
    let text = fs::read_to_string(&path).unwrap();
    let line = text.lines().position(|l| l.trim_start().starts_with("(grid:")).unwrap() + 4096 + 1;
    let col = text.lines().nth(line - 1).unwrap().find('(').unwrap() + 1;
    let output = drape().arg("check").arg(&path).output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {}:{line}:{col}: key at frame 0 has 4 097 pins; the limit is 4 096 pins per key\n",
            path.display()
        )
    );
}

/// Runs `drape args` with its output thrown away and returns its exit code,
/// its stderr and its peak resident memory in kilobytes (`wait4`'s rusage,
/// the figure `/usr/bin/time -v` prints).
// The child is reaped by `wait4`, which also gives its rusage; `Child::wait`
// afterwards could reap an unrelated process that got the same pid.
#[allow(clippy::zombie_processes)]
fn run_measuring_memory(dir: &Path, args: &[&str]) -> (Option<i32>, String, u64) {
    let errors = dir.join("stderr.txt");
    let child = drape().args(args).stdout(Stdio::null()).stderr(fs::File::create(&errors).unwrap()).spawn().unwrap();
    let mut status = 0;
    // SAFETY: all-zero is a valid rusage, which wait4 then fills in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child, not waited for yet; both pointers are valid.
    let waited = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(waited, child.id() as libc::pid_t, "wait4 failed");
    let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
    let text = fs::read_to_string(&errors).unwrap();
    fs::remove_file(&errors).unwrap();
    (code, text, usage.ru_maxrss as u64)
}

/// A 1000-pin table top is checked and exported well within 1 GB: the
/// approximation is local, so memory does not grow with pins × points.
#[test]
fn a_thousand_pins_stay_within_a_gigabyte() {
    let dir = tempfile::tempdir().unwrap();
    let path = pinned_scene(dir.path(), 1000);
    let path = path.to_str().unwrap();
    let out = dir.path().join("pins.pc2");
    for args in [vec!["check", path], vec!["export", path, "-o", out.to_str().unwrap()]] {
        let (code, errors, peak_kb) = run_measuring_memory(dir.path(), &args);
        assert_eq!(code, Some(0), "{args:?}: {errors}");
        println!("{}: peak memory {} MB", args[0], peak_kb / 1024);
        assert!(peak_kb < 1024 * 1024, "{args:?} peaked at {} MB", peak_kb / 1024);
    }
}

/// What `drape export` says on stderr about a key that did not settle at its cap.
const NOT_SETTLED_WARNING: &str = "drape: warning: the key at frame 0 is NOT settled: ";

/// Progress shows on a terminal only. Piped (as here), stderr stays empty
/// unless a key is slow (`DRAPE_SLOW_KEY_SECS`, 5 s by default: set high
/// here so a loaded machine cannot make this key slow, then 0 so every key
/// is), and then holds one plain line for it; on a pseudo-terminal
/// (`script`), the key's relaxation is shown on one line overwritten in
/// place and erased at the end.
#[test]
fn long_work_shows_progress_on_a_terminal_only() {
    let dir = tempfile::tempdir().unwrap();
    // One key on the largest grid: 50 sweeps take a second or two.
    let path = scene_file(dir.path(), "fine.ron", |text| {
        assert!(text.contains(CURTAIN_CAP), "curtain.ron's cap is not {CURTAIN_CAP}");
        text.replace("grid: (33, 25)", "grid: (512, 512)").replace(CURTAIN_CAP, "iterations: 50")
    });
    let obj = dir.path().join("fine.obj");
    let quiet = || {
        let mut drape = drape();
        drape.env("DRAPE_SLOW_KEY_SECS", "1000000");
        drape
    };
    let piped = quiet().arg("check").arg(&path).output().unwrap();
    assert!(piped.status.success());
    assert_eq!(stderr(&piped), "", "nothing but the result when stderr is not a terminal");
    // Export says which key is not settled (50 sweeps leave it moving), and nothing else.
    let piped = quiet().arg("export").arg(&path).arg("-o").arg(&obj).output().unwrap();
    assert!(piped.status.success());
    let text = stderr(&piped);
    assert!(text.lines().count() == 1 && text.starts_with(NOT_SETTLED_WARNING), "{text:?}");
    for args in
        [vec!["check", path.to_str().unwrap()], vec!["export", path.to_str().unwrap(), "-o", obj.to_str().unwrap()]]
    {
        let piped = drape().env("DRAPE_SLOW_KEY_SECS", "0").args(&args).output().unwrap();
        assert!(piped.status.success());
        let text = stderr(&piped);
        let lines: Vec<&str> = text.lines().filter(|line| !line.starts_with(NOT_SETTLED_WARNING)).collect();
        assert_eq!(lines.len(), 1, "{args:?}: one plain line for the slow key: {text:?}");
        assert!(lines[0].starts_with("drape: key 1/1 (frame 0) is still relaxing after "), "{text:?}");
        assert!(lines[0].contains(" s: sweep "), "{text:?}");
        // The relaxation starts on its coarsest grid, so that is the first grid named.
        assert!(lines[0].contains(" × ") && lines[0].ends_with(" grid") && !text.contains('\r'), "{text:?}");
    }

    if Command::new("script").arg("--version").output().is_err() {
        println!("SKIPPED: no `script` (util-linux) to run drape on a pseudo-terminal");
        eprintln!("SKIPPED: no `script` (util-linux) to run drape on a pseudo-terminal");
        return;
    }
    let binary = std::env::var("DRAPE_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_drape").to_string());
    for command in [
        format!("'{binary}' check '{}'", path.display()),
        format!("'{binary}' export '{}' -o '{}'", path.display(), obj.display()),
    ] {
        let run = Command::new("script").args(["-qfec", &command, "/dev/null"]).output().unwrap();
        let terminal = String::from_utf8_lossy(&run.stdout);
        assert!(run.status.success(), "{command}: {terminal}");
        assert!(terminal.contains("\rapproximating key 1/1 (frame 0) from 2 pins\x1b[K"), "{command}: {terminal:?}");
        assert!(terminal.contains("\rrelaxing key 1/1 (frame 0): sweep "), "{command}: {terminal:?}");
        assert!(terminal.contains(" on the 512 × 512 grid\x1b[K"), "{command}: {terminal:?}");
        assert!(terminal.contains("\r\x1b[K"), "the status line is erased: {terminal:?}");
    }
}

// ------------------------------------------------------- signals and leftovers

/// Drape's temporary files and staging directories in `dir`.
fn temporaries_in(dir: &Path) -> Vec<String> {
    names_in(dir).into_iter().filter(|n| n.starts_with('.') && n.contains(".drape-")).collect()
}

/// Starts `drape` with `args` in `dir` and waits until a temporary file or
/// staging directory of it shows in `dir` with its marker written (the
/// write under way; a process killed between making the directory and
/// writing its marker leaves a directory no later write may prove is
/// Drape's, so the kill waits for the marker).
fn start_writing(dir: &Path, args: &[&str]) -> Child {
    start_writing_with(drape(), dir, args)
}

/// [`start_writing`] with `command` as prepared.
fn start_writing_with(mut command: Command, dir: &Path, args: &[&str]) -> Child {
    let mut child = command.args(args).current_dir(dir).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    let started = Instant::now();
    let marked = |name: &String| fs::metadata(dir.join(name).join(".drape-temporary")).is_ok_and(|m| m.len() > 0);
    while !temporaries_in(dir).iter().any(marked) {
        if let Some(status) = child.try_wait().unwrap() {
            let output = child.wait_with_output().unwrap();
            panic!("drape {args:?} ended ({status}) before it could be interrupted: {}", stderr(&output));
        }
        assert!(started.elapsed() < Duration::from_secs(60), "no temporary file showed up in {}", dir.display());
        std::thread::sleep(Duration::from_millis(2));
    }
    child
}

fn send(child: &Child, signal: libc::c_int) {
    // SAFETY: signals our own child, which has not been reaped yet.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, signal) }, 0);
}

#[test]
fn an_interrupted_export_leaves_nothing_behind() {
    let carpet = scene_path("magic_carpet.ron");
    let carpet = carpet.to_str().unwrap();
    for (args, signal, code) in [
        (vec!["export", carpet, "--frames", "0..120", "-o", "x.usda"], libc::SIGINT, 130),
        (vec!["export", carpet, "--frames", "0..120", "-o", "seq.obj"], libc::SIGTERM, 143),
        (vec!["export", carpet, "--frames", "0..120", "-o", "x.pc2"], libc::SIGINT, 130),
    ] {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("keep.txt"), "an earlier file").unwrap();
        let child = start_writing(dir.path(), &args);
        std::thread::sleep(Duration::from_millis(100));
        send(&child, signal);
        let output = child.wait_with_output().unwrap();
        if output.status.success() {
            // It finished before the signal came: then everything is in place.
            assert!(temporaries_in(dir.path()).is_empty(), "{args:?}: {:?}", names_in(dir.path()));
            println!("note: {args:?} finished before the signal arrived");
            continue;
        }
        assert_eq!(output.status.code(), Some(code), "{args:?}: {} {}", output.status, stderr(&output));
        let names = names_in(dir.path());
        assert!(temporaries_in(dir.path()).is_empty(), "{args:?}: nothing left behind: {names:?}");
        if names == ["keep.txt"] {
            continue;
        }
        // The signal came while the finished file was being moved into place:
        // the clean-up waits for that move, so the output is there, and whole.
        let whole = tempfile::tempdir().unwrap();
        let finished = drape().args(&args).current_dir(whole.path()).output().unwrap();
        assert!(finished.status.success(), "{args:?}: {}", stderr(&finished));
        let mut expected = names_in(whole.path());
        expected.push("keep.txt".to_string());
        expected.sort();
        assert_eq!(names, expected, "{args:?}: only whole outputs are left");
        for name in names.iter().filter(|n| *n != "keep.txt") {
            let (got, want) = (dir.path().join(name), whole.path().join(name));
            if want.is_file() {
                assert!(fs::read(&got).unwrap() == fs::read(&want).unwrap(), "{args:?}: {name} is not whole");
            }
        }
        println!("note: {args:?} was interrupted after its output was in place");
    }
}

#[test]
fn an_interrupted_render_sequence_leaves_the_directory_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    fs::create_dir(&frames).unwrap();
    fs::write(frames.join("curtain_0000.png"), "an earlier frame").unwrap();
    let mut child = drape()
        .args(["render", "scenes/curtain.ron", "--frames", "0..120", "--size", "320x180", "-o"])
        .arg(&frames)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the staging directory, then for a frame or two inside it.
    let started = Instant::now();
    let staged = loop {
        if let Some(staging) = temporaries_in(&frames).first() {
            let staging = frames.join(staging);
            let pngs = fs::read_dir(&staging).map(|d| d.flatten().filter(|e| is_png(&e.file_name())).count());
            if pngs.unwrap_or(0) >= 2 {
                break true;
            }
        }
        if child.try_wait().unwrap().is_some() || started.elapsed() > Duration::from_secs(120) {
            break false;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    send(&child, libc::SIGINT);
    let output = child.wait_with_output().unwrap();
    if !staged {
        panic!("the render never staged two frames: {} {}", output.status, stderr(&output));
    }
    assert_eq!(output.status.code(), Some(130), "{} {}", output.status, stderr(&output));
    assert_eq!(names_in(&frames), ["curtain_0000.png"]);
    assert_eq!(fs::read_to_string(frames.join("curtain_0000.png")).unwrap(), "an earlier frame");
}

fn is_png(name: &std::ffi::OsStr) -> bool {
    name.to_string_lossy().ends_with(".png")
}

/// A process id no process has now: a child that has ended (its id is free
/// until reused, which a fresh id this soon after is not).
fn dead_pid() -> u32 {
    let mut gone = Command::new("true").spawn().unwrap();
    let pid = gone.id();
    gone.wait().unwrap();
    pid
}

/// A killed export's temporary goes with the next write into its folder —
/// also for an output name as long as a name may be, whose temporary's name
/// is cut short to fit — while files and folders that only look like a
/// dead process's temporaries stay: they are the user's.
#[test]
fn a_killed_exports_leftovers_go_with_the_next_write() {
    let dir = tempfile::tempdir().unwrap();
    let carpet = scene_path("magic_carpet.ron");
    let long = "k".repeat(250) + ".usda";
    let child = start_writing(dir.path(), &["export", carpet.to_str().unwrap(), "--frames", "0..120", "-o", &long]);
    send(&child, libc::SIGKILL);
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.signal(), Some(libc::SIGKILL));
    let left = temporaries_in(dir.path());
    assert_eq!(left.len(), 1, "SIGKILL cannot be caught: {left:?}");
    assert!(left[0].len() <= 255 && left[0].starts_with(".kkkk"), "{left:?}");
    // Named like a dead process's temporaries, but not Drape's.
    let dead = dead_pid();
    let notes = format!(".notes.drape-{dead}-0.tmp");
    fs::write(dir.path().join(&notes), "my notes").unwrap();
    let work = format!(".work.drape-{dead}-1.staging");
    fs::create_dir(dir.path().join(&work)).unwrap();
    fs::write(dir.path().join(&work).join("draft.obj"), "my draft").unwrap();
    // A temporary of a live process (ours).
    let live = format!(".other.obj.drape-{}-0.tmp", std::process::id());
    fs::write(dir.path().join(&live), "still being written").unwrap();
    let output = drape().args(["export", "scenes/curtain.ron", "-o"]).arg(dir.path().join("y.obj")).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let mut expected = vec![notes, live, work.clone(), "y.obj".to_string()];
    expected.sort();
    assert_eq!(names_in(dir.path()), expected, "the killed export's leftover is gone, the rest stays");
    assert_eq!(fs::read_to_string(dir.path().join(&work).join("draft.obj")).unwrap(), "my draft");
}

/// Output names up to the 255 bytes a file name may take are written, by
/// every kind of write: one file, a file with its side file, a sequence's
/// frames and a rendered picture.
#[test]
fn an_output_name_as_long_as_a_file_name_may_be_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let in_dir = |args: &[&str]| drape().args(args).current_dir(dir.path()).output().unwrap();
    let usda = "u".repeat(244) + ".usda";
    let pc2 = "c".repeat(251) + ".pc2";
    let frames = "s".repeat(241) + ".obj";
    let png = "p".repeat(251) + ".png";
    let curtain = scene_path("curtain.ron");
    let curtain = curtain.to_str().unwrap();
    for args in [
        vec!["export", curtain, "--frames", "0..2", "-o", &usda],
        vec!["export", curtain, "--frames", "0..2", "-o", &pc2],
        vec!["export", curtain, "--frames", "0..2", "-o", &frames],
        vec!["render", curtain, "--size", "32x24", "-o", &png],
    ] {
        let output = in_dir(&args);
        assert!(output.status.success(), "{:?}: {}", &args[..4], stderr(&output));
    }
    let stem = &frames[..frames.len() - 4];
    let mut expected = vec![usda.clone(), pc2.clone(), "c".repeat(251) + ".obj", png.clone()];
    expected.extend((0..3).map(|frame| format!("{stem}_{frame:04}.obj")));
    expected.sort();
    assert_eq!(names_in(dir.path()), expected);
    assert_eq!(usda.len(), 249);
    assert!([&pc2, &png].iter().all(|name| name.len() == 255));
}

/// A background job (`drape … &` from a script) starts with SIGINT ignored
/// and keeps ignoring it, as POSIX has background processes do; a write
/// past the file-size cap it was started with then fails, said in the
/// error, with nothing left behind.
#[test]
fn drape_started_with_ctrl_c_ignored_keeps_ignoring_it_and_stays_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let big = huge_curtain(dir.path());
    let command = drape_with(16 << 20, libc::SIG_IGN);
    let child = start_writing_with(command, dir.path(), &["export", big.to_str().unwrap(), "-o", "x.usda", "--force"]);
    send(&child, libc::SIGINT);
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(1), "{} {}", output.status, stderr(&output));
    // The rough rest shape (20 sweeps) is not settled, and says so first.
    let text = stderr(&output);
    let lines: Vec<&str> = text.lines().filter(|line| !line.starts_with(NOT_SETTLED_WARNING)).collect();
    assert_eq!(lines, ["error: cannot write x.usda: File too large"], "{text:?}");
    assert_eq!(names_in(dir.path()), ["big.ron"]);
}

/// A mesh collider whose file is missing or broken stops every command with
/// the scene's line and column and the reason, exit 1, and nothing written.
#[test]
fn a_missing_or_broken_mesh_file_stops_every_command_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (fixture, why) in [
        ("collider_mesh_missing.ron", "there is no such file"),
        ("collider_mesh_broken.ron", "not a readable OBJ file"),
    ] {
        let scene = format!("tests/data/malformed/{fixture}");
        let out = dir.path().join("out.pc2");
        let picture = dir.path().join("out.png");
        for args in [
            vec!["check", scene.as_str()],
            vec!["export", scene.as_str(), "-o", out.to_str().unwrap()],
            vec!["render", scene.as_str(), "-o", picture.to_str().unwrap()],
        ] {
            let output = run(&args);
            assert_eq!(output.status.code(), Some(1), "{args:?}: {}", stderr(&output));
            let message = stderr(&output);
            assert!(message.contains(&format!("{scene}:9:36: Mesh collider \"chair\"")), "{args:?}: {message}");
            assert!(message.contains(why), "{args:?}: {message}");
        }
        assert!(names_in(dir.path()).is_empty(), "nothing written: {:?}", names_in(dir.path()));
    }
}
