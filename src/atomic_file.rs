//! Safe file writes: readers see the finished new file or the old one, never
//! a partial one, and nothing Drape leaves behind outlives it. Used by scene
//! saves, every exporter and the renderer.
//!
//! - [`write_atomically`] writes one file through a temporary file beside it
//!   that is renamed over the target when complete. A symlink is followed and
//!   its target replaced (the link stays a link); a device or FIFO is written
//!   straight into, never replaced.
//! - [`StagedFiles`] writes a set of files (a frame sequence) into a hidden
//!   staging directory and moves them into place together.
//! - Temporaries are registered while they exist:
//!   [`remove_temporaries_on_signals`] removes them on SIGINT, SIGTERM or
//!   SIGHUP before the process exits, and the first write into a directory
//!   removes those a Drape process that is no longer running left there
//!   (killed with SIGKILL, or a crash).
//!
//! Every temporary is a hidden directory, `.NAME.drape-PID-N.tmp` holding
//! one file on its way to NAME, or `.NAME.drape-PID-N.staging` holding a
//! sequence, PID being the writing process and N a counter. NAME is cut
//! short (on a character boundary) so the whole name fits the 255 bytes a
//! file name may take. Its first file is a marker naming the process and
//! the directory's own device and inode: the clean-up of dead processes'
//! temporaries removes a directory only when its name has exactly that form
//! and its marker matches, so a user's file or folder of a similar name,
//! or a copy of a temporary, is never touched.

use std::collections::HashSet;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Most symlinks followed from an output path to the file it names (Linux's own limit).
const MAX_SYMLINK_HOPS: usize = 40;

/// Streams `write` into `path` so that a reader never sees a partial file.
///
/// - A regular file, or no file yet: `write` goes into a temporary file beside
///   it, which is fsynced and renamed over `path`, keeping an existing file's
///   permissions. On any error (or a panic in `write`) the temporary file is
///   removed and an existing `path` is left untouched.
/// - A symlink: followed (through any number of links, up to 40) and the file
///   it points to is replaced as above; the link stays as it was. A dangling
///   link gets its target created.
/// - A character or block device or a FIFO (`/dev/null`, a named pipe): `write`
///   streams straight into it; it is never replaced. Opening a FIFO waits
///   for a reader, as any program writing to it would.
/// - A directory or a socket: an error, and nothing is written.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let file = write_pending(path, write)?;
    if file.temp.is_none() {
        // A device or FIFO, already written; staged companions wait for a file.
        return Ok(());
    }
    // Files waiting to appear with this one move in under the same hold of
    // the registry, so a signal's clean-up sees all of them or none in place.
    let companions = COMPANIONS.with(|c| std::mem::take(&mut *c.borrow_mut()));
    file.commit_with(companions)
}

thread_local! {
    /// Files written by [`write_pending`] and staged with [`stage_companion`]:
    /// the next [`write_atomically`] on this thread moves them into place with
    /// its own file.
    static COMPANIONS: std::cell::RefCell<Vec<PendingFile>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A file written and synced beside its destination, not yet in place;
/// dropped, it is removed.
pub struct PendingFile {
    /// `None` when the destination was a device or FIFO, written straight away.
    temp: Option<Temporary>,
    target: PathBuf,
}

impl PendingFile {
    /// Moves the file into place.
    pub fn commit(self) -> io::Result<()> {
        self.commit_with(Vec::new())
    }

    /// Moves the file, then `companions`, into place under one hold of the
    /// registry (a signal's clean-up waits for all of them).
    fn commit_with(self, companions: Vec<PendingFile>) -> io::Result<()> {
        let dir = parent_dir(&self.target).to_path_buf();
        let mut registry = registry();
        let mut result = self.commit_locked(&mut registry);
        for companion in companions {
            // After a failure the rest are removed, under the same hold (a
            // drop would wait for the lock held here).
            result = match result {
                Ok(()) => companion.commit_locked(&mut registry),
                Err(error) => {
                    companion.abandon_locked(&mut registry);
                    Err(error)
                }
            };
        }
        drop(registry);
        sync_dir(&dir);
        result
    }

    fn commit_locked(self, registry: &mut Vec<PathBuf>) -> io::Result<()> {
        let PendingFile { temp, target } = self;
        match temp {
            Some(temp) => temp.rename_locked(&target, registry),
            None => Ok(()),
        }
    }

    fn abandon_locked(self, registry: &mut Vec<PathBuf>) {
        if let Some(mut temp) = self.temp {
            temp.remove_locked(registry);
        }
    }
}

/// [`write_atomically`] up to the rename (see there for what a path may be):
/// the file is written and synced
/// beside `path` and moves into place on [`PendingFile::commit`] (or with the
/// next file written, see [`stage_companion`]). A device or FIFO is written
/// straight away.
pub fn write_pending(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<PendingFile> {
    let target = match destination(path)? {
        Destination::Special => {
            stream_into(path, write)?;
            return Ok(PendingFile { temp: None, target: path.to_path_buf() });
        }
        Destination::File(target) => target,
    };
    let dir = parent_dir(&target);
    let Some(file_name) = target.file_name() else {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "the path does not name a file"));
    };
    let (temp, file) = Temporary::create_file(dir, &file_name.to_string_lossy())?;
    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    let file = writer.into_inner().map_err(|e| e.into_error())?;
    if let Ok(existing) = fs::metadata(&target) {
        file.set_permissions(existing.permissions())?;
    }
    file.sync_all()?;
    Ok(PendingFile { temp: Some(temp), target })
}

