//! `evaluate(scene, t)`: the one path from a scene and a time to a mesh.
//!
//! It blends the two rest shapes around t (cached per key by content), then
//! applies the layer stack in order and holds every edge within the cloth's
//! stretch limit, and last keeps every free point and every edge outside
//! the colliders ([`super::keep_out`]). Nothing depends on an earlier frame, so
//! the same t gives a bit-identical mesh however it was reached, and the cost
//! does not grow with t.
//!
//! Every layer goes through [`ApplyLayer`] with the same [`LayerFrame`]. The
//! time is a frame throughout; a time in seconds ([`Evaluator::evaluate`])
//! becomes one first. The layers work on the points as separate x, y, z
//! arrays ([`PointArrays`]), which their loops vectorise; the mesh's
//! positions and normals are written together in the last pass, the
//! normals of the result.

use std::sync::Arc;

use glam::Vec3;

use super::attachments::{carry_to_attachments, posed_key};
use super::blend::{Segment, blend_positions, blend_segment, relaxes_between, segment_at};
use super::cache::{KeyShape, RestShapeCache, key_obstacles_among};
use super::colliders_at::obstacles_at;
use super::detours::{SegmentAsk, SegmentDetours, SegmentPaths};
use super::follow::carry_with_node;
use super::keep_out::{ClearEdges, ClearPoints, keep_edges_out, keep_out, stop_at_surfaces};
use super::keep_side::{keep_sides, moved_since_key, side_key};
use super::layer::{ApplyLayer, LayerFrame, LayerScratch};
use super::posed_solids::PosedSolids;
use super::stretch_limit::StretchLimiter;
use super::track::sample;
use crate::mesh::{Mesh, PointArrays, grid_triangle_indices, grid_uvs};
use crate::scene::{Key, Scene, Timeline};

/// What to include in an evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EvaluateOptions {
    /// Apply the layer stack (false: the blended rest shapes alone).
    pub layers: bool,
}

impl Default for EvaluateOptions {
    fn default() -> Self {
        EvaluateOptions { layers: true }
    }
}

/// Which shape of the cloth a mesh shows: a key's modelling stage, or the animation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stage {
    /// The key in effect at the frame, approximated from its catenary network (before relaxation).
    Approx,
    /// The key in effect at the frame after relaxation.
    Relaxed,
    /// The full animation: blended rest shapes and (unless turned off) the layer stack.
    #[default]
    Animated,
}

/// The time in seconds of a (possibly fractional) frame: frame / fps.
pub fn frame_time_secs(timeline: &Timeline, frame: f64) -> f64 {
    frame / timeline.fps
}

/// Rounds of keeping points and edges out of the colliders and limiting the
/// stretch before the last keep-out: each round shortens what the pushes
/// lengthened. A cap: the rounds stop once nothing is pushed (six let a leg
/// swung through a curtain pass through it at one frame, sixteen none).
const CONTACT_ROUNDS: usize = 16;

/// Evaluates scenes, keeping the rest-shape cache, the colliding
/// references' latest posed solids and scratch buffers between calls. Its
/// results equal [`evaluate`]'s bit for bit: the caches only save work.
#[derive(Debug, Default)]
pub struct Evaluator {
    cache: RestShapeCache,
    solids: PosedSolids,
    ratio: Vec<f32>,
    points: PointArrays,
    /// The layers' buffers; its normal rows also give the mesh its normals.
    scratch: LayerScratch,
    stretch_limiter: StretchLimiter,
    /// The blend before the layers, kept when colliders need to know where a point came from.
    before_layers: PointArrays,
    /// Points pinned in both keys around the frame (only with colliders).
    held: Vec<bool>,
    /// Points found clear of this frame's colliders, where they were then.
    clear_points: ClearPoints,
    /// Edges found clear of this frame's colliders, where their ends were then.
    clear_edges: ClearEdges,
    /// In-betweens' paths round the colliders that never move, per segment.
    detours: SegmentDetours,
}

