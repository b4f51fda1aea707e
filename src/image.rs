//! An RGBA8 picture in memory (sRGB, rows top to bottom) and PNG decoding for
//! the built-in textures and the tests: what `render` reads back from the GPU
//! and `export` writes as PNG or GIF, without either importing the other.

#[derive(Clone, PartialEq, Eq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    /// `width·height·4` bytes, row-major from the top-left corner.
    pub pixels: Vec<u8>,
}

/// Its size only: the pixels would fill a test failure's screen.
impl std::fmt::Debug for RgbaImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "RgbaImage({} × {})", self.width, self.height)
    }
}

/// Most pixels a decoded picture may have (8192 × 8192: 256 MiB as RGBA):
/// a file claiming more is refused before anything is allocated for it.
pub const MAX_DECODED_PIXELS: u64 = 8192 * 8192;

/// Refuses a `width × height` picture over [`MAX_DECODED_PIXELS`].
fn check_size(width: u32, height: u32) -> Result<(), String> {
    if u64::from(width) * u64::from(height) > MAX_DECODED_PIXELS {
        return Err(format!("{width} × {height} pixels is more than Drape reads (8192 × 8192 at most)"));
    }
    Ok(())
}

#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("not a PNG Drape can read: {0}")]
    Decode(String),
}

impl RgbaImage {
    pub fn new(width: u32, height: u32) -> RgbaImage {
        RgbaImage { width, height, pixels: vec![0; width as usize * height as usize * 4] }
    }

