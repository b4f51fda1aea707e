//! A grid's sweeps: the points split by colour into runs and edge chunks,
//! the settling schedule, momentum and the convergence test,
//! in a build for each vector unit (the same result on every x86-64 path).

use std::ops::ControlFlow;

use super::kernel::{Bound, apply, coast, move_point, nudge, point_steps, run_steps};
use super::layout::{BorderChunk, EdgeRun, LANES, Lanes, NEIGHBOURS, Run, STEPS, Split};
use super::self_contact::SelfContact;
use glam::DVec3;

use super::{
    Cancelled, FabricLimits, GRAVITY_BIAS, MAX_SPEED, MOMENTUM, RelaxParams, RelaxProgress, RelaxReport, SETTLE_SWEEPS,
    Settle,
};

/// The free points of one grid split by colour into runs of interior points
/// (every neighbour present), runs along the top and bottom edges, and chunks
/// of the other points near an edge.
pub(super) struct Sweeper {
    cols: usize,
    rows: usize,
    bounds: [Bound; NEIGHBOURS],
    bends: bool,
    position: [Split; 3],
    velocity: [Split; 3],
    runs: [Vec<Run>; 4],
    edge_runs: [Vec<EdgeRun>; 4],
    border: [Vec<BorderChunk>; 4],
    /// This colour's steps: interior runs first, then edge runs, then chunks;
    /// one vector's worth of spare room for the last run's throwaway lanes.
    steps: [Vec<f64>; 3],
    /// The cloth's thickness between its layers, kept after every sweep.
    contact: Option<SelfContact>,
}

impl Sweeper {
    pub(super) fn new(cols: usize, rows: usize, pinned: &[bool], params: &RelaxParams) -> Sweeper {
        let limits = FabricLimits::new(cols, rows, params);
        let (second_u, second_v) = (limits.second_u_min_m, limits.second_v_min_m);
        let (u, v) = (params.rest_u_m, params.rest_v_m);
        let diag = Bound::new(limits.diagonal_min_m, limits.diagonal_max_m);
        let (bend_u, bend_v) = (Bound::new(second_u, f64::INFINITY), Bound::new(second_v, f64::INFINITY));
        let (along_u, along_v) = (Bound::new(u, u), Bound::new(v, v));
        let bounds = [along_u, along_u, along_v, along_v, diag, diag, diag, diag, bend_u, bend_u, bend_v, bend_v];
        let bends = second_u > 0.0 || second_v > 0.0;
        let reach = if bends { 2 } else { 1 };
        let mut runs: [Vec<Run>; 4] = Default::default();
        let mut border: [Vec<(usize, usize)>; 4] = Default::default();
        for j in 0..rows {
            let mut open: [Option<Run>; 4] = [None; 4];
            for i in 0..cols {
                if pinned[j * cols + i] {
                    continue;
                }
                let colour = i.min(cols - 1 - i) % 2 + 2 * (j.min(rows - 1 - j) % 2);
                // Rows near the top and bottom edges make runs too (edge runs, below).
                let in_row = i >= reach && i + reach < cols;
                if !in_row {
                    border[colour].push((i, j));
                    continue;
                }
                match &mut open[colour] {
                    Some(run) if run.i + 2 * run.len == i => run.len += 1,
                    slot => {
                        runs[colour].extend(slot.take());
                        *slot = Some(Run { i, j, len: 1 });
                    }
                }
            }
            for (colour, run) in open.into_iter().enumerate() {
                runs[colour].extend(run);
            }
        }
        let near_edge = |run: &Run| run.j < reach || run.j + reach >= rows;
        let edge_runs = runs.each_ref().map(|runs| {
            let edge = runs.iter().filter(|run| near_edge(run)).map(|&run| EdgeRun {
                run,
                present: STEPS.map(|(_, dj)| if run.j.wrapping_add_signed(dj) < rows { 1.0 } else { 0.0 }),
            });
            edge.collect::<Vec<_>>()
        });
        for runs in &mut runs {
            runs.retain(|run| !near_edge(run));
        }
        let most = (0..4)
            .map(|c| {
                let in_runs = runs[c].iter().chain(edge_runs[c].iter().map(|e| &e.run)).map(|r| r.len).sum::<usize>();
                in_runs + border[c].len()
            })
            .max()
            .unwrap_or(0);
        let split = || [Split::new(cols, rows), Split::new(cols, rows), Split::new(cols, rows)];
        let layout = Split { half: cols.div_ceil(2), len: cols.div_ceil(2) * rows + LANES, data: Vec::new() };
        let border = border.each_ref().map(|points| {
            let chunks = points.chunks(LANES).map(|points| {
                let mut chunk = BorderChunk {
                    len: points.len(),
                    centre: [0; LANES],
                    around: [[0; LANES]; NEIGHBOURS],
                    present: [[0.0; LANES]; NEIGHBOURS],
                };
                for lane in 0..LANES {
                    let (i, j) = points[lane.min(points.len() - 1)];
                    chunk.centre[lane] = layout.slot(i, j) as u32;
                    for (n, &(di, dj)) in STEPS.iter().enumerate() {
                        let (ni, nj) = (i.wrapping_add_signed(di), j.wrapping_add_signed(dj));
                        let inside = ni < cols && nj < rows;
                        let (qi, qj) = if inside { (ni, nj) } else { (i, j) };
                        chunk.around[n][lane] = layout.slot(qi, qj) as u32;
                        chunk.present[n][lane] = if inside { 1.0 } else { 0.0 };
                    }
                }
                chunk
            });
            chunks.collect::<Vec<_>>()
        });
        Sweeper {
            cols,
            rows,
            bounds,
            bends,
            position: split(),
            velocity: split(),
            runs,
            edge_runs,
            border,
            steps: [vec![0.0; most + LANES], vec![0.0; most + LANES], vec![0.0; most + LANES]],
            contact: SelfContact::new(cols, rows, pinned, params.thickness_m, u.min(v)),
        }
    }

