//! The Wave layer, paper eqs. 3–4 as DESIGN.md writes it:
//! displacement = a · magnitude · sin(x·frequency + phase + t·speed) along
//! `axis`, with x = u·cos(direction) + v·sin(direction) the material
//! coordinate along the wave. No azimuth (the paper leaves it out).
//!
//! The argument is a sum of a column term and a row term, so the sine comes
//! from [`WaveTables`]; the time term, reduced in f64, keeps its precision at
//! any t.

use glam::Vec3;

use super::layer::{ApplyLayer, LayerFrame, LayerScratch};
use super::track::sample;
use super::wave_tables::WaveTables;
use crate::mesh::PointArrays;
use crate::scene::{Wave, WaveAxis};

/// Fills `tables` for this frame: column i contributes
/// u_i·cos(dir)·frequency, row j contributes v_j·sin(dir)·frequency + phase + t·speed.
#[inline(always)]
fn fill_tables(tables: &mut WaveTables, wave: &Wave, at: &LayerFrame) {
    let (frame, spacing_m) = (at.frame, at.spacing_m);
    let frequency = sample(&wave.frequency, frame);
    let direction = sample(&wave.direction_deg, frame).to_radians();
    let offset = (sample(&wave.phase, frame) + at.secs() * sample(&wave.speed, frame)) % std::f64::consts::TAU;
    let along_u = direction.cos() * frequency * spacing_m.0;
    let along_v = direction.sin() * frequency * spacing_m.1;
    tables.fill(at.grid, along_u, along_v, offset);
}

/// Adds the wave to the grid's points, attenuated per vertex. Along the
/// normals, each row is displaced as soon as its normals are known (they
/// are all those of the input mesh).
impl ApplyLayer for Wave {
    #[inline(always)]
    fn apply(&self, at: &LayerFrame, weight: f64, scratch: &mut LayerScratch, points: &mut PointArrays) {
        let (cols, rows) = at.grid;
        let amplitude = (weight * sample(&self.magnitude, at.frame)) as f32;
        let falloff = sample(&self.falloff, at.frame) as f32;
        if amplitude == 0.0 || !amplitude.is_finite() {
            return;
        }
        let LayerScratch { attenuation, wave_tables: tables, normal_rows, .. } = scratch;
        fill_tables(tables, self, at);
        let a = attenuation.of(at.ratio, falloff);
        let a_row = |j: usize| &a[j * cols..(j + 1) * cols];
        match self.axis {
            WaveAxis::Normal => {
                normal_rows.start(cols, rows);
                while let Some((j, normals, [x, y, z])) = normal_rows.next_row(points) {
                    tables.row(j, amplitude).displace(a_row(j), normals, x, y, z);
                }
            }
            WaveAxis::Fixed((x, y, z)) => {
                let axis = Vec3::new(x as f32, y as f32, z as f32).normalize_or_zero();
                let axis = [vec![axis.x; cols], vec![axis.y; cols], vec![axis.z; cols]];
                for j in 0..rows {
                    let r = j * cols..(j + 1) * cols;
                    let [x, y, z] = [&mut points.x, &mut points.y, &mut points.z].map(|values| &mut values[r.clone()]);
                    tables.row(j, amplitude).displace(a_row(j), [&axis[0], &axis[1], &axis[2]], x, y, z);
                }
            }
        }
    }
}
