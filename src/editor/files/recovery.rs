//! Crash recovery: while a scene has unsaved changes the editor writes it to a
//! recovery file every little while ([`AutosaveClock`] says when), and deletes
//! the file on a clean save or a clean exit. A recovery file found at start-up
//! therefore means the last session ended without saving, and the editor offers
//! to restore it ([`Recovery::read`], [`RecoveredScene::describe`]).
//!
//! The layout is one file, `recovery.ron`, in the state directory: a few
//! `//` comment lines naming the original file and the time, then the scene as
//! [`crate::scene::to_ron_string`] writes it. One file written atomically can
//! never pair a scene with another scene's metadata, and being a valid scene
//! file it can also be opened by hand.
//!
//! One recovery file serves the whole user: two editors running at once
//! overwrite each other's recovery file.

use std::ffi::OsString;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use crate::atomic_file::write_atomically;
use crate::scene::{MAX_SCENE_FILE_BYTES, Scene, SceneError, parse_bytes, read_capped, to_ron_string};

/// The recovery file's name inside the state directory.
pub const RECOVERY_FILE_NAME: &str = "recovery.ron";

/// Overrides the state directory (tests, CI, portable installs).
pub const STATE_DIR_ENV: &str = "DRAPE_STATE_DIR";

/// Largest recovery file [`Recovery::read`] reads: a scene file's limit
/// plus room for the header lines (the original path, the time).
pub const MAX_RECOVERY_FILE_BYTES: u64 = MAX_SCENE_FILE_BYTES + 64 * 1024;

/// How often a dirty scene is written to the recovery file by default.
pub const DEFAULT_AUTOSAVE_INTERVAL: Duration = Duration::from_secs(30);

const HEADER_FIRST_LINE: &str = "// Drape recovery file: unsaved changes kept by the editor's autosave.";
const ORIGINAL_PREFIX: &str = "// original: ";
const SAVED_AT_PREFIX: &str = "// saved at (unix seconds): ";

/// Drape's state directory: `$DRAPE_STATE_DIR` when set, else
/// `$XDG_STATE_HOME/drape`, else `$HOME/.local/state/drape`; `None` when none
/// of them is set. Empty variables count as unset; a relative
/// `XDG_STATE_HOME` is ignored, as the XDG spec says.
pub fn default_state_dir() -> Option<PathBuf> {
    state_dir_from(|name| std::env::var_os(name))
}

fn state_dir_from(env: impl Fn(&str) -> Option<OsString>) -> Option<PathBuf> {
    super::recent::xdg_dir(env, STATE_DIR_ENV, "XDG_STATE_HOME", ".local/state")
}

/// The recovery file in one directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Recovery {
    dir: PathBuf,
}

/// A scene read back from the recovery file.
#[derive(Clone, Debug, PartialEq)]
pub struct RecoveredScene {
    pub scene: Scene,
    /// The file the scene was opened from or last saved to; `None` for a scene never saved.
    pub original: Option<PathBuf>,
    /// When the recovery file was written.
    pub saved_at: SystemTime,
}

impl Recovery {
    /// The recovery file lives in `dir`, which is created on the first write.
    pub fn new(dir: impl Into<PathBuf>) -> Recovery {
        Recovery { dir: dir.into() }
    }

    /// The directory given to [`Recovery::new`].
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The recovery file's path.
    pub fn file(&self) -> PathBuf {
        self.dir.join(RECOVERY_FILE_NAME)
    }

    /// Writes `scene` to the recovery file atomically (replacing an older one),
    /// noting `original`, the file the scene belongs to (made absolute), and
    /// the current time. Creates the directory when needed.
    pub fn write(&self, scene: &Scene, original: Option<&Path>) -> Result<(), SceneError> {
        self.write_at(scene, original, SystemTime::now())
    }

    fn write_at(&self, scene: &Scene, original: Option<&Path>, saved_at: SystemTime) -> Result<(), SceneError> {
        let path = self.file();
        let write_error = |source| SceneError::Write { path: path.clone(), source };
        fs::create_dir_all(&self.dir).map_err(write_error)?;
        let mut text = format!("{HEADER_FIRST_LINE}\n");
        // A RON string literal escapes quotes and line breaks; a path that is
        // not UTF-8 cannot be written as one and is left out.
        // Absolute, so the restore offer still finds it from another working directory.
        let original = original.map(|path| std::path::absolute(path).unwrap_or_else(|_| path.to_owned()));
        if let Some(original) = original.as_deref().and_then(Path::to_str)
            && let Ok(quoted) = ron::to_string(original)
        {
            text.push_str(&format!("{ORIGINAL_PREFIX}{quoted}\n"));
        }
        let secs = saved_at.duration_since(SystemTime::UNIX_EPOCH).unwrap_or_default().as_secs_f64();
        text.push_str(&format!("{SAVED_AT_PREFIX}{secs:.3}\n"));
        text.push_str(&to_ron_string(scene));
        write_atomically(&path, |w| w.write_all(text.as_bytes())).map_err(write_error)
    }

