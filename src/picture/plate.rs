//! Laying a render over the background plate: the plate fills the picture
//! (scaled to cover it, the overhang cropped evenly), faded over the
//! background colour by its opacity, and the cloth's premultiplied picture
//! goes over it, in linear light as the GPU would blend.

use crate::image::RgbaImage;

/// sRGB byte → linear light.
fn linear_table() -> [f32; 256] {
    std::array::from_fn(|v| {
        let v = v as f32 / 255.0;
        if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
    })
}

/// Linear light (0..1) → sRGB byte, by a table fine enough that every byte is reached.
struct SrgbEncoder(Vec<u8>);

impl SrgbEncoder {
    const STEPS: usize = 4096;

    fn new() -> SrgbEncoder {
        SrgbEncoder(
            (0..=Self::STEPS)
                .map(|i| {
                    let v = i as f32 / Self::STEPS as f32;
                    let s = if v <= 0.003_130_8 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
                    (s * 255.0).round() as u8
                })
                .collect(),
        )
    }

    fn encode(&self, v: f32) -> u8 {
        self.0[(v.clamp(0.0, 1.0) * Self::STEPS as f32).round() as usize]
    }
}

/// `plate` scaled to `width × height` so it covers it (the picture's shape
/// kept, what overhangs cropped evenly), sampled bilinearly. An empty plate
/// gives a transparent picture.
pub fn plate_fitted(plate: &RgbaImage, width: u32, height: u32) -> RgbaImage {
    let mut out = RgbaImage::new(width, height);
    if plate.width == 0 || plate.height == 0 || plate.pixels.len() < plate.width as usize * plate.height as usize * 4 {
        return out;
    }
    if (plate.width, plate.height) == (width, height) {
        let len = out.pixels.len();
        out.pixels.copy_from_slice(&plate.pixels[..len]);
        return out;
    }
    let scale = (width as f32 / plate.width as f32).max(height as f32 / plate.height as f32);
    let (offset_x, offset_y) =
        ((plate.width as f32 * scale - width as f32) * 0.5, (plate.height as f32 * scale - height as f32) * 0.5);
    let (max_x, max_y) = (plate.width as f32 - 1.0, plate.height as f32 - 1.0);
    let texel = |x: usize, y: usize| &plate.pixels[(y * plate.width as usize + x) * 4..][..4];
    for y in 0..height {
        let sy = (((y as f32 + 0.5 + offset_y) / scale) - 0.5).clamp(0.0, max_y);
        let (y0, fy) = (sy.floor() as usize, sy.fract());
        let y1 = (y0 + 1).min(plate.height as usize - 1);
        for x in 0..width {
            let sx = (((x as f32 + 0.5 + offset_x) / scale) - 0.5).clamp(0.0, max_x);
            let (x0, fx) = (sx.floor() as usize, sx.fract());
            let x1 = (x0 + 1).min(plate.width as usize - 1);
            let at = (y as usize * width as usize + x as usize) * 4;
            for c in 0..4 {
                let top = f32::from(texel(x0, y0)[c]) * (1.0 - fx) + f32::from(texel(x1, y0)[c]) * fx;
                let bottom = f32::from(texel(x0, y1)[c]) * (1.0 - fx) + f32::from(texel(x1, y1)[c]) * fx;
                out.pixels[at + c] = (top * (1.0 - fy) + bottom * fy).round() as u8;
            }
        }
    }
    out
}

/// `picture` (what the renderer resolved over transparent black: sRGB bytes
/// of linear colours premultiplied by alpha) laid over `plate` (straight
/// alpha, already [`plate_fitted`] to the picture) which is itself faded in
/// at `opacity` over `background` (linear RGB). The result is opaque.
pub fn over_plate(picture: &RgbaImage, plate: &RgbaImage, opacity: f32, background: [f32; 3]) -> RgbaImage {
    let linear = linear_table();
    let encoder = SrgbEncoder::new();
    let opacity = if opacity.is_finite() { opacity.clamp(0.0, 1.0) } else { 1.0 };
    let mut out = picture.clone();
    let plate_pixels = plate.pixels.chunks_exact(4).chain(std::iter::repeat([0u8; 4].as_slice()));
    for (pixel, plate) in out.pixels.chunks_exact_mut(4).zip(plate_pixels) {
        let alpha = f32::from(pixel[3]) / 255.0;
        let plate_alpha = opacity * f32::from(plate[3]) / 255.0;
        for c in 0..3 {
            let base = background[c] * (1.0 - plate_alpha) + linear[plate[c] as usize] * plate_alpha;
            pixel[c] = encoder.encode(linear[pixel[c] as usize] + base * (1.0 - alpha));
        }
        pixel[3] = 255;
    }
    out
}

