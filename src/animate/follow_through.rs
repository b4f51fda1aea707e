//! The FollowThrough layer: overlapping action without physics. A point far
//! from the pins follows the keyed motion late, as if dragged behind:
//! displacement = key_blend(t − lag · a) − key_blend(t) at that point, with
//! a = (d_cp/d_max)^falloff and key_blend the straight vertex blend of the
//! rest shapes (the same every layer sees, without in-between relaxation).
//! Pins (a = 0) never move; on a held key nothing moves.
//!
//! The lag is a time shift, so a point trails by about its speed × lag × a,
//! and neighbours whose a differ trail by different amounts: the layer's
//! own stretch grows with the speed (unchecked, a carpet at full speed is
//! pulled into 1.5× long spikes). With the cloth's stretch limit on, the lag therefore
//! shortens while the cloth moves so fast that the farthest point, trailing
//! the full lag, would lie further behind than the fabric can give over
//! d_max: behind by at most limit × d_max / max(falloff, 1), which keeps
//! the layer's own stretch within the limit (for falloff ≥ 1). Slow moves
//! keep the full lag; the shortening follows the speed smoothly.

use std::sync::Arc;

use glam::Vec3;

use super::blend::{Segment, segment_at};
use super::cache::KeyShape;
use super::detours::SegmentPaths;
use super::layer::{ApplyLayer, LayerFrame, LayerScratch};
use super::track::sample;
use crate::mesh::PointArrays;
use crate::scene::FollowThrough;

/// The vertex blend of the rest shapes at vertex `k` in `segment`: straight,
/// or round a collider where `paths` say so.
#[inline]
fn blended_vertex(shapes: &[Arc<KeyShape>], paths: &[Arc<SegmentPaths>], segment: Segment, k: usize) -> Vec3 {
    match segment {
        Segment::Hold(index) => shapes[index].positions[k],
        Segment::Between { from, eased } => {
            if let Some(p) = paths.get(from).and_then(|paths| paths.at(k, eased)) {
                return p;
            }
            let (p, q) = (shapes[from].positions[k], shapes[from + 1].positions[k]);
            p + (q - p) * eased as f32
        }
    }
}

/// The lag this frame uses: `lag_secs`, shortened in proportion when the
/// blend moves some vertex further than limit × d_max / max(falloff, 1)
/// between `then` (the blend `lag_secs` ago) and `now`. d_max is blended
/// like the segment, so the cap is continuous in time.
fn lag_within_limit(
    lag_secs: f64,
    limit: f32,
    falloff: f32,
    shapes: &[Arc<KeyShape>],
    paths: &[Arc<SegmentPaths>],
    now: Segment,
    then: Segment,
) -> f64 {
    if !(limit > 0.0 && limit.is_finite()) || then == now {
        return lag_secs;
    }
    let d_max_m = match now {
        Segment::Hold(index) => shapes[index].d_max_m,
        Segment::Between { from, eased } => {
            let (a, b) = (shapes[from].d_max_m, shapes[from + 1].d_max_m);
            a + (b - a) * eased as f32
        }
    };
    let allowed_m = limit * d_max_m / falloff.max(1.0);
    let n = shapes[0].positions.len();
    let farthest_m = (0..n)
        .map(|k| (blended_vertex(shapes, paths, then, k) - blended_vertex(shapes, paths, now, k)).length())
        .fold(0.0f32, f32::max);
    if farthest_m > allowed_m && farthest_m.is_finite() {
        lag_secs * f64::from(allowed_m / farthest_m)
    } else {
        lag_secs
    }
}