    /// The recovery file's scene, if there is a file: `None` when there is
    /// none; `Some(Err(..))` when it cannot be read, is larger than
    /// [`MAX_RECOVERY_FILE_BYTES`] (nothing beyond that is read) or is not a
    /// valid scene (the message names the file, line and column). Missing or unreadable
    /// header lines only lose the original path (`None`) or the time (the
    /// file's modification time instead). Never panics.
    pub fn read(&self) -> Option<Result<RecoveredScene, SceneError>> {
        let path = self.file();
        let bytes = match read_capped(&path, MAX_RECOVERY_FILE_BYTES) {
            Ok(bytes) => bytes,
            Err(SceneError::Read { source, .. }) if source.kind() == io::ErrorKind::NotFound => return None,
            Err(error) => return Some(Err(error)),
        };
        Some(self.parse_recovered(&path, &bytes))
    }

    fn parse_recovered(&self, path: &Path, bytes: &[u8]) -> Result<RecoveredScene, SceneError> {
        let mut scene = parse_bytes(bytes, &path.display().to_string())?;
        // The bytes are UTF-8: `parse_bytes` checked.
        let text = String::from_utf8_lossy(bytes);
        let header = text.lines().take_while(|line| line.starts_with("//"));
        let (mut original, mut saved_at) = (None, None);
        for line in header {
            if let Some(quoted) = line.strip_prefix(ORIGINAL_PREFIX) {
                original = ron::from_str::<String>(quoted).ok().map(PathBuf::from);
            } else if let Some(secs) = line.strip_prefix(SAVED_AT_PREFIX) {
                saved_at = secs
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .and_then(|secs| Duration::try_from_secs_f64(secs).ok())
                    .and_then(|since_epoch| SystemTime::UNIX_EPOCH.checked_add(since_epoch));
            }
        }
        let saved_at =
            saved_at.or_else(|| fs::metadata(path).and_then(|m| m.modified()).ok()).unwrap_or(SystemTime::UNIX_EPOCH);
        // Mesh and reference files are named relative to the original scene file (absolute in an unsaved one).
        let scene_file = original.clone().unwrap_or_else(|| PathBuf::from("untitled.ron"));
        crate::scene::read_meshes(&mut scene, &scene_file, &text)?;
        crate::scene::read_references(&mut scene, &scene_file, &text)?;
        Ok(RecoveredScene { scene, original, saved_at })
    }

    /// Deletes the recovery file (after a clean save or exit, or once the user
    /// restored or declined it). No file is not an error.
    pub fn clear(&self) -> io::Result<()> {
        match fs::remove_file(self.file()) {
            Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(()),
            result => result,
        }
    }
}

impl RecoveredScene {
    /// The restore offer's sentence, e.g. `Unsaved changes to tent.ron from 12
    /// minutes ago` or `Unsaved changes to an untitled scene from 2 hours ago`,
    /// with the age measured at `now`. Relative times need no time zone.
    pub fn describe(&self, now: SystemTime) -> String {
        let what = match self.original.as_deref().and_then(Path::file_name) {
            Some(name) => name.to_string_lossy().into_owned(),
            None => "an untitled scene".to_owned(),
        };
        let age = now.duration_since(self.saved_at).unwrap_or_default();
        format!("Unsaved changes to {what} from {}", describe_age(age))
    }
}

/// `just now`, `40 seconds ago`, `1 minute ago`, `5 hours ago`, `3 days ago`:
/// seconds too, since autosave runs every 30 s and "just now" would hide
/// that the file is older than the last edit.
fn describe_age(age: Duration) -> String {
    let secs = age.as_secs();
    let (count, unit) = match secs {
        0..2 => return "just now".to_owned(),
        2..60 => (secs, "second"),
        60..3_600 => (secs / 60, "minute"),
        3_600..86_400 => (secs / 3_600, "hour"),
        _ => (secs / 86_400, "day"),
    };
    format!("{count} {unit}{} ago", if count == 1 { "" } else { "s" })
}

