//! Frame sequences on disk: the numbered file names of an OBJ sequence (and
//! of `drape render`'s PNG sequences), the directory they are written into,
//! and the frames of an earlier sequence there that a new one would leave
//! mixed with its own.

use std::fs;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use super::error::ExportError;
use super::output::InputFiles;
use crate::scene::frame_list;

/// The file name of one frame of an OBJ sequence: `NAME_0007.obj`; frame
/// numbers are padded to at least four digits, more when the range needs
/// them, so the files sort in frame order (`NAME_-0005.obj` before zero).
pub fn sequence_file_name(name: &str, frame: i32, frames: RangeInclusive<i32>) -> String {
    let width = frame_number_width(*frames.start(), *frames.end());
    format!("{name}_{}.obj", padded_frame(frame, width))
}

/// Digits for the frame numbers of a sequence: at least 4, more when needed.
pub fn frame_number_width(first: i32, last: i32) -> usize {
    let digits = |f: i32| f.unsigned_abs().to_string().len();
    digits(first).max(digits(last)).max(4)
}

/// `frame` zero-padded to `width` digits, with a leading `-` when negative.
pub fn padded_frame(frame: i32, width: usize) -> String {
    let sign = if frame < 0 { "-" } else { "" };
    format!("{sign}{:0width$}", frame.unsigned_abs())
}

/// A scene name as a file-name stem: lower case, runs of anything but
/// letters and digits as one `_` (`Magic carpet` → `magic_carpet`).
pub fn file_stem_for(name: &str) -> String {
    let mut stem = String::new();
    for c in name.trim().chars() {
        if c.is_alphanumeric() {
            stem.extend(c.to_lowercase());
        } else if !stem.ends_with('_') && !stem.is_empty() {
            stem.push('_');
        }
    }
    let stem = stem.trim_end_matches('_').to_string();
    if stem.is_empty() { "frame".to_string() } else { stem }
}

/// Checks that the directory `dir` a sequence is written into exists or
/// can be made: its parent must exist ([`ExportError::MissingDirectory`]
/// otherwise); Drape makes one directory, never a chain of them.
pub fn check_sequence_dir(dir: &Path) -> Result<(), ExportError> {
    if !dir.is_dir()
        && let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(ExportError::MissingDirectory { path: dir.to_path_buf(), dir: parent.to_path_buf() });
    }
    Ok(())
}

/// Makes sure the directory `dir` a sequence is written into exists: it is
/// created when missing, if [`check_sequence_dir`] allows. Returns whether
/// it was created, so that a failed export can remove it again.
pub fn ensure_sequence_dir(dir: &Path) -> Result<bool, ExportError> {
    check_sequence_dir(dir)?;
    if dir.is_dir() {
        return Ok(false);
    }
    fs::create_dir(dir).map_err(|e| ExportError::write(dir, e))?;
    Ok(true)
}

/// The files of one numbered sequence: `DIR/NAME_0000.EXT …` over a range
/// of frames, numbered as [`padded_frame`] pads them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SequenceFiles {
    pub dir: PathBuf,
    pub name: String,
    /// Without the dot: `obj`, `png`.
    pub extension: String,
    pub frames: RangeInclusive<i32>,
}

impl SequenceFiles {
    pub fn new(dir: &Path, name: &str, extension: &str, frames: RangeInclusive<i32>) -> SequenceFiles {
        SequenceFiles { dir: dir.to_path_buf(), name: name.to_owned(), extension: extension.to_owned(), frames }
    }

    /// The file name of `frame`: `NAME_0007.EXT`.
    pub fn file_name(&self, frame: i32) -> String {
        let width = frame_number_width(*self.frames.start(), *self.frames.end());
        format!("{}_{}.{}", self.name, padded_frame(frame, width), self.extension)
    }

