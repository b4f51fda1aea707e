//! Relaxation off the UI thread: the editor asks for the rest shapes its
//! scene lacks, keeps drawing the last scene whose shapes it has, and takes
//! the new shapes when they arrive.
//!
//! One worker thread, one pending job (the newest request replaces an older
//! pending one). A request may supersede the running job, which then stops
//! at its next sweep: edits that each stand on their own (a typed value, an
//! undo, the end of a drag) do, so a stale relaxation of a large grid never
//! delays the shape the user asked for. The moves of a drag in progress do
//! not, so a drag shows each finished shape while it goes on instead of
//! cancelling every relaxation before it can finish. The in-betweens'
//! paths round the still colliders are worked out here too, once the shapes
//! they join are in, so drawing a frame never waits for them.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::animate::KeyShape;
use crate::animate::detours::{SegmentAsk, SegmentPaths};
use crate::scene::{Cloth, Key};
use crate::world::Obstacle;

/// One relaxed key, ready for the evaluator's cache.
pub struct Built {
    pub cloth: Cloth,
    pub key: Key,
    /// The colliders at the key's frame it was relaxed among.
    pub obstacles: Vec<Obstacle>,
    pub shape: Arc<KeyShape>,
}

/// What the worker is doing, for the progress display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaperStatus {
    /// Keys of the running job finished so far, and in all.
    pub keys_done: usize,
    pub keys_total: usize,
    /// The grid level being relaxed and its sweep.
    pub level: (usize, usize),
    pub iteration: u32,
    pub max_iterations: u32,
    pub started: Instant,
    /// The key's shape without the colliders is in, and it is relaxed among
    /// them now (its sweeps count again from the start).
    pub among_colliders: bool,
    /// The relaxing is done: the new shapes' self-crossings are being counted.
    pub counting: bool,
    /// Segments whose paths round the colliders are worked out so far, and in all.
    pub paths: Option<(usize, usize)>,
}

/// One segment's paths, ready for the evaluator ([`crate::animate::Evaluator::insert_paths`]).
pub type BuiltPaths = (SegmentAsk, Arc<SegmentPaths>);

struct Job {
    generation: u64,
    cloth: Cloth,
    keys: Vec<(Key, Vec<Obstacle>)>,
    /// Count where the new shapes pass through themselves once they are all
    /// sent (for the Cloth panel). Not for the moves of a drag: the count
    /// costs about half a relaxation, which the next move should not wait for.
    count_crossings: bool,
    /// Shapes relaxed elsewhere whose crossings to count, after the keys.
    count: Vec<Arc<KeyShape>>,
    /// Segments whose paths round the colliders to work out.
    paths: Vec<SegmentAsk>,
}

struct Shared {
    pending: Mutex<Option<Job>>,
    wake: Condvar,
    /// Jobs older than this generation stop at their next sweep.
    cancel_below: AtomicU64,
    status: Mutex<Option<ShaperStatus>>,
    quit: AtomicBool,
    /// Wakes the UI when a shape is ready.
    repaint: Box<dyn Fn() + Send + Sync>,
}

pub struct Shaper {
    shared: Arc<Shared>,
    results: Receiver<Built>,
    paths: Receiver<BuiltPaths>,
    worker: Option<JoinHandle<()>>,
    next_generation: u64,
}

impl Shaper {
    /// Starts the worker; `repaint` is called from it whenever a shape is ready.
    pub fn new(repaint: impl Fn() + Send + Sync + 'static) -> Shaper {
        let shared = Arc::new(Shared {
            pending: Mutex::new(None),
            wake: Condvar::new(),
            cancel_below: AtomicU64::new(0),
            status: Mutex::new(None),
            quit: AtomicBool::new(false),
            repaint: Box::new(repaint),
        });
        let (sender, results) = mpsc::channel();
        let (paths_sender, paths) = mpsc::channel();
        let worker_shared = shared.clone();
        let worker = std::thread::Builder::new()
            .name("drape-relax".to_owned())
            .spawn(move || work(&worker_shared, &sender, &paths_sender))
            .expect("the relaxation thread starts");
        Shaper { shared, results, paths, worker: Some(worker), next_generation: 1 }
    }

