//! Rest shapes cached by content: a key is relaxed once, however often it is
//! evaluated, and editing one key rebuilds that key only.

use std::collections::HashMap;
use std::ops::ControlFlow;
use std::sync::{Arc, OnceLock};

use glam::Vec3;

use super::attachments::posed_key;
use super::colliders_at::obstacles_at;
use super::falloff::{pin_distance_field, resting_distance_field};
use super::posed_solids::PosedSolids;
use super::stretch_limit::EdgeReach;
use crate::mesh::PointArrays;
use crate::scene::{Cloth, Key, Scene};
use crate::shape::contact::{count_crossings, crossing_advice};
use crate::shape::{Cancelled, Placement, RelaxProgress, RestShape};
use crate::world::{ColliderShape, Obstacle};

/// What animation needs from one key, built once per distinct content.
#[derive(Debug)]
pub struct KeyShape {
    /// Every modelling stage (network, approximation, relaxation) in f64.
    pub rest: RestShape,
    /// The relaxed surface as the mesh stores it, vertex order `j·cols + i`.
    pub positions: Vec<Vec3>,
    /// `positions` split into x, y, z arrays, as the layers work on them.
    pub points: PointArrays,
    /// d_cp/d_max per vertex for this key's pins (0 at the pins, 1 farthest);
    /// for a key without pins, from the points resting on colliders.
    pub ratio: Vec<f32>,
    /// d_max: the largest material distance to the closest pin (or resting point) (m).
    pub d_max_m: f32,
    /// Which vertices this key pins.
    pub pinned: Vec<bool>,
    /// Each structural edge's reach in this key, for the stretch limit.
    pub reach: EdgeReach,
    /// How many edges of the relaxed shape pass through the cloth, once
    /// counted ([`KeyShape::self_crossings`]).
    crossings: OnceLock<usize>,
}

impl KeyShape {
    /// Relaxes `key` on `cloth` among `obstacles` (the colliders at the
    /// key's frame, [`key_obstacles`]; the scene must be valid) and derives the rest.
    pub fn build(cloth: &Cloth, key: &Key, obstacles: &[Obstacle]) -> KeyShape {
        let never_cancelled = &mut |_| ControlFlow::Continue(());
        let rest = RestShape::build_among(cloth, key, obstacles, never_cancelled)
            .expect("a control that never breaks never cancels");
        KeyShape::from_rest(cloth, key, rest, obstacles)
    }