/// Straight-alpha `picture` (as an `--alpha` PNG holds it) over the opaque
/// `base`, blended in linear light: what a compositor does with the frames.
pub fn straight_over(picture: &RgbaImage, base: &RgbaImage) -> RgbaImage {
    let linear = linear_table();
    let encoder = SrgbEncoder::new();
    let mut out = base.clone();
    for (pixel, top) in out.pixels.chunks_exact_mut(4).zip(picture.pixels.chunks_exact(4)) {
        let alpha = f32::from(top[3]) / 255.0;
        for c in 0..3 {
            pixel[c] = encoder.encode(linear[top[c] as usize] * alpha + linear[pixel[c] as usize] * (1.0 - alpha));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filled(width: u32, height: u32, rgba: [u8; 4]) -> RgbaImage {
        RgbaImage { width, height, pixels: rgba.repeat((width * height) as usize) }
    }

    #[test]
    fn the_cloth_covers_the_plate_and_the_plate_shows_where_it_is_not() {
        let mut picture = filled(2, 1, [0, 0, 0, 0]);
        picture.pixels[..4].copy_from_slice(&[200, 10, 10, 255]);
        let plate = filled(2, 1, [30, 140, 220, 255]);
        let out = over_plate(&picture, &plate, 1.0, [0.0; 3]);
        assert_eq!(out.pixel(0, 0), [200, 10, 10, 255], "opaque cloth");
        assert_eq!(out.pixel(1, 0), [30, 140, 220, 255], "the plate, exactly");
        // Half opacity over a black background: half the plate's light.
        let faded = over_plate(&picture, &plate, 0.5, [0.0; 3]).pixel(1, 0);
        let expected = SrgbEncoder::new().encode(linear_table()[220] * 0.5);
        assert!((i32::from(faded[2]) - i32::from(expected)).abs() <= 1, "{faded:?}");
    }

    #[test]
    fn a_half_covered_edge_is_half_cloth_half_plate_in_linear_light() {
        let encoder = SrgbEncoder::new();
        // Linear 0.8 red at coverage 0.5, premultiplied: 0.4.
        let picture = RgbaImage { width: 1, height: 1, pixels: vec![encoder.encode(0.4), 0, 0, 128] };
        let plate = filled(1, 1, [0, 0, 255, 255]);
        let out = over_plate(&picture, &plate, 1.0, [0.0; 3]).pixel(0, 0);
        let half = encoder.encode(1.0 - 128.0 / 255.0);
        assert!((i32::from(out[2]) - i32::from(half)).abs() <= 1, "{out:?}");
        assert!((i32::from(out[0]) - i32::from(encoder.encode(0.4))).abs() <= 1, "{out:?}");
    }

    #[test]
    fn a_plate_of_another_shape_covers_the_picture_cropped_evenly() {
        // 4 × 1: left half red, right half blue; fitted into 1 × 1 it is cropped to its middle.
        let mut plate = filled(4, 2, [255, 0, 0, 255]);
        for y in 0..2 {
            for x in 2..4 {
                plate.pixels[(y * 4 + x) * 4..][..4].copy_from_slice(&[0, 0, 255, 255]);
            }
        }
        let fitted = plate_fitted(&plate, 2, 2);
        assert_eq!((fitted.width, fitted.height), (2, 2));
        assert_eq!(fitted.pixel(0, 0), [255, 0, 0, 255]);
        assert_eq!(fitted.pixel(1, 1), [0, 0, 255, 255]);
        let doubled = plate_fitted(&plate, 8, 4);
        assert_eq!(doubled.pixel(0, 0), [255, 0, 0, 255]);
        assert_eq!(doubled.pixel(7, 3), [0, 0, 255, 255]);
        assert_eq!(plate_fitted(&RgbaImage::new(0, 0), 3, 2).pixels, vec![0; 24], "nothing to fit");
    }

    #[test]
    fn straight_alpha_over_the_plate_matches_the_premultiplied_blend() {
        let encoder = SrgbEncoder::new();
        let mut premultiplied = RgbaImage { width: 1, height: 1, pixels: vec![encoder.encode(0.3), 0, 0, 153] };
        let plate = filled(1, 1, [90, 160, 40, 255]);
        let direct = over_plate(&premultiplied, &plate, 1.0, [0.0; 3]);
        premultiplied.unpremultiply();
        let composited = straight_over(&premultiplied, &plate);
        for c in 0..3 {
            assert!(
                (i32::from(direct.pixels[c]) - i32::from(composited.pixels[c])).abs() <= 2,
                "{direct:?} {composited:?}"
            );
        }
    }
}