impl Evaluator {
    pub fn new() -> Evaluator {
        Evaluator::default()
    }

    /// An evaluator starting from `cache`'s rest shapes (the editor hands an
    /// export the shapes it shows, so nothing is relaxed twice).
    pub fn with_cache(cache: RestShapeCache) -> Evaluator {
        Evaluator { cache, ..Evaluator::default() }
    }

    pub fn cache(&self) -> &RestShapeCache {
        &self.cache
    }

    /// The cache, to look up or store shapes built elsewhere (see [`RestShapeCache::insert`]).
    pub fn cache_mut(&mut self) -> &mut RestShapeCache {
        &mut self.cache
    }

    /// The colliders `key`'s rest shape lies among ([`super::key_obstacles`]),
    /// colliding references' solids from the poses this evaluator built lately.
    pub fn key_obstacles(&self, scene: &Scene, key: &Key) -> Vec<crate::world::Obstacle> {
        key_obstacles_among(scene, key, &self.solids)
    }

    /// The segments of `scene` whose paths round its still colliders are not
    /// kept here, once every key's shape is in the cache (none before): for a
    /// worker to work out ([`SegmentAsk::paths`]) and hand in
    /// ([`Evaluator::insert_paths`]), so that drawing a frame never waits for them.
    pub fn missing_paths(&self, scene: &Scene) -> Vec<SegmentAsk> {
        let shapes: Option<Vec<Arc<KeyShape>>> = scene
            .keys
            .iter()
            .map(|k| self.cache.get(&scene.cloth, &posed_key(scene, k), &self.key_obstacles(scene, k)))
            .collect();
        shapes.map_or_else(Vec::new, |shapes| self.detours.missing(scene, &shapes))
    }

    /// Keeps a segment's paths worked out elsewhere ([`Evaluator::missing_paths`]).
    pub fn insert_paths(&mut self, ask: SegmentAsk, paths: Arc<SegmentPaths>) {
        self.detours.insert(ask, paths);
    }

    /// How many segments' paths this evaluator worked out itself, not handed in.
    pub fn paths_worked_out(&self) -> usize {
        self.detours.worked_out()
    }

    /// The cached shape of one key (built if needed), for callers that show
    /// or export a single key's modelling stages.
    pub fn key_shape(&mut self, scene: &Scene, key: &Key) -> Arc<KeyShape> {
        let obstacles = self.key_obstacles(scene, key);
        self.cache.shape(&scene.cloth, &posed_key(scene, key), &obstacles)
    }

    /// The mesh of `scene` at `t_secs` (frame t_secs · fps), with every layer.
    pub fn evaluate(&mut self, scene: &Scene, t_secs: f64) -> Mesh {
        self.evaluate_with(scene, t_secs, EvaluateOptions::default())
    }

    pub fn evaluate_with(&mut self, scene: &Scene, t_secs: f64, options: EvaluateOptions) -> Mesh {
        let mut mesh = Mesh::default();
        self.evaluate_into(scene, t_secs, options, &mut mesh);
        mesh
    }

    /// The mesh of `scene` at a (possibly fractional) `frame`, with every layer.
    pub fn evaluate_frame(&mut self, scene: &Scene, frame: f64) -> Mesh {
        let mut mesh = Mesh::default();
        self.evaluate_frame_into(scene, frame, EvaluateOptions::default(), &mut mesh);
        mesh
    }

    /// Writes the mesh `stage` shows at `frame` into `mesh`: the animation as
    /// [`Evaluator::evaluate_frame_into`] gives it, or the approximated or
    /// relaxed rest shape of the key in effect at `frame` (`options` only
    /// matter to the animation). The one stage → mesh choice for the
    /// editor's viewport and the exporters.
    pub fn stage_mesh_into(
        &mut self,
        scene: &Scene,
        frame: f64,
        stage: Stage,
        options: EvaluateOptions,
        mesh: &mut Mesh,
    ) {
        if stage == Stage::Animated {
            self.evaluate_frame_into(scene, frame, options, mesh);
            return;
        }
        let shape = self.key_shape(scene, scene.key_in_effect(frame));
        let points = if stage == Stage::Approx { &shape.rest.approximated } else { &shape.rest.relaxed };
        *mesh = Mesh::from_grid(scene.cloth.cols(), scene.cloth.rows(), points);
    }

