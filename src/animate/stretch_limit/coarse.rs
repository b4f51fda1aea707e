//! The stretch limit's coarser grid: every other column and row, on which
//! the evening passes share a gap out along whole chains before the finer
//! grid's own passes (see the parent module).

use super::StretchLimiter;
use crate::mesh::PointArrays;

/// The next coarser grid: every other column and row of the finer one, its
/// first and last included.
#[derive(Clone, Debug, Default)]
pub(super) struct Coarse {
    limiter: StretchLimiter,
    /// The finer grid's column and row of each coarse column and row.
    cols_at: Vec<usize>,
    rows_at: Vec<usize>,
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
        let every_other = |side: usize| -> Vec<usize> {
            let mut at: Vec<usize> = (0..side).step_by(2).collect();
            if side.is_multiple_of(2) {
                at.push(side - 1);
            }
            at
        };
        let coarse = self.coarse.get_or_insert_with(Box::default);
        coarse.limiter.obstacles.clone_from(&self.obstacles);
        coarse.limiter.obstacle_bounds.clone_from(&self.obstacle_bounds);
        coarse.cols_at = every_other(cols);
        coarse.rows_at = every_other(rows);
        let (cc, cr) = (coarse.cols_at.len(), coarse.rows_at.len());
        let Coarse { cols_at, rows_at, ratio: coarse_ratio, points: coarse_points, before, .. } = &mut **coarse;
        let fine = |a: usize, b: usize| rows_at[b] * cols + cols_at[a];
        let coarse_at = || (0..cr).flat_map(|b| (0..cc).map(move |a| fine(a, b)));
        coarse_ratio.clear();
        coarse_ratio.extend(coarse_at().map(|k| ratio[k]));
        for (to, from) in
            [(&mut coarse_points.x, &points.x), (&mut coarse_points.y, &points.y), (&mut coarse_points.z, &points.z)]
        {
            to.clear();
            to.extend(coarse_at().map(|k| from[k]));
        }
        before.clone_from(coarse_points);
        let same_reach = coarse.from_allowed2_u == self.allowed2_u
            && coarse.from_allowed2_v == self.allowed2_v
            && coarse.limiter.allowed2_u.len() == cc * cr;
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
            limiter, cols_at, rows_at, ratio: coarse_ratio, points: coarse_points, before, along_rows, ..
        } = &mut **coarse;
        limiter.sort_for((cc, cr), coarse_ratio);
        limiter.even((cc, cr), coarse_ratio, coarse_points);
        // The coarse moves, bilinear between coarse points (along each coarse
        // row first, then between rows); pins stay.
        let spans = |at: &[usize], side: usize| {
            let mut a = 0;
            (0..side)
                .map(|i| {
                    while a + 2 < at.len() && at[a + 1] <= i {
                        a += 1;
                    }
                    (a, (i - at[a]) as f32 / (at[a + 1] - at[a]) as f32)
                })
                .collect::<Vec<_>>()
        };
        let (spans_u, spans_v) = (spans(cols_at, cols), spans(rows_at, rows));
        for (after, moved, values) in [
            (&coarse_points.x, &mut before.x, &mut points.x),
            (&coarse_points.y, &mut before.y, &mut points.y),
            (&coarse_points.z, &mut before.z, &mut points.z),
        ] {
            for (m, a) in moved.iter_mut().zip(after) {
                *m = a - *m;
            }
            along_rows.clear();
            along_rows.extend((0..cr).flat_map(|b| {
                let moved = &moved[b * cc..(b + 1) * cc];
                spans_u.iter().map(move |&(a, t)| moved[a] * (1.0 - t) + moved[a + 1] * t)
            }));
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