    /// [`KeyShape::build`] with relaxation progress and cancellation (see [`RestShape::build_with`]).
    pub fn build_with(
        cloth: &Cloth,
        key: &Key,
        obstacles: &[Obstacle],
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<KeyShape, Cancelled> {
        Ok(KeyShape::from_rest(cloth, key, RestShape::build_among(cloth, key, obstacles, control)?, obstacles))
    }

    /// The shape among `obstacles` of a key with pins, from `plain`, its
    /// shape without them (see [`RestShape::among_from`]): equal to
    /// [`KeyShape::build_with`] among them, without relaxing it again.
    pub fn among_from(
        plain: &KeyShape,
        cloth: &Cloth,
        key: &Key,
        obstacles: &[Obstacle],
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<KeyShape, Cancelled> {
        let rest = RestShape::among_from(plain.rest.clone(), key, obstacles, control)?;
        Ok(KeyShape::from_rest(cloth, key, rest, obstacles))
    }

    fn from_rest(cloth: &Cloth, key: &Key, rest: RestShape, obstacles: &[Obstacle]) -> KeyShape {
        let positions: Vec<Vec3> = rest.relaxed.iter().map(|p| p.as_vec3()).collect();
        let points = PointArrays::from_vec3s(&positions);
        let (ratio, d_max_m) = if key.pins.is_empty() {
            resting_distance_field(cloth, &rest.relaxed, obstacles)
        } else {
            pin_distance_field(cloth, &key.pins)
        };
        let pinned = rest.placement.iter().map(|p| *p == Placement::Pin).collect();
        let rest_m = (cloth.spacing_u_m() * key.elasticity, cloth.spacing_v_m() * key.elasticity);
        let reach = EdgeReach::of(&points, cloth.cols(), cloth.rows(), rest_m.0 as f32, rest_m.1 as f32);
        KeyShape { rest, positions, points, ratio, d_max_m: d_max_m as f32, pinned, reach, crossings: OnceLock::new() }
    }

    /// How many edges of the relaxed shape pass through the cloth
    /// ([`count_crossings`]), counted on the first call, when asked for (the
    /// editor's worker asks after the shape is shown): a drape that proves one
    /// to one over a plane counts in under 3 ms at 256², one that crosses
    /// itself needs a search (9 ms at 64², 41 ms at 128²). The build's own
    /// count, where contact needed one, is not kept: it is counted again here.
    pub fn self_crossings(&self) -> usize {
        let (cols, rows) = (self.rest.grid.cols, self.rest.grid.rows);
        *self.crossings.get_or_init(|| count_crossings(&self.rest.relaxed, cols, rows))
    }

    /// [`KeyShape::self_crossings`] if it has been counted, without counting.
    pub fn self_crossings_if_counted(&self) -> Option<usize> {
        self.crossings.get().copied()
    }

    /// Whether the rest shape can be relied on: its relaxation or fall
    /// settled clear of every collider and, where the key keeps a thickness
    /// between its folds (`thickness_m`), it passes nowhere through itself
    /// (counting the crossings if they are not yet counted).
    pub fn settled(&self, thickness_m: f64) -> bool {
        self.rest.relax_report.converged && self.through_itself(thickness_m).is_none()
    }

    /// The outcome in a user's words ([`crate::shape::RelaxReport::verdict`]),
    /// unless a shape that settled passes through itself where the key keeps
    /// a thickness: then that, with what to do.
    pub fn verdict(&self, thickness_m: f64) -> String {
        let report = self.rest.relax_report;
        let Some(crossings) = self.through_itself(thickness_m).filter(|_| report.converged) else {
            return report.verdict();
        };
        format!(
            "NOT settled: passes through itself ({crossings} edge{} the cloth) after {} sweep{}; {}",
            if crossings == 1 { " crosses" } else { "s cross" },
            report.iterations,
            if report.iterations == 1 { "" } else { "s" },
            crossing_advice(thickness_m, true)
        )
    }

    /// How many edges cross the cloth, where the key keeps a thickness and some do.
    fn through_itself(&self, thickness_m: f64) -> Option<usize> {
        (thickness_m > 0.0).then(|| self.self_crossings()).filter(|&crossings| crossings > 0)
    }
}

/// Everything that decides a key's rest shape, compared bit for bit (the
/// key's frame and ease do not change its shape, so moving a key in time
/// keeps its cache entry).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct ShapeInputs {
    size_bits: (u64, u64),
    grid: (u32, u32),
    pins: Vec<((u32, u32), [u64; 3])>,
    elasticity_bits: u64,
    stiffness_bits: u64,
    iterations: u32,
    tolerance_bits: u64,
    /// The obstacles' numbers, bit for bit, and the friction on them.
    obstacles: Vec<u64>,
    friction_bits: u64,
    /// Where a key without pins starts (centre, rotation), bit for bit; None with pins.
    placement_bits: Option<[u64; 6]>,
}

/// The colliders a key's rest shape lies among: the scene's at the key's
/// frame, colliding references posed afresh ([`key_obstacles_among`] reuses
/// the solids of poses built lately, as an [`Evaluator`](super::Evaluator) does).
pub fn key_obstacles(scene: &Scene, key: &Key) -> Vec<Obstacle> {
    key_obstacles_among(scene, key, &PosedSolids::new())
}

/// [`key_obstacles`] with colliding references' solids from `solids` where
/// that pose was built lately: the same obstacles.
pub fn key_obstacles_among(scene: &Scene, key: &Key, solids: &PosedSolids) -> Vec<Obstacle> {
    obstacles_at(scene, f64::from(key.frame), solids)
}

/// Every number of `obstacles` as bits, with each kind's tag (a mesh's tag
/// followed by its triangles' fingerprint and count): equal lists, equal shapes.
fn obstacle_bits(obstacles: &[Obstacle]) -> Vec<u64> {
    let mut bits = Vec::new();
    for obstacle in obstacles {
        let (tag, numbers): (u64, Vec<f64>) = match obstacle.shape {
            ColliderShape::Mesh { center, world_from_local, scale, .. } => {
                (5, center.to_array().into_iter().chain([scale]).chain(world_from_local.to_cols_array()).collect())
            }
            ColliderShape::Ground { height } => (0, vec![height]),
            ColliderShape::Sphere { center, radius } => (1, vec![center.x, center.y, center.z, radius]),
            ColliderShape::Capsule { a, b, radius } => (2, vec![a.x, a.y, a.z, b.x, b.y, b.z, radius]),
            ColliderShape::Box { center, half, world_from_local } => (
                3,
                [center.to_array(), half.to_array()]
                    .concat()
                    .into_iter()
                    .chain(world_from_local.to_cols_array())
                    .collect(),
            ),
            ColliderShape::Cylinder { center, radius, half_height, world_from_local } => (
                4,
                center
                    .to_array()
                    .into_iter()
                    .chain([radius, half_height])
                    .chain(world_from_local.to_cols_array())
                    .collect(),
            ),
        };
        bits.push(tag);
        if let ColliderShape::Mesh { solid, .. } = &obstacle.shape {
            bits.extend([solid.fingerprint(), solid.triangle_count() as u64]);
        }
        bits.extend(numbers.iter().chain([&obstacle.thickness]).map(|v| v.to_bits()));
    }
    bits
}

impl ShapeInputs {
    fn of(cloth: &Cloth, key: &Key, obstacles: &[Obstacle]) -> ShapeInputs {
        ShapeInputs {
            size_bits: (cloth.size.0.to_bits(), cloth.size.1.to_bits()),
            grid: cloth.grid,
            pins: key
                .pins
                .iter()
                .map(|p| (p.grid, [p.pos.0.to_bits(), p.pos.1.to_bits(), p.pos.2.to_bits()]))
                .collect(),
            elasticity_bits: key.elasticity.to_bits(),
            stiffness_bits: key.stiffness.to_bits(),
            iterations: key.relax.iterations,
            tolerance_bits: key.relax.tolerance.to_bits(),
            obstacles: obstacle_bits(obstacles),
            // Friction only matters among obstacles: without any, a change keeps the shape.
            friction_bits: if obstacles.is_empty() { 0 } else { key.friction.to_bits() },
            placement_bits: key.pins.is_empty().then(|| {
                let crate::scene::Placement { center: c, rotation_deg: r } = key.placement_or_default();
                [c.0, c.1, c.2, r.0, r.1, r.2].map(f64::to_bits)
            }),
        }
    }
}

/// What a key's shape is built from, as the cache tells shapes apart: keys
/// with equal ids have the same shape, bit for bit, so one build serves both.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ShapeId(ShapeInputs);

impl ShapeId {
    pub fn of(cloth: &Cloth, key: &Key, obstacles: &[Obstacle]) -> ShapeId {
        ShapeId(ShapeInputs::of(cloth, key, obstacles))
    }
}

/// Shapes no key of the latest scene uses are kept for undo and toggling
/// back, up to this many; the least recently used go first.
pub const RETAINED_UNUSED_SHAPES: usize = 16;

/// A content-addressed store of [`KeyShape`]s. A clone shares the shapes
/// (they are reference-counted), so handing a copy to a worker is cheap.
#[derive(Clone, Debug, Default)]
pub struct RestShapeCache {
    entries: HashMap<ShapeInputs, Entry>,
    /// Counts calls to [`RestShapeCache::shapes`]; entries remember the last one that used them.
    generation: u64,
    builds: u64,
}

#[derive(Clone, Debug)]
struct Entry {
    shape: Arc<KeyShape>,
    last_used: u64,
}

impl RestShapeCache {
    pub fn new() -> RestShapeCache {
        RestShapeCache::default()
    }