/// Decides when to autosave: a scene with unsaved changes is written once
/// `interval` has passed since it was last clean or last autosaved, so an edit
/// is on disk at most `interval` later and an idle editor writes nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AutosaveClock {
    pub interval: Duration,
    /// The last autosave, or the last time the scene was seen clean.
    last: Instant,
}

impl AutosaveClock {
    pub fn new(interval: Duration, now: Instant) -> AutosaveClock {
        AutosaveClock { interval, last: now }
    }

    /// Whether to autosave now. Call it every frame with whether the scene has
    /// unsaved changes; it returns true at most once per `interval` and only
    /// while `dirty`, and restarts the interval when it does.
    pub fn due(&mut self, now: Instant, dirty: bool) -> bool {
        if !dirty {
            self.last = now;
            return false;
        }
        if now.saturating_duration_since(self.last) >= self.interval {
            self.last = now;
            return true;
        }
        false
    }

    /// Restarts the interval, e.g. after the user saved.
    pub fn reset(&mut self, now: Instant) {
        self.last = now;
    }

    /// How long until the next autosave if the scene stays dirty: for
    /// `egui::Context::request_repaint_after`, so an idle editor still
    /// autosaves on time.
    pub fn time_until_due(&self, now: Instant) -> Duration {
        self.interval.saturating_sub(now.saturating_duration_since(self.last))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse;

    const TENT: &str = include_str!("../../../scenes/tent.ron");

    fn tent() -> Scene {
        parse(TENT, "tent.ron").unwrap()
    }

    #[test]
    fn no_file_reads_as_none() {
        let dir = tempfile::tempdir().unwrap();
        assert!(Recovery::new(dir.path().join("not/yet")).read().is_none());
    }

    #[test]
    fn write_then_read_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let recovery = Recovery::new(dir.path().join("state/drape"));
        let mut scene = tent();
        scene.name = "Tent, edited".to_owned();
        let original = Path::new("/home/me/scenes/tent \"v2\".ron");
        let before = SystemTime::now() - Duration::from_secs(1);
        recovery.write(&scene, Some(original)).unwrap();
        let recovered = recovery.read().unwrap().unwrap();
        assert_eq!(recovered.scene, scene);
        assert_eq!(recovered.original.as_deref(), Some(original));
        assert!(recovered.saved_at >= before && recovered.saved_at <= SystemTime::now());

        // The file is itself a valid scene file.
        assert_eq!(crate::scene::load(&recovery.file()).unwrap(), scene);

        // A newer write replaces the older one, here for an untitled scene.
        recovery.write(&tent(), None).unwrap();
        let recovered = recovery.read().unwrap().unwrap();
        assert_eq!((recovered.scene, recovered.original), (tent(), None));

        recovery.write(&tent(), Some(Path::new("relative/tent.ron"))).unwrap();
        let original = recovery.read().unwrap().unwrap().original.unwrap();
        assert_eq!(original, std::env::current_dir().unwrap().join("relative/tent.ron"));
    }

    #[test]
    fn clear_removes_the_file_and_tolerates_none() {
        let dir = tempfile::tempdir().unwrap();
        let recovery = Recovery::new(dir.path());
        recovery.write(&tent(), None).unwrap();
        assert!(recovery.file().exists());
        recovery.clear().unwrap();
        assert!(!recovery.file().exists());
        assert!(recovery.read().is_none());
        recovery.clear().unwrap();
    }

    #[test]
    fn a_corrupt_file_is_reported_with_its_place() {
        let dir = tempfile::tempdir().unwrap();
        let recovery = Recovery::new(dir.path());
        fs::write(recovery.file(), "// original: \"/x/tent.ron\"\n(version: 1, cloth: ").unwrap();
        let error = recovery.read().unwrap().unwrap_err();
        let message = error.to_string();
        assert!(message.starts_with(&format!("{}:2:", recovery.file().display())), "{message}");

        fs::write(recovery.file(), b"\xff\xfe\x00").unwrap();
        assert!(recovery.read().unwrap().unwrap_err().to_string().contains("not UTF-8"));
    }