/// Stages `file` to move into place together with the next file this thread
/// writes with [`write_atomically`]; returns how many were staged before, for
/// [`unstage_companions`].
pub fn stage_companion(file: PendingFile) -> usize {
    COMPANIONS.with(|c| {
        let mut c = c.borrow_mut();
        c.push(file);
        c.len() - 1
    })
}

/// The staged files from position `from` on that no write has taken yet.
pub fn unstage_companions(from: usize) -> Vec<PendingFile> {
    COMPANIONS.with(|c| {
        let mut c = c.borrow_mut();
        let from = from.min(c.len());
        c.split_off(from)
    })
}

/// Whether `path` (through its symlinks) is a device, FIFO or socket: a
/// file [`write_atomically`] writes straight into rather than replaces, and
/// beside which no side file (`/dev/null.obj`) should be made.
pub fn is_special_file(path: &Path) -> bool {
    fs::metadata(path).is_ok_and(|meta| !meta.is_file() && !meta.is_dir())
}

/// What an output path leads to.
enum Destination {
    /// A device or a FIFO: written into, never replaced.
    Special,
    /// The regular file to replace (or create): the path itself, or where its symlinks lead.
    File(PathBuf),
}

fn destination(path: &Path) -> io::Result<Destination> {
    match fs::metadata(path) {
        Ok(meta) if meta.is_file() => Ok(Destination::File(follow_symlinks(path)?)),
        Ok(meta) if meta.is_dir() => Err(io::Error::new(io::ErrorKind::IsADirectory, "Is a directory")),
        Ok(meta) => {
            #[cfg(unix)]
            {
                use std::os::unix::fs::FileTypeExt as _;
                if meta.file_type().is_socket() {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidInput,
                        "it is a socket: Drape writes to files, devices and FIFOs only",
                    ));
                }
            }
            let _ = meta;
            Ok(Destination::Special)
        }
        // No file, or a symlink whose target does not exist yet.
        Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(Destination::File(follow_symlinks(path)?)),
        Err(error) => Err(error),
    }
}

/// Where `path` leads through its symlinks (the last component's; the
/// directories on the way resolve by themselves). `path` itself when it is
/// not a symlink.
fn follow_symlinks(path: &Path) -> io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_SYMLINK_HOPS {
        match fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let target = fs::read_link(&current)?;
                current = if target.is_absolute() { target } else { parent_dir(&current).join(target) };
            }
            _ => return Ok(current),
        }
    }
    Err(io::Error::new(io::ErrorKind::InvalidInput, "too many levels of symbolic links"))
}

/// Writes into a device or FIFO as it is: no temporary file, no rename, no sync.
fn stream_into(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let file = File::options().write(true).open(path)?;
    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    writer.flush()
}

/// The directory `path` is in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    }
}

/// Files written into a hidden staging directory inside the target directory
/// and moved into place together by [`StagedFiles::commit`]: until then the
/// target directory holds its old files only. Dropping it uncommitted (an
/// error, a cancel) removes the staging directory and everything in it; so
/// does SIGINT/SIGTERM once [`remove_temporaries_on_signals`] is installed,
/// and a signal during the commit waits for the commit to finish.
pub struct StagedFiles {
    target_dir: PathBuf,
    staging: Temporary,
    names: Vec<String>,
}

impl StagedFiles {
    /// Creates the staging directory `.NAME.drape-PID-N.staging` in
    /// `target_dir`, which must exist.
    pub fn new(target_dir: &Path, name: &str) -> io::Result<StagedFiles> {
        let staging = Temporary::create_dir(target_dir, name)?;
        Ok(StagedFiles { target_dir: target_dir.to_path_buf(), staging, names: Vec::new() })
    }

    /// The staging directory (hidden, inside the target directory).
    pub fn staging_dir(&self) -> &Path {
        &self.staging.path
    }

