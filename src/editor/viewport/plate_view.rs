//! The background plate in the viewport: its pictures decoded on a worker
//! thread (a 4K plate takes longer than a frame), uploaded as egui textures
//! and kept in a cache of bounded size, so scrubbing back and forth shows
//! them at once. While a frame's picture is on its way the nearest one
//! already shown stands in; a wrong path or a broken file is a message.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex, mpsc};

use eframe::egui;

use crate::scene::{Plate, PlateFiles, load_plate_image};

/// Most pictures kept as textures, and most bytes they may take together.
const MAX_CACHED_PICTURES: usize = 48;
const MAX_CACHED_BYTES: usize = 384 * 1024 * 1024;
/// Requests older than the newest few are dropped: scrubbing fast asks for
/// many frames, and only where the playhead is now matters.
const MAX_WAITING_REQUESTS: usize = 3;

/// A decoded picture, or why not, for a file number.
type Decoded = (PathBuf, i64, Result<egui::ColorImage, String>);

/// The requests the worker takes, newest first, and a signal when one
/// comes (or the view closes: `closed`, and the worker ends).
#[derive(Default)]
struct Requests {
    queue: Mutex<(VecDeque<(PathBuf, i64)>, bool)>,
    ready: Condvar,
}

struct Cached {
    path: PathBuf,
    number: i64,
    texture: egui::TextureHandle,
    bytes: usize,
    last_used: u64,
}

/// What the viewport shows of the plate at a frame.
pub enum PlateShown {
    /// The picture (of the frame, or the nearest one while it loads) and its size in pixels.
    Picture(egui::TextureId, [usize; 2]),
    /// Nothing yet: the first picture is on its way.
    Loading,
    /// The plate cannot be shown: why, in a user's words.
    Error(String),
}

pub struct PlateView {
    /// The plate and folder `files` was scanned for.
    scanned: Option<(Plate, PathBuf)>,
    files: Option<Result<PlateFiles, String>>,
    cache: Vec<Cached>,
    failed: Vec<(PathBuf, String)>,
    waiting: Vec<PathBuf>,
    requests: Arc<Requests>,
    results: Option<mpsc::Receiver<Decoded>>,
    clock: u64,
    /// How much of the plate shows in the viewport (a view setting; renders use the scene's `opacity`).
    pub opacity: f32,
}

impl Default for PlateView {
    fn default() -> Self {
        PlateView {
            scanned: None,
            files: None,
            cache: Vec::new(),
            failed: Vec::new(),
            waiting: Vec::new(),
            requests: Arc::new(Requests::default()),
            results: None,
            clock: 0,
            opacity: 1.0,
        }
    }
}

impl PlateView {
    /// What to show of `plate` (beside the scene in `folder`) at `frame`:
    /// asks the worker for pictures not yet decoded and takes what it has done.
    pub fn shown(&mut self, ctx: &egui::Context, plate: &Plate, folder: &Path, frame: f64) -> PlateShown {
        self.rescan_if_changed(plate, folder);
        self.take_decoded(ctx);
        let files = match &self.files {
            Some(Ok(files)) => files,
            Some(Err(why)) => return PlateShown::Error(why.clone()),
            None => return PlateShown::Loading,
        };
        let at = frame.round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32;
        let (wanted, ahead) = (files.frame(at), files.frame(at.saturating_add(1)));
        self.clock += 1;
        if let Some((_, why)) = self.failed.iter().find(|(path, _)| *path == wanted.path) {
            return PlateShown::Error(why.clone());
        }
        if let Some(cached) = self.cache.iter_mut().find(|c| c.path == wanted.path) {
            cached.last_used = self.clock;
            let shown = PlateShown::Picture(cached.texture.id(), cached.texture.size());
            self.request(ctx, ahead.path, ahead.number);
            return shown;
        }
        self.request(ctx, wanted.path, wanted.number);
        // The nearest picture at hand stands in (a sequence changes little frame to frame).
        match self.cache.iter().min_by_key(|c| c.number.abs_diff(wanted.number)) {
            Some(nearest) => PlateShown::Picture(nearest.texture.id(), nearest.texture.size()),
            None => PlateShown::Loading,
        }
    }

    /// Scans the plate's files again when the plate or the scene's folder changed.
    fn rescan_if_changed(&mut self, plate: &Plate, folder: &Path) {
        let same_files = self.scanned.as_ref().is_some_and(|(p, f)| p.file == plate.file && f == folder);
        if same_files && self.scanned.as_ref().is_some_and(|(p, _)| p.frame_offset == plate.frame_offset) {
            return;
        }
        let files = PlateFiles::scan(plate, folder);
        // Pictures of files that are still named stay; a new file name starts afresh.
        if !same_files {
            self.cache.clear();
            self.failed.clear();
        }
        self.files = Some(files);
        self.scanned = Some((plate.clone(), folder.to_owned()));
    }

    fn request(&mut self, ctx: &egui::Context, path: PathBuf, number: i64) {
        if self.waiting.contains(&path) || self.cache.iter().any(|c| c.path == path) {
            return;
        }
        if self.failed.iter().any(|(p, _)| *p == path) {
            return;
        }
        if self.results.is_none() {
            match spawn_worker(ctx.clone(), self.requests.clone()) {
                Ok(results) => self.results = Some(results),
                Err(why) => {
                    self.files = Some(Err(why));
                    return;
                }
            }
        }
        let Ok(mut guard) = self.requests.queue.lock() else {
            return;
        };
        let queue = &mut guard.0;
        queue.push_front((path.clone(), number));
        while queue.len() > MAX_WAITING_REQUESTS {
            if let Some((dropped, _)) = queue.pop_back() {
                self.waiting.retain(|p| *p != dropped);
            }
        }
        self.waiting.push(path);
        self.requests.ready.notify_one();
    }

