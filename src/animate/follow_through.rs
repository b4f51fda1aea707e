//! The FollowThrough layer: overlapping action without physics. A point far
//! from the pins follows the keyed motion late, as if dragged behind:
//! displacement = key_blend(t − lag · a) − key_blend(t) at that point, with
//! a = (d_cp/d_max)^falloff and key_blend the straight vertex blend of the
//! rest shapes (the same every layer sees, without in-between relaxation).
//! Pins (a = 0) never move; on a held key nothing moves.

use std::sync::Arc;

use glam::Vec3;

use super::blend::{Segment, segment_at};
use super::cache::KeyShape;
use super::falloff::AttenuationField;
use super::track::sample;
use crate::mesh::PointArrays;
use crate::scene::{FollowThrough, Key};

/// The straight vertex blend of the rest shapes at vertex `k` in `segment`.
#[inline]
fn blended_vertex(shapes: &[Arc<KeyShape>], segment: Segment, k: usize) -> Vec3 {
    match segment {
        Segment::Hold(index) => shapes[index].positions[k],
        Segment::Between { from, eased } => {
            let (p, q) = (shapes[from].positions[k], shapes[from + 1].positions[k]);
            p + (q - p) * eased as f32
        }
    }
}

/// Adds the follow-through to `points`, attenuated per vertex by `ratio`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn apply(
    follow: &FollowThrough,
    keys: &[Key],
    shapes: &[Arc<KeyShape>],
    fps: f64,
    frame: f64,
    weight: f64,
    ratio: &[f32],
    attenuation: &mut AttenuationField,
    points: &mut PointArrays,
) {
    let lag_secs = sample(&follow.lag, frame);
    let falloff = sample(&follow.falloff, frame) as f32;
    if keys.len() < 2 || weight == 0.0 || !weight.is_finite() || !(lag_secs > 0.0) {
        return;
    }
    let now = segment_at(keys, frame);
    let weight = weight as f32;
    for (k, &a) in attenuation.of(ratio, falloff).iter().enumerate() {
        if a == 0.0 {
            continue;
        }
        let then = segment_at(keys, frame - lag_secs * f64::from(a) * fps);
        if then == now {
            continue;
        }
        let moved = points.get(k) + (blended_vertex(shapes, then, k) - blended_vertex(shapes, now, k)) * weight;
        points.set(k, moved);
    }
}
