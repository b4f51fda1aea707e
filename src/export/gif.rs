//! Animated GIF previews, written frame by frame so a long range never sits in memory.

use std::io::{self, Write};

use crate::image::RgbaImage;

/// Streams frames into an endlessly looping GIF at `fps`.
pub struct GifWriter<W: Write> {
    encoder: gif::Encoder<W>,
    size_px: (u16, u16),
    fps: f64,
    frames_written: u64,
    /// Centiseconds already given to earlier frames, so rounding never drifts from the scene's clock.
    elapsed_cs: u64,
}

/// NeuQuant sampling factor (1 best … 30 fastest): 10 keeps gradients smooth at a fair speed.
const QUANTIZER_SPEED: i32 = 10;

impl<W: Write> GifWriter<W> {
    /// A writer for `size_px` frames (each side 1..=65535) shown at `fps` (> 0).
    pub fn new(out: W, size_px: (u32, u32), fps: f64) -> io::Result<GifWriter<W>> {
        let side = |v: u32| {
            u16::try_from(v).ok().filter(|v| *v > 0).ok_or_else(|| {
                io::Error::new(io::ErrorKind::InvalidInput, format!("a GIF side must be 1 to 65535 pixels, not {v}"))
            })
        };
        let size_px = (side(size_px.0)?, side(size_px.1)?);
        if !(fps.is_finite() && fps > 0.0) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("a GIF needs a positive frame rate, not {fps}"),
            ));
        }
        let mut encoder = gif::Encoder::new(out, size_px.0, size_px.1, &[]).map_err(gif_error)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(gif_error)?;
        Ok(GifWriter { encoder, size_px, fps, frames_written: 0, elapsed_cs: 0 })
    }

    /// Appends one frame; it must have the writer's size.
    pub fn write_frame(&mut self, image: &RgbaImage) -> io::Result<()> {
        if (image.width, image.height) != (self.size_px.0 as u32, self.size_px.1 as u32) {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, "every GIF frame must have the same size"));
        }
        let mut pixels = image.pixels.clone();
        let mut frame = gif::Frame::from_rgba_speed(self.size_px.0, self.size_px.1, &mut pixels, QUANTIZER_SPEED);
        self.frames_written += 1;
        let end_cs = (self.frames_written as f64 * 100.0 / self.fps).round() as u64;
        // GIF delays are whole centiseconds, at least 1 (viewers treat 0 as "as fast as you like").
        frame.delay = end_cs.saturating_sub(self.elapsed_cs).clamp(1, u16::MAX as u64) as u16;
        self.elapsed_cs += frame.delay as u64;
        self.encoder.write_frame(&frame).map_err(gif_error)
    }

    pub fn frames_written(&self) -> u64 {
        self.frames_written
    }

    /// Writes the trailer and hands back the output.
    pub fn finish(self) -> io::Result<W> {
        self.encoder.into_inner().map_err(|e| io::Error::other(e.to_string()))
    }
}

fn gif_error(error: gif::EncodingError) -> io::Error {
    match error {
        gif::EncodingError::Io(error) => error,
        other => io::Error::other(other.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_and_timing_round_trip() {
        let mut writer = GifWriter::new(Vec::new(), (4, 3), 24.0).unwrap();
        for shade in [0u8, 128, 255] {
            let image = RgbaImage { width: 4, height: 3, pixels: [shade, 64, 200, 255].repeat(12) };
            writer.write_frame(&image).unwrap();
        }
        let bytes = writer.finish().unwrap();
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::RGBA);
        let mut decoder = options.read_info(bytes.as_slice()).unwrap();
        let mut delays = Vec::new();
        let mut first_pixels = Vec::new();
        while let Some(frame) = decoder.read_next_frame().unwrap() {
            delays.push(frame.delay);
            first_pixels.push(frame.buffer[0]);
        }
        // 24 fps: 4.17 cs per frame, given as 4, 4, 5 so three frames last 12.5 → 13 cs.
        assert_eq!(delays, vec![4, 4, 5]);
        assert_eq!(first_pixels.len(), 3);
        assert!(first_pixels[0] < 10 && first_pixels[2] > 245);
    }

    #[test]
    fn bad_sizes_and_rates_are_errors() {
        assert!(GifWriter::new(Vec::new(), (0, 3), 24.0).is_err());
        assert!(GifWriter::new(Vec::new(), (70_000, 3), 24.0).is_err());
        assert!(GifWriter::new(Vec::new(), (4, 3), f64::NAN).is_err());
        let mut writer = GifWriter::new(Vec::new(), (4, 3), 24.0).unwrap();
        assert!(writer.write_frame(&RgbaImage::new(2, 2)).is_err());
    }
}
