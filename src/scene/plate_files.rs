//! A plate's files on disk: which numbers of a sequence exist, which file a
//! frame shows (the nearest one where its own is missing), whether each is a
//! picture Drape reads (its header, [`read_plate_header`]) and its picture.

use std::path::{Path, PathBuf};

use super::error::SceneError;
use super::io::MAX_SCENE_FILE_BYTES;
use super::locate::locate;
use super::mesh_files::read_file_bytes;
use super::plate::{Plate, PlatePattern};
use super::plate_header::{PlatePicture, read_plate_header};
use super::read_capped::read_capped;
use super::types::Scene;
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
    /// sequence in its folder) or, for one image, why it is no picture Drape
    /// reads (a folder, a file that is too short, cut short or too large:
    /// its header is read).
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
            if !path.exists() {
                return Err(format!("plate: there is no image {:?} ({})", plate.file, path.display()));
            }
            read_plate_header(&path).map_err(|why| format!("plate: cannot use {:?}: {why}", plate.file))?;
            return Ok(files);
        }
        let first = scene_folder.join(files.pattern.file_name(0));
        let dir = first.parent().map_or_else(|| scene_folder.to_owned(), Path::to_owned);
        // A scene named bare (`drape render shot.ron`) lies in the working folder.
        let dir = if dir.as_os_str().is_empty() { PathBuf::from(".") } else { dir };
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

    /// Reads the header of every file frames `first..=last` show, each
    /// once: the picture the first frame shows and how many files were
    /// read, or the first file that is no picture Drape reads, with the
    /// frame that first shows it.
    pub fn check_pictures(&self, first: i32, last: i32) -> Result<(PlatePicture, usize), String> {
        let mut shown: Option<PlatePicture> = None;
        let (mut files_read, mut last_number) = (0, None);
        for frame in first..=last.max(first) {
            let file = self.frame(frame);
            // Frames run through the files in order: a number repeats only in a run.
            if last_number == Some(file.number) {
                continue;
            }
            last_number = Some(file.number);
            let picture = read_plate_header(&file.path).map_err(|why| {
                let name = self.pattern.file_name(file.number);
                if self.is_sequence() {
                    format!("plate: cannot use {name:?} (shown at frame {frame}): {why}")
                } else {
                    format!("plate: cannot use {name:?}: {why}")
                }
            })?;
            files_read += 1;
            if shown.is_none() {
                shown = Some(picture);
            }
        }
        let Some(picture) = shown else { return Err("plate: no frame shows a file".to_owned()) };
        Ok((picture, files_read))
    }
}

/// A plate vetted as `drape check` vets it: its files found and the header
/// of each file the timeline shows read.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckedPlate {
    pub files: PlateFiles,
    /// What the timeline's first frame shows.
    pub first: PlatePicture,
    /// How many files the timeline shows, each one's header read.
    pub files_read: usize,
}

/// The plate of `scene`, whose file is `scene_file`, vetted: its files
/// found beside the scene file and the header of every file the timeline
/// shows read ([`PlateFiles::check_pictures`]), so a folder, a file too
/// short, cut short, of the wrong kind or too large is found before any
/// frame is drawn. An error points at the plate's `file` in the scene file
/// (which is read again for that). `None` when the scene has no plate.
pub fn check_plate(scene: &Scene, scene_file: &Path) -> Result<Option<CheckedPlate>, SceneError> {
    let Some(plate) = &scene.plate else { return Ok(None) };
    let folder = scene_file.parent().unwrap_or(Path::new(""));
    let (start, end) = (scene.timeline.start, scene.timeline.end);
    let checked = PlateFiles::scan(plate, folder).and_then(|files| {
        let (first, files_read) = files.check_pictures(start, end)?;
        Ok(CheckedPlate { files, first, files_read })
    });
    checked.map(Some).map_err(|why| {
        let text = read_capped(scene_file, MAX_SCENE_FILE_BYTES).ok();
        let at = text.as_deref().and_then(|bytes| locate(std::str::from_utf8(bytes).ok()?, "plate.file"));
        SceneError::invalid(&scene_file.display().to_string(), at, why)
    })
}

/// The PNG or JPEG at `path`, or why not in a user's words. Its header is
/// read first, so a file that is no picture, or claims one too large, is
/// refused before it is read whole.
pub fn load_plate_image(path: &Path) -> Result<RgbaImage, String> {
    read_plate_header(path).map_err(|why| format!("plate {}: {why}", path.display()))?;
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

    /// A folder holding `plates/NAME` for each name: a 2 × 2 PNG.
    fn folder_with(names: &[&str]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("plates")).unwrap();
        for name in names {
            std::fs::write(dir.path().join("plates").join(name), tiny_png()).unwrap();
        }
        dir
    }

    fn tiny_png() -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, 2, 2);
        encoder.set_color(png::ColorType::Rgba);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[90; 16]).unwrap();
        writer.finish().unwrap();
        bytes
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
        std::fs::write(dir.path().join("plates/bg_0001.png"), b"").unwrap();
        let broken = load_plate_image(&dir.path().join("plates/bg_0001.png")).unwrap_err();
        assert!(broken.contains("bg_0001.png") && broken.contains("0 bytes long"), "{broken}");
        std::fs::create_dir(dir.path().join("plates/sky.png")).unwrap();
        let folder = PlateFiles::scan(&plate("plates/sky.png", 0), dir.path()).unwrap_err();
        assert_eq!(folder, "plate: cannot use \"plates/sky.png\": it is a folder, not a regular file");
    }

    #[test]
    fn every_file_the_frames_show_is_read_once_and_a_bad_one_named() {
        let dir = folder_with(&["bg_0001.png", "bg_0002.png", "bg_0005.png"]);
        let files = PlateFiles::scan(&plate("plates/bg_####.png", 0), dir.path()).unwrap();
        let (first, read) = files.check_pictures(0, 9).unwrap();
        assert_eq!((first.width_px, first.height_px, read), (2, 2, 3));
        assert_eq!(files.check_pictures(0, 1).unwrap().1, 1, "frames 0 and 1 both show file 1");
        std::fs::write(dir.path().join("plates/bg_0005.png"), &tiny_png()[..40]).unwrap();
        let cut = files.check_pictures(0, 9).unwrap_err();
        assert!(
            cut.starts_with("plate: cannot use \"plates/bg_0005.png\" (shown at frame 4): the PNG is cut short"),
            "{cut}"
        );
        assert!(files.check_pictures(0, 3).is_ok(), "frames that show file 5 are not asked about");
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
