//! The per-point arithmetic of a sweep: what each constraint asks, summed
//! over a point's neighbours, and moving points by it, [`LANES`] points at a
//! time in plain loops the compiler vectorises.

use super::layout::{LANES, Lanes, NEIGHBOURS, Run, STEPS, Split};
use super::{MOMENTUM, OVER_RELAXATION};

/// One distance constraint: the neighbour stays between `min2` and `max2`
/// squared distance (equal bounds make an equality).
#[derive(Clone, Copy)]
pub(super) struct Bound {
    pub(super) min2: f64,
    pub(super) max2: f64,
}

impl Bound {
    pub(super) fn new(min: f64, max: f64) -> Bound {
        Bound { min2: min * min, max2: max * max }
    }
}

/// Moves the points of `run` by their steps (`steps[axis][first..]`) and
/// keeps their velocity (this sweep's whole move: the carried momentum plus
/// the step); returns the largest squared step. A non-finite step is skipped.
///
/// A velocity above `max_speed2` (squared) is dropped: where the constraints
/// cannot all hold (pins out of the cloth's reach) they can trade moves back
/// and forth, and momentum would build that up without bound.
#[inline(always)]
pub(super) fn apply(
    position: &mut [Split; 3],
    velocity: &mut [Split; 3],
    run: &Run,
    steps: &[Vec<f64>; 3],
    first: usize,
    max_speed2: f64,
) -> f64 {
    let len = run.len;
    // Whole vectors, the last one partly past the run: its spare lanes are
    // computed and then written back as they were (the slots exist: every run
    // reads a vector's worth past its end). A scalar tail had been three in
    // eight points of a 64² sweep.
    let padded = len.next_multiple_of(LANES);
    let [sx, sy, sz] = steps;
    let (sx, sy, sz) = (&sx[first..first + padded], &sy[first..first + padded], &sz[first..first + padded]);
    let [px, py, pz] = position;
    let [vx, vy, vz] = velocity;
    let (i, j) = (run.i, run.j);
    let (px, py, pz) = (px.run_mut(i, j, padded), py.run_mut(i, j, padded), pz.run_mut(i, j, padded));
    let (vx, vy, vz) = (vx.run_mut(i, j, padded), vy.run_mut(i, j, padded), vz.run_mut(i, j, padded));
    // A running maximum per lane, so that the loop vectorises; the steps are
    // finite and non-negative, so the maximum does not depend on the order.
    let mut lane_max = [0.0f64; LANES];
    let mut t = 0;
    while t < len {
        let live = len - t;
        // Copied in and out as whole vectors: through per-lane references the
        // loop stayed scalar (perf: a quarter of a sweep at 64²).
        let load = |s: &[f64]| -> Lanes { *<&Lanes>::try_from(&s[t..t + LANES]).expect("whole lanes") };
        let (old_p, old_v) = ([load(px), load(py), load(pz)], [load(vx), load(vy), load(vz)]);
        let (mut p, mut v) = (old_p, old_v);
        let d = [load(sx), load(sy), load(sz)];
        for lane in 0..LANES {
            let [p0, p1, p2] = &mut p;
            let [v0, v1, v2] = &mut v;
            let step2 = move_point(
                [&mut p0[lane], &mut p1[lane], &mut p2[lane]],
                [&mut v0[lane], &mut v1[lane], &mut v2[lane]],
                [d[0][lane], d[1][lane], d[2][lane]],
                max_speed2,
            );
            let counts = lane < live && step2 > lane_max[lane];
            lane_max[lane] = if counts { step2 } else { lane_max[lane] };
        }
        for axis in 0..3 {
            for lane in 0..LANES {
                p[axis][lane] = if lane < live { p[axis][lane] } else { old_p[axis][lane] };
                v[axis][lane] = if lane < live { v[axis][lane] } else { old_v[axis][lane] };
            }
        }
        for (out, lanes) in [&mut *px, &mut *py, &mut *pz].into_iter().zip(p) {
            out[t..t + LANES].copy_from_slice(&lanes);
        }
        for (out, lanes) in [&mut *vx, &mut *vy, &mut *vz].into_iter().zip(v) {
            out[t..t + LANES].copy_from_slice(&lanes);
        }
        t += LANES;
    }
    lane_max.into_iter().fold(0.0, f64::max)
}

/// Moves a point by `step` without touching its velocity (the edge sweep);
/// a non-finite step is skipped.
#[inline(always)]
pub(super) fn nudge(p: [&mut f64; 3], step: [f64; 3]) {
    if step.iter().all(|d| d.is_finite()) {
        for (p, d) in p.into_iter().zip(step) {
            *p += d;
        }
    }
}

