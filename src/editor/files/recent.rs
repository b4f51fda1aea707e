//! The "Open Recent" list: the scenes the user opened or saved last, newest
//! first, kept in a small text file in the user's config directory so the list
//! survives restarts.
//!
//! The file holds one absolute path per line. It is only a convenience: a
//! missing, unreadable or corrupt file gives an empty list rather than an
//! error, and every save rewrites it whole and atomically.

use std::ffi::OsString;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::atomic_file::write_atomically;

/// How many paths the list keeps; pushing more drops the oldest.
pub const MAX_RECENT_FILES: usize = 10;

/// Largest list file read: ten paths of Linux's longest (4096 bytes) with room
/// to spare. A larger file is not a list Drape wrote and reads as empty.
pub const MAX_RECENT_FILE_BYTES: u64 = 64 * 1024;

/// The list's file name inside [`default_config_dir`].
pub const RECENT_FILES_NAME: &str = "recent-files.txt";

/// Overrides the config directory (tests, CI, portable installs).
pub const CONFIG_DIR_ENV: &str = "DRAPE_CONFIG_DIR";

/// Recently opened or saved scene files, newest first, without duplicates,
/// at most [`MAX_RECENT_FILES`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecentFiles {
    /// Where [`RecentFiles::save`] writes the list.
    config_file: PathBuf,
    paths: Vec<PathBuf>,
}

impl RecentFiles {
    /// Reads the list from `config_file`. A missing or unreadable file, one
    /// over [`MAX_RECENT_FILE_BYTES`] (not read beyond that), or one that is
    /// not a list of paths (it holds NUL bytes), gives an empty list;
    /// lines that are not absolute paths are skipped. Never fails.
    pub fn load(config_file: &Path) -> RecentFiles {
        let mut recent = RecentFiles { config_file: config_file.to_owned(), paths: Vec::new() };
        let Ok(bytes) = crate::scene::read_capped(config_file, MAX_RECENT_FILE_BYTES) else {
            return recent;
        };
        if bytes.contains(&0) {
            return recent;
        }
        for line in bytes.split(|&b| b == b'\n') {
            let line = line.strip_suffix(b"\r").unwrap_or(line);
            if let Some(path) = path_from_bytes(line)
                && path.is_absolute()
                && !recent.paths.contains(&path)
                && recent.paths.len() < MAX_RECENT_FILES
            {
                recent.paths.push(path);
            }
        }
        recent
    }

    /// The file [`RecentFiles::save`] writes to.
    pub fn config_file(&self) -> &Path {
        &self.config_file
    }

    /// The paths, newest first.
    pub fn paths(&self) -> &[PathBuf] {
        &self.paths
    }

    /// Puts `path` at the front. The path is made absolute and, when the file
    /// exists, canonical (symlinks and `..` resolved), so one file reached two
    /// ways is listed once. An earlier entry for it moves to the front; the
    /// oldest entry beyond [`MAX_RECENT_FILES`] is dropped. A path with a line
    /// break cannot be stored one per line and is ignored.
    pub fn push(&mut self, path: &Path) {
        let Some(path) = normalize(path) else {
            return;
        };
        if path.as_os_str().as_encoded_bytes().iter().any(|&b| b == b'\n' || b == b'\r') {
            return;
        }
        self.paths.retain(|p| *p != path);
        self.paths.insert(0, path);
        self.paths.truncate(MAX_RECENT_FILES);
    }

    /// Removes `path` (compared after the same normalisation as
    /// [`RecentFiles::push`]), e.g. when opening it failed. Returns whether it
    /// was listed.
    pub fn remove(&mut self, path: &Path) -> bool {
        let normalized = normalize(path);
        let before = self.paths.len();
        self.paths.retain(|p| p != path && Some(p) != normalized.as_ref());
        self.paths.len() != before
    }

    /// Writes the list to its file atomically, creating the directory.
    pub fn save(&self) -> io::Result<()> {
        if let Some(dir) = self.config_file.parent()
            && !dir.as_os_str().is_empty()
        {
            fs::create_dir_all(dir)?;
        }
        write_atomically(&self.config_file, |w| {
            for path in &self.paths {
                w.write_all(&path_to_bytes(path))?;
                w.write_all(b"\n")?;
            }
            Ok(())
        })
    }
}