    /// Writes the file `file_name` (a plain name, not a path) into the
    /// staging directory (fsynced).
    pub fn write(&mut self, file_name: &str, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
        if !is_plain_file_name(file_name) || file_name == MARKER_NAME {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{file_name:?} is not a file name to stage"),
            ));
        }
        let file = {
            // Created under the lock, so that a signal's clean-up, once it
            // holds the lock, empties the staging directory for good.
            let _registry = registry();
            File::options().write(true).create_new(true).open(self.staging.path.join(file_name))?
        };
        self.names.push(file_name.to_owned());
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        writer.into_inner().map_err(|e| e.into_error())?.sync_all()
    }

    /// Moves every written file into the target directory (replacing files
    /// of the same names) and removes the staging directory. Returns the
    /// final paths in the order the files were written. A signal arriving
    /// meanwhile is handled once every file is in place.
    pub fn commit(self) -> io::Result<Vec<PathBuf>> {
        self.commit_replacing(&[]).map(|committed| committed.files)
    }

    /// [`StagedFiles::commit`], first removing the files named `old` from
    /// the target directory (an earlier sequence's frames that the new one
    /// does not replace), all under the same hold of a signal's clean-up.
    /// A file already gone is passed over; one that is also being written
    /// is replaced, not removed. A removal that fails stops the commit
    /// before any new file moves in.
    pub fn commit_replacing(self, old: &[String]) -> io::Result<Committed> {
        if let Some(bad) = old.iter().find(|name| !is_plain_file_name(name)) {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("{bad:?} is not a file name to remove")));
        }
        let hold_signals = registry();
        let mut committed = Committed::default();
        let mut result = self.remove_old(old, &mut committed.removed);
        if result.is_ok() {
            committed.files.reserve(self.names.len());
            for name in &self.names {
                let target = self.target_dir.join(name);
                result = fs::rename(self.staging.path.join(name), &target);
                if result.is_err() {
                    break;
                }
                committed.files.push(target);
            }
        }
        drop(hold_signals);
        sync_dir(&self.target_dir);
        // Removes the staging directory, emptied unless a rename failed.
        drop(self);
        result.map(|()| committed)
    }

    fn remove_old(&self, old: &[String], removed: &mut Vec<PathBuf>) -> io::Result<()> {
        for name in old.iter().filter(|name| !self.names.contains(name)) {
            let path = self.target_dir.join(name);
            match fs::remove_file(&path) {
                Ok(()) => removed.push(path),
                Err(error) if error.kind() == io::ErrorKind::NotFound => {}
                Err(error) => return Err(error),
            }
        }
        Ok(())
    }
}

/// What [`StagedFiles::commit_replacing`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Committed {
    /// The files moved into place, in the order they were written.
    pub files: Vec<PathBuf>,
    /// The earlier files removed.
    pub removed: Vec<PathBuf>,
}

/// A name of a file in a directory: no separator, not `.` or `..`.
fn is_plain_file_name(name: &str) -> bool {
    !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains('\0')
        && !name.chars().any(std::path::is_separator)
}

// ---------------------------------------------------------- file identity

/// A regular file as the disk knows it (device and inode on Unix): two
/// paths with the same identity are one file, whatever their names, hard
/// links or symlinks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileIdentity {
    #[cfg(unix)]
    id: (u64, u64),
    #[cfg(not(unix))]
    id: PathBuf,
}

impl FileIdentity {
    /// The identity of the regular file `path` leads to (through
    /// symlinks); `None` when it leads to none (nothing there, a directory,
    /// a device or FIFO).
    pub fn of(path: &Path) -> Option<FileIdentity> {
        let meta = fs::metadata(path).ok().filter(fs::Metadata::is_file)?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt as _;
            Some(FileIdentity { id: (meta.dev(), meta.ino()) })
        }
        #[cfg(not(unix))]
        {
            let _ = meta;
            Some(FileIdentity { id: path.canonicalize().ok()? })
        }
    }
}

// ------------------------------------------------------------ temporaries

/// Temporaries that exist now, to be removed if a signal ends the process.
/// Holding the lock defers that removal.
static REGISTRY: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Directories already swept of dead processes' temporaries by this process.
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

/// The longest file name most file systems take, in bytes.
const MAX_FILE_NAME_BYTES: usize = 255;
/// The marker each temporary directory holds, written before anything else.
const MARKER_NAME: &str = ".drape-temporary";
/// The file inside a `.tmp` directory that becomes the written file.
const TEMPORARY_FILE_NAME: &str = "file";
/// A marker is a few short lines; anything longer is not one.
const MAX_MARKER_BYTES: u64 = 256;

fn registry() -> MutexGuard<'static, Vec<PathBuf>> {
    REGISTRY.lock().unwrap_or_else(PoisonError::into_inner)
}

/// What a temporary directory holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TemporaryKind {
    /// One file on its way to its name: `.NAME.drape-PID-N.tmp`.
    File,
    /// A sequence's files: `.NAME.drape-PID-N.staging`.
    Staging,
}

impl TemporaryKind {
    fn suffix(self) -> &'static str {
        match self {
            TemporaryKind::File => "tmp",
            TemporaryKind::Staging => "staging",
        }
    }
}

/// A temporary directory with its marker, removed with everything in it
/// when dropped.
struct Temporary {
    path: PathBuf,
    /// Moved into place or removed already.
    gone: bool,
}

