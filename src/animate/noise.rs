//! Seeded, smooth 3D value noise with four independent channels, for wind gusts.
//!
//! Random values in [−1, 1] sit on an integer lattice (from an integer hash of
//! the cell and the seed, so every machine gives the same noise) and are
//! blended with a quintic fade, which makes the field C² smooth. Four channels
//! share one hash per lattice corner.
//!
//! Speed matters (a gust layer runs on every vertex every frame), so a cell's
//! trilinear interpolant is kept as polynomial coefficients while points stay
//! inside it, and [`FractalSampler::sample_lanes`] evaluates four points at
//! once with one SIMD lane per point, taking and returning them as
//! per-coordinate and per-channel vectors (no transposes). Every path
//! performs the same operations in the same order per value, so all give
//! bit-identical results.
//!
//! Positions are split into a lattice offset (integers) and a small local
//! part, so a field scrolled far away (t = 10 000 s of wind) keeps full f32
//! precision.

use glam::{IVec3, Mat4, Vec3, Vec4};

/// Fractal sum of `octaves` value-noise layers at `local + cell_offset`, each
/// octave at twice the frequency and half the amplitude of the previous,
/// normalised back to [−1, 1]. `octaves` is clamped to 1..=8. Non-finite
/// input gives zeros rather than NaN.
pub fn fractal4(local: Vec3, cell_offset: IVec3, octaves: u32, seed: u32) -> Vec4 {
    FractalSampler::new(octaves, seed, cell_offset).sample(local)
}

/// [`fractal4`] for many nearby points around one lattice offset: it
/// remembers the interpolants of recently used cells of each octave, so the
/// points inside one cell (neighbouring vertices of a cloth, whose spacing is
/// much smaller than a gust) hash its corners once. The results equal
/// [`fractal4`]'s bit for bit, whatever the order of the points.
#[derive(Clone, Debug)]
pub struct FractalSampler {
    seed: u32,
    octaves: usize,
    /// Octave weights 1, ½, ¼, … normalised to sum to 1.
    weights: [f32; MAX_OCTAVES],
    /// The lattice offset of each octave (doubling, wrapping like the cells).
    offsets: [IVec3; MAX_OCTAVES],
    /// Coordinates below this stay below 2²² at the finest octave, where
    /// [`floor4`] is exact.
    lane_limit: f32,
    /// The floored local corner of the cell in each of [`CELL_SLOTS`] slots
    /// per octave (octave-major); NaN marks an empty slot, as it equals nothing.
    keys: Vec<Vec3>,
    cells: Vec<CellValues>,
    /// Per octave, the cell that all four lanes of the latest
    /// [`FractalSampler::sample_lanes`] pass fell in: its corner in every
    /// lane (NaN: none) and its index in `cells`. The next four vertices of
    /// a row are nearly always in it too, and then need no slot lookup.
    last_cell: [([Vec4; 3], usize); MAX_OCTAVES],
}

impl Default for FractalSampler {
    fn default() -> Self {
        FractalSampler::new(1, 0, IVec3::ZERO)
    }
}

/// Cells remembered per octave (a power of two), direct-mapped by their
/// corner: enough for the cells a few rows of a cloth cross, so the next row
/// finds those of the previous one.
const CELL_SLOTS: usize = 64;

/// The slot of a cell among [`CELL_SLOTS`], from the bits of its floored
/// coordinates (cheaper than converting them to integers).
#[inline(always)]
fn slot(floor: Vec3) -> usize {
    let h = floor.x.to_bits() ^ floor.y.to_bits().rotate_left(11) ^ floor.z.to_bits().rotate_left(22);
    let h = h.wrapping_mul(0x9e37_79b9);
    (h >> 26) as usize & (CELL_SLOTS - 1)
}

const MAX_OCTAVES: usize = 8;