    /// The frame `file_name` holds when it is named as a frame of a
    /// sequence of this name and extension, whatever its range: `NAME_`, an
    /// optional `-`, at least four digits, `.EXT`, exactly.
    pub fn frame_of(&self, file_name: &str) -> Option<i32> {
        let number = file_name.strip_prefix(self.name.as_str())?.strip_prefix('_')?;
        let number = number.strip_suffix(self.extension.as_str())?.strip_suffix('.')?;
        let digits = number.strip_prefix('-').unwrap_or(number);
        if digits.len() < 4 || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        number.parse().ok()
    }

    /// Whether this sequence writes the file `file_name`.
    fn writes(&self, file_name: &str) -> bool {
        self.frame_of(file_name).is_some_and(|frame| self.frames.contains(&frame) && self.file_name(frame) == file_name)
    }

    /// The files in the directory named as frames of this sequence that it
    /// does not write (an earlier, longer or otherwise numbered run's), in
    /// frame order: left there, a loader would play them with the new
    /// frames. Directories are not frames; symlinks are (a loader follows
    /// them). None when the directory does not exist yet.
    pub fn old_frames(&self) -> Result<OldFrames, ExportError> {
        let entries = match fs::read_dir(&self.dir) {
            Ok(entries) => entries,
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(OldFrames::default()),
            Err(error) => return Err(ExportError::write(&self.dir, error)),
        };
        let mut found = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|e| ExportError::write(&self.dir, e))?;
            let Some(name) = entry.file_name().to_str().map(str::to_owned) else { continue };
            let Some(frame) = self.frame_of(&name) else { continue };
            if self.writes(&name) || entry.file_type().is_ok_and(|t| t.is_dir()) {
                continue;
            }
            found.push((frame, name));
        }
        found.sort();
        Ok(OldFrames { files: found })
    }

    /// Every file in the directory this sequence writes over or, replacing
    /// an earlier sequence, removes: those of its own names that exist, and
    /// `old`.
    pub fn touched_files(&self, old: &OldFrames) -> Vec<PathBuf> {
        let existing = self.frames.clone().map(|frame| self.dir.join(self.file_name(frame))).filter(|p| p.exists());
        existing.chain(old.files.iter().map(|(_, name)| self.dir.join(name))).collect()
    }

    /// Checks the directory before (and again just before moving the new
    /// frames in, as it may have changed meanwhile): no file this sequence
    /// writes over or would remove is one of `inputs`, and frames of an
    /// earlier sequence that it does not write are refused unless
    /// `replace`. Returns those frames, for [`crate::atomic_file::StagedFiles::commit_replacing`]
    /// to remove when replacing.
    pub fn check_directory(&self, inputs: &InputFiles, replace: bool) -> Result<OldFrames, ExportError> {
        let old = self.old_frames()?;
        for path in self.touched_files(&old) {
            inputs.check(&path, Some("a frame of the sequence".to_owned()))?;
        }
        if !replace {
            self.refuse_old(&old)?;
        }
        Ok(old)
    }

    /// The refusal of `old`, naming its frames, or `Ok` when there are none.
    pub fn refuse_old(&self, old: &OldFrames) -> Result<(), ExportError> {
        if old.is_empty() {
            return Ok(());
        }
        let frames: Vec<i32> = old.files.iter().map(|(frame, _)| *frame).collect();
        let (first, last) = (&old.files[0].1, &old.files[old.files.len() - 1].1);
        Err(ExportError::OldFrames {
            dir: self.dir.clone(),
            pattern: format!("{}_####.{}", self.name, self.extension),
            count: old.files.len(),
            frames: shortened(&frame_list(&frames)),
            files: if first == last { first.clone() } else { format!("{first} … {last}") },
        })
    }
}

/// Files of an earlier sequence that a new one does not write, in frame order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OldFrames {
    /// Each file's frame and name.
    pub files: Vec<(i32, String)>,
}

impl OldFrames {
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    pub fn names(&self) -> Vec<String> {
        self.files.iter().map(|(_, name)| name.clone()).collect()
    }
}