/// [`apply`] for one point; returns its squared step (0 if not finite).
#[inline(always)]
pub(super) fn move_point(p: [&mut f64; 3], v: [&mut f64; 3], step: [f64; 3], max_speed2: f64) -> f64 {
    let finite = step[0].is_finite() && step[1].is_finite() && step[2].is_finite();
    let [dx, dy, dz] = if finite { step } else { [0.0; 3] };
    let [px, py, pz] = p;
    *px += dx;
    *py += dy;
    *pz += dz;
    let [vx, vy, vz] = v;
    let w = (*vx * MOMENTUM + dx, *vy * MOMENTUM + dy, *vz * MOMENTUM + dz);
    let keep = w.0 * w.0 + w.1 * w.1 + w.2 * w.2 <= max_speed2;
    (*vx, *vy, *vz) = if keep { w } else { (0.0, 0.0, 0.0) };
    dx * dx + dy * dy + dz * dz
}

/// Carries the points of `run` on by their momentum before a sweep.
#[inline(always)]
pub(super) fn coast(position: &mut [Split; 3], velocity: &[Split; 3], run: &Run) {
    for axis in 0..3 {
        let p = position[axis].run_mut(run.i, run.j, run.len);
        let v = velocity[axis].run(run.i, run.j, run.len);
        for t in 0..run.len {
            p[t] += v[t] * MOMENTUM;
        }
    }
}

/// Steps of the points of one run, into `steps` from `first` on: one flat
/// loop over contiguous slices, so that it vectorises across points.
/// Neighbours with `present` 0 are read as the points themselves.
#[inline(always)]
pub(super) fn run_steps<const BENDS: bool>(
    position: &[Split; 3],
    run: &Run,
    present: &[f64; NEIGHBOURS],
    bounds: &[Bound; NEIGHBOURS],
    gravity: f64,
    steps: &mut [Vec<f64>; 3],
    first: usize,
) {
    // Whole chunks of lanes: spare lanes past the run compute throwaway steps.
    let padded = run.len.next_multiple_of(LANES);
    // Without bending the second neighbours are never read (they may lie past the edge).
    let mut at = [0; NEIGHBOURS];
    for (n, at) in at.iter_mut().enumerate() {
        let (di, dj) = if (n < 8 || BENDS) && present[n] != 0.0 { STEPS[n] } else { (0, 0) };
        *at = position[0].slot(run.i.wrapping_add_signed(di), run.j.wrapping_add_signed(dj));
    }
    // Plain loops rather than `array::map`, whose closures are not inlined:
    // setting up the slices that way costs 5% of a sweep.
    let centre_at = position[0].slot(run.i, run.j);
    let mut centre: [&[f64]; 3] = [&[]; 3];
    let mut around: [[&[f64]; NEIGHBOURS]; 3] = [[&[]; NEIGHBOURS]; 3];
    for axis in 0..3 {
        let data = &position[axis].data;
        centre[axis] = &data[centre_at..centre_at + padded];
        for n in 0..NEIGHBOURS {
            around[axis][n] = &data[at[n]..at[n] + padded];
        }
    }
    let [sx, sy, sz] = steps;
    let out = first..first + padded;
    let out = [&mut sx[out.clone()], &mut sy[out.clone()], &mut sz[out]];
    run_kernel::<BENDS>(centre, &around, present, bounds, gravity, out);
}

/// The loop of [`run_steps`], [`LANES`] points at a time; the outputs are
/// separate `&mut` slices so the compiler knows they alias no input.
#[inline(always)]
pub(super) fn run_kernel<const BENDS: bool>(
    centre: [&[f64]; 3],
    around: &[[&[f64]; NEIGHBOURS]; 3],
    present: &[f64; NEIGHBOURS],
    bounds: &[Bound; NEIGHBOURS],
    gravity: f64,
    [sx, sy, sz]: [&mut [f64]; 3],
) {
    let mut t = 0;
    while t + LANES <= centre[0].len() {
        let load = |s: &[f64]| -> Lanes { *<&Lanes>::try_from(&s[t..t + LANES]).expect("whole lanes") };
        let q = |n: usize| [load(around[0][n]), load(around[1][n]), load(around[2][n])];
        let p = [load(centre[0]), load(centre[1]), load(centre[2])];
        let step = point_steps::<BENDS, LANES>(&p, &q, &|n| [present[n]; LANES], bounds, gravity);
        sx[t..t + LANES].copy_from_slice(&step[0]);
        sy[t..t + LANES].copy_from_slice(&step[1]);
        sz[t..t + LANES].copy_from_slice(&step[2]);
        t += LANES;
    }
}