    /// Asks for the shapes of `keys` on `cloth`, each among its colliders
    /// ([`crate::animate::key_obstacles`]), replacing any pending request.
    /// With `supersede`, a running relaxation stops too.
    pub fn request(&mut self, cloth: &Cloth, keys: Vec<(Key, Vec<Obstacle>)>, supersede: bool) {
        let generation = self.next_generation;
        self.next_generation += 1;
        if supersede {
            self.shared.cancel_below.store(generation, Ordering::Relaxed);
        }
        let mut pending = self.shared.pending.lock().unwrap_or_else(PoisonError::into_inner);
        *pending = Some(Job {
            generation,
            cloth: cloth.clone(),
            keys,
            count_crossings: supersede,
            count: Vec::new(),
            paths: Vec::new(),
        });
        self.shared.wake.notify_one();
    }

    /// Asks for the paths of `segments` round their colliders, unless a
    /// request is pending (the shapes asked then make these stale; false);
    /// each comes back through [`Shaper::take_paths`].
    pub fn work_out_paths(&mut self, cloth: &Cloth, segments: Vec<SegmentAsk>) -> bool {
        self.queue_when_idle(|generation| Job {
            generation,
            cloth: cloth.clone(),
            keys: Vec::new(),
            count_crossings: false,
            count: Vec::new(),
            paths: segments,
        })
    }

    /// Asks for the self-crossings of `shapes` to be counted
    /// ([`KeyShape::self_crossings`]) unless a request is pending; the
    /// shapes then know them and the UI is woken.
    pub fn count_crossings(&mut self, cloth: &Cloth, shapes: Vec<Arc<KeyShape>>) {
        self.queue_when_idle(|generation| Job {
            generation,
            cloth: cloth.clone(),
            keys: Vec::new(),
            count_crossings: true,
            count: shapes,
            paths: Vec::new(),
        });
    }

    /// Queues the job `make` builds for its generation, unless a request is
    /// pending (false): follow-up work never replaces shapes asked for.
    fn queue_when_idle(&mut self, make: impl FnOnce(u64) -> Job) -> bool {
        let mut pending = self.shared.pending.lock().unwrap_or_else(PoisonError::into_inner);
        if pending.is_some() {
            return false;
        }
        let generation = self.next_generation;
        self.next_generation += 1;
        *pending = Some(make(generation));
        self.shared.wake.notify_one();
        true
    }

    /// Stops the running relaxation at its next sweep and drops the pending request.
    pub fn cancel(&mut self) {
        self.shared.cancel_below.store(self.next_generation, Ordering::Relaxed);
        *self.shared.pending.lock().unwrap_or_else(PoisonError::into_inner) = None;
    }

    /// The shapes finished since the last call.
    pub fn take_built(&self) -> Vec<Built> {
        self.results.try_iter().collect()
    }

    /// The segments' paths finished since the last call.
    pub fn take_paths(&self) -> Vec<BuiltPaths> {
        self.paths.try_iter().collect()
    }

