//! Reading a rendered texture back into an [`RgbaImage`] on the CPU.

use crate::image::RgbaImage;

#[derive(Debug, thiserror::Error)]
#[error("reading the picture back from the GPU failed: {0}")]
pub struct ReadbackError(String);

/// Copies an RGBA8 texture (single sample, mip 0) to the CPU and waits for it.
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<RgbaImage, ReadbackError> {
    let (width, height) = (texture.width(), texture.height());
    let unpadded_row = width * 4;
    let padded_row = unpadded_row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("drape readback"),
        size: padded_row as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("drape readback") });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        let _ = sender.send(result);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| ReadbackError(e.to_string()))?;
    receiver
        .recv()
        .map_err(|_| ReadbackError("the device dropped the mapping".into()))?
        .map_err(|e| ReadbackError(e.to_string()))?;
    let mut image = RgbaImage::new(width, height);
    {
        let mapped = buffer.get_mapped_range(..).map_err(|e| ReadbackError(e.to_string()))?;
        for y in 0..height as usize {
            let src = &mapped[y * padded_row as usize..][..unpadded_row as usize];
            image.pixels[y * unpadded_row as usize..][..unpadded_row as usize].copy_from_slice(src);
        }
    }
    buffer.unmap();
    Ok(image)
}
