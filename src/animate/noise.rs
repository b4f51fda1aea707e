//! Seeded, smooth 3D value noise with four independent channels, for wind gusts.
//!
//! Random values in [−1, 1] sit on an integer lattice (from an integer hash of
//! the cell and the seed, so every machine gives the same noise) and are
//! blended with a quintic fade, which makes the field C² smooth. Four channels
//! share one hash per lattice corner and are interpolated together as a
//! `Vec4`, which is what makes a gust layer cheap enough to run per frame.
//!
//! Positions are split into a lattice offset (integers) and a small local
//! part, so a field scrolled far away (t = 10 000 s of wind) keeps full f32
//! precision.

use glam::{IVec3, Vec3, Vec4};

/// Fractal sum of `octaves` value-noise layers at `local + cell_offset`, each
/// octave at twice the frequency and half the amplitude of the previous,
/// normalised back to [−1, 1]. `octaves` is clamped to 1..=8. Non-finite
/// input gives zeros rather than NaN.
pub fn fractal4(local: Vec3, cell_offset: IVec3, octaves: u32, seed: u32) -> Vec4 {
    if !local.is_finite() {
        return Vec4::ZERO;
    }
    let octaves = octaves.clamp(1, 8);
    let mut sum = Vec4::ZERO;
    let mut amplitude = 1.0;
    let mut total = 0.0;
    let (mut local, mut offset) = (local, cell_offset);
    for octave in 0..octaves {
        sum += value4(local, offset, seed.wrapping_add(octave.wrapping_mul(0x9e37_79b9))) * amplitude;
        total += amplitude;
        amplitude *= 0.5;
        local *= 2.0;
        offset = IVec3::new(offset.x.wrapping_mul(2), offset.y.wrapping_mul(2), offset.z.wrapping_mul(2));
    }
    sum / total
}

/// One octave: the four channels of the noise at lattice point `cell_offset` + `local`.
pub fn value4(local: Vec3, cell_offset: IVec3, seed: u32) -> Vec4 {
    let floor = local.floor();
    let f = local - floor;
    let cell = IVec3::new(
        (floor.x as i32).wrapping_add(cell_offset.x),
        (floor.y as i32).wrapping_add(cell_offset.y),
        (floor.z as i32).wrapping_add(cell_offset.z),
    );
    let w = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let corner = |dx: i32, dy: i32, dz: i32| {
        lattice_value(cell.x.wrapping_add(dx), cell.y.wrapping_add(dy), cell.z.wrapping_add(dz), seed)
    };
    let x00 = corner(0, 0, 0).lerp(corner(1, 0, 0), w.x);
    let x10 = corner(0, 1, 0).lerp(corner(1, 1, 0), w.x);
    let x01 = corner(0, 0, 1).lerp(corner(1, 0, 1), w.x);
    let x11 = corner(0, 1, 1).lerp(corner(1, 1, 1), w.x);
    x00.lerp(x10, w.y).lerp(x01.lerp(x11, w.y), w.z)
}

/// Four values in [−1, 1] for a lattice point, one per byte of its hash.
#[inline]
fn lattice_value(x: i32, y: i32, z: i32, seed: u32) -> Vec4 {
    let h = hash(x, y, z, seed);
    let byte = |shift: u32| ((h >> shift) & 0xff) as f32 * (2.0 / 255.0) - 1.0;
    Vec4::new(byte(0), byte(8), byte(16), byte(24))
}

/// A well-mixed 32-bit hash of a lattice point and the seed (the "lowbias32"
/// finaliser over a multiplicative combination of the coordinates).
#[inline]
fn hash(x: i32, y: i32, z: i32, seed: u32) -> u32 {
    let mut h = seed
        ^ (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ (z as u32).wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_samples() -> impl Iterator<Item = Vec3> {
        (0..2000).map(|k| {
            let k = k as f32;
            Vec3::new((k * 0.137).sin() * 7.3, (k * 0.071).cos() * 5.1, k * 0.013 - 9.0)
        })
    }

    #[test]
    fn values_stay_in_range_and_are_deterministic() {
        for p in grid_samples() {
            let n = fractal4(p, IVec3::ZERO, 3, 42);
            assert!(n.abs().max_element() <= 1.0 + 1e-6, "{n} at {p}");
            assert_eq!(n, fractal4(p, IVec3::ZERO, 3, 42));
        }
    }

    #[test]
    fn lattice_points_carry_their_hashed_value() {
        let p = Vec3::new(3.0, -2.0, 5.0);
        assert_eq!(value4(p, IVec3::ZERO, 1), lattice_value(3, -2, 5, 1));
    }

    #[test]
    fn the_field_is_smooth() {
        // A step of 1e-3 cells changes the value by at most ~ max slope · step.
        for p in grid_samples() {
            let a = value4(p, IVec3::ZERO, 9);
            let b = value4(p + Vec3::splat(1e-3), IVec3::ZERO, 9);
            assert!((a - b).abs().max_element() < 0.02, "{a} vs {b} at {p}");
        }
    }

    #[test]
    fn seeds_and_channels_are_independent() {
        let mut same_seed = 0;
        let mut same_channel = 0;
        let mut mean = Vec4::ZERO;
        let count = 2000;
        for p in grid_samples() {
            let a = value4(p, IVec3::ZERO, 1);
            let b = value4(p, IVec3::ZERO, 2);
            mean += a;
            same_seed += usize::from((a.x - b.x).abs() < 1e-3);
            same_channel += usize::from((a.x - a.y).abs() < 1e-3);
        }
        mean /= count as f32;
        assert!(same_seed < 20 && same_channel < 20, "{same_seed}, {same_channel}");
        assert!(mean.abs().max_element() < 0.1, "channels average near 0: {mean}");
    }

    #[test]
    fn the_offset_split_is_exact_on_whole_cells() {
        let p = Vec3::new(0.25, 0.5, 0.75);
        let far = IVec3::new(1_000_000, -3, 70_000);
        let direct = value4(p + Vec3::new(0.0, -3.0, 0.0), IVec3::new(1_000_000, 0, 70_000), 5);
        assert_eq!(value4(p, far, 5), direct);
    }

    #[test]
    fn non_finite_input_gives_zero() {
        assert_eq!(fractal4(Vec3::new(f32::NAN, 0.0, 0.0), IVec3::ZERO, 2, 0), Vec4::ZERO);
        assert_eq!(fractal4(Vec3::splat(f32::INFINITY), IVec3::ZERO, 2, 0), Vec4::ZERO);
    }
}