    /// The running relaxation, if any.
    pub fn status(&self) -> Option<ShaperStatus> {
        *self.shared.status.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Whether a request is pending or running.
    pub fn is_busy(&self) -> bool {
        self.shared.pending.lock().unwrap_or_else(PoisonError::into_inner).is_some() || self.status().is_some()
    }

    /// Blocks until the worker is idle or `timeout` passes (tests and scripted runs).
    pub fn wait_idle(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        while self.is_busy() {
            if Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        true
    }
}

impl Drop for Shaper {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::Relaxed);
        self.shared.cancel_below.store(u64::MAX, Ordering::Relaxed);
        self.shared.wake.notify_one();
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

fn work(shared: &Shared, results: &Sender<Built>, paths: &Sender<BuiltPaths>) {
    loop {
        let job = {
            let mut pending = shared.pending.lock().unwrap_or_else(PoisonError::into_inner);
            loop {
                if shared.quit.load(Ordering::Relaxed) {
                    return;
                }
                if let Some(job) = pending.take() {
                    // Marked running before the lock is released, so `is_busy` never sees a gap.
                    let status = ShaperStatus {
                        keys_done: 0,
                        keys_total: job.keys.len(),
                        level: (job.cloth.cols(), job.cloth.rows()),
                        iteration: 0,
                        max_iterations: 0,
                        started: Instant::now(),
                        among_colliders: false,
                        counting: job.keys.is_empty() && job.paths.is_empty(),
                        paths: (job.keys.is_empty() && !job.paths.is_empty()).then_some((0, job.paths.len())),
                    };
                    *shared.status.lock().unwrap_or_else(PoisonError::into_inner) = Some(status);
                    break job;
                }
                pending = shared.wake.wait(pending).unwrap_or_else(PoisonError::into_inner);
            }
        };
        run(shared, results, paths, job);
        *shared.status.lock().unwrap_or_else(PoisonError::into_inner) = None;
        (shared.repaint)();
    }
}

/// Changes the status the UI shows, while the worker has one.
fn update_status(shared: &Shared, change: impl FnOnce(&mut ShaperStatus)) {
    if let Some(status) = shared.status.lock().unwrap_or_else(PoisonError::into_inner).as_mut() {
        change(status);
    }
}

fn run(shared: &Shared, results: &Sender<Built>, paths: &Sender<BuiltPaths>, job: Job) {
    let total = job.keys.len();
    let mut finished = Vec::with_capacity(total);
    for (done, (key, obstacles)) in job.keys.into_iter().enumerate() {
        update_status(shared, |status| {
            status.keys_done = done;
            status.among_colliders = false;
        });
        let mut control = |progress: crate::shape::RelaxProgress| {
            if job.generation < shared.cancel_below.load(Ordering::Relaxed) {
                return ControlFlow::Break(());
            }
            update_status(shared, |status| {
                status.level = (progress.cols, progress.rows);
                status.iteration = progress.iteration;
                status.max_iterations = progress.max_iterations;
            });
            ControlFlow::Continue(())
        };
        // A key with pins among colliders: its shape without them first (kept,
        // so moving a collider later re-shapes only the keys it reaches), and
        // that shape itself where the cloth does not reach them.
        let shape = if key.pins.is_empty() || obstacles.is_empty() {
            KeyShape::build_with(&job.cloth, &key, &obstacles, &mut control).map(Arc::new)
        } else {
            KeyShape::build_with(&job.cloth, &key, &[], &mut control).map(Arc::new).and_then(|plain| {
                let built =
                    Built { cloth: job.cloth.clone(), key: key.clone(), obstacles: Vec::new(), shape: plain.clone() };
                if results.send(built).is_err() {
                    return Err(crate::shape::Cancelled);
                }
                if plain.rest.touches_obstacles(&obstacles) {
                    update_status(shared, |status| status.among_colliders = true);
                    KeyShape::among_from(&plain, &job.cloth, &key, &obstacles, &mut control).map(Arc::new)
                } else {
                    Ok(plain)
                }
            })
        };
        let Ok(shape) = shape else {
            return;
        };
        finished.push(shape.clone());
        let built = Built { cloth: job.cloth.clone(), key, obstacles, shape };
        if results.send(built).is_err() {
            return;
        }
        (shared.repaint)();
    }
    let segments = job.paths.len();
    for (done, ask) in job.paths.into_iter().enumerate() {
        if job.generation < shared.cancel_below.load(Ordering::Relaxed) {
            return;
        }
        update_status(shared, |status| status.paths = Some((done, segments)));
        let worked_out = Arc::new(ask.paths());
        if paths.send((ask, worked_out)).is_err() {
            return;
        }
        (shared.repaint)();
    }
    if job.count_crossings {
        update_status(shared, |status| status.counting = true);
        for shape in finished.into_iter().chain(job.count) {
            // A newer request goes first; the panel then counts nothing for these shapes.
            if shared.pending.lock().unwrap_or_else(PoisonError::into_inner).is_some() {
                return;
            }
            shape.self_crossings();
        }
        (shared.repaint)();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn scene() -> Scene {
        crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap()
    }

    /// Among colliders a key with pins comes back twice: its shape without
    /// them (kept for the next collider move) and its shape among them, each
    /// equal to a build here.
    #[test]
    fn a_key_among_colliders_comes_back_with_its_shape_without_them() {
        use crate::world::{ColliderShape, Obstacle};
        let s = scene();
        // Without a thickness between its folds: the fall over the ball
        // crosses itself, and keeping its folds apart would only cost time here.
        let key = Key { thickness: 0.0, ..s.keys[0].clone() };
        let ball = |x: f64| Obstacle {
            shape: ColliderShape::Sphere { center: glam::DVec3::new(x, 1.0, 0.0), radius: 0.3 },
            thickness: 0.003,
        };
        let mut shaper = Shaper::new(|| {});
        for obstacles in [vec![ball(30.0)], vec![ball(0.0)]] {
            shaper.request(&s.cloth, vec![(key.clone(), obstacles.clone())], true);
            assert!(shaper.wait_idle(Duration::from_secs(120)));
            let built = shaper.take_built();
            let among: Vec<usize> = built.iter().map(|b| b.obstacles.len()).collect();
            assert_eq!(among, [0, 1], "without, then among");
            assert_eq!(built[0].shape.positions, KeyShape::build(&s.cloth, &key, &[]).positions);
            assert_eq!(built[1].shape.positions, KeyShape::build(&s.cloth, &key, &obstacles).positions);
        }
    }

    #[test]
    fn shapes_built_on_the_worker_equal_shapes_built_here() {
        let s = scene();
        let mut shaper = Shaper::new(|| {});
        shaper.request(&s.cloth, s.keys.iter().map(|k| (k.clone(), Vec::new())).collect(), true);
        assert!(shaper.wait_idle(Duration::from_secs(60)));
        let built = shaper.take_built();
        assert_eq!(built.len(), s.keys.len());
        for (b, key) in built.iter().zip(&s.keys) {
            assert_eq!(b.key, *key);
            assert_eq!(b.shape.positions, KeyShape::build(&s.cloth, key, &[]).positions);
        }
        assert!(shaper.status().is_none());
    }

    #[test]
    fn a_superseding_request_drops_the_stale_one() {
        let mut s = scene();
        s.cloth.grid = (129, 129);
        s.keys[0].relax.iterations = 100_000;
        s.keys[0].relax.tolerance = 0.0;
        s.keys.truncate(1);
        let mut shaper = Shaper::new(|| {});
        shaper.request(&s.cloth, s.keys.iter().map(|k| (k.clone(), Vec::new())).collect(), true);
        // Wait until it is running, then ask for something small instead.
        while shaper.status().is_none_or(|status| status.iteration == 0) {
            std::thread::sleep(Duration::from_millis(1));
        }
        let mut small = scene();
        small.cloth.grid = (9, 9);
        small.keys.truncate(1);
        for pin in &mut small.keys[0].pins {
            pin.grid = (pin.grid.0.min(8), pin.grid.1.min(8));
        }
        small.keys[0].pins.dedup_by_key(|p| p.grid);
        shaper.request(&small.cloth, small.keys.iter().map(|k| (k.clone(), Vec::new())).collect(), true);
        assert!(shaper.wait_idle(Duration::from_secs(60)), "the huge relaxation was cancelled");
        let built = shaper.take_built();
        assert_eq!(built.len(), 1);
        assert_eq!(built[0].cloth.grid, (9, 9));
    }
}