impl Temporary {
    /// Creates a `.tmp` directory in `dir` for the file `name` and the file
    /// inside it, never reusing an existing one.
    fn create_file(dir: &Path, name: &str) -> io::Result<(Temporary, File)> {
        let temp = Temporary::create(dir, name, TemporaryKind::File)?;
        let file = {
            // Created under the lock, so that a signal's clean-up, once it
            // holds the lock, empties the directory for good.
            let _registry = registry();
            File::options().write(true).create_new(true).open(temp.file_path())?
        };
        Ok((temp, file))
    }

    /// Creates the staging directory `.NAME.drape-PID-N.staging` in `dir`.
    fn create_dir(dir: &Path, name: &str) -> io::Result<Temporary> {
        Temporary::create(dir, name, TemporaryKind::Staging)
    }

    fn create(dir: &Path, name: &str, kind: TemporaryKind) -> io::Result<Temporary> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        remove_stale_temporaries(dir);
        let pid = std::process::id();
        let mut attempts = 0;
        loop {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = dir.join(temporary_name(name, pid, n, kind));
            // Created, marked and registered under the lock, so a signal's
            // clean-up sees every temporary that exists.
            let mut registry = registry();
            match fs::create_dir(&path) {
                Ok(()) => {
                    registry.push(path.clone());
                    let mut temp = Temporary { path, gone: false };
                    if let Err(error) = write_marker(&temp.path, pid) {
                        temp.remove_locked(&mut registry);
                        return Err(error);
                    }
                    return Ok(temp);
                }
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists && attempts < 100 => attempts += 1,
                Err(error) => return Err(error),
            }
        }
    }

    /// The file a `.tmp` directory holds.
    fn file_path(&self) -> PathBuf {
        self.path.join(TEMPORARY_FILE_NAME)
    }

    /// Moves the file this `.tmp` directory holds to `target` and removes
    /// the directory (also when the move fails), with the registry held by
    /// the caller.
    fn rename_locked(mut self, target: &Path, registry: &mut Vec<PathBuf>) -> io::Result<()> {
        let renamed = fs::rename(self.file_path(), target);
        self.remove_locked(registry);
        renamed
    }

    /// Removes the directory and what is left in it, with the registry held.
    fn remove_locked(&mut self, registry: &mut Vec<PathBuf>) {
        let _ = fs::remove_dir_all(&self.path);
        registry.retain(|p| *p != self.path);
        self.gone = true;
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if self.gone {
            return;
        }
        let mut registry = registry();
        self.remove_locked(&mut registry);
    }
}

/// `.NAME.drape-PID-N.SUFFIX`, NAME cut at a character boundary so the
/// whole name takes at most [`MAX_FILE_NAME_BYTES`].
fn temporary_name(name: &str, pid: u32, n: u64, kind: TemporaryKind) -> String {
    let tail = format!(".drape-{pid}-{n}.{}", kind.suffix());
    let room = MAX_FILE_NAME_BYTES - 1 - tail.len();
    let mut cut = name.len().min(room);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!(".{}{tail}", &name[..cut])
}

/// The writing process's id in a temporary directory's name, and what it
/// holds, when the name has exactly the form [`temporary_name`] gives it:
/// `.NAME.drape-PID-N.tmp` or `.NAME.drape-PID-N.staging`, NAME not empty,
/// PID and N decimal numbers without leading zeros.
fn temporary_owner(file_name: &str) -> Option<(u32, TemporaryKind)> {
    if file_name.len() > MAX_FILE_NAME_BYTES {
        return None;
    }
    let (rest, kind) = match file_name.strip_suffix(".tmp") {
        Some(rest) => (rest, TemporaryKind::File),
        None => (file_name.strip_suffix(".staging")?, TemporaryKind::Staging),
    };
    let (name, ids) = rest.strip_prefix('.')?.rsplit_once(".drape-")?;
    let (pid, n) = ids.split_once('-')?;
    if name.is_empty() || !is_plain_number(pid) || !is_plain_number(n) {
        return None;
    }
    n.parse::<u64>().ok()?;
    let pid = pid.parse().ok().filter(|&pid| pid > 0)?;
    Some((pid, kind))
}

/// Digits only, and no leading zero unless it is `0`.
fn is_plain_number(text: &str) -> bool {
    !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) && (text == "0" || !text.starts_with('0'))
}

/// What the marker in the temporary directory `dir` of process `pid` says:
/// the process and the directory's own device and inode, so that a copy of
/// the directory, or a marker put into another one, does not match.
fn marker_text(pid: u32, dir: &fs::Metadata) -> String {
    format!(
        "Drape's temporary directory, removed by Drape once its process has ended\npid {pid}\ndirectory {}\n",
        directory_identity(dir)
    )
}

fn directory_identity(dir: &fs::Metadata) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        format!("{}:{}", dir.dev(), dir.ino())
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        String::new()
    }
}