/// Adds the follow-through to `points`, attenuated per vertex; with the
/// cloth's stretch limit off (0) the lag is never shortened.
impl ApplyLayer for FollowThrough {
    #[inline(always)]
    fn apply(&self, at: &LayerFrame, weight: f64, scratch: &mut LayerScratch, points: &mut PointArrays) {
        let LayerFrame { frame, fps, keys, shapes, .. } = *at;
        let lag_secs = sample(&self.lag, frame);
        let falloff = sample(&self.falloff, frame) as f32;
        if keys.len() < 2 || weight == 0.0 || !weight.is_finite() || !(lag_secs > 0.0) {
            return;
        }
        let now = segment_at(keys, frame);
        let then = segment_at(keys, frame - lag_secs * fps);
        let lag_secs = lag_within_limit(lag_secs, at.stretch_limit, falloff, shapes, at.paths, now, then);
        let weight = weight as f32;
        for (k, &a) in scratch.attenuation.of(at.ratio, falloff).iter().enumerate() {
            if a == 0.0 {
                continue;
            }
            let then = segment_at(keys, frame - lag_secs * f64::from(a) * fps);
            if then == now {
                continue;
            }
            let moved = points.get(k)
                + (blended_vertex(shapes, at.paths, then, k) - blended_vertex(shapes, at.paths, now, k)) * weight;
            points.set(k, moved);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::blend::blend_segment;
    use crate::animate::evaluate::Evaluator;
    use crate::animate::stretch_limit::longest_stretch;
    use crate::scene::{Cloth, Ease, Key, Pin, RelaxSettings};

    /// A 1 m cloth held at its four corners, moved `travel_m` along z in 12 frames.
    fn keys(travel_m: f64) -> (Cloth, Vec<Key>) {
        let cloth = Cloth::new((1.0, 1.0), (17, 17));
        let key = |frame, z: f64| {
            let pin = |grid, x, zz: f64| Pin::at(grid, (x, 1.0, zz + z));
            Key {
                frame,
                pins: vec![
                    pin((0, 0), -0.5, -0.5),
                    pin((16, 0), 0.5, -0.5),
                    pin((0, 16), -0.5, 0.5),
                    pin((16, 16), 0.5, 0.5),
                ],
                elasticity: 1.1,
                stiffness: 0.2,
                relax: RelaxSettings::default(),
                ease: Ease::Linear,
                inbetween_relax: 0,
                thickness: crate::scene::DEFAULT_THICKNESS_M,
                friction: crate::scene::DEFAULT_FRICTION,
                placement: None,
            }
        };
        (cloth, vec![key(0, 0.0), key(12, travel_m)])
    }

    /// The cloth at `frame` with the layer alone (no stretch limit afterwards), and its longest edge.
    fn trailing(travel_m: f64, limit: f32, frame: f64) -> (Vec<Vec3>, f64) {
        let (cloth, keys) = keys(travel_m);
        let mut evaluator = Evaluator::new();
        let shapes: Vec<_> = keys.iter().map(|k| evaluator.cache_mut().shape(&cloth, k, &[])).collect();
        let mut points = PointArrays::default();
        let mut ratio = Vec::new();
        blend_segment(&keys, &shapes, segment_at(&keys, frame), None, &mut points, &mut ratio);
        let follow = FollowThrough { lag: 0.3.into(), falloff: 1.0.into(), ..FollowThrough::with_start_values() };
        let (cols, rows) = (cloth.cols(), cloth.rows());
        let at = LayerFrame {
            frame,
            fps: 24.0,
            grid: (cols, rows),
            spacing_m: (cloth.spacing_u_m(), cloth.spacing_v_m()),
            stretch_limit: limit,
            ratio: &ratio,
            keys: &keys,
            shapes: &shapes,
            paths: &[],
        };
        follow.apply(&at, 1.0, &mut LayerScratch::default(), &mut points);
        let positions: Vec<Vec3> = (0..points.len()).map(|k| points.get(k)).collect();
        let rest = cloth.spacing_u_m() * 1.1;
        let longest = longest_stretch(&positions, (cloth.cols(), cloth.rows()), rest, rest);
        (positions, longest)
    }

    #[test]
    fn a_fast_move_trails_without_stretching_the_cloth_past_its_limit() {
        // 5 m in half a second: a time lag alone stretches the cloth far past 10 %.
        let (_, unlimited) = trailing(5.0, 0.0, 8.0);
        assert!(unlimited > 1.3, "without a limit the lag tears: {unlimited}");
        let (capped, longest) = trailing(5.0, 0.1, 8.0);
        assert!(longest <= 1.1 + 0.02, "the layer keeps within the limit: {longest}");
        // It still trails: the middle lags behind (−z) the blend.
        let (held, _) = trailing(5.0, 0.1, 8.0 + 1e-9);
        let middle = 8 * 17 + 8;
        let (cloth, keys) = keys(5.0);
        let mut evaluator = Evaluator::new();
        let shapes: Vec<_> = keys.iter().map(|k| evaluator.cache_mut().shape(&cloth, k, &[])).collect();
        let blended = blended_vertex(&shapes, &[], segment_at(&keys, 8.0), middle);
        assert!(capped[middle].z < blended.z - 0.02, "the middle trails: {} vs {}", capped[middle].z, blended.z);
        assert!((held[middle] - capped[middle]).length() < 1e-3, "the cap is continuous in time");
    }

    #[test]
    fn a_slow_move_keeps_the_full_lag() {
        // 5 cm in half a second: nothing near the limit, the cap changes nothing.
        assert_eq!(trailing(0.05, 0.1, 8.0).0, trailing(0.05, 0.0, 8.0).0);
    }
}