/// Drape's config directory: `$DRAPE_CONFIG_DIR` when set, else
/// `$XDG_CONFIG_HOME/drape`, else `$HOME/.config/drape`; `None` when none of
/// them is set. Empty variables count as unset, and `XDG_CONFIG_HOME` must be
/// absolute (the XDG spec says to ignore a relative one).
pub fn default_config_dir() -> Option<PathBuf> {
    config_dir_from(|name| std::env::var_os(name))
}

/// [`default_config_dir`] with the environment passed in, so it can be tested
/// without changing the process environment.
fn config_dir_from(env: impl Fn(&str) -> Option<OsString>) -> Option<PathBuf> {
    xdg_dir(env, CONFIG_DIR_ENV, "XDG_CONFIG_HOME", ".config")
}

/// The lookup shared by the config and state directories: an override
/// variable, then the XDG variable + `drape`, then `$HOME/<home_relative>/drape`.
pub(crate) fn xdg_dir(
    env: impl Fn(&str) -> Option<OsString>,
    override_var: &str,
    xdg_var: &str,
    home_relative: &str,
) -> Option<PathBuf> {
    let set = |name: &str| env(name).filter(|value| !value.is_empty()).map(PathBuf::from);
    if let Some(dir) = set(override_var) {
        return Some(dir);
    }
    if let Some(dir) = set(xdg_var).filter(|dir| dir.is_absolute()) {
        return Some(dir.join("drape"));
    }
    set("HOME").map(|home| home.join(home_relative).join("drape"))
}

/// Absolute and, when possible, canonical; `None` only when the current
/// directory is needed and unknown.
fn normalize(path: &Path) -> Option<PathBuf> {
    fs::canonicalize(path).ok().or_else(|| std::path::absolute(path).ok())
}

#[cfg(unix)]
fn path_from_bytes(bytes: &[u8]) -> Option<PathBuf> {
    use std::os::unix::ffi::OsStrExt;
    (!bytes.is_empty()).then(|| PathBuf::from(std::ffi::OsStr::from_bytes(bytes)))
}

#[cfg(unix)]
fn path_to_bytes(path: &Path) -> Vec<u8> {
    use std::os::unix::ffi::OsStrExt;
    path.as_os_str().as_bytes().to_vec()
}

// Elsewhere paths are written as UTF-8; a line that is not UTF-8 is skipped.
#[cfg(not(unix))]
fn path_from_bytes(bytes: &[u8]) -> Option<PathBuf> {
    std::str::from_utf8(bytes).ok().filter(|s| !s.is_empty()).map(PathBuf::from)
}