    fn take_decoded(&mut self, ctx: &egui::Context) {
        let Some(results) = &self.results else {
            return;
        };
        let decoded: Vec<Decoded> = results.try_iter().collect();
        for (path, number, picture) in decoded {
            self.waiting.retain(|p| *p != path);
            match picture {
                Ok(image) => {
                    let bytes = image.pixels.len() * 4;
                    let name = format!("plate {}", path.display());
                    let texture = ctx.load_texture(name, image, egui::TextureOptions::LINEAR);
                    self.clock += 1;
                    self.cache.push(Cached { path, number, texture, bytes, last_used: self.clock });
                    self.evict();
                }
                Err(why) => self.failed.push((path, why)),
            }
        }
    }

    /// Drops the least recently shown pictures past the cache's bounds.
    fn evict(&mut self) {
        while self.cache.len() > MAX_CACHED_PICTURES
            || (self.cache.len() > 1 && self.cache.iter().map(|c| c.bytes).sum::<usize>() > MAX_CACHED_BYTES)
        {
            let Some(oldest) = self.cache.iter().enumerate().min_by_key(|(_, c)| c.last_used).map(|(i, _)| i) else {
                return;
            };
            self.cache.swap_remove(oldest);
        }
    }
}

impl Drop for PlateView {
    fn drop(&mut self) {
        if let Ok(mut guard) = self.requests.queue.lock() {
            guard.1 = true;
        }
        self.requests.ready.notify_all();
    }
}

/// A thread that decodes the newest request, over and over, until the view closes.
fn spawn_worker(ctx: egui::Context, requests: Arc<Requests>) -> Result<mpsc::Receiver<Decoded>, String> {
    let (sender, receiver) = mpsc::channel();
    let spawned = std::thread::Builder::new().name("plate loader".into()).spawn(move || {
        loop {
            let Ok(mut guard) = requests.queue.lock() else {
                return;
            };
            while guard.0.is_empty() && !guard.1 {
                guard = match requests.ready.wait(guard) {
                    Ok(guard) => guard,
                    Err(_) => return,
                };
            }
            let Some((path, number)) = guard.0.pop_front().filter(|_| !guard.1) else {
                return;
            };
            drop(guard);
            let picture = load_plate_image(&path).map(|image| {
                let size = [image.width as usize, image.height as usize];
                egui::ColorImage::from_rgba_unmultiplied(size, &image.pixels)
            });
            if sender.send((path, number, picture)).is_err() {
                return;
            }
            ctx.request_repaint();
        }
    });
    spawned.map_err(|error| format!("cannot start the plate loader: {error}"))?;
    Ok(receiver)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::RgbaImage;
    use crate::scene::Param;

    fn plate(file: &str) -> Plate {
        Plate { file: file.to_owned(), frame_offset: 0, opacity: Param::Constant(1.0) }
    }

    /// Asks until the worker has answered (or a few seconds pass).
    fn settled(view: &mut PlateView, ctx: &egui::Context, plate: &Plate, folder: &Path, frame: f64) -> PlateShown {
        for _ in 0..400 {
            match view.shown(ctx, plate, folder, frame) {
                PlateShown::Loading => std::thread::sleep(std::time::Duration::from_millis(10)),
                shown => return shown,
            }
        }
        PlateShown::Loading
    }

    #[test]
    fn pictures_load_off_the_ui_thread_and_stay_cached() {
        let dir = tempfile::tempdir().unwrap();
        for (number, width) in [(1, 4), (2, 6)] {
            let image = RgbaImage { width, height: 2, pixels: vec![200; width as usize * 8] };
            let mut file = std::fs::File::create(dir.path().join(format!("bg_{number}.png"))).unwrap();
            crate::export::write_png(&image, &mut file).unwrap();
        }
        let ctx = egui::Context::default();
        let mut view = PlateView::default();
        let plate = plate("bg_#.png");
        let PlateShown::Picture(_, size) = settled(&mut view, &ctx, &plate, dir.path(), 1.0) else {
            panic!("frame 1's picture never came");
        };
        assert_eq!(size, [4, 2]);
        // Frame 7 has no file: it holds the nearest, frame 2's.
        for _ in 0..400 {
            if let PlateShown::Picture(_, [6, 2]) = view.shown(&ctx, &plate, dir.path(), 7.0) {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        assert!(matches!(view.shown(&ctx, &plate, dir.path(), 7.0), PlateShown::Picture(_, [6, 2])));
        assert_eq!(view.cache.len(), 2, "both pictures kept");
    }

    #[test]
    fn a_wrong_path_or_a_broken_file_is_a_message() {
        let dir = tempfile::tempdir().unwrap();
        let ctx = egui::Context::default();
        let mut view = PlateView::default();
        let PlateShown::Error(why) = view.shown(&ctx, &plate("nowhere.png"), dir.path(), 0.0) else {
            panic!("a missing plate is an error");
        };
        assert!(why.contains("nowhere.png"), "{why}");
        std::fs::write(dir.path().join("broken.png"), b"not a picture").unwrap();
        let PlateShown::Error(why) = settled(&mut view, &ctx, &plate("broken.png"), dir.path(), 0.0) else {
            panic!("a broken plate is an error");
        };
        assert!(why.contains("broken.png") && why.contains("PNG"), "{why}");
    }
}