    /// The shape of every key of `scene`, in key order (attached pins where
    /// their attachments are at the key's frame, among the colliders there,
    /// colliding references' solids from `solids`), building the ones not
    /// cached yet. The scene must be valid.
    pub fn shapes(&mut self, scene: &Scene, solids: &PosedSolids) -> Vec<Arc<KeyShape>> {
        self.generation += 1;
        let shapes = scene
            .keys
            .iter()
            .map(|key| self.shape(&scene.cloth, &posed_key(scene, key), &key_obstacles_among(scene, key, solids)))
            .collect();
        self.evict();
        shapes
    }

    /// The shape of one key among `obstacles` ([`key_obstacles`]), built if it is not cached.
    pub fn shape(&mut self, cloth: &Cloth, key: &Key, obstacles: &[Obstacle]) -> Arc<KeyShape> {
        let generation = self.generation;
        let inputs = ShapeInputs::of(cloth, key, obstacles);
        if let Some(entry) = self.entries.get_mut(&inputs) {
            entry.last_used = generation;
            return entry.shape.clone();
        }
        if let Some(plain) = self.plain_untouched(cloth, key, obstacles) {
            self.entries.insert(inputs, Entry { shape: plain.clone(), last_used: generation });
            return plain;
        }
        let shape = Arc::new(KeyShape::build(cloth, key, obstacles));
        self.builds += 1;
        self.entries.insert(inputs, Entry { shape: shape.clone(), last_used: generation });
        shape
    }

