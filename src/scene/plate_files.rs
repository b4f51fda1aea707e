//! A plate's files on disk: which numbers of a sequence exist, which file a
//! frame shows (the nearest one where its own is missing) and its picture.

use std::path::{Path, PathBuf};

use super::mesh_files::read_file_bytes;
use super::plate::{Plate, PlatePattern};
use crate::image::RgbaImage;

/// A plate resolved against the scene file's folder.
#[derive(Clone, Debug, PartialEq)]
pub struct PlateFiles {
    /// The `file` as the scene writes it, for messages.
    pub file: String,
    pattern: PlatePattern,
    folder: PathBuf,
    frame_offset: i64,
    /// The numbers of a sequence's files on disk, ascending; empty for one image.
    numbers: Vec<i64>,
}

/// Which file a frame shows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlateFrame {
    pub path: PathBuf,
    /// The file's number (a sequence's; 0 for one image): frames showing the
    /// same number show the same picture.
    pub number: i64,
    /// Its own file is missing: it holds the nearest one's.
    pub held: bool,
}

impl PlateFiles {
    /// Finds the plate's files next to the scene file in `scene_folder`; an
    /// error says what is missing where (no such image, no file of the
    /// sequence in its folder).
    pub fn scan(plate: &Plate, scene_folder: &Path) -> Result<PlateFiles, String> {
        let pattern = PlatePattern::parse(&plate.file)?;
        let mut files = PlateFiles {
            file: plate.file.clone(),
            pattern,
            folder: scene_folder.to_owned(),
            frame_offset: i64::from(plate.frame_offset),
            numbers: Vec::new(),
        };
        if !files.pattern.is_sequence() {
            let path = scene_folder.join(&plate.file);
            if !path.is_file() {
                return Err(format!("plate: there is no image {:?} ({})", plate.file, path.display()));
            }
            return Ok(files);
        }
        let first = scene_folder.join(files.pattern.file_name(0));
        let dir = first.parent().map_or_else(|| scene_folder.to_owned(), Path::to_owned);
        let entries = std::fs::read_dir(&dir).map_err(|error| {
            format!("plate: cannot read the folder of {:?} ({}: {error})", plate.file, dir.display())
        })?;
        files.numbers = entries
            .filter_map(|entry| entry.ok()?.file_name().to_str().and_then(|name| files.pattern.number_in(name)))
            .collect();
        files.numbers.sort_unstable();
        files.numbers.dedup();
        if files.numbers.is_empty() {
            return Err(format!(
                "plate: no file in {} is named like {:?} (e.g. {})",
                dir.display(),
                plate.file,
                files.pattern.file_name(1)
            ));
        }
        Ok(files)
    }

    pub fn is_sequence(&self) -> bool {
        self.pattern.is_sequence()
    }

    /// How many files a sequence has (1 for one image).
    pub fn count(&self) -> usize {
        self.numbers.len().max(1)
    }

    /// The lowest and highest numbers of a sequence's files.
    pub fn number_range(&self) -> Option<(i64, i64)> {
        Some((*self.numbers.first()?, *self.numbers.last()?))
    }

    /// The file frame `frame` shows: number `frame + frame_offset`, or the
    /// nearest number on disk (the earlier of two as near).
    pub fn frame(&self, frame: i32) -> PlateFrame {
        if !self.is_sequence() {
            return PlateFrame { path: self.folder.join(&self.file), number: 0, held: false };
        }
        let wanted = i64::from(frame) + self.frame_offset;
        let number = match self.numbers.binary_search(&wanted) {
            Ok(_) => wanted,
            Err(at) => {
                let before = at.checked_sub(1).map(|i| self.numbers[i]);
                let after = self.numbers.get(at).copied();
                match (before, after) {
                    (Some(b), Some(a)) => {
                        if wanted - b <= a - wanted {
                            b
                        } else {
                            a
                        }
                    }
                    (Some(b), None) => b,
                    (None, Some(a)) => a,
                    (None, None) => wanted,
                }
            }
        };
        let path = self.folder.join(self.pattern.file_name(number));
        PlateFrame { path, number, held: number != wanted }
    }

    /// The frames of `first..=last` whose own file is missing.
    pub fn missing(&self, first: i32, last: i32) -> Vec<i32> {
        (first..=last).filter(|&frame| self.frame(frame).held).collect()
    }

