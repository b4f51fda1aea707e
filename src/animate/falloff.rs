//! The pin-distance attenuation of the paper's eqs. 2 and 4:
//! a = (d_cp / d_max)^falloff, with d_cp measured in material space (u, v).

use crate::scene::{Cloth, Pin};
use crate::world::Obstacle;

/// d_cp/d_max for every grid point of `cloth` (vertex order `j·cols + i`):
/// the material distance to the closest of `pins`, over its largest value on
/// the cloth. Exactly 0 at the pins, 1 at the farthest point. With no pins, or
/// when every point is pinned, the field is all zeros (nothing may move).
pub fn pin_distance_ratio(cloth: &Cloth, pins: &[Pin]) -> Vec<f32> {
    pin_distance_field(cloth, pins).0
}

/// [`pin_distance_ratio`] and d_max, the largest material distance to the
/// closest pin (m; 0 with no pins or every point pinned).
pub fn pin_distance_field(cloth: &Cloth, pins: &[Pin]) -> (Vec<f32>, f64) {
    let (du, dv) = (cloth.spacing_u_m(), cloth.spacing_v_m());
    let pins_uv: Vec<(f64, f64)> = pins.iter().map(|p| (f64::from(p.grid.0) * du, f64::from(p.grid.1) * dv)).collect();
    distance_ratio(cloth, &pins_uv, |_| false)
}

/// d_cp/d_max with d_cp the material distance from each grid point to the
/// closest of `targets` (material (u, v), m), 0 where `held` says so; d_max
/// its largest value. All zeros (and d_max 0) when nothing is farther than 0.
fn distance_ratio(cloth: &Cloth, targets: &[(f64, f64)], held: impl Fn(usize) -> bool) -> (Vec<f32>, f64) {
    let (cols, rows) = (cloth.cols(), cloth.rows());
    let (du, dv) = (cloth.spacing_u_m(), cloth.spacing_v_m());
    let mut distance = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        let v = j as f64 * dv;
        for i in 0..cols {
            if held(j * cols + i) {
                distance.push(0.0);
                continue;
            }
            let u = i as f64 * du;
            let closest2 =
                targets.iter().map(|&(pu, pv)| (u - pu) * (u - pu) + (v - pv) * (v - pv)).fold(f64::INFINITY, f64::min);
            distance.push(closest2.sqrt());
        }
    }
    let d_max = distance.iter().copied().filter(|d| d.is_finite()).fold(0.0, f64::max);
    if d_max <= 0.0 {
        return (vec![0.0; cols * rows], 0.0);
    }
    (distance.iter().map(|&d| if d.is_finite() { (d / d_max) as f32 } else { 0.0 }).collect(), d_max)
}

/// How much farther than its thickness a point may be from a collider's
/// surface and still rest on it (m).
const RESTING_WITHIN_M: f64 = 2e-3;
/// How upright a surface must face to hold the cloth up (the y of its
/// outward direction): a table top, a ball's upper half, not a table's side.
const HOLDING_UP_Y: f64 = 0.5;

/// For a key without pins, d_cp/d_max measured from the points of its rest
/// shape `positions` that rest on the `obstacles` (within their thickness
/// and 2 mm, on a surface facing up): the colliders hold the cloth as pins
/// would, so the layers move what hangs free (a tablecloth's overhang) and
/// leave what lies on the table. All zeros when nothing rests on them.
pub fn resting_distance_field(cloth: &Cloth, positions: &[glam::DVec3], obstacles: &[Obstacle]) -> (Vec<f32>, f64) {
    let (cols, rows) = (cloth.cols(), cloth.rows());
    let n = cols * rows;
    if positions.len() != n {
        return (vec![0.0; n], 0.0);
    }
    let resting: Vec<bool> = positions
        .iter()
        .map(|&p| {
            obstacles.iter().any(|o| {
                let s = o.shape.surface_point(p);
                s.distance <= o.thickness + RESTING_WITHIN_M && s.outward.y >= HOLDING_UP_Y
            })
        })
        .collect();
    // The nearest resting point of a free one is on the resting region's
    // edge (a resting point with every neighbour resting has one nearer),
    // so only those are measured to.
    let (du, dv) = (cloth.spacing_u_m(), cloth.spacing_v_m());
    let edge: Vec<(f64, f64)> = (0..n)
        .filter(|&k| resting[k])
        .filter(|&k| {
            let (i, j) = (k % cols, k / cols);
            let free = |i: usize, j: usize| !resting[j * cols + i];
            (i > 0 && free(i - 1, j))
                || (i + 1 < cols && free(i + 1, j))
                || (j > 0 && free(i, j - 1))
                || (j + 1 < rows && free(i, j + 1))
        })
        .map(|k| ((k % cols) as f64 * du, (k / cols) as f64 * dv))
        .collect();
    distance_ratio(cloth, &edge, |k| resting[k])
}