/// One lattice cell's trilinear interpolant as polynomial coefficients in the
/// fade weights (w): v = c0 + c1·wx + c2·wy + c3·wz + c4·wx·wy + c5·wy·wz +
/// c6·wx·wz + c7·wx·wy·wz, summed in that order.
#[derive(Clone, Copy, Debug)]
struct CellValues {
    coefficients: [Vec4; 8],
    /// `coefficients[k][channel]` in every lane, for [`CellValues::interpolate_lanes`].
    splatted: [[Vec4; 8]; 4],
}

impl CellValues {
    const EMPTY: CellValues = CellValues { coefficients: [Vec4::ZERO; 8], splatted: [[Vec4::ZERO; 8]; 4] };

    /// Makes this the interpolant of the cell with lowest corner `cell`.
    fn set(&mut self, cell: IVec3, seed: u32) {
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
        for (channel, splatted) in self.splatted.iter_mut().enumerate() {
            *splatted = self.coefficients.map(|c| Vec4::splat(c[channel]));
        }
    }

    /// The four channels at one point with fade weights w.
    #[inline(always)]
    fn interpolate(&self, w: Vec3) -> Vec4 {
        let c = &self.coefficients;
        let (wxy, wyz, wxz) = (w.x * w.y, w.y * w.z, w.x * w.z);
        let wxyz = wxy * w.z;
        c[0] + c[1] * w.x + c[2] * w.y + c[3] * w.z + c[4] * wxy + c[5] * wyz + c[6] * wxz + c[7] * wxyz
    }

    /// One channel at four points (one per lane) with fade weights and their
    /// products (see [`lane_weights`]): the same sums as
    /// [`CellValues::interpolate`], lane by lane.
    #[inline(always)]
    fn interpolate_lanes(&self, channel: usize, w: &[Vec4; 7]) -> Vec4 {
        let c = &self.splatted[channel];
        let [wx, wy, wz, wxy, wyz, wxz, wxyz] = *w;
        c[0] + c[1] * wx + c[2] * wy + c[3] * wz + c[4] * wxy + c[5] * wyz + c[6] * wxz + c[7] * wxyz
    }
}

/// Fade weights of four points and the products [`CellValues::interpolate_lanes`] uses.
#[inline(always)]
fn lane_weights(wx: Vec4, wy: Vec4, wz: Vec4) -> [Vec4; 7] {
    let (wxy, wyz, wxz) = (wx * wy, wy * wz, wx * wz);
    [wx, wy, wz, wxy, wyz, wxz, wxy * wz]
}

impl FractalSampler {
    /// A sampler of `octaves` octaves (clamped to 1..=8) of the noise seeded
    /// `seed`, for points given relative to lattice point `cell_offset`.
    pub fn new(octaves: u32, seed: u32, cell_offset: IVec3) -> FractalSampler {
        let mut sampler = FractalSampler {
            seed,
            octaves: 1,
            weights: [0.0; MAX_OCTAVES],
            offsets: [IVec3::ZERO; MAX_OCTAVES],
            lane_limit: 0.0,
            keys: Vec::new(),
            cells: Vec::new(),
            last_cell: [([Vec4::NAN; 3], 0); MAX_OCTAVES],
        };
        sampler.reset(octaves, seed, cell_offset);
        sampler
    }

    /// Makes this sampler equal to `FractalSampler::new(octaves, seed,
    /// cell_offset)`, keeping its buffers.
    pub fn reset(&mut self, octaves: u32, seed: u32, cell_offset: IVec3) {
        let octaves = octaves.clamp(1, MAX_OCTAVES as u32) as usize;
        let total: f32 = (0..octaves).map(|o| 0.5f32.powi(o as i32)).sum();
        self.weights = std::array::from_fn(|o| 0.5f32.powi(o as i32) / total);
        let mut offset = cell_offset;
        for slot in &mut self.offsets {
            *slot = offset;
            offset = offset.wrapping_mul(IVec3::splat(2));
        }
        self.lane_limit = MAGIC_FLOOR_RANGE / 2f32.powi(octaves as i32);
        self.seed = seed;
        self.octaves = octaves;
        self.keys.clear();
        self.keys.resize(octaves * CELL_SLOTS, Vec3::NAN);
        self.last_cell = [([Vec4::NAN; 3], 0); MAX_OCTAVES];
        if self.cells.len() < octaves * CELL_SLOTS {
            self.cells.resize(octaves * CELL_SLOTS, CellValues::EMPTY);
        }
    }