/// Most characters of a frame list in a message.
const MAX_FRAME_LIST_CHARS: usize = 80;

/// `list` cut after its last whole entry within [`MAX_FRAME_LIST_CHARS`], with `, …`.
fn shortened(list: &str) -> String {
    if list.chars().count() <= MAX_FRAME_LIST_CHARS {
        return list.to_owned();
    }
    let head: String = list.chars().take(MAX_FRAME_LIST_CHARS).collect();
    match head.rfind(", ") {
        Some(cut) => format!("{}, …", &head[..cut]),
        None => format!("{head}…"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequence_numbers_are_padded_to_sort() {
        assert_eq!(sequence_file_name("carpet", 1, 0..=120), "carpet_0001.obj");
        assert_eq!(sequence_file_name("carpet", 120, 0..=120), "carpet_0120.obj");
        assert_eq!(padded_frame(-5, frame_number_width(-5, 123_456)), "-000005");
        assert_eq!(padded_frame(123_456, frame_number_width(-5, 123_456)), "123456");
    }

    #[test]
    fn scene_names_become_file_stems() {
        assert_eq!(file_stem_for("Magic carpet"), "magic_carpet");
        assert_eq!(file_stem_for("  Flag / pole #2 "), "flag_pole_2");
        assert_eq!(file_stem_for(""), "frame");
    }

    #[test]
    fn only_a_sequence_s_own_names_are_its_frames() {
        let seq = SequenceFiles::new(Path::new("seq"), "curtain", "obj", 0..=3);
        assert_eq!(seq.file_name(2), "curtain_0002.obj");
        assert_eq!(seq.frame_of("curtain_0004.obj"), Some(4));
        assert_eq!(seq.frame_of("curtain_-0005.obj"), Some(-5));
        assert_eq!(seq.frame_of("curtain_12345.obj"), Some(12_345));
        for other in [
            "curtain_004.obj",
            "curtain_0004.png",
            "curtain_0004.obj.bak",
            "curtain_v2_0004.obj",
            "curtain0004.obj",
            "Curtain_0004.obj",
            "curtain_+0004.obj",
            "curtain_00 4.obj",
            "curtain_99999999999.obj",
            "other_0004.obj",
        ] {
            assert_eq!(seq.frame_of(other), None, "{other}");
        }
        assert!(seq.writes("curtain_0003.obj"));
        assert!(!seq.writes("curtain_00003.obj"), "another numbering of a frame it writes");
        assert!(!seq.writes("curtain_0004.obj"));
    }

    #[test]
    fn old_frames_are_found_and_named() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["curtain_0000.obj", "curtain_0004.obj", "curtain_0005.obj", "curtain_0009.obj", "notes.txt"] {
            fs::write(dir.path().join(name), "old").unwrap();
        }
        fs::create_dir(dir.path().join("curtain_0007.obj")).unwrap();
        let seq = SequenceFiles::new(dir.path(), "curtain", "obj", 0..=3);
        let old = seq.old_frames().unwrap();
        assert_eq!(old.names(), ["curtain_0004.obj", "curtain_0005.obj", "curtain_0009.obj"]);
        let error = seq.refuse_old(&old).unwrap_err().to_string();
        assert_eq!(
            error,
            format!(
                "{} already holds 3 frames of a curtain_####.obj sequence that the new one does not replace \
                 (frames 4, 5, 9: curtain_0004.obj … curtain_0009.obj): a loader would play them mixed with the \
                 new frames; write the sequence into another folder, or replace the old one",
                dir.path().display()
            )
        );
        let missing = SequenceFiles::new(&dir.path().join("new"), "curtain", "obj", 0..=3);
        assert!(missing.old_frames().unwrap().is_empty());
        let long = shortened(&frame_list(&(0..100).map(|f| f * 2).collect::<Vec<_>>()));
        assert!(long.starts_with("0, 2, 4, ") && long.ends_with("0, …") && long.chars().count() <= 83, "{long}");
    }
}
