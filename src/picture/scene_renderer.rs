//! A scene at a frame to an RGBA image without a window: `drape render`, the
//! golden-image tests.

use crate::animate::Evaluator;
use crate::animate::track::sample;
use crate::image::RgbaImage;
use crate::mesh::Mesh;
use crate::render::headless::RenderError;
use crate::render::overlay::PinState;
use crate::render::readback::read_texture;
use crate::render::{FrameInput, GpuContext, OffscreenTarget, OrbitCamera, RenderOptions, Renderer, Style, ToonLook};
use crate::scene::{Param, PlateFiles, Scene};

use super::colliders::collider_solids;
use super::framing::Framing;
use super::key_overlay::{SceneOverlays, key_overlay};
use super::plate::{over_plate, plate_fitted};
use super::references::reference_solids;
use super::shot::scene_shot_camera_at;

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
    framing: Framing,
    context: GpuContext,
    renderer: Renderer,
    target: OffscreenTarget,
    evaluator: Evaluator,
    options: RenderOptions,
    overlays: SceneOverlays,
    mesh: Mesh,
    plate: Option<PlateBackdrop>,
}

/// The plate a render is laid over, and the picture last read from it.
struct PlateBackdrop {
    files: PlateFiles,
    opacity: Param,
    /// The number of the file last read, fitted to the picture.
    last: Option<(i64, RgbaImage)>,
}

impl SceneRenderer {
    /// Builds every key's rest shape and frames them as [`Framing::of_scene`] does.
    pub fn new(context: GpuContext, scene: &Scene, size_px: (u32, u32), overlays: SceneOverlays) -> SceneRenderer {
        let mut evaluator = Evaluator::new();
        let aspect = size_px.0 as f32 / size_px.1.max(1) as f32;
        let framing = Framing::of_scene(&mut evaluator, scene, aspect);
        let options =
            RenderOptions { wireframe: overlays.wireframe, ground: Some(framing.ground), ..RenderOptions::default() }
                .with_texture(scene.cloth.texture);
        let renderer = Renderer::new(&context.device, &context.queue);
        let target = OffscreenTarget::new(&context.device, size_px);
        let mesh = evaluator.evaluate_frame(scene, scene.timeline.start as f64);
        SceneRenderer { framing, context, renderer, target, evaluator, options, overlays, mesh, plate: None }
    }

    /// Lays every picture from now on over the plate `files` at `opacity`
    /// (`None`: over the ground and background as usual). The cloth, its
    /// overlays, colliders and references are drawn; the ground is not.
    pub fn set_plate(&mut self, plate: Option<(PlateFiles, Param)>) {
        self.plate = plate.map(|(files, opacity)| PlateBackdrop { files, opacity, last: None });
    }

    pub fn context(&self) -> &GpuContext {
        &self.context
    }

    pub fn camera(&self) -> &OrbitCamera {
        &self.framing.camera
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
        self.evaluator.evaluate_frame_into(scene, frame, Default::default(), &mut self.mesh);
        let shot = scene_shot_camera_at(scene, frame, self.target.size_px()).filter(|_| !self.overlays.view_camera);
        match shot {
            Some(shot) => self.framing.camera = shot,
            None => self.framing.follow(&self.mesh),
        }
        let shadow_pass = self.overlays.shadow_pass;
        let plate = self.plate.is_some() && !self.overlays.alpha && !shadow_pass;
        self.options.ground = (shadow_pass || !(self.overlays.alpha || plate)).then_some(self.framing.ground);
        self.options.transparent = self.overlays.alpha || plate || shadow_pass;
        self.options.shadow_only = shadow_pass;
        self.options.style = scene_style(scene, self.overlays);
        let overlay = key_overlay(&mut self.evaluator, scene, frame, &self.mesh, self.overlays, |_| PinState::Normal);
        let mut solids = Vec::new();
        if !self.overlays.hide_colliders && !self.overlays.alpha && !shadow_pass {
            solids.push(collider_solids(scene, frame, 1.0));
        }
        if !self.overlays.hide_references && !self.overlays.alpha && !shadow_pass {
            solids.extend(reference_solids(scene, frame, 1.0));
        }
        let input = FrameInput {
            mesh: &self.mesh,
            camera: &self.framing.camera,
            options: &self.options,
            ghosts: &[],
            overlay: &overlay,
            solids: &solids,
        };
        self.renderer.render(&self.context.device, &self.context.queue, &self.target, input);
        let mut image = read_texture(&self.context.device, &self.context.queue, self.target.resolved())?;
        if self.overlays.alpha || shadow_pass {
            image.unpremultiply();
        } else if let Some(backdrop) = &mut self.plate {
            let shown = backdrop.files.frame(frame.round() as i32);
            if backdrop.last.as_ref().is_none_or(|(number, _)| *number != shown.number) {
                let picture = crate::scene::load_plate_image(&shown.path).map_err(RenderError::Input)?;
                backdrop.last = Some((shown.number, plate_fitted(&picture, image.width, image.height)));
            }
            if let Some((_, fitted)) = &backdrop.last {
                let opacity = sample(&backdrop.opacity, frame) as f32;
                image = over_plate(&image, fitted, opacity, self.options.background);
            }
        }
        Ok(image)
    }
}

/// The style `overlays` asks for: toon in the scene's toon settings, or lit.
fn scene_style(scene: &Scene, overlays: SceneOverlays) -> Style {
    if overlays.toon { Style::Toon(ToonLook::from_settings(&scene.cloth.toon)) } else { Style::Lit }
}