    pub(super) fn run(
        &mut self,
        positions: &mut [DVec3],
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        self.load(positions);
        #[cfg(target_arch = "x86_64")]
        let report = if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU supports AVX-512F, checked just above.
            unsafe { self.sweeps_avx512(params, settle, control) }
        } else if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            unsafe { self.sweeps_avx2(params, settle, control) }
        } else {
            self.sweeps(params, settle, control)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let report = self.sweeps(params, settle, control);
        self.store(positions);
        report
    }

    pub(super) fn load(&mut self, positions: &[DVec3]) {
        for j in 0..self.rows {
            for i in 0..self.cols {
                let p = positions[j * self.cols + i];
                for (axis, value) in self.position.iter_mut().zip([p.x, p.y, p.z]) {
                    *axis.get_mut(i, j) = value;
                }
            }
        }
    }

    pub(super) fn store(&self, positions: &mut [DVec3]) {
        let [x, y, z] = &self.position;
        for j in 0..self.rows {
            for i in 0..self.cols {
                positions[j * self.cols + i] = DVec3::new(x.get(i, j), y.get(i, j), z.get(i, j));
            }
        }
    }

    /// The same sweeps with eight points per vector: about 12% faster than
    /// AVX2 on the benchmark (Xeon, 64² and 128²), bit-for-bit the same result.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    pub(super) fn sweeps_avx512(
        &mut self,
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        self.sweeps(params, settle, control)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) fn sweeps_avx2(
        &mut self,
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        self.sweeps(params, settle, control)
    }

    #[inline(always)]
    pub(super) fn sweeps(
        &mut self,
        params: &RelaxParams,
        settle: Settle,
        control: &mut dyn FnMut(RelaxProgress) -> ControlFlow<()>,
    ) -> Result<RelaxReport, Cancelled> {
        let min_rest = params.rest_u_m.min(params.rest_v_m);
        let max_speed2 = (MAX_SPEED * min_rest).powi(2);
        let mut report = RelaxReport::default();
        // Settling: the first sweeps also pull every free point down a little, fading
        // to nothing, so slack cloth hangs instead of staying where the approximation
        // left it; the remaining sweeps enforce the constraints alone.
        let settle_sweeps = if settle == Settle::Yes { SETTLE_SWEEPS } else { 0 };
        for iteration in 0..settle_sweeps.saturating_add(params.max_iterations) {
            let settling = iteration < settle_sweeps;
            if let Some(contact) = &mut self.contact {
                contact.begin(&self.position, &self.velocity);
            }
            let gravity =
                if settling { -GRAVITY_BIAS * min_rest * (1.0 - iteration as f64 / settle_sweeps as f64) } else { 0.0 };
            for colour in 0..4 {
                for run in self.runs[colour].iter().chain(self.edge_runs[colour].iter().map(|e| &e.run)) {
                    coast(&mut self.position, &self.velocity, run);
                }
                for at in self.border[colour].iter().flat_map(BorderChunk::centres) {
                    for (p, v) in self.position.iter_mut().zip(&self.velocity) {
                        p.data[at] += v.data[at] * MOMENTUM;
                    }
                }
            }
            // Largest squared step of an interior point and of a point near an edge.
            let (mut max_step2, mut max_edge2) = (0.0f64, 0.0f64);
            for colour in 0..4 {
                // Every point of a colour moves from the same positions: its neighbours
                // are of other colours, or mirror images of each other.
                let mut filled = 0;
                for r in 0..self.runs[colour].len() {
                    let run = self.runs[colour][r];
                    self.run_steps(&run, &[1.0; NEIGHBOURS], gravity, filled);
                    filled += run.len;
                }
                filled = self.edge_run_steps_from(colour, gravity, filled);
                self.border_steps_from(colour, gravity, filled);
                let mut done = 0;
                for run in &self.runs[colour] {
                    let step2 = apply(&mut self.position, &mut self.velocity, run, &self.steps, done, max_speed2);
                    max_step2 = max_step2.max(step2);
                    done += run.len;
                }
                for EdgeRun { run, .. } in &self.edge_runs[colour] {
                    let step2 = apply(&mut self.position, &mut self.velocity, run, &self.steps, done, max_speed2);
                    max_edge2 = max_edge2.max(step2);
                    done += run.len;
                }
                // Points near an edge one by one, straight from their slots.
                let [px, py, pz] = &mut self.position;
                let [vx, vy, vz] = &mut self.velocity;
                let [sx, sy, sz] = &self.steps;
                for (k, at) in self.border[colour].iter().flat_map(BorderChunk::centres).enumerate() {
                    let t = done + k;
                    let step2 = move_point(
                        [&mut px.data[at], &mut py.data[at], &mut pz.data[at]],
                        [&mut vx.data[at], &mut vy.data[at], &mut vz.data[at]],
                        [sx[t], sy[t], sz[t]],
                        max_speed2,
                    );
                    max_edge2 = max_edge2.max(step2);
                }
            }
            let kept = self
                .contact
                .as_mut()
                .map(|contact| contact.keep_apart(&mut self.position, &mut self.velocity, MOMENTUM));
            // The settling sweeps are part of what the shape is, not of the cap's budget.
            report.iterations = (iteration + 1).saturating_sub(settle_sweeps);
            if kept.as_ref().is_some_and(|kept| kept.overwhelmed) {
                // Folds too crowded to keep apart: stopped, not settled.
                report.last_move_m = f64::INFINITY;
                report.last_move = f64::INFINITY;
                break;
            }
            let held2 = kept.and_then(|kept| kept.residual2);
            report.last_move_m = held2.unwrap_or(max_step2.max(max_edge2)).sqrt();
            report.last_move = report.last_move_m / min_rest;
            let progress = RelaxProgress {
                cols: self.cols,
                rows: self.rows,
                iteration: iteration + 1,
                max_iterations: settle_sweeps.saturating_add(params.max_iterations),
                last_move_m: report.last_move_m,
            };
            if control(progress).is_break() {
                return Err(Cancelled);
            }
            if !settling && report.last_move < params.tolerance {
                report.converged = true;
                break;
            }
            // Only with an interior to compare against: on a grid that is all edge
            // (a lone cell) the extra sweeps would just fight the momentum.
            let has_interior = self.runs.iter().any(|runs| !runs.is_empty());
            if !settling && has_interior && max_edge2 > max_step2 {
                if let Some(contact) = &mut self.contact {
                    contact.begin(&self.position, &self.velocity);
                }
                self.edge_sweep();
                if let Some(contact) = &mut self.contact {
                    contact.keep_apart(&mut self.position, &mut self.velocity, MOMENTUM);
                }
            }
        }
        Ok(report)
    }

    /// One extra sweep over the points near an edge, without momentum (their
    /// velocity is left as it is). Where the largest move is at an edge, the
    /// free edge settles more slowly than the interior (fewer neighbours pull
    /// on it), and the whole grid would keep sweeping for it: on 256² the
    /// finest level converges in 86 sweeps with it and runs into a 200-sweep
    /// cap without it. Its moves do not count towards convergence; the next full
    /// sweep's do. Inlined so that it is compiled for the vector unit of the
    /// sweeps that call it (not inlined it ran scalar: 5% of a 64² build).
    #[inline(always)]
    fn edge_sweep(&mut self) {
        for colour in 0..4 {
            let filled = self.edge_run_steps_from(colour, 0.0, 0);
            self.border_steps_from(colour, 0.0, filled);
            let [px, py, pz] = &mut self.position;
            let [sx, sy, sz] = &self.steps;
            let mut done = 0;
            for EdgeRun { run, .. } in &self.edge_runs[colour] {
                let (i, j, len) = (run.i, run.j, run.len);
                let (px, py, pz) = (px.run_mut(i, j, len), py.run_mut(i, j, len), pz.run_mut(i, j, len));
                for t in 0..len {
                    let k = done + t;
                    nudge([&mut px[t], &mut py[t], &mut pz[t]], [sx[k], sy[k], sz[k]]);
                }
                done += len;
            }
            for (k, at) in self.border[colour].iter().flat_map(BorderChunk::centres).enumerate() {
                let k = done + k;
                nudge([&mut px.data[at], &mut py.data[at], &mut pz.data[at]], [sx[k], sy[k], sz[k]]);
            }
        }
    }

    /// Steps of the points of one run, into `steps` from `first` on; neighbours
    /// with `present` 0 are read as the points themselves.
    #[inline(always)]
    fn run_steps(&mut self, run: &Run, present: &[f64; NEIGHBOURS], gravity: f64, first: usize) {
        if self.bends {
            run_steps::<true>(&self.position, run, present, &self.bounds, gravity, &mut self.steps, first);
        } else {
            run_steps::<false>(&self.position, run, present, &self.bounds, gravity, &mut self.steps, first);
        }
    }

    /// Steps of the edge runs of `colour`, into `steps` from `first` on; returns
    /// where they end.
    #[inline(always)]
    fn edge_run_steps_from(&mut self, colour: usize, gravity: f64, first: usize) -> usize {
        let mut filled = first;
        for e in 0..self.edge_runs[colour].len() {
            let EdgeRun { run, present } = self.edge_runs[colour][e];
            self.run_steps(&run, &present, gravity, filled);
            filled += run.len;
        }
        filled
    }

    /// Steps of the points of `colour` near an edge, into `steps` from `first` on.
    #[inline(always)]
    fn border_steps_from(&mut self, colour: usize, gravity: f64, first: usize) {
        for (c, chunk) in self.border[colour].iter().enumerate() {
            let step = self.border_steps(chunk, gravity);
            let at = first + c * LANES;
            for (steps, lanes) in self.steps.iter_mut().zip(step) {
                steps[at..at + chunk.len].copy_from_slice(&lanes[..chunk.len]);
            }
        }
    }

    /// Steps of the points of `chunk`, side by side.
    #[inline(always)]
    fn border_steps(&self, chunk: &BorderChunk, gravity: f64) -> [Lanes; 3] {
        let mut p = [[0.0; LANES]; 3];
        let mut q = [[[0.0; LANES]; 3]; NEIGHBOURS];
        for (p, axis) in p.iter_mut().zip(&self.position) {
            for (p, &at) in p.iter_mut().zip(&chunk.centre) {
                *p = axis.data[at as usize];
            }
        }
        for (q, around) in q.iter_mut().zip(&chunk.around) {
            for (q, axis) in q.iter_mut().zip(&self.position) {
                for (q, &at) in q.iter_mut().zip(around) {
                    *q = axis.data[at as usize];
                }
            }
        }
        let present = &chunk.present;
        if self.bends {
            point_steps::<true, LANES>(&p, &|n| q[n], &|n| present[n], &self.bounds, gravity)
        } else {
            point_steps::<false, LANES>(&p, &|n| q[n], &|n| present[n], &self.bounds, gravity)
        }
    }
}

/// Distance between second neighbours (spacing `rest` apart along a line) when
/// the line bends on a circle of radius `radius`: 2·rest·√(1 − (rest/2r)²);
/// 0 when the radius allows any fold.
pub(super) fn min_second_neighbour_distance(rest: f64, radius: f64) -> f64 {
    let half_ratio = rest / (2.0 * radius);
    if !(half_ratio < 1.0) {
        return 0.0;
    }
    2.0 * rest * (1.0 - half_ratio * half_ratio).sqrt()
}