    /// The index in `cells` of the cell of `octave` whose floored corner is
    /// `floor`, from its slot or hashed anew.
    #[inline(always)]
    fn cell_index(&mut self, octave: usize, floor: Vec3) -> usize {
        let index = octave * CELL_SLOTS + slot(floor);
        if self.keys[index] != floor {
            self.fill(index, octave, floor);
        }
        index
    }

    /// Kept out of line: it runs once per cell, and inlining it into the
    /// per-point loops would crowd out their registers.
    #[cold]
    #[inline(never)]
    fn fill(&mut self, index: usize, octave: usize, floor: Vec3) {
        let cell = floor.as_ivec3().wrapping_add(self.offsets[octave]);
        self.cells[index].set(cell, octave_seed(self.seed, octave));
        self.keys[index] = floor;
        if self.last_cell[octave].1 == index {
            self.last_cell[octave].0 = [Vec4::NAN; 3];
        }
    }

    /// The noise at one point.
    #[inline]
    pub fn sample(&mut self, local: Vec3) -> Vec4 {
        if !local.is_finite() {
            return Vec4::ZERO;
        }
        let mut sum = Vec4::ZERO;
        let mut local = local;
        for octave in 0..self.octaves {
            let floor = Vec3::new(floor_f32(local.x), floor_f32(local.y), floor_f32(local.z));
            let weight = self.weights[octave];
            let index = self.cell_index(octave, floor);
            sum += self.cells[index].interpolate(fade3(local - floor)) * weight;
            local *= 2.0;
        }
        sum
    }

    /// The noise at four points given as their x, y and z coordinates, one
    /// lane per point; returns the four channels, each with one lane per
    /// point. Equal to four calls to [`FractalSampler::sample`]: lanes that
    /// fall in one cell are evaluated together, with every lane's arithmetic
    /// done as the one-point path does it.
    #[inline(always)]
    pub fn sample_lanes(&mut self, x: Vec4, y: Vec4, z: Vec4) -> [Vec4; 4] {
        // Each coordinate compared on its own: NaN fails the comparison
        // (a lane-wise max would drop it and leave a lane in no cell).
        let limit = Vec4::splat(self.lane_limit);
        let inside = x.abs().cmplt(limit) & y.abs().cmplt(limit) & z.abs().cmplt(limit);
        if !inside.all() {
            // Far out or not finite: the one-point path handles every case.
            let points = [0, 1, 2, 3].map(|lane| self.sample(Vec3::new(x[lane], y[lane], z[lane])));
            let channels = Mat4::from_cols(points[0], points[1], points[2], points[3]).transpose();
            return [channels.x_axis, channels.y_axis, channels.z_axis, channels.w_axis];
        }
        let (mut x, mut y, mut z) = (x, y, z);
        let mut sum = [Vec4::ZERO; 4];
        for octave in 0..self.octaves {
            let (fx, fy, fz) = (floor4(x), floor4(y), floor4(z));
            let w = lane_weights(fade4(x - fx), fade4(y - fy), fade4(z - fz));
            let weight = self.weights[octave];
            let (last_corner, last_index) = self.last_cell[octave];
            let in_last = fx.cmpeq(last_corner[0]) & fy.cmpeq(last_corner[1]) & fz.cmpeq(last_corner[2]);
            if in_last.all() {
                let cell = &self.cells[last_index];
                for (channel, total) in sum.iter_mut().enumerate() {
                    *total += cell.interpolate_lanes(channel, &w) * weight;
                }
            } else {
                // One pass per distinct cell among the lanes, each adding to its own lanes.
                let floors = [fx.to_array(), fy.to_array(), fz.to_array()];
                let (mut lane, mut pending) = (0, 0b1111u32);
                loop {
                    let floor = Vec3::new(floors[0][lane], floors[1][lane], floors[2][lane]);
                    let corner = [Vec4::splat(floor.x), Vec4::splat(floor.y), Vec4::splat(floor.z)];
                    let same = fx.cmpeq(corner[0]) & fy.cmpeq(corner[1]) & fz.cmpeq(corner[2]);
                    let index = self.cell_index(octave, floor);
                    let cell = &self.cells[index];
                    if same.all() {
                        for (channel, total) in sum.iter_mut().enumerate() {
                            *total += cell.interpolate_lanes(channel, &w) * weight;
                        }
                        self.last_cell[octave] = (corner, index);
                        break;
                    }
                    for (channel, total) in sum.iter_mut().enumerate() {
                        let value = cell.interpolate_lanes(channel, &w);
                        *total = Vec4::select(same, *total + value * weight, *total);
                    }
                    pending &= !same.bitmask();
                    if pending == 0 {
                        break;
                    }
                    lane = pending.trailing_zeros() as usize & 3;
                }
            }
            x *= 2.0;
            y *= 2.0;
            z *= 2.0;
        }
        sum
    }
}