/// Writes the marker into the directory `dir`, just made by process `pid`.
fn write_marker(dir: &Path, pid: u32) -> io::Result<()> {
    let text = marker_text(pid, &fs::symlink_metadata(dir)?);
    let mut marker = File::options().write(true).create_new(true).open(dir.join(MARKER_NAME))?;
    marker.write_all(text.as_bytes())
}

/// Whether `dir` (seen as `meta`, not through a symlink) holds the marker
/// process `pid` wrote into it, proving it is that process's temporary.
fn has_marker(dir: &Path, meta: &fs::Metadata, pid: u32) -> bool {
    let mut options = File::options();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    }
    let Ok(file) = options.open(dir.join(MARKER_NAME)) else { return false };
    if !file.metadata().is_ok_and(|m| m.is_file()) {
        return false;
    }
    let mut text = Vec::new();
    if io::Read::read_to_end(&mut io::Read::take(file, MAX_MARKER_BYTES + 1), &mut text).is_err() {
        return false;
    }
    text == marker_text(pid, meta).as_bytes()
}

/// Removes from `dir` the temporaries of Drape processes that no longer
/// run: directories named exactly as Drape names them and holding the
/// marker their process wrote. Once per directory per process, best effort
/// (unreadable directories and what cannot be removed are left).
fn remove_stale_temporaries(dir: &Path) {
    {
        let mut swept = SWEPT.lock().unwrap_or_else(PoisonError::into_inner);
        if !swept.get_or_insert_with(HashSet::new).insert(dir.to_path_buf()) {
            return;
        }
    }
    let Ok(entries) = fs::read_dir(dir) else { return };
    let own_pid = std::process::id();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some((pid, _)) = name.to_str().and_then(temporary_owner) else { continue };
        // Not followed through a symlink: a link named like a temporary is left alone.
        let Ok(meta) = entry.metadata() else { continue };
        let path = entry.path();
        if pid != own_pid && meta.is_dir() && !process_is_running(pid) && has_marker(&path, &meta, pid) {
            let _ = fs::remove_dir_all(&path);
        }
    }
}

