//! In-betweens (paper §3.3): where a frame falls among the keys, and the
//! blend of the two rest shapes around it under the segment's easing.
//!
//! Vertices blend straight from one rest shape to the other, so a pin in both
//! keys moves between its two positions and a pin in one key only is let go
//! (or caught) as smoothly as the easing. The d_cp/d_max fields of the two
//! keys blend the same way, so layer attenuation never pops when the pins
//! change. Straight blending shortens cloth whose keys differ a lot; a key's
//! `inbetween_relax` re-relaxes its segment's in-betweens from the blend.

use glam::{DVec3, Vec3};

use super::cache::KeyShape;
use super::detours::SegmentPaths;
use super::ease;
use crate::mesh::PointArrays;
use crate::scene::Key;
use crate::shape::{RelaxParams, refine};

/// Where a frame falls among the keys (keys in increasing frame order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// On key `index`, before the first key or after the last: its rest shape as is.
    Hold(usize),
    /// Between key `from` and key `from + 1`, `eased` of the way (the
    /// segment's curve at the elapsed fraction; Back and Elastic leave [0, 1]).
    Between { from: usize, eased: f64 },
}

/// The segment at `frame` (fractional frames are in-betweens). NaN holds the first key.
pub fn segment_at(keys: &[Key], frame: f64) -> Segment {
    let Some(last) = keys.len().checked_sub(1) else { return Segment::Hold(0) };
    if !(frame > f64::from(keys[0].frame)) {
        return Segment::Hold(0);
    }
    if frame >= f64::from(keys[last].frame) {
        return Segment::Hold(last);
    }
    // The last key at or before `frame`; it is not the last key.
    let from = keys.partition_point(|k| f64::from(k.frame) <= frame) - 1;
    let start = f64::from(keys[from].frame);
    if frame == start {
        return Segment::Hold(from);
    }
    let span = f64::from(keys[from + 1].frame) - start;
    let eased = ease::apply(keys[from].ease, (frame - start) / span);
    if eased == 0.0 { Segment::Hold(from) } else { Segment::Between { from, eased } }
}

/// The straight blend of two rest shapes' vertices: a + (b − a)·e, written into `out`.
#[inline(always)]
pub fn blend_positions(a: &PointArrays, b: &PointArrays, eased: f32, out: &mut PointArrays) {
    for ((a, b), out) in
        [(&a.x, &b.x), (&a.y, &b.y), (&a.z, &b.z)].into_iter().zip([&mut out.x, &mut out.y, &mut out.z])
    {
        out.clear();
        out.extend(a.iter().zip(b).map(|(&p, &q)| p + (q - p) * eased));
    }
}

/// The blended d_cp/d_max field, written into `out`; never below 0, so a
/// point pinned in both keys stays at 0 even under overshooting curves.
#[inline(always)]
pub fn blend_ratio(a: &[f32], b: &[f32], eased: f32, out: &mut Vec<f32>) {
    out.clear();
    out.extend(a.iter().zip(b).map(|(&p, &q)| (p + (q - p) * eased).max(0.0)));
}

/// Whether `segment` is an in-between its from-key's `inbetween_relax` re-relaxes.
pub fn relaxes_between(keys: &[Key], segment: Segment) -> bool {
    matches!(segment, Segment::Between { from, eased } if keys[from].inbetween_relax > 0 && eased != 1.0)
}

/// The rest-shape blend at a segment: positions and d_cp/d_max field, with the
/// from-key's `inbetween_relax` sweeps applied to in-betweens, those
/// starting from the segment's `paths` round the colliders.
#[inline(always)]
pub fn blend_segment(
    keys: &[Key],
    shapes: &[std::sync::Arc<KeyShape>],
    segment: Segment,
    paths: Option<&SegmentPaths>,
    points: &mut PointArrays,
    ratio: &mut Vec<f32>,
) {
    match segment {
        Segment::Hold(index) => {
            let rest = &shapes[index].points;
            points.x.clone_from(&rest.x);
            points.y.clone_from(&rest.y);
            points.z.clone_from(&rest.z);
            ratio.clear();
            ratio.extend_from_slice(&shapes[index].ratio);
        }
        Segment::Between { from, eased } => {
            let (a, b) = (&shapes[from], &shapes[from + 1]);
            if relaxes_between(keys, segment) {
                let mut relaxed = Vec::new();
                let sweeps = keys[from].inbetween_relax;
                relaxed_inbetween(&keys[from], &keys[from + 1], a, b, (eased, paths), sweeps, &mut relaxed);
                points.set_from_vec3s(&relaxed);
            } else {
                blend_positions(&a.points, &b.points, eased as f32, points);
            }
            blend_ratio(&a.ratio, &b.ratio, eased as f32, ratio);
        }
    }
}

