//! Pictures without a window: a mesh, or a scene at a frame, to an RGBA image.

use glam::Vec3;

use super::camera::{OrbitCamera, bounds};
use super::context::{ContextError, GpuContext};
use super::overlay::{Overlay, PinState};
use super::readback::{ReadbackError, read_texture};
use super::renderer::{FrameInput, Ground, RenderOptions, Renderer};
use super::target::OffscreenTarget;
use crate::animate::{Evaluator, frame_time_secs};
use crate::image::RgbaImage;
use crate::mesh::Mesh;
use crate::scene::Scene;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Context(#[from] ContextError),
    #[error(transparent)]
    Readback(#[from] ReadbackError),
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

/// Which overlays a scene picture shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneOverlays {
    pub wireframe: bool,
    /// Red dots on the pins of the key in effect.
    pub pins: bool,
    /// The catenary network (with conflicts) of the key in effect.
    pub catenaries: bool,
    /// The key's triangulation of its pins, drawn on the surface.
    pub triangulation: bool,
}

/// One picture of `scene` at `frame`, framed as [`SceneRenderer::new`] does,
/// on `context` or on a device of its own when none is given.
pub fn render_scene_frame(
    context: Option<&GpuContext>,
    scene: &Scene,
    frame: f64,
    size_px: (u32, u32),
    overlays: SceneOverlays,
) -> Result<RgbaImage, RenderError> {
    let context = match context {
        Some(context) => context.clone(),
        None => GpuContext::headless()?,
    };
    SceneRenderer::new(context, scene, size_px, overlays).render_frame(scene, frame)
}

/// Renders frames of one scene in turn, reusing the device, the renderer's
/// buffers, the target and the evaluator's rest-shape cache: the way to render
/// a sequence. Memory does not grow with the number of frames.
pub struct SceneRenderer {
    /// Whether the camera and ground move with the cloth (see [`SceneRenderer::new`]).
    follow: bool,
    context: GpuContext,
    renderer: Renderer,
    target: OffscreenTarget,
    evaluator: Evaluator,
    camera: OrbitCamera,
    options: RenderOptions,
    overlays: SceneOverlays,
    mesh: Mesh,
}

impl SceneRenderer {
    /// Builds every key's rest shape and puts the ground under them. The
    /// camera is the scene's saved view if it has one; otherwise it frames all
    /// the keys, so the view holds still through the animation.
    /// When the cloth travels much farther than its own size (a flying carpet),
    /// a fixed view would show it tiny: the camera then keeps the framing of
    /// the largest single key and follows the cloth's centre, the ground grid
    /// showing the travel.
    pub fn new(context: GpuContext, scene: &Scene, size_px: (u32, u32), overlays: SceneOverlays) -> SceneRenderer {
        let mut evaluator = Evaluator::new();
        let (rest_min, rest_max) = scene_bounds(&mut evaluator, scene);
        let (min, max) = padded((rest_min, rest_max));
        let key_extent_m = largest_key_extent(&mut evaluator, scene);
        let follow = scene.view.is_none() && (max - min).max_element() > FOLLOW_TRAVEL_RATIO * key_extent_m;
        let aspect = size_px.0 as f32 / size_px.1.max(1) as f32;
        let (camera, ground) = if let Some(view) = &scene.view {
            let mut ground = Ground::under(min, max);
            ground.height_m = Ground::under(rest_min, rest_max).height_m;
            (OrbitCamera::from_view(view), ground)
        } else if follow {
            let half = Vec3::splat(key_extent_m * 0.5);
            let center = (min + max) * 0.5;
            let mut camera = OrbitCamera::framing(min, max, aspect);
            camera.frame_bounds(center - half, center + half, aspect);
            let mut ground = Ground::under(center - half, center + half);
            ground.height_m = Ground::under(rest_min, rest_max).height_m;
            (camera, ground)
        } else {
            let mut ground = Ground::under(min, max);
            ground.height_m = Ground::under(rest_min, rest_max).height_m;
            (OrbitCamera::framing(min, max, aspect), ground)
        };
        let options = RenderOptions { wireframe: overlays.wireframe, ground: Some(ground), ..RenderOptions::default() }
            .with_texture(scene.cloth.texture);
        let renderer = Renderer::new(&context.device, &context.queue);
        let target = OffscreenTarget::new(&context.device, size_px);
        let mesh = evaluator.evaluate(scene, frame_time_secs(&scene.timeline, scene.timeline.start as f64));
        SceneRenderer { follow, context, renderer, target, evaluator, camera, options, overlays, mesh }
    }

    pub fn context(&self) -> &GpuContext {
        &self.context
    }

    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    pub fn size_px(&self) -> (u32, u32) {
        self.target.size_px()
    }

    /// The mesh of the last rendered frame.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Renders `scene` (the one given to `new`, or an edit of it with the same
    /// framing) at `frame` and reads the picture back.
    pub fn render_frame(&mut self, scene: &Scene, frame: f64) -> Result<RgbaImage, RenderError> {
        let t_secs = frame_time_secs(&scene.timeline, frame);
        self.evaluator.evaluate_into(scene, t_secs, Default::default(), &mut self.mesh);
        if self.follow
            && let Some((lo, hi)) = bounds(&self.mesh.positions)
        {
            let center = (lo + hi) * 0.5;
            self.camera.target = center;
            if let Some(ground) = &mut self.options.ground {
                ground.center = glam::Vec2::new(center.x, center.z);
            }
        }
        let overlay = key_overlay(&mut self.evaluator, scene, frame, &self.mesh, self.overlays);
        let input = FrameInput {
            mesh: &self.mesh,
            camera: &self.camera,
            options: &self.options,
            ghosts: &[],
            overlay: &overlay,
        };
        self.renderer.render(&self.context.device, &self.context.queue, &self.target, input);
        Ok(read_texture(&self.context.device, &self.context.queue, self.target.resolved())?)
    }
}

/// The overlays `show` asks for, for the key in effect at `frame`, drawn on `mesh`
/// (the wireframe is a render option, not an overlay).
pub fn key_overlay(evaluator: &mut Evaluator, scene: &Scene, frame: f64, mesh: &Mesh, show: SceneOverlays) -> Overlay {
    let mut overlay = Overlay::default();
    let key = scene.key_in_effect(frame);
    if show.catenaries || show.triangulation {
        let shape = evaluator.key_shape(&scene.cloth, key);
        if show.triangulation {
            overlay.add_triangulation(mesh, &shape.rest.network);
        }
        if show.catenaries {
            overlay.add_catenary_network(&shape.rest.network);
        }
    }
    if show.pins {
        let pins = key.pins.iter().map(|p| ((p.grid.0 as usize, p.grid.1 as usize), PinState::Normal));
        overlay.add_pins(mesh, pins);
    }
    overlay
}

/// The camera follows the cloth when its keys span more than this many times the largest key's own size.
pub const FOLLOW_TRAVEL_RATIO: f32 = 2.5;

/// The largest side of any single key's rest shape box.
fn largest_key_extent(evaluator: &mut Evaluator, scene: &Scene) -> f32 {
    let mut extent_m: f32 = 0.0;
    for key in &scene.keys {
        if let Some((lo, hi)) = bounds(&evaluator.key_shape(&scene.cloth, key).positions) {
            extent_m = extent_m.max((hi - lo).max_element());
        }
    }
    extent_m.max(0.1)
}

/// The box holding every key's relaxed rest shape.
pub fn scene_bounds(evaluator: &mut Evaluator, scene: &Scene) -> (Vec3, Vec3) {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for key in &scene.keys {
        let shape = evaluator.key_shape(&scene.cloth, key);
        if let Some((lo, hi)) = bounds(&shape.positions) {
            min = min.min(lo);
            max = max.max(hi);
        }
    }
    if !(min.is_finite() && max.is_finite()) {
        return (Vec3::ZERO, Vec3::ONE);
    }
    (min, max)
}

/// `min..max` widened by 10% of its largest side all round: room for the layers' motion.
fn padded((min, max): (Vec3, Vec3)) -> (Vec3, Vec3) {
    let margin = Vec3::splat((max - min).max_element() * 0.1);
    (min - margin, max + margin)
}
