//! Progress of long `check`, `export` and `render` work on stderr. On a
//! terminal: one status line overwritten in place (`\r`), or a bar of
//! frames, erased when the work is done, so the terminal keeps only the
//! results. When stderr is a pipe or a file (scripts, farm logs, tests) a
//! key whose rest shape takes longer than [`slow_key`] says so in one plain
//! line, and nothing else is written.

use std::io::{self, IsTerminal, Write};
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use drape::animate::attachments::posed_key;
use drape::animate::{Evaluator, KeyShape, ShapeId};
use drape::scene::{Key, Scene};
use drape::shape::RelaxProgress;
use drape::world::Obstacle;

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
/// cache, several at once on the machine's cores (each key's shape is its
/// own, so the shapes equal what the evaluator would build by itself, one
/// after another, bit for bit). `status` shows which keys are being
/// approximated and how far their relaxations have come: `relaxing key 2/5
/// (frame 48): sweep 1200/100000 on the 1024 × 256 grid`; where stderr is
/// not a terminal, a key that takes longer than [`slow_key`] says so once,
/// in a plain line.
pub fn build_key_shapes<'k>(
    evaluator: &mut Evaluator,
    scene: &Scene,
    keys: impl ExactSizeIterator<Item = &'k Key>,
    status: &mut StatusLine,
) {
    let count = keys.len();
    let cloth = &scene.cloth;
    let mut jobs: Vec<KeyJob> = Vec::new();
    let mut which = Vec::new();
    for (index, key) in keys.enumerate() {
        let obstacles = evaluator.key_obstacles(scene, key);
        // Attached pins where their attachments are at the key's frame.
        let key = posed_key(scene, key).into_owned();
        let id = ShapeId::of(cloth, &key, &obstacles);
        if evaluator.cache().get(cloth, &key, &obstacles).is_some() || jobs.iter().any(|job| job.id == id) {
            continue;
        }
        which.push(format!("key {}/{count} (frame {})", index + 1, key.frame));
        jobs.push(KeyJob { key, obstacles, id });
    }
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get()).min(jobs.len());
    let next = AtomicUsize::new(0);
    let shown = Mutex::new(Shown { status, doing: vec![None; jobs.len()], which });
    let slow = slow_key();
    let built: Vec<(usize, KeyShape)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut built = Vec::new();
                    loop {
                        let at = next.fetch_add(1, Ordering::Relaxed);
                        let Some(job) = jobs.get(at) else { break built };
                        lock(&shown).start(at, job.key.pins.len());
                        let started = Instant::now();
                        let mut told = false;
                        let mut report = |progress: RelaxProgress| {
                            let mut shown = lock(&shown);
                            if !told && started.elapsed() >= slow {
                                told = true;
                                let line = format!(
                                    "drape: {} is still relaxing after {:.0} s: sweep {}/{} on the {} × {} grid",
                                    shown.which[at],
                                    started.elapsed().as_secs_f64(),
                                    progress.iteration,
                                    progress.max_iterations,
                                    progress.cols,
                                    progress.rows
                                );
                                shown.status.note_plainly(&line);
                            }
                            shown.relaxing(at, progress);
                            ControlFlow::Continue(())
                        };
                        // The report never breaks, so the build is never cancelled.
                        let shape = KeyShape::build_with(cloth, &job.key, &job.obstacles, &mut report);
                        lock(&shown).doing[at] = None;
                        built.extend(shape.ok().map(|shape| (at, shape)));
                    }
                })
            })
            .collect();
        // A builder that panicked passes its panic on, as building in place would.
        workers
            .into_iter()
            .flat_map(|worker| worker.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)))
            .collect()
    });
    for (at, shape) in built {
        let job = &jobs[at];
        evaluator.cache_mut().insert(cloth, &job.key, &job.obstacles, Arc::new(shape));
    }
    lock(&shown).status.clear();
}

/// A key whose rest shape is to be built: the key with its pins posed and
/// the colliders at its frame.
struct KeyJob {
    key: Key,
    obstacles: Vec<Obstacle>,
    id: ShapeId,
}

/// What a key being built is doing.
#[derive(Clone, Copy)]
enum Doing {
    /// Approximating from this many pins.
    Approximating(usize),
    Relaxing(RelaxProgress),
}

/// The status line, how it names each key to build and what each is doing,
/// shared by the builders.
struct Shown<'s> {
    status: &'s mut StatusLine,
    which: Vec<String>,
    doing: Vec<Option<Doing>>,
}

impl Shown<'_> {
    /// Key `at` begins: shown at once (a new phase of work).
    fn start(&mut self, at: usize, pins: usize) {
        self.doing[at] = Some(Doing::Approximating(pins));
        self.status.show_now(&line(&self.which, &self.doing));
    }

    /// Key `at`'s relaxation has come to `progress`: shown unless the line was just drawn.
    fn relaxing(&mut self, at: usize, progress: RelaxProgress) {
        self.doing[at] = Some(Doing::Relaxing(progress));
        let Shown { status, which, doing } = self;
        status.show(|| line(which, doing));
    }
}

/// What the first key being built is doing, and how many more are, in one
/// line short enough not to wrap (a wrapped status line cannot be redrawn in place).
fn line(which: &[String], doing: &[Option<Doing>]) -> String {
    let mut each = which.iter().zip(doing).filter_map(|(which, doing)| Some((which, (*doing)?)));
    let Some((which, first)) = each.next() else { return String::new() };
    let mut line = match first {
        Doing::Approximating(pins) => {
            format!("approximating {which} from {pins} pin{}", if pins == 1 { "" } else { "s" })
        }
        Doing::Relaxing(RelaxProgress { iteration, max_iterations, cols, rows, .. }) => {
            format!("relaxing {which}: sweep {iteration}/{max_iterations} on the {cols} × {rows} grid")
        }
    };
    let more = each.count();
    if more > 0 {
        line += &format!(" (and {more} more key{})", if more == 1 { "" } else { "s" });
    }
    line
}

/// The lock's guard, also after a builder panicked holding it (the status line is still whole).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}