fn octave_seed(seed: u32, octave: usize) -> u32 {
    seed.wrapping_add((octave as u32).wrapping_mul(0x9e37_79b9))
}

/// One octave: the four channels of the noise at lattice point `cell_offset` + `local`.
pub fn value4(local: Vec3, cell_offset: IVec3, seed: u32) -> Vec4 {
    let floor = Vec3::new(floor_f32(local.x), floor_f32(local.y), floor_f32(local.z));
    let mut values = CellValues::EMPTY;
    values.set(floor.as_ivec3().wrapping_add(cell_offset), seed);
    values.interpolate(fade3(local - floor))
}

/// Adding and subtracting 1.5·2²³ rounds an f32 to the nearest integer when
/// |x| < 2²²: the sum lands where the spacing of f32 values is exactly 1.
const MAGIC_ROUND: f32 = 12_582_912.0;
const MAGIC_FLOOR_RANGE: f32 = 4_194_304.0;

/// floor(x) without a libm call (x86-64's baseline has no rounding
/// instruction): round to nearest, then step down where that rounded up.
/// Exact for |x| < 2³¹; beyond that the value saturates (still finite).
#[inline(always)]
fn floor_f32(x: f32) -> f32 {
    let rounded = if x.abs() < MAGIC_FLOOR_RANGE { (x + MAGIC_ROUND) - MAGIC_ROUND } else { (x as i32) as f32 };
    if rounded > x { rounded - 1.0 } else { rounded }
}

/// [`floor_f32`] in every lane, for |x| < 2²² (the caller checks).
#[inline(always)]
fn floor4(x: Vec4) -> Vec4 {
    let rounded = (x + Vec4::splat(MAGIC_ROUND)) - Vec4::splat(MAGIC_ROUND);
    Vec4::select(rounded.cmpgt(x), rounded - Vec4::ONE, rounded)
}

/// The quintic fade 6f⁵ − 15f⁴ + 10f³ of each coordinate.
#[inline(always)]
fn fade3(f: Vec3) -> Vec3 {
    f * f * f * (f * (f * 6.0 - 15.0) + 10.0)
}

