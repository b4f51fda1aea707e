//! The Wave layer, paper eqs. 3–4 as DESIGN.md writes it:
//! displacement = a · magnitude · sin(x·frequency + phase + t·speed) along
//! `axis`, with x = u·cos(direction) + v·sin(direction) the material
//! coordinate along the wave. No azimuth (the paper leaves it out).
//!
//! The argument is a sum of a column term and a row term, so the sine is
//! built from one table per column and one per row by the angle-addition
//! formula: two multiplies per vertex instead of a sine, and the time term,
//! reduced in f64, keeps its precision at any t.

use glam::Vec3;

use super::falloff::AttenuationField;
use super::track::sample;
use crate::mesh::{NormalRows, PointArrays};
use crate::scene::{Wave, WaveAxis};

/// Per-column and per-row sines and cosines of the wave's argument.
#[derive(Debug, Default)]
pub struct WaveTables {
    column_sin: Vec<f32>,
    column_cos: Vec<f32>,
    row_sin: Vec<f32>,
    row_cos: Vec<f32>,
}

impl WaveTables {
    /// Fills the tables: column i contributes u_i·cos(dir)·frequency, row j
    /// contributes v_j·sin(dir)·frequency + phase + t·speed.
    fn fill(&mut self, wave: &Wave, frame: f64, t_secs: f64, spacing_m: (f64, f64), grid: (usize, usize)) {
        let frequency = sample(&wave.frequency, frame);
        let direction = sample(&wave.direction_deg, frame).to_radians();
        let offset = (sample(&wave.phase, frame) + t_secs * sample(&wave.speed, frame)) % std::f64::consts::TAU;
        let along_u = direction.cos() * frequency * spacing_m.0;
        let along_v = direction.sin() * frequency * spacing_m.1;
        let fill = |sin: &mut Vec<f32>, cos: &mut Vec<f32>, n: usize, step: f64, offset: f64| {
            sin.clear();
            cos.clear();
            for k in 0..n {
                let (s, c) = (k as f64 * step + offset).sin_cos();
                sin.push(s as f32);
                cos.push(c as f32);
            }
        };
        fill(&mut self.column_sin, &mut self.column_cos, grid.0, along_u, 0.0);
        fill(&mut self.row_sin, &mut self.row_cos, grid.1, along_v, offset);
    }
}

/// Adds the wave to the `cols × rows` grid `points`, attenuated per vertex
/// by `ratio` (d_cp/d_max). Along the normals, each row is displaced as soon
/// as its normals are known (they are all those of the input mesh);
/// `tables` and `normal_rows` are scratch space.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn apply(
    wave: &Wave,
    frame: f64,
    t_secs: f64,
    weight: f64,
    spacing_m: (f64, f64),
    grid: (usize, usize),
    ratio: &[f32],
    attenuation: &mut AttenuationField,
    points: &mut PointArrays,
    tables: &mut WaveTables,
    normal_rows: &mut NormalRows,
) {
    let (cols, rows) = grid;
    let amplitude = (weight * sample(&wave.magnitude, frame)) as f32;
    let falloff = sample(&wave.falloff, frame) as f32;
    if amplitude == 0.0 || !amplitude.is_finite() {
        return;
    }
    tables.fill(wave, frame, t_secs, spacing_m, grid);
    let a = attenuation.of(ratio, falloff);
    let a_row = |j: usize| &a[j * cols..(j + 1) * cols];
    match wave.axis {
        WaveAxis::Normal => {
            normal_rows.start(cols, rows);
            while let Some((j, normals, [x, y, z])) = normal_rows.next_row(points) {
                displace_row(tables, j, amplitude, a_row(j), normals, x, y, z);
            }
        }
        WaveAxis::Fixed((x, y, z)) => {
            let axis = Vec3::new(x as f32, y as f32, z as f32).normalize_or_zero();
            let axis = [vec![axis.x; cols], vec![axis.y; cols], vec![axis.z; cols]];
            for j in 0..rows {
                let r = j * cols..(j + 1) * cols;
                let [x, y, z] = [&mut points.x, &mut points.y, &mut points.z].map(|values| &mut values[r.clone()]);
                displace_row(tables, j, amplitude, a_row(j), [&axis[0], &axis[1], &axis[2]], x, y, z);
            }
        }
    }
}

/// Row j of the wave: p += axis · (amplitude · sin(A + B) · a), with
/// sin(A + B) = sin A cos B + cos A sin B. Each output is its own argument,
/// so the loop needs no overlap checks to vectorise.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn displace_row(
    tables: &WaveTables,
    j: usize,
    amplitude: f32,
    a: &[f32],
    [ax, ay, az]: [&[f32]; 3],
    x: &mut [f32],
    y: &mut [f32],
    z: &mut [f32],
) {
    let cols = a.len();
    let (row_sin, row_cos) = (tables.row_sin[j], tables.row_cos[j]);
    let (column_sin, column_cos) = (&tables.column_sin[..cols], &tables.column_cos[..cols]);
    let (ax, ay, az) = (&ax[..cols], &ay[..cols], &az[..cols]);
    let (x, y, z) = (&mut x[..cols], &mut y[..cols], &mut z[..cols]);
    for i in 0..cols {
        let wave_sin = column_sin[i] * row_cos + column_cos[i] * row_sin;
        let s = amplitude * wave_sin * a[i];
        x[i] += ax[i] * s;
        y[i] += ay[i] * s;
        z[i] += az[i] * s;
    }
}
