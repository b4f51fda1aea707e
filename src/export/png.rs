//! PNG pictures of rendered frames (8-bit sRGB RGBA).

use std::io::{self, Write};

use crate::image::RgbaImage;

/// Encodes `image` as a PNG into `out`, tagged sRGB. Fast compression: frames
/// of a sequence are written as they are rendered.
pub fn write_png(image: &RgbaImage, out: &mut dyn Write) -> io::Result<()> {
    let mut encoder = png::Encoder::new(out, image.width, image.height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header().map_err(png_error)?;
    writer.write_image_data(&image.pixels).map_err(png_error)?;
    writer.finish().map_err(png_error)
}

fn png_error(error: png::EncodingError) -> io::Error {
    match error {
        png::EncodingError::IoError(error) => error,
        other => io::Error::other(other.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_through_the_decoder() {
        let mut image = RgbaImage::new(3, 2);
        for (k, byte) in image.pixels.iter_mut().enumerate() {
            *byte = (k * 11) as u8;
        }
        let mut bytes = Vec::new();
        write_png(&image, &mut bytes).unwrap();
        assert_eq!(RgbaImage::decode_png(&bytes).unwrap(), image);
    }
}