/// The blend of two rest shapes re-relaxed for `sweeps` fine-grid sweeps, in
/// f64 from the f64 rest shapes. Every pin of either key is held at its
/// blended position: pins in both keys move between their positions, and a
/// pin being let go or caught travels with the blend. Fabric values blend with
/// the same easing, clamped between the two keys' values. Points that go
/// round a collider (`paths`) start from their path, so the relaxation
/// starts from a blend that passes through nothing.
///
/// A rest shape relaxed to its tolerance still drifts a little under further
/// sweeps, so the correction is faded in and out with 4·e·(1 − e): full
/// halfway, where straight blending shortens the cloth most, and nothing at
/// the keys, so the segment starts and ends exactly on its keys' shapes.
pub fn relaxed_inbetween(
    key_a: &Key,
    key_b: &Key,
    a: &KeyShape,
    b: &KeyShape,
    (eased, paths): (f64, Option<&SegmentPaths>),
    sweeps: u32,
    out: &mut Vec<Vec3>,
) {
    let grid = a.rest.grid;
    let mut blended: Vec<DVec3> =
        a.rest.relaxed.iter().zip(&b.rest.relaxed).map(|(&p, &q)| p + (q - p) * eased).collect();
    if let Some(paths) = paths {
        paths.go_round_f64(eased, &mut blended);
    }
    let pinned: Vec<bool> = a.pinned.iter().zip(&b.pinned).map(|(&p, &q)| p || q).collect();
    let mix = |x: f64, y: f64| (x + (y - x) * eased).clamp(x.min(y), x.max(y));
    let elasticity = mix(key_a.elasticity, key_b.elasticity);
    let params = RelaxParams {
        rest_u_m: grid.spacing_u_m * elasticity,
        rest_v_m: grid.spacing_v_m * elasticity,
        stiffness: mix(key_a.stiffness, key_b.stiffness),
        // Contact costs a pair search per frame; blends of drapes that never
        // reach themselves have nothing to keep apart.
        thickness_m: if a.rest.kept_apart || b.rest.kept_apart { mix(key_a.thickness, key_b.thickness) } else { 0.0 },
        max_iterations: sweeps,
        tolerance: key_a.relax.tolerance.min(key_b.relax.tolerance),
    };
    let mut relaxed = blended.clone();
    refine(&mut relaxed, grid.cols, grid.rows, &pinned, &params);
    let fade = (4.0 * eased * (1.0 - eased)).clamp(0.0, 1.0);
    out.clear();
    out.extend(blended.iter().zip(&relaxed).map(|(&b, &r)| (b + (r - b) * fade).as_vec3()));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Ease, Pin, RelaxSettings};

    fn key(frame: i32, ease: Ease) -> Key {
        Key {
            frame,
            pins: vec![Pin::at((0, 0), (0.0, 1.0, 0.0))],
            elasticity: 1.0,
            stiffness: 0.2,
            relax: RelaxSettings::default(),
            ease,
            inbetween_relax: 0,
            thickness: crate::scene::DEFAULT_THICKNESS_M,
            friction: crate::scene::DEFAULT_FRICTION,
            placement: None,
        }
    }

    #[test]
    fn segments_hold_outside_and_on_keys() {
        let keys = [key(0, Ease::Linear), key(10, Ease::Linear), key(30, Ease::Step)];
        assert_eq!(segment_at(&keys, -5.0), Segment::Hold(0));
        assert_eq!(segment_at(&keys, 0.0), Segment::Hold(0));
        assert_eq!(segment_at(&keys, 10.0), Segment::Hold(1));
        assert_eq!(segment_at(&keys, 30.0), Segment::Hold(2));
        assert_eq!(segment_at(&keys, 1e9), Segment::Hold(2));
        assert_eq!(segment_at(&keys, f64::NAN), Segment::Hold(0));
        assert_eq!(segment_at(&keys, 5.0), Segment::Between { from: 0, eased: 0.5 });
        assert_eq!(segment_at(&keys, 15.0), Segment::Between { from: 1, eased: 0.25 });
        assert_eq!(segment_at(&[], 3.0), Segment::Hold(0));
    }

    #[test]
    fn step_holds_the_earlier_key_until_the_next() {
        let keys = [key(0, Ease::Step), key(10, Ease::Linear)];
        assert_eq!(segment_at(&keys, 9.999), Segment::Hold(0));
        assert_eq!(segment_at(&keys, 10.0), Segment::Hold(1));
    }

    #[test]
    fn blends_hit_both_ends_exactly() {
        let a = [Vec3::new(1.0, 2.0, 3.0), Vec3::new(-0.1, 0.7, 1e-3)];
        let b = [Vec3::new(4.0, -2.0, 0.5), Vec3::new(0.3, 0.3, -2.0)];
        let (a, b) = (PointArrays::from_vec3s(&a), PointArrays::from_vec3s(&b));
        let mut out = PointArrays::default();
        blend_positions(&a, &b, 0.0, &mut out);
        assert_eq!(out, a);
        blend_positions(&a, &b, 0.5, &mut out);
        assert_eq!(out.get(0), Vec3::new(2.5, 0.0, 1.75));
        let mut ratio = Vec::new();
        blend_ratio(&[0.0, 0.5], &[0.0, 1.0], 1.2, &mut ratio);
        assert_eq!(ratio[0], 0.0, "pinned in both keys stays pinned under overshoot");
        blend_ratio(&[0.0, 0.5], &[0.3, 1.0], -0.5, &mut ratio);
        assert_eq!(ratio[0], 0.0, "never negative");
    }
}