#[inline(always)]
fn fade4(f: Vec4) -> Vec4 {
    f * f * f * (f * (f * 6.0 - 15.0) + 10.0)
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
        let offset = IVec3::new(4, 0, -2);
        let mut sampler = FractalSampler::new(3, 11, offset);
        let points: Vec<Vec3> = grid_samples().collect();
        for p in points.iter().chain(points.iter().rev()) {
            assert_eq!(sampler.sample(*p), fractal4(*p, offset, 3, 11));
        }
        // A reset sampler forgets the cells of its previous offset and seed.
        sampler.reset(2, 12, IVec3::ZERO);
        for p in &points {
            assert_eq!(sampler.sample(*p), fractal4(*p, IVec3::ZERO, 2, 12));
        }
        for p in [-1.5f32, -1.0, -0.25, 0.0, 0.999_999_9, 2.0, -1e-30, 2_097_151.5, -4_194_303.5, 8_388_607.5] {
            assert_eq!(floor_f32(p), p.floor(), "{p}");
            if p.abs() < MAGIC_FLOOR_RANGE {
                assert_eq!(floor4(Vec4::splat(p)), Vec4::splat(p.floor()), "{p}");
            }
        }
    }

    /// The four lanes of [`FractalSampler::sample_lanes`] as one value per point.
    fn lanes_at(sampler: &mut FractalSampler, points: [Vec3; 4]) -> [Vec4; 4] {
        let axis = |k: usize| Vec4::from_array(points.map(|p| p[k]));
        let [c0, c1, c2, c3] = sampler.sample_lanes(axis(0), axis(1), axis(2));
        let by_point = Mat4::from_cols(c0, c1, c2, c3).transpose();
        [by_point.x_axis, by_point.y_axis, by_point.z_axis, by_point.w_axis]
    }

    #[test]
    fn four_lanes_equal_four_single_samples() {
        let points: Vec<Vec3> = grid_samples().collect();
        let offset = IVec3::new(-3, 7, 1);
        let mut lanes = FractalSampler::new(2, 8, offset);
        let mut single = FractalSampler::new(2, 8, offset);
        // Neighbouring points (mostly one cell per group), scattered ones
        // (mixed cells) and groups of two cells in every arrangement.
        let scattered: Vec<Vec3> = points.iter().step_by(97).copied().collect();
        let (p, q) = (Vec3::new(0.2, 0.3, 0.4), Vec3::new(1.7, 0.3, -0.6));
        let pairs: Vec<Vec3> =
            (0..16).flat_map(|bits| (0..4).map(move |k| if bits >> k & 1 == 1 { q } else { p })).collect();
        for group in points.chunks_exact(4).chain(scattered.chunks_exact(4)).chain(pairs.chunks_exact(4)) {
            let group = [group[0], group[1], group[2], group[3]];
            let together = lanes_at(&mut lanes, group);
            for (p, value) in group.iter().zip(together) {
                assert_eq!(value, single.sample(*p), "{p}");
            }
        }
        let near = Vec3::new(0.2, 0.3, 0.4);
        let same_cell = [near, near + Vec3::splat(0.01), near + Vec3::splat(0.02), near + Vec3::splat(0.03)];
        let mut fresh = FractalSampler::new(2, 8, IVec3::ZERO);
        let together = lanes_at(&mut fresh, same_cell);
        for (p, value) in same_cell.iter().zip(together) {
            assert_eq!(value, fractal4(*p, IVec3::ZERO, 2, 8));
        }
        for bad in
            [Vec3::NAN, Vec3::new(f32::NAN, 0.3, 0.4), Vec3::new(0.2, f32::NAN, 0.4), Vec3::new(0.2, 0.3, f32::NAN)]
        {
            let values = lanes_at(&mut fresh, [near, bad, near, near]);
            assert_eq!(values[1], Vec4::ZERO, "{bad}");
            assert_eq!(values[0], fractal4(near, IVec3::ZERO, 2, 8));
        }
        let far = [near, Vec3::splat(3e6), near, Vec3::splat(-1e9)];
        for (p, value) in far.iter().zip(lanes_at(&mut fresh, far)) {
            assert_eq!(value, fractal4(*p, IVec3::ZERO, 2, 8), "{p}");
        }
    }

    #[test]
    fn non_finite_input_gives_zero() {
        assert_eq!(fractal4(Vec3::new(f32::NAN, 0.0, 0.0), IVec3::ZERO, 2, 0), Vec4::ZERO);
        assert_eq!(fractal4(Vec3::splat(f32::INFINITY), IVec3::ZERO, 2, 0), Vec4::ZERO);
    }
}