    /// The cached shape of `key`, if there is one; never builds. Among
    /// obstacles a pinned key's cached shape without them counts when it
    /// does not reach them (it is then the same shape, bit for bit).
    pub fn get(&self, cloth: &Cloth, key: &Key, obstacles: &[Obstacle]) -> Option<Arc<KeyShape>> {
        let exact = self.entries.get(&ShapeInputs::of(cloth, key, obstacles)).map(|entry| entry.shape.clone());
        exact.or_else(|| self.plain_untouched(cloth, key, obstacles))
    }

    /// `key`'s cached shape without obstacles, if it has pins, `obstacles`
    /// is not empty and that shape does not reach them. Moving a collider
    /// then re-shapes only the keys it touches.
    fn plain_untouched(&self, cloth: &Cloth, key: &Key, obstacles: &[Obstacle]) -> Option<Arc<KeyShape>> {
        if key.pins.is_empty() || obstacles.is_empty() {
            return None;
        }
        let plain = self.entries.get(&ShapeInputs::of(cloth, key, &[]))?;
        (!plain.shape.rest.touches_obstacles(obstacles)).then(|| plain.shape.clone())
    }

    /// Stores a shape built elsewhere (the editor relaxes on a worker thread).
    /// `shape` must be `KeyShape::build(cloth, key, obstacles)`'s result for these inputs.
    pub fn insert(&mut self, cloth: &Cloth, key: &Key, obstacles: &[Obstacle], shape: Arc<KeyShape>) {
        let entry = Entry { shape, last_used: self.generation };
        self.entries.insert(ShapeInputs::of(cloth, key, obstacles), entry);
    }