#[cfg(not(unix))]
fn path_to_bytes(path: &Path) -> Vec<u8> {
    path.to_string_lossy().into_owned().into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(dir: &Path, name: &str) -> PathBuf {
        let path = dir.join(name);
        fs::write(&path, "").unwrap();
        fs::canonicalize(path).unwrap()
    }

    #[test]
    fn a_missing_file_gives_an_empty_list() {
        let dir = tempfile::tempdir().unwrap();
        let recent = RecentFiles::load(&dir.path().join("nothing-here.txt"));
        assert!(recent.paths().is_empty());
        // A directory where the file should be is unreadable as a file: also empty.
        assert!(RecentFiles::load(dir.path()).paths().is_empty());
    }

    #[test]
    fn a_corrupt_file_gives_an_empty_list_or_only_its_good_lines() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("recent.txt");
        fs::write(&file, b"\x00\x01\xffgarbage\x00\n/tmp/a.ron\n").unwrap();
        assert!(RecentFiles::load(&file).paths().is_empty());

        fs::write(&file, "relative/path.ron\n\n/abs/one.ron\r\n/abs/one.ron\n   \n/abs/two.ron").unwrap();
        let recent = RecentFiles::load(&file);
        assert_eq!(recent.paths(), [PathBuf::from("/abs/one.ron"), PathBuf::from("/abs/two.ron")]);
    }

    #[test]
    fn an_endless_file_reads_as_an_empty_list() {
        assert!(RecentFiles::load(Path::new("/dev/zero")).paths().is_empty());
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("recent.txt");
        let mut text = "/abs/one.ron\n".to_string();
        text.push_str(&"/".repeat(MAX_RECENT_FILE_BYTES as usize));
        fs::write(&file, text).unwrap();
        assert!(RecentFiles::load(&file).paths().is_empty());
    }

    #[test]
    fn push_moves_to_the_front_dedupes_and_caps() {
        let dir = tempfile::tempdir().unwrap();
        let mut recent = RecentFiles::load(&dir.path().join("recent.txt"));
        let files: Vec<PathBuf> = (0..12).map(|i| touch(dir.path(), &format!("s{i}.ron"))).collect();
        for file in &files {
            recent.push(file);
        }
        assert_eq!(recent.paths().len(), MAX_RECENT_FILES);
        assert_eq!(recent.paths()[0], files[11]);
        assert_eq!(recent.paths()[9], files[2]);

        // The same file reached through `..` is one entry, moved to the front.
        let roundabout = dir.path().join("sub/../s5.ron");
        fs::create_dir(dir.path().join("sub")).unwrap();
        recent.push(&roundabout);
        assert_eq!(recent.paths()[0], files[5]);
        assert_eq!(recent.paths().len(), MAX_RECENT_FILES);
        assert_eq!(recent.paths().iter().filter(|p| **p == files[5]).count(), 1);
    }

    #[test]
    fn push_makes_relative_paths_absolute_even_for_missing_files() {
        let mut recent = RecentFiles::load(Path::new("/nonexistent/recent.txt"));
        recent.push(Path::new("not-yet-saved.ron"));
        assert!(recent.paths()[0].is_absolute());
        assert!(recent.paths()[0].ends_with("not-yet-saved.ron"));
        recent.push(Path::new("/tmp/line\nbreak.ron"));
        assert_eq!(recent.paths().len(), 1, "a path with a line break is not stored");
    }

    #[test]
    fn remove_takes_the_path_out() {
        let dir = tempfile::tempdir().unwrap();
        let mut recent = RecentFiles::load(&dir.path().join("recent.txt"));
        let (a, b) = (touch(dir.path(), "a.ron"), touch(dir.path(), "b.ron"));
        recent.push(&a);
        recent.push(&b);
        assert!(recent.remove(&a));
        assert!(!recent.remove(&a));
        assert_eq!(recent.paths(), std::slice::from_ref(&b));
        // A file deleted since it was listed can still be removed by its listed path.
        fs::remove_file(&b).unwrap();
        assert!(recent.remove(&b));
        assert!(recent.paths().is_empty());
    }

    #[test]
    fn save_then_load_round_trips_and_creates_the_directory() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("config/drape/recent.txt");
        let mut recent = RecentFiles::load(&file);
        let files: Vec<PathBuf> = ["x.ron", "y y.ron", "ünï.ron"].iter().map(|n| touch(dir.path(), n)).collect();
        for file in &files {
            recent.push(file);
        }
        recent.save().unwrap();
        let loaded = RecentFiles::load(&file);
        assert_eq!(loaded, recent);
        assert_eq!(loaded.paths()[0], files[2]);
        assert_eq!(loaded.config_file(), file);
    }

    #[test]
    fn the_config_dir_follows_the_override_then_xdg_then_home() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| vars.iter().find(|(k, _)| *k == name).map(|(_, v)| OsString::from(v))
        };
        const ALL: &[(&str, &str)] =
            &[("DRAPE_CONFIG_DIR", "/ci/cfg"), ("XDG_CONFIG_HOME", "/xdg"), ("HOME", "/home/me")];
        assert_eq!(config_dir_from(env(ALL)), Some(PathBuf::from("/ci/cfg")));
        const NO_OVERRIDE: &[(&str, &str)] =
            &[("DRAPE_CONFIG_DIR", ""), ("XDG_CONFIG_HOME", "/xdg"), ("HOME", "/home/me")];
        assert_eq!(config_dir_from(env(NO_OVERRIDE)), Some(PathBuf::from("/xdg/drape")));
        const RELATIVE_XDG: &[(&str, &str)] = &[("XDG_CONFIG_HOME", "rel"), ("HOME", "/home/me")];
        assert_eq!(config_dir_from(env(RELATIVE_XDG)), Some(PathBuf::from("/home/me/.config/drape")));
        assert_eq!(config_dir_from(env(&[])), None);
    }
}
