//! The Sway layer, paper eq. 2 as DESIGN.md writes it:
//! displacement = a · magnitude · speed · normalize(direction) · osc(t),
//! osc = sin(2π·frequency·t + phase) when frequency > 0, else 1.

use glam::{DVec3, Vec3};

use super::layer::{ApplyLayer, LayerFrame, LayerScratch};
use super::track::sample;
use crate::mesh::PointArrays;
use crate::scene::Sway;

/// The whole-cloth displacement before attenuation (metres), weight included.
/// A zero or non-finite direction gives no displacement.
pub fn displacement(sway: &Sway, at: &LayerFrame, weight: f64) -> DVec3 {
    let frame = at.frame;
    let frequency_hz = sample(&sway.frequency, frame);
    let osc = if frequency_hz > 0.0 {
        (std::f64::consts::TAU * frequency_hz * at.secs() + sample(&sway.phase, frame)).sin()
    } else {
        1.0
    };
    let direction = DVec3::new(sway.direction.0, sway.direction.1, sway.direction.2).normalize_or_zero();
    direction * (weight * sample(&sway.magnitude, frame) * sample(&sway.speed, frame) * osc)
}

/// Adds the sway to `points`, attenuated per vertex.
impl ApplyLayer for Sway {
    #[inline(always)]
    fn apply(&self, at: &LayerFrame, weight: f64, scratch: &mut LayerScratch, points: &mut PointArrays) {
        let d = displacement(self, at, weight).as_vec3();
        let falloff = sample(&self.falloff, at.frame) as f32;
        if d == Vec3::ZERO || !d.is_finite() {
            return;
        }
        let a = scratch.attenuation.of(at.ratio, falloff);
        for (values, d) in [(&mut points.x, d.x), (&mut points.y, d.y), (&mut points.z, d.z)] {
            for (p, &a) in values.iter_mut().zip(a) {
                *p += d * a;
            }
        }
    }
}