    /// How many shapes have been built (relaxations run) so far.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Drops the least recently used entries beyond those of the current
    /// generation plus [`RETAINED_UNUSED_SHAPES`].
    fn evict(&mut self) {
        let current = self.generation;
        let mut unused: Vec<(u64, ShapeInputs)> = self
            .entries
            .iter()
            .filter(|(_, e)| e.last_used != current)
            .map(|(k, e)| (e.last_used, k.clone()))
            .collect();
        if unused.len() <= RETAINED_UNUSED_SHAPES {
            return;
        }
        unused.sort_by_key(|(last_used, _)| *last_used);
        let excess = unused.len() - RETAINED_UNUSED_SHAPES;
        for (_, inputs) in unused.into_iter().take(excess) {
            self.entries.remove(&inputs);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Ease, Pin, RelaxSettings};

    fn key(frame: i32, height: f64) -> Key {
        Key {
            frame,
            pins: vec![Pin::at((0, 0), (-0.5, height, 0.0)), Pin::at((8, 0), (0.5, height, 0.0))],
            elasticity: 1.1,
            stiffness: 0.2,
            relax: RelaxSettings { iterations: 20, tolerance: 1e-4 },
            ease: Ease::EaseInOut,
            inbetween_relax: 0,
            thickness: crate::scene::DEFAULT_THICKNESS_M,
            friction: crate::scene::DEFAULT_FRICTION,
            placement: None,
        }
    }

    fn scene(keys: Vec<Key>) -> Scene {
        Scene { cloth: Cloth::new((1.0, 1.0), (9, 9)), keys, ..Scene::default() }
    }

    #[test]
    fn editing_one_key_rebuilds_only_that_key() {
        let mut cache = RestShapeCache::new();
        let mut s = scene(vec![key(0, 1.0), key(24, 1.2), key(48, 1.4)]);
        let first = cache.shapes(&s, &PosedSolids::new());
        assert_eq!(cache.builds(), 3);
        cache.shapes(&s, &PosedSolids::new());
        assert_eq!(cache.builds(), 3, "nothing changed, nothing rebuilt");
        s.keys[1].pins[0].pos.1 = 1.25;
        let second = cache.shapes(&s, &PosedSolids::new());
        assert_eq!(cache.builds(), 4);
        assert!(Arc::ptr_eq(&first[0], &second[0]) && Arc::ptr_eq(&first[2], &second[2]));
        assert!(!Arc::ptr_eq(&first[1], &second[1]));
        // Timing and easing do not change a shape.
        s.keys[1].frame = 30;
        s.keys[1].ease = Ease::Bounce;
        cache.shapes(&s, &PosedSolids::new());
        assert_eq!(cache.builds(), 4);
    }

    #[test]
    fn a_collider_a_key_does_not_reach_reuses_its_shape_without_colliders() {
        let mut cache = RestShapeCache::new();
        let s = scene(vec![key(0, 1.0)]);
        let plain = cache.shapes(&s, &PosedSolids::new())[0].clone();
        assert_eq!(cache.builds(), 1);
        let obstacle =
            |center: glam::DVec3| Obstacle { shape: ColliderShape::Sphere { center, radius: 0.2 }, thickness: 0.003 };
        // A ball far from the hanging cloth: the same shape, nothing built.
        let far = [obstacle(glam::DVec3::new(3.0, 0.0, 0.0))];
        assert!(cache.get(&s.cloth, &s.keys[0], &far).is_some_and(|shape| Arc::ptr_eq(&shape, &plain)));
        assert!(Arc::ptr_eq(&cache.shape(&s.cloth, &s.keys[0], &far), &plain));
        assert_eq!(cache.builds(), 1);
        assert_eq!(KeyShape::build(&s.cloth, &s.keys[0], &far).positions, plain.positions, "what a build gives");
        // A ball in the cloth: built among it, and so is what the shape-from-plain path gives.
        let inside = [obstacle(glam::DVec3::new(0.0, 0.8, 0.0))];
        assert!(cache.get(&s.cloth, &s.keys[0], &inside).is_none());
        let among = cache.shape(&s.cloth, &s.keys[0], &inside);
        assert_eq!(cache.builds(), 2);
        assert_ne!(among.positions, plain.positions);
        let never = &mut |_| ControlFlow::Continue(());
        let from_plain = KeyShape::among_from(&plain, &s.cloth, &s.keys[0], &inside, never).unwrap();
        assert_eq!(from_plain.positions, among.positions);
        assert_eq!(from_plain.ratio, among.ratio);
    }

    #[test]
    fn equal_keys_share_one_shape() {
        let mut cache = RestShapeCache::new();
        let shapes = cache.shapes(&scene(vec![key(0, 1.0), key(24, 1.0)]), &PosedSolids::new());
        assert_eq!(cache.builds(), 1);
        assert!(Arc::ptr_eq(&shapes[0], &shapes[1]));
    }

    #[test]
    fn unused_shapes_are_evicted_beyond_the_retained_count() {
        let mut cache = RestShapeCache::new();
        for step in 0..RETAINED_UNUSED_SHAPES + 5 {
            cache.shapes(&scene(vec![key(0, 1.0 + step as f64 * 0.01)]), &PosedSolids::new());
        }
        assert_eq!(cache.len(), RETAINED_UNUSED_SHAPES + 1);
        // The most recent edits are still there: undoing one step costs nothing.
        let builds = cache.builds();
        cache.shapes(&scene(vec![key(0, 1.0 + (RETAINED_UNUSED_SHAPES + 3) as f64 * 0.01)]), &PosedSolids::new());
        assert_eq!(cache.builds(), builds);
    }
}
