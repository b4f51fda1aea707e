//! Long work started from a window (File ▸ Export, File ▸ Render) on a
//! worker thread: its progress, its Cancel and its result, so the window
//! never waits on it and the UI keeps drawing.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use eframe::egui;

/// Work running on its own thread, producing a `T`.
pub(in crate::editor) struct WorkerJob<T> {
    handle: JoinHandle<T>,
    done: Arc<AtomicU64>,
    /// 0 until the work knows how much there is.
    total: Arc<AtomicU64>,
    cancel: Arc<AtomicBool>,
    started: Instant,
}

impl<T: Send + 'static> WorkerJob<T> {
    /// Runs `work` on a new thread. It reports `(done, total)` through the
    /// callback it is given (each report repaints the window within a tenth
    /// of a second) and should stop soon after the flag it is given is set.
    pub(in crate::editor) fn start(
        ctx: egui::Context,
        work: impl FnOnce(&mut dyn FnMut(u64, u64), &AtomicBool) -> T + Send + 'static,
    ) -> WorkerJob<T> {
        let (done, total) = (Arc::new(AtomicU64::new(0)), Arc::new(AtomicU64::new(0)));
        let cancel = Arc::new(AtomicBool::new(false));
        let (worker_done, worker_total, worker_cancel) = (Arc::clone(&done), Arc::clone(&total), Arc::clone(&cancel));
        let handle = std::thread::spawn(move || {
            let mut progress = |d: u64, t: u64| {
                worker_done.store(d, Ordering::Relaxed);
                worker_total.store(t, Ordering::Relaxed);
                ctx.request_repaint_after(Duration::from_millis(100));
            };
            let result = work(&mut progress, &worker_cancel);
            ctx.request_repaint();
            result
        });
        WorkerJob { handle, done, total, cancel, started: Instant::now() }
    }

    /// Whether the work has ended (returned or panicked): [`Self::join`] will not wait.
    pub(in crate::editor) fn is_finished(&self) -> bool {
        self.handle.is_finished()
    }

    /// The work's result (`Err` when its thread panicked) and how long it
    /// ran; waits for it unless [`Self::is_finished`].
    pub(in crate::editor) fn join(self) -> (std::thread::Result<T>, Duration) {
        let elapsed = self.started.elapsed();
        (self.handle.join(), elapsed)
    }
}

impl<T> WorkerJob<T> {
    /// Asks the work to stop; it ends with whatever it returns for a cancel.
    pub(in crate::editor) fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// A progress bar, `done of total units, seconds` (or `preparing` while
    /// the total is unknown) and Cancel.
    pub(in crate::editor) fn progress_ui(&self, ui: &mut egui::Ui, units: &str, preparing: &str) {
        let (done, total) = (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed));
        let elapsed = self.started.elapsed().as_secs_f64();
        let fraction = if total == 0 { 0.0 } else { done as f32 / total as f32 };
        ui.add(egui::ProgressBar::new(fraction).show_percentage().animate(true));
        ui.horizontal(|ui| {
            if total == 0 {
                ui.label(format!("{preparing}, {elapsed:.1} s"));
            } else {
                ui.label(format!("{done} of {total} {units}, {elapsed:.1} s"));
            }
            if ui.button("Cancel").clicked() {
                self.cancel();
            }
        });
    }
}