    /// [`Evaluator::evaluate_frame_into`] at `t_secs`, the frame t_secs · fps.
    pub fn evaluate_into(&mut self, scene: &Scene, t_secs: f64, options: EvaluateOptions, mesh: &mut Mesh) {
        self.evaluate_frame_into(scene, t_secs * scene.timeline.fps, options, mesh);
    }

    /// Writes the mesh of `scene` at a (possibly fractional) `frame` into
    /// `mesh`, reusing its buffers (UVs and indices are only rewritten when
    /// the grid changes, so `mesh` should only be written by this evaluator).
    ///
    /// The scene must be valid ([`Scene::validate`]). A frame whose time in
    /// seconds is not finite evaluates as the first key held.
    pub fn evaluate_frame_into(&mut self, scene: &Scene, frame: f64, options: EvaluateOptions, mesh: &mut Mesh) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            unsafe { self.evaluate_avx2(scene, frame, options, mesh) };
            return;
        }
        self.evaluate_portable(scene, frame, options, mesh);
    }

    /// [`Evaluator::evaluate_portable`] compiled for AVX2, so that the
    /// per-vertex loops (all inlined into it) run eight lanes wide and the
    /// four-lane ones use three-operand instructions. AVX2 alone brings no
    /// fused multiply-add and every operation stays IEEE-exact, so the result
    /// equals the portable build's bit for bit (a test checks it).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn evaluate_avx2(&mut self, scene: &Scene, frame: f64, options: EvaluateOptions, mesh: &mut Mesh) {
        self.evaluate_portable(scene, frame, options, mesh);
    }

    #[inline(always)]
    fn evaluate_portable(&mut self, scene: &Scene, frame: f64, options: EvaluateOptions, mesh: &mut Mesh) {
        let (cols, rows) = (scene.cloth.cols(), scene.cloth.rows());
        if mesh.cols != cols || mesh.rows != rows || mesh.indices.len() != (cols - 1) * (rows - 1) * 6 {
            mesh.cols = cols;
            mesh.rows = rows;
            mesh.uvs = grid_uvs(cols, rows);
            mesh.indices = grid_triangle_indices(cols, rows);
        }
        let fps = scene.timeline.fps;
        let frame = if frame_time_secs(&scene.timeline, frame).is_finite() { frame } else { f64::NEG_INFINITY };
        let points = &mut self.points;
        if scene.keys.is_empty() {
            // Only reachable with an unvalidated scene: lay the cloth out flat.
            let flat: Vec<Vec3> = (0..rows)
                .flat_map(|j| {
                    (0..cols).map(move |i| {
                        let (u, v) = scene.cloth.material_uv(i, j);
                        Vec3::new(u as f32, 0.0, v as f32)
                    })
                })
                .collect();
            points.set_from_vec3s(&flat);
        } else {
            let shapes = self.cache.shapes(scene, &self.solids);
            let segment = segment_at(&scene.keys, frame);
            let paths = self.detours.at_frame(scene, &shapes, frame);
            let segment_paths = match segment {
                Segment::Between { from, .. } => paths.get(from).map(|p| &**p),
                Segment::Hold(_) => None,
            };
            blend_segment(&scene.keys, &shapes, segment, segment_paths, points, &mut self.ratio);
            let (a, b, eased) = match segment {
                Segment::Hold(index) => (index, index, 0.0),
                Segment::Between { from, eased } => (from, from + 1, eased),
            };
            let obstacles = obstacles_at(scene, frame, &self.solids);
            let key = side_key(segment);
            let moved = moved_since_key(scene, key, frame);
            // A relaxed in-between among colliders: the relaxation knows no
            // colliders, so it starts from the blend round them, and each
            // point's move from that blend stops at the first surface it meets.
            let relaxes = relaxes_between(&scene.keys, segment);
            let relaxed = !obstacles.is_empty() && relaxes;
            if relaxed {
                blend_positions(&shapes[a].points, &shapes[b].points, eased as f32, &mut self.before_layers);
            }
            // A relaxed blend starts from the paths already; its unrelaxed twin goes round them here.
            let went_round = if relaxed {
                Some(&mut self.before_layers)
            } else if relaxes {
                None
            } else {
                Some(&mut *points)
            };
            if let (Some(paths), Some(went_round)) = (segment_paths, went_round) {
                paths.go_round(eased, went_round);
            }
            carry_with_node(scene, &shapes, (a, b, eased), frame, points);
            carry_to_attachments(scene, (a, b), eased, frame, points);
            if relaxed {
                carry_with_node(scene, &shapes, (a, b, eased), frame, &mut self.before_layers);
                carry_to_attachments(scene, (a, b), eased, frame, &mut self.before_layers);
                stop_at_surfaces(&obstacles, &self.before_layers, points);
            }
            self.clear_points.forget();
            self.clear_edges.forget();
            self.held.clear();
            if obstacles.is_empty() {
                self.before_layers = PointArrays::default();
            } else {
                // Only points pinned at both ends of the segment stay put; one
                // being let go or caught is cloth, and keeps out like cloth.
                self.held.extend(shapes[a].pinned.iter().zip(&shapes[b].pinned).map(|(p, q)| *p && *q));
                keep_sides(&moved, &shapes[key].points, &self.held, points);
                self.before_layers.clone_from(points);
            }
            self.scratch.attenuation.clear();
            if options.layers {
                let at = LayerFrame {
                    frame,
                    fps,
                    grid: (cols, rows),
                    spacing_m: (scene.cloth.spacing_u_m(), scene.cloth.spacing_v_m()),
                    stretch_limit: scene.cloth.stretch_limit as f32,
                    ratio: &self.ratio,
                    keys: &scene.keys,
                    shapes: &shapes,
                    paths: &paths,
                };
                for layer in scene.layers.iter().filter(|l| l.enabled()) {
                    let weight = sample(layer.weight(), frame);
                    if weight == 0.0 || !weight.is_finite() {
                        continue;
                    }
                    layer.apply(&at, weight, &mut self.scratch, points);
                }
                let reaches = [&shapes[a].reach, &shapes[b].reach];
                let reaches = if a == b { &reaches[..1] } else { &reaches[..] };
                let limit = scene.cloth.stretch_limit as f32;
                self.stretch_limiter.set_obstacles(&obstacles);
                self.stretch_limiter.apply(limit, (cols, rows), &self.ratio, reaches, points);
                // Pushing points and edges out of a collider can lengthen the
                // edges around them, and the limit can pull them back in:
                // alternate, and keep out last, so nothing ends inside.
                for _ in 0..CONTACT_ROUNDS {
                    let sides_kept = keep_sides(&moved, &shapes[key].points, &self.held, points);
                    let points_out = sides_kept
                        | keep_out(&obstacles, &self.held, &self.before_layers, &mut self.clear_points, points);
                    let edges_out = keep_edges_out(
                        &obstacles,
                        &self.held,
                        &self.before_layers,
                        (cols, rows),
                        &mut self.clear_edges,
                        points,
                    );
                    if !points_out && !edges_out {
                        break;
                    }
                    self.stretch_limiter.apply(limit, (cols, rows), &self.ratio, reaches, points);
                }
            }
            keep_out(&obstacles, &self.held, &self.before_layers, &mut self.clear_points, points);
        }
        // The mesh's positions and normals, interleaved row by row.
        let interleave = |out: &mut Vec<Vec3>, [x, y, z]: [&[f32]; 3]| {
            out.extend(x.iter().zip(y).zip(z).map(|((&x, &y), &z)| Vec3::new(x, y, z)));
        };
        mesh.positions.clear();
        mesh.normals.clear();
        let normal_rows = &mut self.scratch.normal_rows;
        normal_rows.start(cols, rows);
        while let Some((_, normals, [x, y, z])) = normal_rows.next_row(points) {
            interleave(&mut mesh.normals, normals);
            interleave(&mut mesh.positions, [x, y, z]);
        }
    }
}

