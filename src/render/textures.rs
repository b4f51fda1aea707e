//! The cloth textures Drape ships ([`look::texture_png`]), uploaded once with
//! a full mip chain so they stay calm when the cloth is small on screen.

use crate::image::RgbaImage;
use crate::look;
use crate::scene::ClothTexture;

/// The built-in picture for a texture choice; `Plain` is one white texel.
pub fn builtin_image(texture: ClothTexture) -> RgbaImage {
    let Some(bytes) = look::texture_png(texture) else {
        return RgbaImage { width: 1, height: 1, pixels: vec![255; 4] };
    };
    RgbaImage::decode_png(bytes).expect("the textures in assets/ are valid PNGs, checked by a test")
}

/// Halves an image with a 2×2 box filter in linear light (odd sides round down, never below 1).
pub fn half_size(image: &RgbaImage) -> RgbaImage {
    let (w, h) = ((image.width / 2).max(1), (image.height / 2).max(1));
    let mut out = RgbaImage::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0.0f32; 4];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let p = image.pixel((2 * x + dx).min(image.width - 1), (2 * y + dy).min(image.height - 1));
                for (sum, &channel) in sum.iter_mut().zip(&p[..3]) {
                    *sum += srgb_to_linear(channel);
                }
                sum[3] += p[3] as f32 / 255.0;
            }
            let at = ((y * w + x) * 4) as usize;
            for (pixel, sum) in out.pixels[at..at + 3].iter_mut().zip(&sum[..3]) {
                *pixel = linear_to_srgb(sum / 4.0);
            }
            out.pixels[at + 3] = (sum[3] / 4.0 * 255.0).round() as u8;
        }
    }
    out
}

fn srgb_to_linear(v: u8) -> f32 {
    let v = v as f32 / 255.0;
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

fn linear_to_srgb(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0).round() as u8
}

/// Uploads `image` as an sRGB texture with every mip level.
pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, image: &RgbaImage, label: &str) -> wgpu::Texture {
    let mip_level_count = 32 - image.width.max(image.height).leading_zeros();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: image.width, height: image.height, depth_or_array_layers: 1 },
        mip_level_count,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let mut level_image = image.clone();
    for mip_level in 0..mip_level_count {
        if mip_level > 0 {
            level_image = half_size(&level_image);
        }
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &level_image.pixels,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(level_image.width * 4), rows_per_image: None },
            wgpu::Extent3d { width: level_image.width, height: level_image.height, depth_or_array_layers: 1 },
        );
    }
    texture
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_textures_decode() {
        for texture in [ClothTexture::Plain, ClothTexture::Carpet, ClothTexture::Checker] {
            let image = builtin_image(texture);
            assert_eq!(image.pixels.len(), (image.width * image.height * 4) as usize);
        }
        assert_eq!(builtin_image(ClothTexture::Carpet).width, 512);
    }

    #[test]
    fn halving_averages_in_linear_light() {
        let image = RgbaImage { width: 2, height: 1, pixels: vec![0, 0, 0, 255, 255, 255, 255, 255] };
        let half = half_size(&image);
        assert_eq!((half.width, half.height), (1, 1));
        // Half black, half white is 50% linear, which is 188 in sRGB (not 128).
        assert_eq!(half.pixel(0, 0), [188, 188, 188, 255]);
    }

    #[test]
    fn srgb_round_trips() {
        for v in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(v)), v);
        }
        assert_eq!(linear_to_srgb(f32::NAN), 0);
    }
}
