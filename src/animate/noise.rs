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
    FractalSampler::new(octaves, seed).sample(local, cell_offset)
}

/// [`fractal4`] for many nearby points: it remembers the lattice values of the
/// last cell of each octave, so a run of points inside one cell (neighbouring
/// vertices of a cloth, whose spacing is much smaller than a gust) hashes its
/// corners once. The results equal [`fractal4`]'s bit for bit.
#[derive(Clone, Debug)]
pub struct FractalSampler {
    seed: u32,
    octaves: usize,
    cells: [CellValues; MAX_OCTAVES],
}

const MAX_OCTAVES: usize = 8;

/// One lattice cell's trilinear interpolant as polynomial coefficients in the
/// fade weights (w): v = c0 + c1·wx + c2·wy + c3·wz + c4·wx·wy + c5·wy·wz +
/// c6·wx·wz + c7·wx·wy·wz. Computed once per cell, it costs a point seven
/// multiply-adds instead of seven lerps.
#[derive(Clone, Copy, Debug)]
struct CellValues {
    cell: IVec3,
    coefficients: [Vec4; 8],
    valid: bool,
}

impl CellValues {
    const EMPTY: CellValues = CellValues { cell: IVec3::ZERO, coefficients: [Vec4::ZERO; 8], valid: false };

    fn fill(&mut self, cell: IVec3, seed: u32) {
        // Corner index bit 0: +x, bit 1: +y, bit 2: +z.
        let v: [Vec4; 8] = std::array::from_fn(|index| {
            lattice_value(
                cell.x.wrapping_add((index & 1) as i32),
                cell.y.wrapping_add(((index >> 1) & 1) as i32),
                cell.z.wrapping_add(((index >> 2) & 1) as i32),
                seed,
            )
        });
        self.coefficients = [
            v[0],
            v[1] - v[0],
            v[2] - v[0],
            v[4] - v[0],
            v[3] - v[2] - v[1] + v[0],
            v[6] - v[4] - v[2] + v[0],
            v[5] - v[4] - v[1] + v[0],
            v[7] - v[6] - v[5] - v[3] + v[4] + v[2] + v[1] - v[0],
        ];
        self.cell = cell;
        self.valid = true;
    }

    #[inline(always)]
    fn interpolate(&self, w: Vec3) -> Vec4 {
        let c = &self.coefficients;
        let a = c[0] + c[2] * w.y;
        let b = c[1] + c[4] * w.y;
        let z = c[3] + c[5] * w.y;
        let xz = c[6] + c[7] * w.y;
        a + z * w.z + (b + xz * w.z) * w.x
    }
}

impl FractalSampler {
    pub fn new(octaves: u32, seed: u32) -> FractalSampler {
        let octaves = octaves.clamp(1, MAX_OCTAVES as u32) as usize;
        FractalSampler { seed, octaves, cells: [CellValues::EMPTY; MAX_OCTAVES] }
    }

    #[inline]
    pub fn sample(&mut self, local: Vec3, cell_offset: IVec3) -> Vec4 {
        if !local.is_finite() {
            return Vec4::ZERO;
        }
        // Octave weights 1, ½, ¼, … normalised to sum to 1.
        let mut weight = 1.0 / (2.0 - 0.5f32.powi(self.octaves as i32 - 1));
        let mut sum = Vec4::ZERO;
        let (mut local, mut offset) = (local, cell_offset);
        for (octave, cell) in self.cells[..self.octaves].iter_mut().enumerate() {
            sum += value4_cached(local, offset, self.seed, octave, cell) * weight;
            weight *= 0.5;
            local *= 2.0;
            offset = IVec3::new(offset.x.wrapping_mul(2), offset.y.wrapping_mul(2), offset.z.wrapping_mul(2));
        }
        sum
    }
}

fn octave_seed(seed: u32, octave: usize) -> u32 {
    seed.wrapping_add((octave as u32).wrapping_mul(0x9e37_79b9))
}

/// One octave: the four channels of the noise at lattice point `cell_offset` + `local`.
pub fn value4(local: Vec3, cell_offset: IVec3, seed: u32) -> Vec4 {
    value4_cached(local, cell_offset, seed, 0, &mut CellValues::EMPTY.clone())
}

/// floor(x) as an integer without a libm call (x86-64's baseline has no
/// rounding instruction); saturates outside the i32 range.
#[inline]
fn floor_i32(x: f32) -> i32 {
    let i = x as i32;
    i - i32::from((i as f32) > x)
}

#[inline(always)]
fn value4_cached(local: Vec3, cell_offset: IVec3, seed: u32, octave: usize, cache: &mut CellValues) -> Vec4 {
    let floor = IVec3::new(floor_i32(local.x), floor_i32(local.y), floor_i32(local.z));
    let f = local - floor.as_vec3();
    let cell = IVec3::new(
        floor.x.wrapping_add(cell_offset.x),
        floor.y.wrapping_add(cell_offset.y),
        floor.z.wrapping_add(cell_offset.z),
    );
    if !cache.valid || cache.cell != cell {
        cache.fill(cell, octave_seed(seed, octave));
    }
    cache.interpolate(f * f * f * (f * (f * 6.0 - 15.0) + 10.0))
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
    fn the_sampler_equals_the_direct_sum_in_any_order() {
        let mut sampler = FractalSampler::new(3, 11);
        let points: Vec<Vec3> = grid_samples().collect();
        for p in points.iter().chain(points.iter().rev()) {
            assert_eq!(sampler.sample(*p, IVec3::new(4, 0, -2)), fractal4(*p, IVec3::new(4, 0, -2), 3, 11));
        }
        for p in [-1.5f32, -1.0, -0.25, 0.0, 0.999_999_9, 2.0] {
            assert_eq!(floor_i32(p), p.floor() as i32, "{p}");
        }
    }

    #[test]
    fn non_finite_input_gives_zero() {
        assert_eq!(fractal4(Vec3::new(f32::NAN, 0.0, 0.0), IVec3::ZERO, 2, 0), Vec4::ZERO);
        assert_eq!(fractal4(Vec3::splat(f32::INFINITY), IVec3::ZERO, 2, 0), Vec4::ZERO);
    }
}
