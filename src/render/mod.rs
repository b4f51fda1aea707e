//! Drawing the cloth with wgpu: the same code for the editor's viewport and
//! for headless pictures (CLI, tests). It draws meshes, overlays and a camera
//! into a texture and knows nothing of scenes' keys or their evaluation
//! (that is [`crate::picture`]'s), nor of egui or windows.
//!
//! - [`context`]: a device without a window (Mesa's lavapipe or llvmpipe on GPU-less machines);
//! - [`camera`]: the orbit camera and projection;
//! - [`renderer`]: pipelines and buffers; draws a mesh, ghosts and overlays into a target;
//! - [`target`]: the 4× MSAA offscreen target with depth, resolved to sRGB;
//! - [`overlay`]: line segments and markers drawn over the cloth, pins among them;
//! - [`solids`]: shapes drawn beside the cloth (colliders), opaque or see-through;
//! - [`style`]: lit or toon; [`ink`]: the toon style's ink lines (border, silhouette, creases);
//! - [`headless`]: one call from a mesh to an image; [`readback`]: a texture back to the CPU;
//! - [`compose`]: copies a finished picture into another render pass (the editor's window).

pub mod camera;
pub mod compose;
pub mod context;
pub mod gpu_mesh;
pub mod headless;
pub mod ink;
pub mod overlay;
pub mod pipelines;
pub mod readback;
pub mod renderer;
pub mod solids;
pub mod style;
pub mod target;
pub mod textures;
pub mod uniforms;

pub use camera::OrbitCamera;
pub use context::{ContextError, GpuContext};
pub use overlay::{Overlay, PinState};
pub use renderer::{FrameInput, Ghost, Ground, RenderOptions, Renderer};
pub use solids::{SolidTexture, Solids};
pub use style::{Style, ToonLook};
pub use target::OffscreenTarget;
