//! Pictures without a window: one call from a mesh, a camera and overlays to an RGBA image.

use super::context::{ContextError, GpuContext};
use super::readback::{ReadbackError, read_texture};
use super::renderer::{FrameInput, Renderer};
use super::target::OffscreenTarget;
use crate::image::RgbaImage;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Context(#[from] ContextError),
    #[error(transparent)]
    Readback(#[from] ReadbackError),
    /// A file the picture is drawn over (a plate) could not be read: what and where.
    #[error("{0}")]
    Input(String),
}

/// Renders one picture of `input` at `size_px` on `context`, or on a device of
/// its own when none is given.
pub fn render_mesh(
    context: Option<&GpuContext>,
    input: FrameInput,
    size_px: (u32, u32),
) -> Result<RgbaImage, RenderError> {
    let owned;
    let context = match context {
        Some(context) => context,
        None => {
            owned = GpuContext::headless()?;
            &owned
        }
    };
    let mut renderer = Renderer::new(&context.device, &context.queue);
    let target = OffscreenTarget::new(&context.device, size_px);
    renderer.render(&context.device, &context.queue, &target, input);
    Ok(read_texture(&context.device, &context.queue, target.resolved())?)
}
