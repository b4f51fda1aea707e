//! In-betweens that go round the colliders that never move: where the
//! straight blend would carry a point through a table (a cloth lifted off
//! it, or put back on it), the point takes a path round the solid instead
//! ([`crate::world::path_around`]), decided by where it rests in the two
//! keys alone. Each point moves along its path by the segment's easing, the
//! same share of the path as the straight blend would be of the line, so a
//! segment still starts and ends exactly on its keys' shapes and every
//! frame depends on the scene and the frame only.

use std::sync::Arc;

use super::cache::KeyShape;
use super::colliders_at::still_obstacles;
use super::track::sample;
use crate::mesh::PointArrays;
use crate::scene::{Layer, Scene};
use crate::world::{Obstacle, Polyline, path_around};

/// Most threads working out one segment's paths.
const MAX_THREADS: usize = 16;

/// One point's path round the colliders between two keys.
#[derive(Clone, Debug, PartialEq)]
pub struct Detour {
    /// The grid point (index `j·cols + i`).
    pub point: usize,
    /// From the first key's position through the path's inner points to the second's.
    pub path: Polyline,
}

/// The paths of one segment's detoured points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SegmentPaths {
    detours: Vec<Detour>,
    /// Per grid point, its detour's index in `detours` (`u32::MAX`: none).
    of_point: Vec<u32>,
}

impl SegmentPaths {
    /// The paths round `obstacles` of every point that the straight blend
    /// from `a` to `b` would carry through one; points pinned in both keys
    /// move between their pins as the animator put them.
    pub fn between(a: &KeyShape, b: &KeyShape, obstacles: &[Obstacle]) -> SegmentPaths {
        let threads = std::thread::available_parallelism().map_or(1, |c| c.get()).clamp(1, MAX_THREADS);
        SegmentPaths::between_on(a, b, obstacles, threads)
    }

    /// [`SegmentPaths::between`], worked out on `threads` threads.
    fn between_on(a: &KeyShape, b: &KeyShape, obstacles: &[Obstacle], threads: usize) -> SegmentPaths {
        let n = a.points.len().min(b.points.len());
        let mut paths = SegmentPaths::default();
        if obstacles.is_empty() {
            return paths;
        }
        let around = |point: usize| {
            if a.pinned.get(point) == Some(&true) && b.pinned.get(point) == Some(&true) {
                return None;
            }
            let (from, to) = (a.points.get(point).as_dvec3(), b.points.get(point).as_dvec3());
            let inner = path_around(obstacles, from, to)?;
            Some(Polyline::through(std::iter::once(from).chain(inner).chain(std::iter::once(to)).collect()))
        };
        // Each point's path is its own: worked out on every core (the points
        // dealt out in turn, as the ones that go round cluster near a rim) and
        // put back in point order, the same on any count of cores.
        let threads = threads.max(1);
        let mut found: Vec<(usize, Polyline)> = std::thread::scope(|scope| {
            let dealt: Vec<_> = (0..threads)
                .map(|first| {
                    let around = &around;
                    scope.spawn(move || {
                        (first..n).step_by(threads).filter_map(|p| Some((p, around(p)?))).collect::<Vec<_>>()
                    })
                })
                .collect();
            dealt.into_iter().flat_map(|d| d.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))).collect()
        });
        found.sort_unstable_by_key(|(point, _)| *point);
        for (point, path) in found {
            if paths.of_point.is_empty() {
                paths.of_point = vec![u32::MAX; n];
            }
            paths.of_point[point] = paths.detours.len() as u32;
            paths.detours.push(Detour { point, path });
        }
        paths
    }

    /// The detoured points' paths.
    pub fn detours(&self) -> &[Detour] {
        &self.detours
    }

    /// Where point `k` is `eased` of the way between the keys, if it goes
    /// round a collider; `None` for a point that blends straight, and under
    /// overshooting easings (below 0 or past 1), which blend straight.
    #[inline]
    pub fn at(&self, k: usize, eased: f64) -> Option<glam::Vec3> {
        let &index = self.of_point.get(k)?;
        let detour = self.detours.get(index as usize)?;
        (eased > 0.0 && eased < 1.0).then(|| detour.path.at(eased).as_vec3())
    }

    /// Moves every detoured point of a blend `eased` of the way between its keys onto its path.
    pub fn go_round(&self, eased: f64, points: &mut PointArrays) {
        for detour in &self.detours {
            if let Some(p) = self.at(detour.point, eased)
                && detour.point < points.len()
            {
                points.set(detour.point, p);
            }
        }
    }

    /// [`SegmentPaths::go_round`] in f64 positions.
    pub fn go_round_f64(&self, eased: f64, points: &mut [glam::DVec3]) {
        if !(eased > 0.0 && eased < 1.0) {
            return;
        }
        for detour in &self.detours {
            if let Some(p) = points.get_mut(detour.point) {
                *p = detour.path.at(eased);
            }
        }
    }
}

/// Segments' detours among the scene's still colliders, kept by the
/// segment's two rest shapes and its obstacles.
#[derive(Debug, Default)]
pub struct SegmentDetours {
    entries: Vec<Entry>,
    /// Segments worked out here rather than handed in ([`SegmentDetours::insert`]).
    worked_out: usize,
}

#[derive(Debug)]
struct Entry {
    segment: SegmentAsk,
    paths: Arc<SegmentPaths>,
}

/// One segment whose paths are to be worked out: its keys' rest shapes and
/// the still colliders between them.
#[derive(Clone, Debug)]
pub struct SegmentAsk {
    pub a: Arc<KeyShape>,
    pub b: Arc<KeyShape>,
    pub obstacles: Vec<Obstacle>,
}

