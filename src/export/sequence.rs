//! Frame sequences on disk: the numbered file names of an OBJ sequence (and
//! of `drape render`'s PNG sequences) and the directory they are written into.

use std::fs;
use std::ops::RangeInclusive;
use std::path::Path;

use super::error::ExportError;

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
}