/// a = ratio^falloff for a ratio in [0, 1]. A point with ratio 0 is held by
/// a pin and never moves, whatever the exponent (so 0^0 is 0 here); a
/// negative or NaN ratio counts as 0; falloff is clamped to ≥ 0.
#[inline]
pub fn attenuation(ratio: f32, falloff: f32) -> f32 {
    if !(ratio > 0.0) {
        return 0.0;
    }
    if falloff == 1.0 { ratio } else { ratio.powf(falloff.max(0.0)) }
}

/// [`attenuation`] of every vertex for one falloff, kept while the falloff
/// stays the same, so the layers of a frame that share a falloff (usually
/// all of them) compute it once.
#[derive(Clone, Debug, Default)]
pub struct AttenuationField {
    /// The falloff `values` hold, by its bits; None: nothing computed yet.
    falloff_bits: Option<u32>,
    values: Vec<f32>,
}

impl AttenuationField {
    /// Forgets the values: call it whenever the ratio field changes.
    pub fn clear(&mut self) {
        self.falloff_bits = None;
    }

    /// a = ratio^falloff for every entry of `ratio`, which must be the field
    /// passed since the last [`AttenuationField::clear`].
    #[inline(always)]
    pub fn of(&mut self, ratio: &[f32], falloff: f32) -> &[f32] {
        if self.falloff_bits != Some(falloff.to_bits()) || self.values.len() != ratio.len() {
            self.values.clear();
            if falloff == 1.0 {
                // The common case, as a select the compiler vectorises.
                self.values.extend(ratio.iter().map(|&r| if r > 0.0 { r } else { 0.0 }));
            } else {
                self.values.extend(ratio.iter().map(|&r| attenuation(r, falloff)));
            }
            self.falloff_bits = Some(falloff.to_bits());
        }
        &self.values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cloth_without_pins_is_held_where_it_rests_on_a_surface_facing_up() {
        use crate::world::ColliderShape;
        use glam::{DMat3, DVec3};
        // A 5 × 5 cloth 1 m square, level at 1.003 m, half over a box whose top is at 1 m.
        let cloth = Cloth::new((1.0, 1.0), (5, 5));
        let positions: Vec<DVec3> =
            (0..25).map(|k| DVec3::new((k % 5) as f64 * 0.25 - 0.5, 1.003, (k / 5) as f64 * 0.25 - 0.5)).collect();
        let table = ColliderShape::Box {
            center: DVec3::new(-0.5, 0.5, 0.0),
            half: DVec3::new(0.5, 0.5, 1.0),
            world_from_local: DMat3::IDENTITY,
        };
        let (ratio, d_max) = resting_distance_field(&cloth, &positions, &[Obstacle { shape: table, thickness: 0.003 }]);
        // Columns 0..=2 lie on the top (x ≤ 0); columns 3 and 4 hang free, 0.25 and 0.5 m from it.
        for j in 0..5 {
            assert_eq!(&ratio[j * 5..j * 5 + 5], &[0.0, 0.0, 0.0, 0.5, 1.0]);
        }
        assert!((d_max - 0.5).abs() < 1e-12);
        // Nothing resting (a wall beside, facing sideways; or nothing at all): all zeros.
        let wall = ColliderShape::Box {
            center: DVec3::new(-1.0, 1.0, 0.0),
            half: DVec3::new(0.497, 1.0, 1.0),
            world_from_local: DMat3::IDENTITY,
        };
        let beside = resting_distance_field(&cloth, &positions, &[Obstacle { shape: wall, thickness: 0.003 }]);
        assert_eq!(beside, (vec![0.0; 25], 0.0));
        assert_eq!(resting_distance_field(&cloth, &positions, &[]), (vec![0.0; 25], 0.0));
    }

    fn pin(i: u32, j: u32) -> Pin {
        Pin::at((i, j), (0.0, 0.0, 0.0))
    }

    #[test]
    fn ratio_is_zero_at_pins_and_one_at_the_farthest_point() {
        let cloth = Cloth::new((2.0, 1.0), (5, 3));
        let ratio = pin_distance_ratio(&cloth, &[pin(0, 0), pin(4, 0)]);
        assert_eq!(ratio[0], 0.0);
        assert_eq!(ratio[4], 0.0);
        // The farthest points from both top corners: bottom middle (2, 2) at √(1² + 1²).
        assert_eq!(ratio[2 * 5 + 2], 1.0);
        // (1, 0): 0.5 m from the left pin.
        assert!((ratio[1] - (0.5 / 2f64.sqrt()) as f32).abs() < 1e-7);
        assert!(ratio.iter().all(|r| (0.0..=1.0).contains(r)));
    }

    #[test]
    fn distance_is_measured_in_material_space() {
        // Non-square spacing: 0.5 m along u, 0.25 m along v.
        let cloth = Cloth::new((1.0, 0.5), (3, 3));
        let ratio = pin_distance_ratio(&cloth, &[pin(0, 0)]);
        let d_max = (1.0f64 + 0.25).sqrt();
        assert!((ratio[1] - (0.5 / d_max) as f32).abs() < 1e-7);
        assert!((ratio[3] - (0.25 / d_max) as f32).abs() < 1e-7);
    }

    #[test]
    fn fully_pinned_or_pinless_cloth_has_a_zero_field() {
        let cloth = Cloth::new((1.0, 1.0), (2, 2));
        assert_eq!(pin_distance_ratio(&cloth, &[pin(0, 0), pin(1, 0), pin(0, 1), pin(1, 1)]), vec![0.0; 4]);
        assert_eq!(pin_distance_ratio(&cloth, &[]), vec![0.0; 4]);
    }

    #[test]
    fn attenuation_keeps_pins_still_for_any_exponent() {
        assert_eq!(attenuation(0.0, 0.0), 0.0);
        assert_eq!(attenuation(0.0, 2.0), 0.0);
        assert_eq!(attenuation(-0.5, 1.0), 0.0);
        assert_eq!(attenuation(f32::NAN, 1.0), 0.0);
        assert_eq!(attenuation(0.25, 1.0), 0.25);
        assert_eq!(attenuation(0.5, 2.0), 0.25);
        assert_eq!(attenuation(0.5, 0.0), 1.0);
        assert_eq!(attenuation(0.5, -1.0), 1.0, "negative exponents clamp to 0");
        assert_eq!(attenuation(1.0, f32::INFINITY), 1.0);
        assert_eq!(attenuation(0.5, f32::NAN), 1.0, "a NaN exponent counts as 0");
    }

    #[test]
    fn the_field_equals_attenuation_and_follows_its_falloff() {
        let ratio = [0.0, 0.25, 1.0, -0.5, f32::NAN, 0.5];
        let mut field = AttenuationField::default();
        for falloff in [1.0, 2.0, 1.0, 0.0, f32::NAN] {
            let values = field.of(&ratio, falloff).to_vec();
            let expected: Vec<f32> = ratio.iter().map(|&r| attenuation(r, falloff)).collect();
            assert_eq!(
                values.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                expected.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
            );
        }
        field.clear();
        assert_eq!(field.of(&[0.5], 1.0), &[0.5]);
    }
}