impl SegmentAsk {
    /// The segment's paths ([`SegmentPaths::between`]).
    pub fn paths(&self) -> SegmentPaths {
        SegmentPaths::between(&self.a, &self.b, &self.obstacles)
    }

    /// Whether `other` is this segment: the same two shapes (not only equal ones) and obstacles.
    pub fn same(&self, other: &SegmentAsk) -> bool {
        Arc::ptr_eq(&self.a, &other.a) && Arc::ptr_eq(&self.b, &other.b) && self.obstacles == other.obstacles
    }
}

/// Segments whose detours are kept at most (the oldest go first).
const KEPT_SEGMENTS: usize = 64;

impl SegmentDetours {
    /// The detours of the segments of `scene` (`shapes` its keys' rest
    /// shapes, in order) that `frame` reads: the one it falls in, and those
    /// a follow-through layer's lag reaches back into; every other segment
    /// is given no detours, so what a frame gets never depends on what was
    /// evaluated before. Each is worked out once per content; none without
    /// still colliders. A key with in-between relaxation blends its segment
    /// straight, as the relaxation decides.
    pub fn at_frame(&mut self, scene: &Scene, shapes: &[Arc<KeyShape>], frame: f64) -> Vec<Arc<SegmentPaths>> {
        let segments = shapes.len().saturating_sub(1);
        if scene.colliders.is_empty() || segments == 0 || !frame.is_finite() {
            return Vec::new();
        }
        let lag_frames = scene
            .layers
            .iter()
            .filter(|layer| layer.enabled())
            .filter_map(|layer| match layer {
                Layer::FollowThrough(f) => Some(sample(&f.lag, frame)),
                _ => None,
            })
            .filter(|lag| lag.is_finite())
            .fold(0.0, f64::max)
            * scene.timeline.fps;
        let earliest = frame - lag_frames.max(0.0);
        let none = Arc::new(SegmentPaths::default());
        (0..segments)
            .map(|from| {
                let (key_a, key_b) = (&scene.keys[from], &scene.keys[from + 1]);
                let read = f64::from(key_b.frame) > earliest && f64::from(key_a.frame) < frame;
                if !read {
                    return none.clone();
                }
                segment_ask(scene, shapes, from).map_or_else(|| none.clone(), |ask| self.between(ask))
            })
            .collect()
    }

    /// Every segment of `scene` (`shapes` its keys' rest shapes) that has
    /// paths to go round and none kept: what a worker can work out ahead and
    /// hand in ([`SegmentDetours::insert`]), so that no frame waits for them.
    pub fn missing(&self, scene: &Scene, shapes: &[Arc<KeyShape>]) -> Vec<SegmentAsk> {
        if scene.colliders.is_empty() {
            return Vec::new();
        }
        (0..shapes.len().saturating_sub(1))
            .filter_map(|from| segment_ask(scene, shapes, from))
            .filter(|ask| self.kept(ask).is_none())
            .collect()
    }

    /// Keeps `paths`, worked out elsewhere for `ask` ([`SegmentAsk::paths`]).
    pub fn insert(&mut self, ask: SegmentAsk, paths: Arc<SegmentPaths>) {
        if self.kept(&ask).is_some() {
            return;
        }
        if self.entries.len() == KEPT_SEGMENTS {
            self.entries.remove(0);
        }
        self.entries.push(Entry { segment: ask, paths });
    }

    /// How many segments were worked out here, not handed in.
    pub fn worked_out(&self) -> usize {
        self.worked_out
    }

    fn kept(&self, ask: &SegmentAsk) -> Option<usize> {
        self.entries.iter().position(|e| e.segment.same(ask))
    }

    /// The detours of `ask`, from the kept ones or worked out.
    fn between(&mut self, ask: SegmentAsk) -> Arc<SegmentPaths> {
        if let Some(index) = self.kept(&ask) {
            return self.entries[index].paths.clone();
        }
        let paths = Arc::new(ask.paths());
        self.worked_out += 1;
        self.insert(ask, paths.clone());
        paths
    }
}

/// The segment from key `from` to the next, among the still colliders.
fn segment_ask(scene: &Scene, shapes: &[Arc<KeyShape>], from: usize) -> Option<SegmentAsk> {
    let (key_a, key_b) = (scene.keys.get(from)?, scene.keys.get(from + 1)?);
    let obstacles = still_obstacles(scene, key_a.thickness.max(key_b.thickness));
    Some(SegmentAsk { a: shapes.get(from)?.clone(), b: shapes.get(from + 1)?.clone(), obstacles })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::Evaluator;

    #[test]
    fn the_paths_are_the_same_on_any_count_of_threads() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tablecloth_pull.ron");
        let Ok(scene) = crate::scene::load(&path) else { panic!("the bundled tablecloth pull loads") };
        let mut evaluator = Evaluator::new();
        let shapes: Vec<Arc<KeyShape>> = scene.keys.iter().map(|k| evaluator.key_shape(&scene, k)).collect();
        let obstacles = still_obstacles(&scene, scene.keys[0].thickness);
        let mut detoured = 0;
        for pair in shapes.windows(2) {
            let one = SegmentPaths::between_on(&pair[0], &pair[1], &obstacles, 1);
            assert_eq!(SegmentPaths::between_on(&pair[0], &pair[1], &obstacles, 3), one);
            assert_eq!(SegmentPaths::between_on(&pair[0], &pair[1], &obstacles, 8), one);
            detoured += one.detours().len();
        }
        assert!(detoured > 0, "some points go round the table");
    }
}