    /// The picture frame `frame` shows.
    pub fn load(&self, frame: i32) -> Result<RgbaImage, String> {
        load_plate_image(&self.frame(frame).path)
    }
}

/// The PNG or JPEG at `path`, or why not in a user's words.
pub fn load_plate_image(path: &Path) -> Result<RgbaImage, String> {
    let bytes = read_file_bytes(path).map_err(|why| format!("plate {}: {why}", path.display()))?;
    RgbaImage::decode(&bytes, None).map_err(|why| format!("plate {}: {why}", path.display()))
}

/// Frames as a short list: `3, 7–9, 12` (runs of three or more as a range).
pub fn frame_list(frames: &[i32]) -> String {
    let mut parts = Vec::new();
    let mut index = 0;
    while index < frames.len() {
        let start = frames[index];
        let mut end = index;
        while end + 1 < frames.len() && frames[end + 1] == frames[end] + 1 {
            end += 1;
        }
        match end - index {
            0 => parts.push(start.to_string()),
            1 => parts.extend([start.to_string(), frames[end].to_string()]),
            _ => parts.push(format!("{start}–{}", frames[end])),
        }
        index = end + 1;
    }
    parts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder_with(names: &[&str]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("plates")).unwrap();
        for name in names {
            std::fs::write(dir.path().join("plates").join(name), b"").unwrap();
        }
        dir
    }

    fn plate(file: &str, frame_offset: i32) -> Plate {
        Plate { file: file.to_owned(), frame_offset, opacity: super::super::Param::Constant(1.0) }
    }

    #[test]
    fn a_missing_frame_holds_the_nearest_file_the_earlier_of_two() {
        let dir = folder_with(&["bg_0001.png", "bg_0002.png", "bg_0005.png", "bg_0008.png", "notes.txt"]);
        let files = PlateFiles::scan(&plate("plates/bg_####.png", 0), dir.path()).unwrap();
        assert_eq!(files.number_range(), Some((1, 8)));
        assert_eq!(files.count(), 4);
        let number = |frame| files.frame(frame).number;
        assert_eq!([number(1), number(2), number(3), number(4), number(6), number(7)], [1, 2, 2, 5, 5, 8]);
        assert_eq!([number(-10), number(100)], [1, 8], "before the first and after the last");
        assert!(!files.frame(5).held && files.frame(6).held);
        assert_eq!(files.frame(3).path, dir.path().join("plates/bg_0002.png"));
        assert_eq!(files.missing(0, 9), vec![0, 3, 4, 6, 7, 9]);
    }

    #[test]
    fn the_offset_shifts_frames_onto_file_numbers() {
        let dir = folder_with(&["bg_1001.png", "bg_1002.png"]);
        let files = PlateFiles::scan(&plate("plates/bg_####.png", 1000), dir.path()).unwrap();
        assert_eq!(files.frame(2).number, 1002);
        assert!(files.missing(1, 2).is_empty());
    }

    #[test]
    fn a_wrong_path_says_what_is_missing_where() {
        let dir = folder_with(&["bg_0001.png"]);
        let none = PlateFiles::scan(&plate("plates/fg_####.png", 0), dir.path()).unwrap_err();
        assert!(none.contains("no file") && none.contains("fg_0001.png"), "{none}");
        let still = PlateFiles::scan(&plate("plates/sky.png", 0), dir.path()).unwrap_err();
        assert!(still.contains("no image \"plates/sky.png\""), "{still}");
        let folder = PlateFiles::scan(&plate("elsewhere/bg_##.png", 0), dir.path()).unwrap_err();
        assert!(folder.contains("cannot read the folder"), "{folder}");
        let broken = load_plate_image(&dir.path().join("plates/bg_0001.png")).unwrap_err();
        assert!(broken.contains("bg_0001.png") && broken.contains("PNG and JPEG"), "{broken}");
    }

    #[test]
    fn one_image_shows_at_every_frame() {
        let dir = folder_with(&["sky.png"]);
        let files = PlateFiles::scan(&plate("plates/sky.png", 0), dir.path()).unwrap();
        assert_eq!(files.frame(-4), files.frame(400));
        assert!(files.missing(0, 100).is_empty());
    }

    #[test]
    fn frame_lists_run_together() {
        assert_eq!(frame_list(&[3, 7, 8, 9, 12, 13]), "3, 7–9, 12, 13");
        assert_eq!(frame_list(&[]), "");
    }
}
