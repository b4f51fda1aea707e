//! The editor window's size: the last one the user left it at, kept in a
//! small text file beside the recent-files list, and fitted to the screen
//! it opens on.
//!
//! Like the recent-files list it is only a convenience: a missing, unreadable
//! or nonsensical file gives the default size, never an error.

use std::path::Path;

use eframe::egui::{Vec2, vec2};

use crate::atomic_file::write_atomically;

/// The file's name inside the config directory.
pub const WINDOW_SIZE_NAME: &str = "window-size.txt";

/// The size the window opens at the first time, points: room for the
/// panels, the grid editor and the viewport, before fitting to the screen.
pub const DEFAULT_WINDOW_SIZE: Vec2 = vec2(1600.0, 1000.0);

/// The smallest size kept or opened at, points: the panels still fit.
pub const MIN_WINDOW_SIZE: Vec2 = vec2(800.0, 560.0);

/// Largest size read back, points a side: anything larger was not written by Drape.
const MAX_SIDE: f32 = 16384.0;

/// Room left around the window on the screen, points: the desktop's panels and the title bar.
const SCREEN_MARGIN: Vec2 = vec2(40.0, 80.0);

/// The size saved in `file` (`WIDTH HEIGHT` in points), if it holds one
/// between [`MIN_WINDOW_SIZE`] and 16384 a side.
pub fn load(file: &Path) -> Option<Vec2> {
    let bytes = crate::scene::read_capped(file, 256).ok()?;
    let text = std::str::from_utf8(&bytes).ok()?;
    let mut numbers = text.split_whitespace().map(str::parse::<f32>);
    let (Some(Ok(width)), Some(Ok(height)), None) = (numbers.next(), numbers.next(), numbers.next()) else {
        return None;
    };
    let size = vec2(width, height);
    let fits = |v: f32, min: f32| v.is_finite() && (min..=MAX_SIDE).contains(&v);
    (fits(size.x, MIN_WINDOW_SIZE.x) && fits(size.y, MIN_WINDOW_SIZE.y)).then_some(size)
}

/// Writes `size` to `file` (atomically, making its folder when missing).
pub fn save(file: &Path, size: Vec2) -> std::io::Result<()> {
    if let Some(folder) = file.parent() {
        std::fs::create_dir_all(folder)?;
    }
    let text = format!("{} {}\n", size.x.round(), size.y.round());
    write_atomically(file, |out| out.write_all(text.as_bytes()))
}

/// `wanted` made to fit a screen of `screen` points (with room for the
/// desktop around it), never below [`MIN_WINDOW_SIZE`].
pub fn fitted(wanted: Vec2, screen: Vec2) -> Vec2 {
    let room = (screen - SCREEN_MARGIN).max(MIN_WINDOW_SIZE);
    wanted.min(room).max(MIN_WINDOW_SIZE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_size_reads_back_and_nonsense_reads_as_none() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("config").join(WINDOW_SIZE_NAME);
        assert_eq!(load(&file), None, "no file yet");
        save(&file, vec2(1712.4, 1003.6)).unwrap();
        assert_eq!(load(&file), Some(vec2(1712.0, 1004.0)));
        for nonsense in ["", "1600", "1600 1000 3", "wide tall", "NaN 900", "100 100", "99999 900"] {
            std::fs::write(&file, nonsense).unwrap();
            assert_eq!(load(&file), None, "{nonsense:?}");
        }
    }

    #[test]
    fn the_size_fits_the_screen_and_keeps_the_panels_room() {
        assert_eq!(fitted(DEFAULT_WINDOW_SIZE, vec2(2560.0, 1440.0)), DEFAULT_WINDOW_SIZE);
        assert_eq!(fitted(DEFAULT_WINDOW_SIZE, vec2(1366.0, 768.0)), vec2(1326.0, 688.0));
        assert_eq!(fitted(DEFAULT_WINDOW_SIZE, vec2(640.0, 480.0)), MIN_WINDOW_SIZE);
    }
}