/// Whether a process with this id exists (on other systems than Unix: assumed so).
fn process_is_running(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else { return true };
        if pid <= 0 {
            return true;
        }
        // SAFETY: signal 0 only checks that the process exists and may be signalled.
        let alive = unsafe { libc::kill(pid, 0) } == 0;
        alive || io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// Makes a rename durable. Best effort: some file systems cannot sync a
/// directory, and the new file is already in place by now.
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(handle) = File::open(dir) {
        let _ = handle.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

// ---------------------------------------------------------------- signals

/// On SIGINT, SIGTERM and SIGHUP: removes every temporary file and staging
/// directory that exists (waiting for a [`StagedFiles::commit`] under way to
/// finish), then ends the process with status 128 + the signal's number (130
/// for Ctrl+C, 143 for SIGTERM). A signal that was ignored when this is
/// called (`nohup`) stays ignored. Call once, early; later calls do nothing.
/// Does nothing on systems other than Unix.
pub fn remove_temporaries_on_signals() -> io::Result<()> {
    #[cfg(unix)]
    return signals::install();
    #[cfg(not(unix))]
    Ok(())
}

#[cfg(unix)]
mod signals {
    use std::io;
    use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

    /// The pipe's write end, for the signal handler.
    static WAKE_FD: AtomicI32 = AtomicI32::new(-1);
    static INSTALLED: AtomicBool = AtomicBool::new(false);

    /// Only writes the signal's number into the pipe (async-signal-safe);
    /// the clean-up runs on an ordinary thread.
    extern "C" fn on_signal(signal: libc::c_int) {
        let byte = signal as u8;
        // SAFETY: write(2) is async-signal-safe; the fd stays open for the process's life.
        unsafe { libc::write(WAKE_FD.load(Ordering::Relaxed), (&raw const byte).cast(), 1) };
    }

    pub(super) fn install() -> io::Result<()> {
        if INSTALLED.swap(true, Ordering::SeqCst) {
            return Ok(());
        }
        let mut fds = [0 as libc::c_int; 2];
        // SAFETY: `fds` has room for the two descriptors.
        if unsafe { libc::pipe(fds.as_mut_ptr()) } != 0 {
            return Err(io::Error::last_os_error());
        }
        let [read_fd, write_fd] = fds;
        // SAFETY: fcntl on descriptors just created; a full pipe must not block the handler.
        unsafe {
            libc::fcntl(read_fd, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(write_fd, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(write_fd, libc::F_SETFL, libc::fcntl(write_fd, libc::F_GETFL) | libc::O_NONBLOCK);
        }
        WAKE_FD.store(write_fd, Ordering::Relaxed);
        std::thread::Builder::new().name("drape-signals".into()).spawn(move || wait_and_clean_up(read_fd))?;
        for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            // SAFETY: plain sigaction calls with zeroed, then filled, structures.
            unsafe {
                let mut current: libc::sigaction = std::mem::zeroed();
                if libc::sigaction(signal, std::ptr::null(), &mut current) != 0 {
                    return Err(io::Error::last_os_error());
                }
                if current.sa_sigaction == libc::SIG_IGN {
                    continue;
                }
                let mut action: libc::sigaction = std::mem::zeroed();
                action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
                action.sa_flags = libc::SA_RESTART;
                libc::sigemptyset(&mut action.sa_mask);
                if libc::sigaction(signal, &action, std::ptr::null_mut()) != 0 {
                    return Err(io::Error::last_os_error());
                }
            }
        }
        Ok(())
    }

    fn wait_and_clean_up(read_fd: libc::c_int) {
        let mut byte = 0u8;
        loop {
            // SAFETY: reads one byte into `byte`.
            let read = unsafe { libc::read(read_fd, (&raw mut byte).cast(), 1) };
            if read == 1 {
                break;
            }
            if read < 0 && io::Error::last_os_error().kind() == io::ErrorKind::Interrupted {
                continue;
            }
            return;
        }
        // Held until the process ends: nothing new is created meanwhile.
        let registry = super::registry();
        for path in registry.iter() {
            let _ = std::fs::remove_dir_all(path);
        }
        // SAFETY: _exit ends the process at once, without running other threads' code
        // (a render in progress, atexit handlers) that could hang.
        unsafe { libc::_exit(128 + libc::c_int::from(byte)) }
    }
}

/// The OS's description of an I/O error without the `(os error N)` suffix,
/// for messages that already say which file and what was being done.
pub fn io_reason(error: &io::Error) -> String {
    let text = error.to_string();
    match text.rfind(" (os error ") {
        Some(cut) if text.ends_with(')') => text[..cut].to_owned(),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    #[test]
    fn failed_write_keeps_old_file_and_removes_temp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        fs::write(&path, "old").unwrap();
        let err = write_atomically(&path, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("disk full"))
        });
        assert_eq!(err.unwrap_err().to_string(), "disk full");
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(names_in(dir.path()), ["out.txt"], "temp file removed");
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert!(!registry().iter().any(|p| p.starts_with(dir.path())), "nothing left registered");
    }

    #[test]
    fn missing_directory_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no/such/dir/out.txt");
        assert_eq!(write_atomically(&path, |w| w.write_all(b"x")).unwrap_err().kind(), io::ErrorKind::NotFound);
    }

    #[cfg(unix)]
    #[test]
    fn symlinks_are_followed_and_stay_links() {
        let dir = tempfile::tempdir().unwrap();
        fs::create_dir(dir.path().join("real")).unwrap();
        let target = dir.path().join("real/scene.ron");
        fs::write(&target, "old").unwrap();
        // A relative link to a relative link.
        std::os::unix::fs::symlink("real/scene.ron", dir.path().join("inner")).unwrap();
        std::os::unix::fs::symlink("inner", dir.path().join("outer")).unwrap();
        write_atomically(&dir.path().join("outer"), |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        for link in ["inner", "outer"] {
            assert!(fs::symlink_metadata(dir.path().join(link)).unwrap().file_type().is_symlink(), "{link}");
        }
        assert_eq!(names_in(&dir.path().join("real")), ["scene.ron"]);
        // A dangling link gets its target.
        std::os::unix::fs::symlink("real/new.ron", dir.path().join("dangling")).unwrap();
        write_atomically(&dir.path().join("dangling"), |w| w.write_all(b"made")).unwrap();
        assert_eq!(fs::read_to_string(dir.path().join("real/new.ron")).unwrap(), "made");
        // A loop is an error.
        std::os::unix::fs::symlink("loop_b", dir.path().join("loop_a")).unwrap();
        std::os::unix::fs::symlink("loop_a", dir.path().join("loop_b")).unwrap();
        assert!(write_atomically(&dir.path().join("loop_a"), |w| w.write_all(b"x")).is_err());
    }

    #[test]
    fn temporary_names_are_recognised_exactly() {
        assert_eq!(temporary_owner(".carpet.usda.drape-4242-7.tmp"), Some((4242, TemporaryKind::File)));
        assert_eq!(temporary_owner(".magic_carpet.drape-17-0.staging"), Some((17, TemporaryKind::Staging)));
        assert_eq!(temporary_owner(".a.b.drape-1-2.drape-3-4.tmp"), Some((3, TemporaryKind::File)));
        for other in [
            "carpet.usda.drape-1-2.tmp",
            ".x.1-2.tmp",
            ".x.drape-1.tmp",
            ".x.drape-a-2.tmp",
            ".x.drape-1-2",
            "..drape-1-2.tmp",
            ".x.drape-01-2.tmp",
            ".x.drape-1-02.tmp",
            ".x.drape-0-2.tmp",
            ".x.drape-+1-2.tmp",
            ".x.drape-1-2-3.tmp",
            ".x.drape-99999999999-2.tmp",
        ] {
            assert_eq!(temporary_owner(other), None, "{other}");
        }
    }

    #[test]
    fn temporary_names_fit_any_output_name() {
        for name in ["a".repeat(255), "é".repeat(127) + "x", "carpet.usda".to_string()] {
            for kind in [TemporaryKind::File, TemporaryKind::Staging] {
                let temp = temporary_name(&name, u32::MAX, u64::MAX, kind);
                assert!(temp.len() <= MAX_FILE_NAME_BYTES, "{} bytes: {temp}", temp.len());
                assert_eq!(temporary_owner(&temp), Some((u32::MAX, kind)), "{temp}");
                let kept = &temp[1..temp.rfind(".drape-").unwrap()];
                assert!(name.starts_with(kept) && !kept.is_empty(), "{temp}");
            }
        }
        assert_eq!(temporary_name("carpet.usda", 42, 7, TemporaryKind::File), ".carpet.usda.drape-42-7.tmp");
    }

    #[test]
    fn an_output_name_of_255_bytes_is_written() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["n".repeat(251) + ".obj", "é".repeat(125) + "x.obj"] {
            let path = dir.path().join(&name);
            write_atomically(&path, |w| w.write_all(b"whole")).unwrap();
            assert_eq!(fs::read_to_string(&path).unwrap(), "whole");
            let mut staged = StagedFiles::new(dir.path(), &name).unwrap();
            staged.write("frame_0000.obj", |w| w.write_all(b"frame")).unwrap();
            staged.commit().unwrap();
        }
        assert_eq!(names_in(dir.path()).len(), 3, "two outputs and a frame: {:?}", names_in(dir.path()));
    }

    /// A process id no process has now: a child that has ended (its id is
    /// free until reused, which a fresh id this soon after is not).
    #[cfg(unix)]
    fn dead_pid() -> u32 {
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        pid
    }

    /// What a Drape process `pid` killed mid-write leaves in `dir`: its
    /// marked temporary directory with a file in it.
    #[cfg(unix)]
    fn leftover(dir: &Path, name: &str, pid: u32, kind: TemporaryKind) -> String {
        let temp = temporary_name(name, pid, 3, kind);
        fs::create_dir(dir.join(&temp)).unwrap();
        write_marker(&dir.join(&temp), pid).unwrap();
        fs::write(dir.join(&temp).join("seq_0001.obj"), "stale").unwrap();
        temp
    }

    #[cfg(unix)]
    #[test]
    fn temporaries_of_dead_processes_are_removed_on_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let dead = dead_pid();
        let live = std::process::id();
        let parent = std::os::unix::process::parent_id();
        leftover(dir.path(), "out.txt", dead, TemporaryKind::File);
        leftover(dir.path(), "seq", dead, TemporaryKind::Staging);
        leftover(dir.path(), &"s".repeat(255), dead, TemporaryKind::Staging);
        let other = leftover(dir.path(), "other", parent, TemporaryKind::File);
        let own = leftover(dir.path(), "own", live, TemporaryKind::File);
        write_atomically(&dir.path().join("out.txt"), |w| w.write_all(b"x")).unwrap();
        assert_eq!(names_in(dir.path()), [other, own, "out.txt".to_string()]);
    }

    /// Files and folders that only look like a dead process's temporaries
    /// are the user's: a name alone proves nothing.
    #[cfg(unix)]
    #[test]
    fn what_drape_cannot_prove_it_wrote_is_never_removed() {
        let dir = tempfile::tempdir().unwrap();
        let dead = dead_pid();
        let notes = format!(".notes.drape-{dead}-0.tmp");
        fs::write(dir.path().join(&notes), "my notes").unwrap();
        let work = format!(".work.drape-{dead}-1.staging");
        fs::create_dir(dir.path().join(&work)).unwrap();
        fs::write(dir.path().join(&work).join("draft.txt"), "my draft").unwrap();
        // A folder with a marker that names another directory: a copy of a
        // temporary, or a marker put there by hand.
        let copy = format!(".copy.drape-{dead}-2.tmp");
        let real = leftover(dir.path(), "real", dead, TemporaryKind::File);
        fs::create_dir(dir.path().join(&copy)).unwrap();
        fs::copy(dir.path().join(&real).join(MARKER_NAME), dir.path().join(&copy).join(MARKER_NAME)).unwrap();
        fs::write(dir.path().join(&copy).join("kept.txt"), "kept").unwrap();
        // A marker of another process than the name says.
        let other_pid = format!(".mixed.drape-{}-3.tmp", dead_pid());
        fs::create_dir(dir.path().join(&other_pid)).unwrap();
        write_marker(&dir.path().join(&other_pid), dead).unwrap();
        // A symlink named like a temporary, to a marked directory elsewhere.
        let elsewhere = tempfile::tempdir().unwrap();
        let target = leftover(elsewhere.path(), "target", dead, TemporaryKind::File);
        let link = format!(".link.drape-{dead}-4.tmp");
        std::os::unix::fs::symlink(elsewhere.path().join(&target), dir.path().join(&link)).unwrap();

        write_atomically(&dir.path().join("out.txt"), |w| w.write_all(b"x")).unwrap();
        let mut expected = vec![notes, work.clone(), copy.clone(), other_pid, link, "out.txt".to_string()];
        expected.sort();
        assert_eq!(names_in(dir.path()), expected, "only the real leftover {real} is gone");
        assert_eq!(fs::read_to_string(dir.path().join(&work).join("draft.txt")).unwrap(), "my draft");
        assert_eq!(names_in(&dir.path().join(&copy)), [MARKER_NAME, "kept.txt"]);
        assert_eq!(names_in(elsewhere.path()), [target]);
    }

    #[test]
    fn a_temporary_holds_its_marker_while_it_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let mut inside = Vec::new();
        write_atomically(&dir.path().join("out.txt"), |w| {
            let temp = names_in(dir.path()).into_iter().find(|n| n.starts_with(".out.txt.drape-")).unwrap();
            inside = names_in(&dir.path().join(temp));
            w.write_all(b"x")
        })
        .unwrap();
        assert_eq!(inside, [MARKER_NAME, TEMPORARY_FILE_NAME]);
        assert_eq!(names_in(dir.path()), ["out.txt"]);
    }

    #[test]
    fn staged_files_appear_together_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("f_1.txt"), "old 1").unwrap();
        let mut staged = StagedFiles::new(dir.path(), "f").unwrap();
        staged.write("f_1.txt", |w| w.write_all(b"new 1")).unwrap();
        staged.write("f_2.txt", |w| w.write_all(b"new 2")).unwrap();
        assert_eq!(fs::read_to_string(dir.path().join("f_1.txt")).unwrap(), "old 1");
        drop(staged);
        assert_eq!(names_in(dir.path()), ["f_1.txt"], "abandoned: staging removed, old file kept");

        let mut staged = StagedFiles::new(dir.path(), "f").unwrap();
        staged.write("f_1.txt", |w| w.write_all(b"new 1")).unwrap();
        staged.write("f_2.txt", |w| w.write_all(b"new 2")).unwrap();
        let files = staged.commit().unwrap();
        assert_eq!(files, [dir.path().join("f_1.txt"), dir.path().join("f_2.txt")]);
        assert_eq!(names_in(dir.path()), ["f_1.txt", "f_2.txt"]);
        assert_eq!(fs::read_to_string(dir.path().join("f_1.txt")).unwrap(), "new 1");
    }

    #[test]
    fn a_commit_can_remove_an_earlier_sequence_s_other_frames() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["f_1.txt", "f_2.txt", "f_3.txt", "notes.txt"] {
            fs::write(dir.path().join(name), "old").unwrap();
        }
        let mut staged = StagedFiles::new(dir.path(), "f").unwrap();
        staged.write("f_1.txt", |w| w.write_all(b"new 1")).unwrap();
        let old = ["f_1.txt", "f_2.txt", "f_3.txt", "f_9.txt"].map(String::from);
        let committed = staged.commit_replacing(&old).unwrap();
        assert_eq!(committed.files, [dir.path().join("f_1.txt")]);
        assert_eq!(committed.removed, [dir.path().join("f_2.txt"), dir.path().join("f_3.txt")], "f_9 was not there");
        assert_eq!(names_in(dir.path()), ["f_1.txt", "notes.txt"]);
        assert_eq!(fs::read_to_string(dir.path().join("f_1.txt")).unwrap(), "new 1");

        let staged = StagedFiles::new(dir.path(), "f").unwrap();
        let error = staged.commit_replacing(&["../notes.txt".to_string()]).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        let mut staged = StagedFiles::new(dir.path(), "f").unwrap();
        assert_eq!(staged.write(MARKER_NAME, |w| w.write_all(b"x")).unwrap_err().kind(), io::ErrorKind::InvalidInput);
        drop(staged);
        assert_eq!(names_in(dir.path()), ["f_1.txt", "notes.txt"]);
    }

    #[cfg(unix)]
    #[test]
    fn file_identity_sees_through_links_and_names() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.ron");
        fs::write(&scene, "scene").unwrap();
        fs::hard_link(&scene, dir.path().join("hard.obj")).unwrap();
        std::os::unix::fs::symlink("scene.ron", dir.path().join("soft.obj")).unwrap();
        fs::write(dir.path().join("other.ron"), "scene").unwrap();
        let id = FileIdentity::of(&scene).unwrap();
        assert_eq!(FileIdentity::of(&dir.path().join("hard.obj")), Some(id.clone()));
        assert_eq!(FileIdentity::of(&dir.path().join("soft.obj")), Some(id.clone()));
        assert_eq!(FileIdentity::of(&dir.path().join(".").join("scene.ron")), Some(id.clone()));
        assert_ne!(FileIdentity::of(&dir.path().join("other.ron")), Some(id));
        assert_eq!(FileIdentity::of(dir.path()), None, "a directory");
        assert_eq!(FileIdentity::of(&dir.path().join("missing")), None);
    }
}
