//! The Noise layer: wind gusts as smooth, seeded turbulence scrolling with the wind.
//!
//! displacement = a · amplitude · ((1 − turbulence) · gust · wind + turbulence · swirl)
//! where `wind` is the unit wind direction, gust = ½ + ½·n₀ ∈ [0, 1] pushes
//! downwind only, swirl = (n₁, n₂, n₃) ∈ [−1, 1]³, and n are four channels of
//! fractal value noise sampled at (p − wind · speed · t) / scale.

use glam::{DVec3, IVec3, Vec3, Vec4};

use super::falloff::attenuation;
use super::noise::FractalSampler;
use super::track::sample;
use crate::scene::Noise;

/// Adds the gusts to `positions` (the layer's input mesh, whose points also
/// sample the noise), attenuated per vertex by `ratio` (d_cp/d_max).
pub fn apply(noise: &Noise, frame: f64, t_secs: f64, weight: f64, ratio: &[f32], positions: &mut [Vec3]) {
    let amplitude = weight * sample(&noise.amplitude, frame);
    let scale_m = sample(&noise.scale, frame);
    let wind = DVec3::new(noise.direction.0, noise.direction.1, noise.direction.2).normalize_or_zero();
    if amplitude == 0.0 || !amplitude.is_finite() || !(scale_m > 0.0) || wind == DVec3::ZERO {
        return;
    }
    let turbulence = sample(&noise.turbulence, frame).clamp(0.0, 1.0) as f32;
    let falloff = sample(&noise.falloff, frame) as f32;
    // The scroll in lattice cells, split into whole cells and a small rest in
    // f64, so long shots keep their precision.
    let scroll = wind * (sample(&noise.speed, frame) * t_secs / scale_m);
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
    let mut sampler = FractalSampler::new(noise.octaves, noise.seed);
    let blow = |p: &mut Vec3, a: f32, n: Vec4| {
        let gust = 0.5 + 0.5 * n.x;
        let swirl = Vec3::new(n.y, n.z, n.w);
        *p += (push * gust + swirl * turbulence) * (amplitude * a);
    };
    // Four neighbouring vertices at a time: one SIMD lane each.
    let mut chunks = positions.chunks_exact_mut(4).zip(ratio.chunks_exact(4));
    for (p, r) in &mut chunks {
        let a = [0, 1, 2, 3].map(|k| attenuation(r[k], falloff));
        if a == [0.0; 4] {
            continue;
        }
        let n = sampler.sample4([0, 1, 2, 3].map(|k| p[k] * inverse_scale - rest), cell_offset);
        for k in 0..4 {
            // Pins (a = 0) are left bit-for-bit alone.
            if a[k] != 0.0 {
                blow(&mut p[k], a[k], n[k]);
            }
        }
    }
    let done = positions.len() / 4 * 4;
    for (p, &r) in positions[done..].iter_mut().zip(&ratio[done..]) {
        let a = attenuation(r, falloff);
        if a != 0.0 {
            let n = sampler.sample(*p * inverse_scale - rest, cell_offset);
            blow(p, a, n);
        }
    }
}
