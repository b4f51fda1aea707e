//! The stretch limit's coarser grid: every other column and row, on which
//! the evening passes share a gap out along whole chains before the finer
//! grid's own passes (see the parent module).

use super::StretchLimiter;
use crate::mesh::PointArrays;

/// The next coarser grid: every other column and row of the finer one, its
/// first and last included.
#[derive(Clone, Debug, Default)]
pub(super) struct Coarse {
    pub(super) limiter: StretchLimiter,
    /// The finer grid these were made for.
    fine_grid: (usize, usize),
    /// The finer grid's column and row of each coarse column and row.
    cols_at: Vec<usize>,
    rows_at: Vec<usize>,
    /// For each fine column (row): the coarse column (row) before it and how
    /// far it lies towards the next one, for interpolating the coarse moves.
    spans_u: Vec<(usize, f32)>,
    spans_v: Vec<(usize, f32)>,
    ratio: Vec<f32>,
    points: PointArrays,
    /// The coarse points as they were before the coarse limit moved them,
    /// then how far it moved them.
    before: PointArrays,
    /// The finer grid's squared reaches the coarse ones were summed from.
    from_allowed2_u: Vec<f32>,
    from_allowed2_v: Vec<f32>,
    /// One axis of the coarse moves along each coarse row, at every fine column.
    along_rows: Vec<f32>,
}

impl StretchLimiter {
    /// Evens out the coarser grid (every other column and row, the last ones
    /// included), each coarse edge allowed the summed reach of the fine edges
    /// it spans, and moves the fine points by the coarse moves, interpolated.
    pub(super) fn even_coarse(&mut self, (cols, rows): (usize, usize), ratio: &[f32], points: &mut PointArrays) {
        let coarse = self.coarse.get_or_insert_with(|| {
            let mut coarse = Box::<Coarse>::default();
            coarse.limiter.set_point_obstacles(&self.obstacles);
            coarse
        });
        if coarse.fine_grid != (cols, rows) {
            coarse.fine_grid = (cols, rows);
            coarse.cols_at = every_other(cols);
            coarse.rows_at = every_other(rows);
            coarse.spans_u = spans(&coarse.cols_at, cols);
            coarse.spans_v = spans(&coarse.rows_at, rows);
            // The coarse reaches are summed again for the new grid.
            coarse.from_allowed2_u.clear();
            coarse.from_allowed2_v.clear();
        }
        let (cc, cr) = (coarse.cols_at.len(), coarse.rows_at.len());
        let Coarse { cols_at, rows_at, ratio: coarse_ratio, points: coarse_points, before, .. } = &mut **coarse;
        // Row by row, so each row's gather is one sized extend.
        let gather = |to: &mut Vec<f32>, from: &[f32]| {
            to.clear();
            for &j in rows_at.iter() {
                let row = &from[j * cols..(j + 1) * cols];
                to.extend(cols_at.iter().map(|&i| row[i]));
            }
        };
        gather(coarse_ratio, ratio);
        for (to, from) in
            [(&mut coarse_points.x, &points.x), (&mut coarse_points.y, &points.y), (&mut coarse_points.z, &points.z)]
        {
            gather(to, from);
        }
        before.clone_from(coarse_points);
        let same_reach = coarse.from_allowed2_u == self.allowed2_u && coarse.from_allowed2_v == self.allowed2_v;
        if !same_reach {
            coarse.from_allowed2_u.clone_from(&self.allowed2_u);
            coarse.from_allowed2_v.clone_from(&self.allowed2_v);
            let Coarse { limiter, cols_at, rows_at, .. } = &mut **coarse;
            let fine = |a: usize, b: usize| rows_at[b] * cols + cols_at[a];
            // A coarse edge may be as long as the fine edges it spans, end to end.
            let reach = |allowed2: &[f32], from: usize, step: usize, count: usize| -> f32 {
                let length: f32 = (0..count).map(|e| allowed2[from + e * step].sqrt()).sum();
                length * length
            };
            limiter.allowed2_u.clear();
            limiter.allowed2_u.resize(cc * cr, 0.0);
            limiter.allowed2_v.clear();
            limiter.allowed2_v.resize(cc * cr, 0.0);
            for b in 0..cr {
                for a in 0..cc {
                    let c = b * cc + a;
                    if a + 1 < cc {
                        limiter.allowed2_u[c] = reach(&self.allowed2_u, fine(a, b), 1, cols_at[a + 1] - cols_at[a]);
                    }
                    if b + 1 < cr {
                        limiter.allowed2_v[c] = reach(&self.allowed2_v, fine(a, b), cols, rows_at[b + 1] - rows_at[b]);
                    }
                }
            }
        }
        let Coarse {
            limiter, ratio: coarse_ratio, points: coarse_points, before, along_rows, spans_u, spans_v, ..
        } = &mut **coarse;
        limiter.sort_for((cc, cr), coarse_ratio);
        limiter.even((cc, cr), coarse_ratio, coarse_points);
        // The coarse moves, bilinear between coarse points (along each coarse
        // row first, then between rows); pins stay.
        for (after, moved, values) in [
            (&coarse_points.x, &mut before.x, &mut points.x),
            (&coarse_points.y, &mut before.y, &mut points.y),
            (&coarse_points.z, &mut before.z, &mut points.z),
        ] {
            for (m, a) in moved.iter_mut().zip(after) {
                *m = a - *m;
            }
            along_rows.clear();
            for b in 0..cr {
                let moved = &moved[b * cc..(b + 1) * cc];
                along_rows.extend(spans_u.iter().map(|&(a, t)| moved[a] * (1.0 - t) + moved[a + 1] * t));
            }
            let spans_v = &*spans_v;
            for (j, &(b, s)) in spans_v.iter().enumerate() {
                let (top, bottom) =
                    (&along_rows[b * cols..(b + 1) * cols], &along_rows[(b + 1) * cols..(b + 2) * cols]);
                let row = j * cols..(j + 1) * cols;
                for (((value, &r), &top), &bottom) in
                    values[row.clone()].iter_mut().zip(&ratio[row]).zip(top).zip(bottom)
                {
                    let delta = top * (1.0 - s) + bottom * s;
                    // A select, not a branch, so the row runs in vectors.
                    *value = if r > 0.0 && delta.is_finite() { *value + delta } else { *value };
                }
            }
        }
    }
}

/// Every other index of a side of `side` points, the last one included.
fn every_other(side: usize) -> Vec<usize> {
    let mut at: Vec<usize> = (0..side).step_by(2).collect();
    if side.is_multiple_of(2) {
        at.push(side - 1);
    }
    at
}

/// For each of `side` fine indices, the coarse index `at[a]` at or before it
/// (never the last) and its fraction of the way to `at[a + 1]`.
fn spans(at: &[usize], side: usize) -> Vec<(usize, f32)> {
    let mut a = 0;
    (0..side)
        .map(|i| {
            while a + 2 < at.len() && at[a + 1] <= i {
                a += 1;
            }
            (a, (i - at[a]) as f32 / (at[a + 1] - at[a]) as f32)
        })
        .collect()
}