    /// The pixel at column `x`, row `y`; panics outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside {}×{}", self.width, self.height);
        let at = (y as usize * self.width as usize + x as usize) * 4;
        [self.pixels[at], self.pixels[at + 1], self.pixels[at + 2], self.pixels[at + 3]]
    }

    /// Turns colours premultiplied by alpha in linear light (what a
    /// render resolved over transparent black holds) into straight ones, as
    /// PNG stores them; alpha 0 pixels become transparent black.
    pub fn unpremultiply(&mut self) {
        let to_linear = |v: u8| {
            let v = f32::from(v) / 255.0;
            if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
        };
        let to_srgb = |v: f32| {
            let v = v.clamp(0.0, 1.0);
            let s = if v <= 0.003_130_8 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
            (s * 255.0).round() as u8
        };
        for pixel in self.pixels.chunks_exact_mut(4) {
            let alpha = f32::from(pixel[3]) / 255.0;
            if pixel[3] == 255 {
                continue;
            }
            for channel in &mut pixel[..3] {
                *channel = if alpha > 0.0 { to_srgb(to_linear(*channel) / alpha) } else { 0 };
            }
        }
    }

    /// Decodes PNG or JPEG bytes (told by their first bytes, else by
    /// `mime_type`) into RGBA8; the error says what the bytes are not.
    pub fn decode(bytes: &[u8], mime_type: Option<&str>) -> Result<RgbaImage, String> {
        let is_png =
            bytes.starts_with(b"\x89PNG") || (mime_type == Some("image/png") && !bytes.starts_with(&[0xFF, 0xD8]));
        let is_jpeg = bytes.starts_with(&[0xFF, 0xD8]) || mime_type == Some("image/jpeg");
        if is_png {
            return RgbaImage::decode_png(bytes).map_err(|error| format!("not a readable PNG ({error})"));
        }
        if is_jpeg {
            use zune_core::bytestream::ZCursor;
            use zune_core::colorspace::ColorSpace;
            use zune_core::options::DecoderOptions;
            let options = DecoderOptions::default().jpeg_set_out_colorspace(ColorSpace::RGBA);
            let mut decoder = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), options);
            decoder.decode_headers().map_err(|error| format!("not a readable JPEG ({error:?})"))?;
            if let Some(info) = decoder.info() {
                check_size(u32::from(info.width), u32::from(info.height))?;
            }
            let rgba = decoder.decode().map_err(|error| format!("not a readable JPEG ({error:?})"))?;
            let info = decoder.info().ok_or("not a readable JPEG (no size)")?;
            let (width, height) = (u32::from(info.width), u32::from(info.height));
            return Ok(RgbaImage { width, height, pixels: rgba });
        }
        Err("only PNG and JPEG images are read".to_owned())
    }

    /// Decodes a PNG of any colour type and bit depth into RGBA8.
    pub fn decode_png(bytes: &[u8]) -> Result<RgbaImage, ImageError> {
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = decoder.read_info().map_err(|e| ImageError::Decode(e.to_string()))?;
        let header = reader.info();
        check_size(header.width, header.height).map_err(ImageError::Decode)?;
        let size = reader.output_buffer_size().ok_or_else(|| ImageError::Decode("image too large".into()))?;
        let mut buffer = vec![0; size];
        let info = reader.next_frame(&mut buffer).map_err(|e| ImageError::Decode(e.to_string()))?;
        let (width, height) = (info.width, info.height);
        let channels = match info.color_type {
            png::ColorType::Grayscale => 1,
            png::ColorType::GrayscaleAlpha => 2,
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            png::ColorType::Indexed => return Err(ImageError::Decode("palette left unexpanded".into())),
        };
        let mut image = RgbaImage::new(width, height);
        for y in 0..height as usize {
            let row = &buffer[y * info.line_size..][..width as usize * channels];
            for x in 0..width as usize {
                let src = &row[x * channels..][..channels];
                let rgba = match channels {
                    1 => [src[0], src[0], src[0], 255],
                    2 => [src[0], src[0], src[0], src[1]],
                    3 => [src[0], src[1], src[2], 255],
                    _ => [src[0], src[1], src[2], src[3]],
                };
                image.pixels[(y * width as usize + x) * 4..][..4].copy_from_slice(&rgba);
            }
        }
        Ok(image)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_picture_claiming_too_many_pixels_is_refused_before_it_is_read() {
        // A PNG header for 30 000 × 30 000 (3.6 GB as RGBA), and no pixels.
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut ihdr = b"IHDR".to_vec();
        ihdr.extend(30_000u32.to_be_bytes());
        ihdr.extend(30_000u32.to_be_bytes());
        ihdr.extend([8, 6, 0, 0, 0]);
        png.extend(13u32.to_be_bytes());
        png.extend(&ihdr);
        png.extend(crc32fast::hash(&ihdr).to_be_bytes());
        for kind in [b"IDAT", b"IEND"] {
            png.extend(0u32.to_be_bytes());
            png.extend(kind);
            png.extend(crc32fast::hash(kind).to_be_bytes());
        }
        let error = RgbaImage::decode(&png, None).unwrap_err();
        assert!(error.contains("30000 × 30000 pixels is more than Drape reads"), "{error}");
    }

    #[test]
    fn premultiplied_edges_come_back_straight() {
        // Half covered: linear 0.5 × (1, 0.2, 0) over transparent black, stored as sRGB.
        let encode = |v: f32| {
            let s = if v <= 0.003_130_8 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
            (s * 255.0).round() as u8
        };
        let mut image = RgbaImage {
            width: 3,
            height: 1,
            pixels: vec![encode(0.5), encode(0.1), 0, 128, 10, 20, 30, 255, 7, 7, 7, 0],
        };
        image.unpremultiply();
        assert!((i32::from(image.pixels[0]) - 255).abs() <= 2, "{:?}", &image.pixels[..4]);
        assert!((i32::from(image.pixels[1]) - i32::from(encode(0.2))).abs() <= 2, "{:?}", &image.pixels[..4]);
        assert_eq!(&image.pixels[4..8], &[10, 20, 30, 255], "opaque pixels stay");
        assert_eq!(&image.pixels[8..], &[0, 0, 0, 0], "nothing there: transparent black");
    }
}
