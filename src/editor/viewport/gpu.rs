//! The 3D viewport: Drape's renderer drawn through egui-wgpu's paint callback.
//!
//! GPU resources (renderer, offscreen target, compositor) are built once and
//! live in egui-wgpu's `callback_resources`; each frame's callback carries only
//! that frame's values. `prepare` draws into the viewport's own target with the
//! window's encoder; `paint` only composites the finished picture.

use std::sync::Arc;

use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor};

use crate::mesh::Mesh;
use crate::render::compose::Compositor;
use crate::render::{FrameInput, Ghost, OffscreenTarget, OrbitCamera, Overlay, RenderOptions, Renderer, Solids};

struct ViewportResources {
    renderer: Renderer,
    target: OffscreenTarget,
    compositor: Compositor,
}

/// Builds the viewport's GPU resources on the window's device; call once at start.
pub fn install(render_state: &egui_wgpu::RenderState) {
    let device = &render_state.device;
    let target = OffscreenTarget::new(device, (1, 1));
    let mut compositor = Compositor::new(device, render_state.target_format, 1);
    compositor.set_source(device, &target);
    let resources = ViewportResources { renderer: Renderer::new(device, &render_state.queue), target, compositor };
    render_state.renderer.write().callback_resources.insert(resources);
}

/// One frame of the viewport.
pub struct ViewportFrame {
    pub mesh: Arc<Mesh>,
    pub camera: OrbitCamera,
    pub options: RenderOptions,
    pub overlay: Arc<Overlay>,
    /// Onion-skin ghosts.
    pub ghosts: Arc<Vec<Ghost<Arc<Mesh>>>>,
    /// The scene's colliders and references at the frame shown, a set per colour.
    pub solids: Arc<Vec<Solids>>,
    /// The viewport's size in physical pixels.
    pub size_px: (u32, u32),
}

impl CallbackTrait for ViewportFrame {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let Some(resources) = resources.get_mut::<ViewportResources>() else {
            return Vec::new();
        };
        if resources.target.resize(device, self.size_px) {
            resources.compositor.set_source(device, &resources.target);
        }
        let ghosts: Vec<Ghost<&Mesh>> = self.ghosts.iter().map(Ghost::borrowed).collect();
        let input = FrameInput {
            mesh: &self.mesh,
            camera: &self.camera,
            options: &self.options,
            ghosts: &ghosts,
            overlay: &self.overlay,
            solids: &self.solids,
        };
        resources.renderer.prepare(device, queue, resources.target.size_px(), input);
        resources.renderer.encode(encoder, &resources.target);
        Vec::new()
    }

    fn paint(
        &self,
        _info: eframe::egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(resources) = resources.get::<ViewportResources>() {
            resources.compositor.draw(pass);
        }
    }
}