/// The move of one point: the average of what its violated constraints ask,
/// over-relaxed, plus the settling pull. `present[n]` is 0 for a neighbour
/// outside the grid (then `q[n]` is the point itself).
///
/// For an edge d of squared length l² outside its bounds, with r² the nearer
/// bound, a constraint asks for d·(l² − r²)/(l² + r²): the exact d·(l − r)/l
/// to first order near rest, within 21% of it for any stretch, bounded by the
/// edge itself, and without a square root. Branch-free, so that runs of
/// points vectorise and unpredictable long-or-short edges cost nothing.
#[inline(always)]
pub(super) fn point_steps<const BENDS: bool, const L: usize>(
    p: &[[f64; L]; 3],
    q: &impl Fn(usize) -> [[f64; L]; 3],
    present: &impl Fn(usize) -> [f64; L],
    bounds: &[Bound; NEIGHBOURS],
    gravity: f64,
) -> [[f64; L]; 3] {
    // Mirror-image neighbours are summed in pairs first, so that a mirrored
    // neighbourhood gives the mirrored sum exactly.
    let mut total = add(four(p, q, present, bounds, 0), four(p, q, present, bounds, 4));
    if BENDS {
        let mut bend = four(p, q, present, bounds, 8);
        for axis in bend.iter_mut() {
            for value in axis.iter_mut() {
                *value *= BEND_WEIGHT;
            }
        }
        total = add(total, bend);
    }
    let mut step = [[0.0; L]; 3];
    for lane in 0..L {
        let count = total[3][lane];
        let scale = if count > 0.0 { OVER_RELAXATION / count } else { 0.0 };
        for axis in 0..3 {
            step[axis][lane] = total[axis][lane] * scale;
        }
        step[1][lane] += gravity;
    }
    step
}

/// Share of a violated bending bound in a point's average, against 1 for
/// every other constraint. Where pins bend stiff cloth more than it allows,
/// the bounds and the edges' lengths cannot all hold, and at full weight the
/// bending asks keep the sweeps drifting: at full weight 16 of 200 random
/// layouts (and all 20 large ones at the default stiffness) never settle; at
/// one half, 1 of 200 and 0 of 20 (BENCHMARKS.md, "Stiff cloth"). A power of two, so
/// mirrored neighbourhoods still give mirrored sums exactly.
const BEND_WEIGHT: f64 = 0.5;

/// Pull along x, y, z and the number of violated constraints, per lane.
pub(super) type Pull<const L: usize> = [[f64; L]; 4];

/// Neighbours `o..o + 4` (two mirror-image pairs), each pair summed first.
#[inline(always)]
pub(super) fn four<const L: usize>(
    p: &[[f64; L]; 3],
    q: &impl Fn(usize) -> [[f64; L]; 3],
    present: &impl Fn(usize) -> [f64; L],
    bounds: &[Bound; NEIGHBOURS],
    o: usize,
) -> Pull<L> {
    let (a, b) =
        (constraint(p, &q(o), &present(o), &bounds[o]), constraint(p, &q(o + 1), &present(o + 1), &bounds[o + 1]));
    let (c, d) = (
        constraint(p, &q(o + 2), &present(o + 2), &bounds[o + 2]),
        constraint(p, &q(o + 3), &present(o + 3), &bounds[o + 3]),
    );
    add(add(a, b), add(c, d))
}

#[inline(always)]
pub(super) fn add<const L: usize>(a: Pull<L>, b: Pull<L>) -> Pull<L> {
    let mut out = a;
    for c in 0..4 {
        for lane in 0..L {
            out[c][lane] += b[c][lane];
        }
    }
    out
}

/// One constraint on `L` points side by side.
///
/// The division is skipped when the constraint holds on every lane (then f is
/// exactly 0 anyway): shear and bending bounds are mostly slack, and the
/// division is the costliest operation of a sweep.
#[inline(always)]
pub(super) fn constraint<const L: usize>(
    p: &[[f64; L]; 3],
    q: &[[f64; L]; 3],
    present: &[f64; L],
    b: &Bound,
) -> Pull<L> {
    let mut d = [[0.0; L]; 3];
    let (mut l2, mut r2) = ([0.0; L], [0.0; L]);
    let mut holds = true;
    for lane in 0..L {
        for axis in 0..3 {
            d[axis][lane] = q[axis][lane] - p[axis][lane];
        }
        let [dx, dy, dz] = [d[0][lane], d[1][lane], d[2][lane]];
        l2[lane] = dx * dx + dy * dy + dz * dz;
        let r = if l2[lane] < b.min2 { b.min2 } else { l2[lane] };
        r2[lane] = if r > b.max2 { b.max2 } else { r };
        holds &= l2[lane] == r2[lane];
    }
    let mut f = [0.0; L];
    if !holds {
        for lane in 0..L {
            // MIN_POSITIVE only matters for l = r = 0 (0, not NaN).
            f[lane] = (l2[lane] - r2[lane]) / (l2[lane] + r2[lane] + f64::MIN_POSITIVE);
        }
    }
    let mut out = [[0.0; L]; 4];
    for lane in 0..L {
        for axis in 0..3 {
            out[axis][lane] = d[axis][lane] * f[lane];
        }
        out[3][lane] = if l2[lane] == r2[lane] { 0.0 } else { present[lane] };
    }
    out
}
