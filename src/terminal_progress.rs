//! Progress of long `check`, `export` and `render` work on stderr. On a
//! terminal: one status line overwritten in place (`\r`), or a bar of
//! frames, erased when the work is done, so the terminal keeps only the
//! results. When stderr is a pipe or a file (scripts, farm logs, tests) a
//! key whose rest shape takes longer than [`slow_key`] says so in one plain
//! line, and nothing else is written.

use std::io::{self, IsTerminal, Write};
use std::ops::ControlFlow;
use std::sync::Arc;
use std::time::{Duration, Instant};

use drape::animate::attachments::posed_key;
use drape::animate::{Evaluator, KeyShape};
use drape::scene::{Key, Scene};
use drape::shape::RelaxProgress;

/// How long a key's rest shape may take before a stderr that is not a
/// terminal hears of it: 5 s, or `DRAPE_SLOW_KEY_SECS` (0 names every key).
fn slow_key() -> Duration {
    let secs = std::env::var("DRAPE_SLOW_KEY_SECS").ok().and_then(|v| v.trim().parse::<f64>().ok());
    secs.filter(|s| s.is_finite() && *s >= 0.0).map_or(Duration::from_secs(5), Duration::from_secs_f64)
}

/// Redraws at most this often: fast enough to read as live, rare enough to cost nothing.
const REDRAW_EVERY: Duration = Duration::from_millis(100);

/// One status line on stderr (see the module doc).
pub struct StatusLine {
    enabled: bool,
    shown: bool,
    last_drawn: Option<Instant>,
}

impl StatusLine {
    /// A status line that draws only when stderr is a terminal.
    pub fn on_stderr() -> StatusLine {
        StatusLine { enabled: io::stderr().is_terminal(), shown: false, last_drawn: None }
    }

    /// Shows `text()` in place of the previous status, unless the last one is
    /// younger than a tenth of a second (`text` is then not even called).
    pub fn show(&mut self, text: impl FnOnce() -> String) {
        if !self.enabled || self.last_drawn.is_some_and(|at| at.elapsed() < REDRAW_EVERY) {
            return;
        }
        self.draw(&text());
    }

    /// Shows `text` now, however recently the line was drawn (a new phase of work).
    pub fn show_now(&mut self, text: &str) {
        if self.enabled {
            self.draw(text);
        }
    }

    fn draw(&mut self, text: &str) {
        // `\x1b[K` erases what a longer earlier status left to the right.
        let mut stderr = io::stderr().lock();
        let _ = write!(stderr, "\r{text}\x1b[K");
        let _ = stderr.flush();
        self.shown = true;
        self.last_drawn = Some(Instant::now());
    }

    /// Writes `text` as a line of its own when stderr is not a terminal
    /// (where the status line is drawn, it already says as much).
    pub fn note_plainly(&mut self, text: &str) {
        if !self.enabled {
            let mut stderr = io::stderr().lock();
            let _ = writeln!(stderr, "{text}");
            let _ = stderr.flush();
        }
    }

    /// Erases the status line, leaving the cursor where it began.
    pub fn clear(&mut self) {
        if self.shown {
            let mut stderr = io::stderr().lock();
            let _ = write!(stderr, "\r\x1b[K");
            let _ = stderr.flush();
            self.shown = false;
            self.last_drawn = None;
        }
    }
}

impl Drop for StatusLine {
    fn drop(&mut self) {
        self.clear();
    }
}

/// A bar counting `total` frames, `what` naming them (`frames`, `frames
/// evaluated`); hidden unless stderr is a terminal.
pub fn frame_bar(total: u64, what: &'static str) -> indicatif::ProgressBar {
    if !io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    let style = indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}  {per_sec}  eta {eta}")
        .expect("the progress template is valid");
    bar.set_style(style);
    bar.set_message(what);
    bar
}

/// Builds the rest shapes of `keys` (those not cached yet) into `evaluator`'s
/// cache, showing on `status` which key is being approximated and how far
/// its relaxation has come: `relaxing key 2/5 (frame 48): sweep 1200/100000
/// on the 1024 × 256 grid`; where stderr is not a terminal, a key that takes
/// longer than [`slow_key`] says so once, in a plain line. The shapes equal
/// what the evaluator would build by itself; only the progress is new.
pub fn build_key_shapes<'k>(
    evaluator: &mut Evaluator,
    scene: &Scene,
    keys: impl ExactSizeIterator<Item = &'k Key>,
    status: &mut StatusLine,
) {
    let count = keys.len();
    let slow = slow_key();
    for (index, key) in keys.enumerate() {
        let (cloth, obstacles) = (&scene.cloth, evaluator.key_obstacles(scene, key));
        // Attached pins where their attachments are at the key's frame.
        let key = &*posed_key(scene, key);
        if evaluator.cache().get(cloth, key, &obstacles).is_some() {
            continue;
        }
        let which = format!("key {}/{count} (frame {})", index + 1, key.frame);
        let pins = key.pins.len();
        status.show_now(&format!("approximating {which} from {pins} pin{}", if pins == 1 { "" } else { "s" }));
        let started = Instant::now();
        let mut told = false;
        let mut report = |progress: RelaxProgress| {
            if !told && started.elapsed() >= slow {
                told = true;
                status.note_plainly(&format!(
                    "drape: key {}/{count} (frame {}) is still relaxing after {:.0} s: sweep {}/{} on the {} × {} grid",
                    index + 1,
                    key.frame,
                    started.elapsed().as_secs_f64(),
                    progress.iteration,
                    progress.max_iterations,
                    progress.cols,
                    progress.rows
                ));
            }
            status.show(|| {
                format!(
                    "relaxing {which}: sweep {}/{} on the {} × {} grid",
                    progress.iteration, progress.max_iterations, progress.cols, progress.rows
                )
            });
            ControlFlow::Continue(())
        };
        // The report never breaks, so the build is never cancelled.
        if let Ok(shape) = KeyShape::build_with(cloth, key, &obstacles, &mut report) {
            evaluator.cache_mut().insert(cloth, key, &obstacles, Arc::new(shape));
        }
    }
    status.clear();
}
