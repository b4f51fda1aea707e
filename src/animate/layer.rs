//! The one interface of the layers: every kind implements [`ApplyLayer`],
//! reading one [`LayerFrame`] (the time, the cloth's grid, the pin-distance
//! field, the keys and their rest shapes) and moving the points in place.
//!
//! The time is a frame (possibly fractional): parameters are sampled at it,
//! and a layer whose motion runs in seconds reads [`LayerFrame::secs`], the
//! same frame / fps that [`super::frame_time_secs`] gives.

use std::sync::Arc;

use super::cache::KeyShape;
use super::detours::SegmentPaths;
use super::falloff::AttenuationField;
use super::noise::FractalSampler;
use super::wave_tables::WaveTables;
use crate::mesh::{NormalRows, PointArrays};
use crate::scene::{Key, Layer};

/// What every layer reads at one frame; the same for every layer of the stack.
#[derive(Clone, Copy, Debug)]
pub struct LayerFrame<'a> {
    /// The frame (possibly fractional) every parameter is sampled at.
    pub frame: f64,
    /// The timeline's frames per second.
    pub fps: f64,
    /// The grid's columns and rows.
    pub grid: (usize, usize),
    /// The material distance between neighbouring columns and rows (m).
    pub spacing_m: (f64, f64),
    /// The cloth's stretch limit (0: off).
    pub stretch_limit: f32,
    /// d_cp/d_max per vertex, blended like the rest shapes; the attenuation
    /// a = ratio^falloff comes from it through [`LayerScratch::attenuation`].
    pub ratio: &'a [f32],
    /// The scene's keys and their rest shapes, for layers that blend them at other times.
    pub keys: &'a [Key],
    pub shapes: &'a [Arc<KeyShape>],
    /// Per segment, the points whose blend goes round a collider ([`super::detours`]); empty without colliders.
    pub paths: &'a [Arc<SegmentPaths>],
}

impl LayerFrame<'_> {
    /// The time in seconds: frame / fps.
    #[inline(always)]
    pub fn secs(&self) -> f64 {
        self.frame / self.fps
    }
}

/// Buffers the layers reuse between frames; their contents never change a result.
#[derive(Debug, Default)]
pub struct LayerScratch {
    /// a = ratio^falloff, kept while the falloff stays the same (clear it
    /// whenever the ratio field changes).
    pub attenuation: AttenuationField,
    pub wave_tables: WaveTables,
    pub normal_rows: NormalRows,
    pub sampler: FractalSampler,
}

/// One layer's math: adds its displacement, scaled by `weight` (finite and
/// not 0), to `points`, the cloth as the layers before it left it.
pub trait ApplyLayer {
    fn apply(&self, at: &LayerFrame, weight: f64, scratch: &mut LayerScratch, points: &mut PointArrays);
}

impl ApplyLayer for Layer {
    #[inline(always)]
    fn apply(&self, at: &LayerFrame, weight: f64, scratch: &mut LayerScratch, points: &mut PointArrays) {
        match self {
            Layer::Sway(l) => l.apply(at, weight, scratch, points),
            Layer::Wave(l) => l.apply(at, weight, scratch, points),
            Layer::Gusts(l) => l.apply(at, weight, scratch, points),
            Layer::FollowThrough(l) => l.apply(at, weight, scratch, points),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::Evaluator;
    use crate::animate::blend::{blend_segment, segment_at};

    /// A cloth held at two corners, moved between two keys.
    const MOVING: &str = r#"(
        version: 1,
        cloth: (size: (1.0, 0.8), grid: (9, 7)),
        keys: [
            (frame: 0, pins: [(grid: (0, 0), pos: (-0.5, 1.0, 0.0)), (grid: (8, 0), pos: (0.5, 1.0, 0.0))]),
            (frame: 12, pins: [(grid: (0, 0), pos: (-0.5, 1.0, 0.4)), (grid: (8, 0), pos: (0.5, 1.0, 0.4))]),
        ],
    )"#;

    #[test]
    fn every_layer_kind_moves_the_cloth_through_the_one_interface() {
        let Ok(scene) = crate::scene::parse(MOVING, "moving") else { panic!("the test scene parses") };
        let mut evaluator = Evaluator::new();
        let shapes: Vec<_> = scene.keys.iter().map(|key| evaluator.key_shape(&scene, key)).collect();
        let frame = 5.0;
        let (mut blended, mut ratio) = (PointArrays::default(), Vec::new());
        blend_segment(&scene.keys, &shapes, segment_at(&scene.keys, frame), None, &mut blended, &mut ratio);
        let at = LayerFrame {
            frame,
            fps: scene.timeline.fps,
            grid: (scene.cloth.cols(), scene.cloth.rows()),
            spacing_m: (scene.cloth.spacing_u_m(), scene.cloth.spacing_v_m()),
            stretch_limit: 0.0,
            ratio: &ratio,
            keys: &scene.keys,
            shapes: &shapes,
            paths: &[],
        };
        for &kind in Layer::KINDS {
            let Some(layer) = Layer::with_start_values(kind) else { panic!("{kind} has start values") };
            let mut points = blended.clone();
            layer.apply(&at, 1.0, &mut LayerScratch::default(), &mut points);
            assert_ne!(points, blended, "{kind} moves the cloth");
            assert_eq!(points.get(0), blended.get(0), "{kind} leaves the pins alone");
        }
    }
}
