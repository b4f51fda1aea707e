//! The Gusts layer: wind as smooth, seeded turbulence scrolling with the wind.
//!
//! displacement = a · amplitude · ((1 − turbulence) · gust · wind + turbulence · swirl)
//! where `wind` is the unit wind direction, gust = ½ + ½·n₀ ∈ [0, 1] pushes
//! downwind only, swirl = (n₁, n₂, n₃) ∈ [−1, 1]³, and n are four channels of
//! fractal value noise sampled at (p − wind · speed · t) / scale.

use glam::{DVec3, IVec3, Vec3, Vec4};

use super::layer::{ApplyLayer, LayerFrame, LayerScratch};
use super::track::sample;
use crate::mesh::PointArrays;
use crate::scene::Gusts;

/// Adds the gusts to `points` (the layer's input mesh, whose points also
/// sample the noise), attenuated per vertex. The sampler's state never
/// changes the result.
impl ApplyLayer for Gusts {
    #[inline(always)]
    fn apply(&self, at: &LayerFrame, weight: f64, scratch: &mut LayerScratch, points: &mut PointArrays) {
        let amplitude = weight * sample(&self.amplitude, at.frame);
        let scale_m = sample(&self.scale, at.frame);
        let wind = DVec3::new(self.direction.0, self.direction.1, self.direction.2).normalize_or_zero();
        if amplitude == 0.0 || !amplitude.is_finite() || !(scale_m > 0.0) || wind == DVec3::ZERO {
            return;
        }
        let turbulence = sample(&self.turbulence, at.frame).clamp(0.0, 1.0) as f32;
        let falloff = sample(&self.falloff, at.frame) as f32;
        // The scroll in lattice cells, split into whole cells and a small rest in
        // f64, so long shots keep their precision.
        let scroll = wind * (sample(&self.speed, at.frame) * at.secs() / scale_m);
        let whole = scroll.floor();
        let cell_offset = if whole.abs().max_element() < f64::from(i32::MAX) {
            IVec3::new(-(whole.x as i32), -(whole.y as i32), -(whole.z as i32))
        } else {
            IVec3::ZERO
        };
        let rest = (scroll - whole).as_vec3();
        let inverse_scale = (1.0 / scale_m) as f32;
        let push = wind.as_vec3() * (1.0 - turbulence);
        let amplitude = amplitude as f32;
        let LayerScratch { attenuation, sampler, .. } = scratch;
        sampler.reset(self.octaves, self.seed, cell_offset);
        let a = attenuation.of(at.ratio, falloff);
        // displacement = (push · gust + swirl · turbulence) · (amplitude · a),
        // gust = ½ + ½·n₀, swirl = (n₁, n₂, n₃): per lane or per point alike.
        let PointArrays { x, y, z } = points;
        let n = a.len();
        let whole = n / 4 * 4;
        for start in (0..whole).step_by(4) {
            let range = start..start + 4;
            let a = Vec4::from_slice(&a[range.clone()]);
            // Pins (a = 0) are left bit-for-bit alone.
            let moving = a.cmpne(Vec4::ZERO);
            if !moving.any() {
                continue;
            }
            let p = [&x[range.clone()], &y[range.clone()], &z[range.clone()]].map(Vec4::from_slice);
            let [n0, n1, n2, n3] = sampler.sample_lanes(
                p[0] * inverse_scale - rest.x,
                p[1] * inverse_scale - rest.y,
                p[2] * inverse_scale - rest.z,
            );
            let gust = 0.5 + 0.5 * n0;
            let strength = amplitude * a;
            let moved = [
                p[0] + (push.x * gust + n1 * turbulence) * strength,
                p[1] + (push.y * gust + n2 * turbulence) * strength,
                p[2] + (push.z * gust + n3 * turbulence) * strength,
            ];
            for (values, (moved, p)) in [&mut *x, &mut *y, &mut *z].into_iter().zip(moved.into_iter().zip(p)) {
                Vec4::select(moving, moved, p).write_to_slice(&mut values[range.clone()]);
            }
        }
        for k in whole..n {
            if a[k] != 0.0 {
                let p = Vec3::new(x[k], y[k], z[k]);
                let n = sampler.sample(p * inverse_scale - rest);
                let gust = 0.5 + 0.5 * n.x;
                let swirl = Vec3::new(n.y, n.z, n.w);
                let moved = p + (push * gust + swirl * turbulence) * (amplitude * a[k]);
                (x[k], y[k], z[k]) = (moved.x, moved.y, moved.z);
            }
        }
    }
}