/// The mesh of `scene` at `t_secs` (frame t_secs · fps): rest shapes blended
/// under the segment's easing, then every enabled layer in order. A pure
/// function of its inputs; it relaxes every key, so interactive callers keep
/// an [`Evaluator`] instead.
pub fn evaluate(scene: &Scene, t_secs: f64) -> Mesh {
    Evaluator::new().evaluate(scene, t_secs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every layer kind on an odd-sized grid (loop tails in every pass), with
    /// falloffs other than 1 and 3-octave gusts.
    const EVERY_LAYER: &str = r#"(
        version: 1,
        cloth: (size: (1.3, 0.9), grid: (23, 14)),
        keys: [
            (frame: 0, pins: [(grid: (0, 0), pos: (-0.6, 1.0, 0.0)), (grid: (22, 0), pos: (0.6, 1.0, 0.0))]),
            (frame: 30, pins: [(grid: (0, 0), pos: (-0.5, 1.2, 0.2)), (grid: (11, 0), pos: (0.0, 1.3, 0.1))],
             elasticity: 1.2, ease: Linear),
        ],
        layers: [
            Sway((name: "sway", magnitude: 0.1, direction: (1.0, 0.5, 2.0), speed: 1.5, frequency: 0.8, falloff: 2.0)),
            Wave((name: "normal", magnitude: 0.04, frequency: 9.0, speed: 3.0, direction_deg: 30.0, falloff: 1.5)),
            Wave((name: "fixed", magnitude: 0.02, frequency: 5.0, speed: 1.0, axis: Fixed((0.0, 1.0, 1.0)))),
            Gusts((name: "gusts", amplitude: 0.05, scale: 0.3, speed: 2.0, direction: (0.3, 0.1, 1.0),
                   turbulence: 0.6, octaves: 3, seed: 7, falloff: 0.7)),
            FollowThrough((name: "trail", lag: 0.3)),
        ],
    )"#;

    #[test]
    fn vectorised_and_portable_builds_agree_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let mut scenes = vec![crate::scene::parse(EVERY_LAYER, "every layer").unwrap()];
            for name in ["flag", "magic_carpet", "tablecloth_pull", "swing"] {
                let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.ron"));
                scenes.push(crate::scene::load(&path).unwrap());
            }
            let bits = |points: &[Vec3]| points.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
            let mut evaluator = Evaluator::new();
            for scene in &scenes {
                let (mut portable, mut vectorised) = (evaluator.evaluate(scene, 0.0), evaluator.evaluate(scene, 0.0));
                for t_secs in [0.0, 0.3, 0.61, 2.0, 4.9, 10_000.0, 1.25] {
                    let frame = t_secs * scene.timeline.fps;
                    evaluator.evaluate_portable(scene, frame, EvaluateOptions::default(), &mut portable);
                    // SAFETY: the CPU supports AVX2, checked above.
                    unsafe { evaluator.evaluate_avx2(scene, frame, EvaluateOptions::default(), &mut vectorised) };
                    assert_eq!(bits(&portable.positions), bits(&vectorised.positions), "{} at {t_secs} s", scene.name);
                    assert_eq!(bits(&portable.normals), bits(&vectorised.normals), "{} at {t_secs} s", scene.name);
                }
                let plain = evaluator.evaluate_with(scene, 1.25, EvaluateOptions { layers: false });
                assert_ne!(plain.positions, portable.positions, "{}: the layers move the cloth", scene.name);
            }
        }
    }
}
