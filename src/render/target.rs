//! The offscreen target every picture is drawn into: 4× multisampled colour
//! and depth, resolved into a single-sample sRGB texture that can be read
//! back (headless) or sampled (the editor composites it into its window).

/// sRGB storage: shaders write linear light and the hardware encodes it.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
pub const SAMPLE_COUNT: u32 = 4;

pub struct OffscreenTarget {
    size_px: (u32, u32),
    msaa_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
}

impl OffscreenTarget {
    /// A target of `size_px`; each side is clamped to 1..=the device's largest texture.
    pub fn new(device: &wgpu::Device, size_px: (u32, u32)) -> OffscreenTarget {
        let max_px = device.limits().max_texture_dimension_2d;
        let size_px = (size_px.0.clamp(1, max_px), size_px.1.clamp(1, max_px));
        let extent = wgpu::Extent3d { width: size_px.0, height: size_px.1, depth_or_array_layers: 1 };
        let texture = |label, format, sample_count, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let msaa = texture("drape msaa colour", COLOR_FORMAT, SAMPLE_COUNT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let depth = texture("drape depth", DEPTH_FORMAT, SAMPLE_COUNT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let resolved = texture(
            "drape resolved colour",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        OffscreenTarget {
            size_px,
            msaa_view: msaa.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            resolved_view: resolved.create_view(&Default::default()),
            resolved,
        }
    }

    /// Recreates the textures when the size changed; returns whether it did.
    pub fn resize(&mut self, device: &wgpu::Device, size_px: (u32, u32)) -> bool {
        if size_px == self.size_px {
            return false;
        }
        *self = OffscreenTarget::new(device, size_px);
        true
    }

    pub fn size_px(&self) -> (u32, u32) {
        self.size_px
    }

    pub fn msaa_view(&self) -> &wgpu::TextureView {
        &self.msaa_view
    }

    pub fn depth_view(&self) -> &wgpu::TextureView {
        &self.depth_view
    }

    /// The finished picture (sRGB, single sample).
    pub fn resolved(&self) -> &wgpu::Texture {
        &self.resolved
    }

    pub fn resolved_view(&self) -> &wgpu::TextureView {
        &self.resolved_view
    }
}