    #[test]
    fn an_oversized_file_is_refused_without_reading_it_whole() {
        let dir = tempfile::tempdir().unwrap();
        let recovery = Recovery::new(dir.path());
        // Sparse: a file that says it is larger than the limit, without filling the disk.
        fs::File::create(recovery.file()).unwrap().set_len(MAX_RECOVERY_FILE_BYTES + 1).unwrap();
        let error = recovery.read().unwrap().unwrap_err();
        assert!(matches!(error, SceneError::TooLarge { .. }), "{error}");
        assert!(error.to_string().ends_with("recovery.ron is too large for a scene file: over 64 MiB"), "{error}");
    }

    #[test]
    fn a_damaged_header_loses_only_the_metadata() {
        let dir = tempfile::tempdir().unwrap();
        let recovery = Recovery::new(dir.path());
        let text = format!("{ORIGINAL_PREFIX}\"unterminated\n{SAVED_AT_PREFIX}soon\n{TENT}");
        fs::write(recovery.file(), text).unwrap();
        let recovered = recovery.read().unwrap().unwrap();
        assert_eq!((recovered.scene, recovered.original), (tent(), None));
        let modified = fs::metadata(recovery.file()).unwrap().modified().unwrap();
        assert_eq!(recovered.saved_at, modified);
    }

    #[test]
    fn an_unwritable_directory_is_a_write_error() {
        let dir = tempfile::tempdir().unwrap();
        let blocker = dir.path().join("file-not-dir");
        fs::write(&blocker, "").unwrap();
        let error = Recovery::new(&blocker).write(&tent(), None).unwrap_err();
        assert!(matches!(error, SceneError::Write { .. }), "{error}");
    }

    #[test]
    fn describe_names_the_file_and_the_age() {
        let saved_at = SystemTime::UNIX_EPOCH + Duration::from_secs(1_000_000);
        let recovered = RecoveredScene { scene: tent(), original: Some("/s/tent.ron".into()), saved_at };
        let after = |secs| saved_at + Duration::from_secs(secs);
        assert_eq!(recovered.describe(after(1)), "Unsaved changes to tent.ron from just now");
        assert_eq!(recovered.describe(after(40)), "Unsaved changes to tent.ron from 40 seconds ago");
        assert_eq!(recovered.describe(after(60)), "Unsaved changes to tent.ron from 1 minute ago");
        assert_eq!(recovered.describe(after(12 * 60 + 30)), "Unsaved changes to tent.ron from 12 minutes ago");
        assert_eq!(recovered.describe(after(2 * 3_600)), "Unsaved changes to tent.ron from 2 hours ago");
        assert_eq!(recovered.describe(after(3 * 86_400)), "Unsaved changes to tent.ron from 3 days ago");
        let untitled = RecoveredScene { original: None, ..recovered };
        // A clock that went backwards reads as "just now", not a panic.
        assert_eq!(
            untitled.describe(saved_at - Duration::from_secs(9)),
            "Unsaved changes to an untitled scene from just now"
        );
    }

    #[test]
    fn the_autosave_clock_waits_an_interval_after_the_first_unsaved_change() {
        let start = Instant::now();
        let at = |secs| start + Duration::from_secs(secs);
        let mut clock = AutosaveClock::new(Duration::from_secs(30), start);
        assert!(!clock.due(at(100), false), "clean scenes are never autosaved");
        assert!(!clock.due(at(110), true), "10 s after the change");
        assert_eq!(clock.time_until_due(at(110)), Duration::from_secs(20));
        assert!(clock.due(at(130), true));
        assert!(!clock.due(at(131), true), "at most once per interval");
        assert!(clock.due(at(160), true));
        clock.reset(at(170));
        assert!(!clock.due(at(199), true));
        assert!(clock.due(at(200), true));
        assert_eq!(clock.time_until_due(at(500)), Duration::ZERO);
    }

    #[test]
    fn the_state_dir_follows_the_override_then_xdg_then_home() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| vars.iter().find(|(k, _)| *k == name).map(|(_, v)| OsString::from(v))
        };
        const ALL: &[(&str, &str)] =
            &[("DRAPE_STATE_DIR", "/ci/state"), ("XDG_STATE_HOME", "/xdg"), ("HOME", "/home/me")];
        assert_eq!(state_dir_from(env(ALL)), Some(PathBuf::from("/ci/state")));
        assert_eq!(state_dir_from(env(&[("XDG_STATE_HOME", "/xdg")])), Some(PathBuf::from("/xdg/drape")));
        assert_eq!(state_dir_from(env(&[("HOME", "/home/me")])), Some(PathBuf::from("/home/me/.local/state/drape")));
        assert_eq!(state_dir_from(env(&[])), None);
    }
}
