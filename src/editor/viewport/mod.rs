//! The 3D viewport in the centre and the view bar that chooses what it
//! shows: the stage of the method, the cloth's overlays, the ground, onion
//! skin and a camera that follows the cloth. Mouse and keys are in
//! [`input`]; the GPU side is in [`gpu`].

mod attach_input;
mod collider_drag;
mod collider_input;
pub mod gizmo;
pub mod gpu;
mod input;
pub mod picking;
pub mod pin_drag;
mod plate_view;
pub mod reference_pick;
mod shot;
pub mod shot_view;
pub mod stale_cloth;
mod style;

use std::sync::Arc;

use eframe::egui::{self, Sense};
use eframe::egui_wgpu;

use self::collider_drag::ColliderDrag;
use self::gizmo::Gizmo;
use self::gpu::ViewportFrame;
use self::pin_drag::{AxisLock, PinDrag};
use self::plate_view::PlateView;
use self::stale_cloth::{StaleCloth, stale_look};
use super::number_field::number_field;
use super::shown::OnionSkin;
use super::workspace::Workspace;
use crate::animate;
use crate::animate::colliders_at::shape_at;
use crate::picture::framed::{cloth_and_touched, view_holds};
use crate::picture::{SceneOverlays, collider_solids, reference_solids};
use crate::render::camera::bounds;
use crate::render::overlay::{Marker, PIN_RADIUS_PX, PinState, Segment, colors};
use crate::render::{Ground, OrbitCamera, Overlay, RenderOptions, Solids};
use crate::scene::{ClothTexture, Layer};

/// The selected collider's outline: the selected pins' yellow.
const COLLIDER_SELECTED: [f32; 4] = colors::PIN_SELECTED;
/// Colliders drawn as wire: the props' warm grey, lighter.
const COLLIDER_WIRE: [f32; 4] = [0.78, 0.72, 0.64, 0.8];
/// References drawn as lines: a cool blue-grey, apart from the colliders' warm wire.
const REFERENCE_WIRE: [f32; 4] = [0.55, 0.66, 0.82, 0.6];
/// The outline of the collider under the mouse.
const COLLIDER_HOVERED: [f32; 4] = [1.0, 1.0, 1.0, 0.55];
/// How far from the view's centre to its edges F puts what it frames at
/// most, and the room it leaves round it at least, points: a gizmo's arrow
/// on a pin at the edge stays in view.
const FRAMED_FILL: f32 = 0.85;
const FRAMED_ROOM_PT: f32 = gizmo::ARROW_LENGTH_PT + 12.0;

/// What the viewport shows besides the cloth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ViewToggles {
    pub wireframe: bool,
    pub texture: bool,
    pub pins: bool,
    pub catenaries: bool,
    pub triangulation: bool,
    pub ground: bool,
    /// Onion skin: ghosts of the `onion_frames` frames before and after, `onion_spacing` frames apart.
    pub onion: bool,
    pub onion_frames: u32,
    pub onion_spacing: u32,
    pub colliders: SolidLook,
    /// How referenced glTF files (characters, props) are drawn.
    pub references: SolidLook,
    /// Shows the scene's background plate behind the cloth while looking through the shot camera.
    pub plate: bool,
    /// Draws in the toon style instead of lit (View ▸ Style).
    pub toon: bool,
}

/// How the viewport draws the scene's colliders, or its references.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SolidLook {
    #[default]
    Shaded,
    /// Half transparent, so the cloth behind and under them shows.
    SeeThrough,
    /// Lines only: a mesh's triangles' edges, a primitive's outline.
    Wire,
    Hidden,
}

impl SolidLook {
    pub const ALL: [SolidLook; 4] = [SolidLook::Shaded, SolidLook::SeeThrough, SolidLook::Wire, SolidLook::Hidden];

    pub fn label(self) -> &'static str {
        match self {
            SolidLook::Shaded => "Shaded",
            SolidLook::SeeThrough => "See-through",
            SolidLook::Wire => "Wire",
            SolidLook::Hidden => "Hidden",
        }
    }
}

impl Default for ViewToggles {
    fn default() -> Self {
        ViewToggles {
            wireframe: false,
            texture: true,
            pins: true,
            catenaries: false,
            triangulation: false,
            ground: true,
            onion: false,
            onion_frames: 2,
            onion_spacing: 4,
            colliders: SolidLook::Shaded,
            references: SolidLook::Shaded,
            plate: true,
            toon: false,
        }
    }
}

/// Which stage of the method the viewport shows (the paper's Fig. 3 b–f).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stage {
    /// The animation at the playhead: blended rest shapes and the layer stack.
    #[default]
    Animation,
    /// The relaxed rest shape of the key being edited.
    Relaxed,
    /// The surface approximated from the catenary network, before relaxation.
    Approximated,
    /// The catenary network, its conflicts and the triangulation, over the approximated surface.
    Catenaries,
}

impl Stage {
    pub const ALL: [Stage; 4] = [Stage::Animation, Stage::Relaxed, Stage::Approximated, Stage::Catenaries];

    pub fn label(self) -> &'static str {
        match self {
            Stage::Animation => "Animation",
            Stage::Relaxed => "Relaxed rest shape",
            Stage::Approximated => "Approximated surface",
            Stage::Catenaries => "Catenary network",
        }
    }

    /// The cloth's shape under this stage's drawing.
    pub fn mesh_stage(self) -> animate::Stage {
        match self {
            Stage::Animation => animate::Stage::Animated,
            Stage::Relaxed => animate::Stage::Relaxed,
            Stage::Approximated | Stage::Catenaries => animate::Stage::Approx,
        }
    }
}

/// The viewport's own state: its camera and ground, what it shows, a pin drag in progress.
pub struct ViewportPanel {
    camera: OrbitCamera,
    ground: Ground,
    toggles: ViewToggles,
    /// The plate's pictures, loaded off the UI thread.
    plate_view: PlateView,
    /// Said in the camera's frame where the plate's picture should be (loading, or why not).
    plate_note: Option<(String, egui::Color32)>,
    stage: Stage,
    pin_drag: Option<PinDrag>,
    /// The document the viewport's drags belong to ([`Workspace::document_number`]).
    document: u64,
    collider_drag: Option<ColliderDrag>,
    /// The collider under the mouse (no cloth point being nearer), outlined.
    hovered_collider: Option<usize>,
    /// The shown document version the ground was last checked against.
    ground_version: u64,
    /// The viewport's size in pixels, last frame.
    size_px: (u32, u32),
    /// Where a box selection started (points), while the button is held.
    box_select: Option<egui::Pos2>,
    /// The playhead and the cloth's centre when the camera last followed it.
    follow_anchor: Option<(f64, glam::Vec3)>,
    /// Where the viewport was drawn last frame (points).
    rect: egui::Rect,
    /// Where it was drawn the frame before.
    rect_before: egui::Rect,
    /// The window is being resized: a saved view is judged at its new size.
    saved_view_held: bool,
    /// Whether the GPU viewport is available (false only in tests without wgpu).
    has_gpu: bool,
    /// The orbiting camera while the shot camera is looked through.
    orbit_before_shot: Option<OrbitCamera>,
    /// Whether the cloth drawn is an old shape while the new one is solved.
    stale: StaleCloth,
    /// Frame the cloth once the viewport's shape is known (a scene without a
    /// saved view), or once the shot camera is no longer looked through.
    frame_all_pending: bool,
    /// Frame the cloth once shown if the saved view does not see it at the opened frame.
    reveal_pending: bool,
    /// The colliders last tessellated and what they were made from, so a
    /// repaint without a change (orbiting, hovering) does not build them again.
    solids_cache: Option<(SolidsKey, DrawnSolids)>,
}

/// The solids (a set per colour) and wire lines a viewport draws for the
/// colliders and references.
type DrawnSolids = (Arc<Vec<Solids>>, Arc<Vec<Segment>>);

/// What a viewport's solids and wire depend on: the colliders and
/// references (files by their loaded data, which equality of the scene's
/// parts ignores), the frame, the clock and the looks.
#[derive(Clone, PartialEq)]
struct SolidsKey {
    colliders: Vec<crate::scene::Collider>,
    /// Each mesh collider's loaded data by address.
    meshes: Vec<Option<usize>>,
    references: Vec<crate::scene::Reference>,
    /// Each reference's rig by address.
    rigs: Vec<Option<usize>>,
    frame_bits: u64,
    fps_bits: u64,
    look: SolidLook,
    reference_look: SolidLook,
}

/// This frame's viewport: where it is and what the pointer did there.
pub struct ViewportArea {
    rect: egui::Rect,
    response: egui::Response,
    size_px: (u32, u32),
    pub aspect: f32,
}

impl ViewportPanel {
    /// A viewport on `w`'s scene: its saved view, else a camera framing its
    /// keys (framed again once shown) that follows a travelling cloth.
    pub fn new(w: &mut Workspace, has_gpu: bool) -> ViewportPanel {
        let scene = w.doc.scene();
        let saved = scene.view.as_ref().map(OrbitCamera::from_view);
        let framed = saved.is_none();
        if framed {
            let travels = w.shown.travels();
            w.session.set_follow(travels);
        }
        let (min, max) = w.shown.bounds();
        ViewportPanel {
            camera: saved.unwrap_or_else(|| OrbitCamera::framing(min, max, 16.0 / 9.0)),
            ground: Ground::under(min, max),
            toggles: ViewToggles::default(),
            plate_view: PlateView::default(),
            plate_note: None,
            stage: Stage::default(),
            pin_drag: None,
            document: w.document_number(),
            collider_drag: None,
            hovered_collider: None,
            box_select: None,
            size_px: (1, 1),
            ground_version: 0,
            follow_anchor: None,
            rect: egui::Rect::NOTHING,
            rect_before: egui::Rect::NOTHING,
            saved_view_held: false,
            has_gpu,
            orbit_before_shot: None,
            stale: StaleCloth::default(),
            frame_all_pending: framed,
            reveal_pending: !framed,
            solids_cache: None,
        }
    }

    /// Holds off judging a saved view (whether it crops the cloth) while the window changes size.
    pub fn hold_saved_view(&mut self, held: bool) {
        self.saved_view_held = held;
    }

    /// Where the viewport was drawn last frame, in points.
    pub fn rect(&self) -> egui::Rect {
        self.rect
    }

    /// The orbiting camera (the shot camera's view while looking through it).
    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    /// The camera for file handling: Open puts a scene's saved view on it.
    pub fn camera_mut(&mut self) -> &mut OrbitCamera {
        &mut self.camera
    }

    /// Whether the cloth is drawn in the toon style (the Render window starts with it).
    pub fn toon(&self) -> bool {
        self.toggles.toon
    }

    /// Whether the last frame drew the cloth as stale: grey, the old shape
    /// on screen while the document's new one is solved.
    pub fn cloth_drawn_stale(&self) -> bool {
        self.stale.drawn_stale()
    }

    /// The translate gizmo on the selected pins, as drawn last frame.
    pub fn drawn_gizmo(&self, w: &Workspace) -> Option<Gizmo> {
        self.gizmo(w, self.size_px)
    }

    /// View ▸ Frame all: leaves the shot camera and frames the cloth once
    /// the viewport's shape is known.
    pub fn frame_all_from_menu(&mut self, w: &mut Workspace) {
        w.session.look_through_camera(false);
        self.frame_all_pending = true;
    }

    /// The View menu's stages of the method, one shown.
    pub fn stage_menu_ui(&mut self, ui: &mut egui::Ui) {
        for stage in Stage::ALL {
            ui.radio_value(&mut self.stage, stage, stage.label());
        }
    }

    /// Where a world point appears on screen (points), `None` behind the camera.
    pub fn screen_pos(&self, world: glam::Vec3) -> Option<egui::Pos2> {
        let rect = self.rect;
        // Projected at one pixel per point: the camera only needs the aspect ratio.
        let size = (rect.width().round().max(1.0) as u32, rect.height().round().max(1.0) as u32);
        let at = self.camera.project(world, size)?;
        Some(rect.min + egui::vec2(at.x * rect.width() / size.0 as f32, at.y * rect.height() / size.1 as f32))
    }

    /// Rebuilds the shown mesh and ghosts for the playhead, the stage and the soloed layer.
    pub fn refresh(&self, w: &mut Workspace) {
        let session = &w.session;
        w.shown.refresh_mesh(session.frame(), self.stage.mesh_stage(), session.solo_layer());
        let onion = (self.toggles.onion && self.stage == Stage::Animation)
            .then_some(OnionSkin { frames: self.toggles.onion_frames, spacing: self.toggles.onion_spacing });
        w.shown.refresh_ghosts(session.frame(), onion, session.solo_layer());
    }

    /// The pin drag in progress in `w`'s document, if any.
    pub fn pin_drag(&self, w: &Workspace) -> Option<&PinDrag> {
        self.pin_drag.as_ref().filter(|_| self.document == w.document_number())
    }

    /// Undo or Redo during a pin drag: the drag ends where it is.
    pub fn abandon_pin_drag(&mut self) {
        self.pin_drag = None;
    }

    /// A drag begun in a document that was since replaced ends.
    fn follow_document(&mut self, w: &Workspace) {
        if self.document != w.document_number() {
            self.document = w.document_number();
            self.pin_drag = None;
        }
    }

    /// Takes the viewport's area and this frame's mouse input (camera, hover, pins).
    pub fn input_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) -> ViewportArea {
        self.follow_document(w);
        let rect = ui.available_rect_before_wrap();
        let response = ui.allocate_rect(rect, Sense::click_and_drag());
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Viewport"));
        self.rect_before = std::mem::replace(&mut self.rect, rect);
        let aspect = rect.width() / rect.height().max(1.0);
        let pixels_per_point = ui.ctx().pixels_per_point();
        let size_px = (
            (rect.width() * pixels_per_point).round().max(1.0) as u32,
            (rect.height() * pixels_per_point).round().max(1.0) as u32,
        );
        self.size_px = size_px;
        self.look_through_shot(w, rect);
        self.pointer_input(ui, w, &response, size_px);
        ViewportArea { rect, response, size_px, aspect }
    }

    /// Brings the shown shapes up to date and draws them into `area`.
    pub fn draw_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace, area: ViewportArea) {
        self.follow_document(w);
        w.shown.sync(&w.doc);
        if let Some((min, max)) = w.shown.take_opened_bounds() {
            self.ground = Ground::under(min, max);
            // Follow starts from where the new scene's cloth is, not the last one's.
            self.follow_anchor = None;
            match w.doc.scene().view {
                Some(_) => self.reveal_pending = true,
                None => {
                    self.frame_all_pending = true;
                    let travels = w.shown.travels();
                    w.session.set_follow(travels);
                }
            }
        }
        if w.shown.version() != self.ground_version {
            // Keys moved beyond the ground (a carpet flown further): lay a new one under them all.
            self.ground_version = w.shown.version();
            let (min, max) = w.shown.bounds();
            if !self.ground.covers(min, max) {
                self.ground = Ground::under(min, max);
            }
        }
        self.refresh(w);
        let behind = w.doc.scene() != w.shown.scene();
        let stale = self.stale.update(behind, !w.shown.is_shaped(), ui.ctx());
        // Looking through the shot camera, its picture is the framing: the
        // orbiting view is framed once the Camera toggle is turned off.
        if !w.session.through_camera() {
            // A saved view is judged once the viewport holds still at the
            // window's size: a new window's first frames are laid out at
            // another size, and a view saved wider was then taken to crop the
            // cloth and reframed.
            let laid_out = !self.saved_view_held && self.rect_before == self.rect;
            if self.reveal_pending && !laid_out {
                ui.ctx().request_repaint();
            }
            let reveal = laid_out && std::mem::take(&mut self.reveal_pending);
            if std::mem::take(&mut self.frame_all_pending) || (reveal && !self.holds_what_is_framed(w, area.aspect)) {
                self.frame_cloth(w, area.aspect);
            }
        }
        if !w.session.through_camera() {
            self.follow_cloth(w);
        }
        if let Some((i, j)) = w.session.hovered()
            && let Some(pointer) = area.response.hover_pos()
        {
            let pinned = w.doc.scene().keys[w.edit_key_index()].pins.iter().any(|p| p.grid == (i, j));
            let text = format!("({i}, {j}){}", if pinned { " pin" } else { "" });
            let at = pointer + egui::vec2(14.0, -18.0);
            let font = egui::FontId::proportional(13.0);
            let galley = ui.painter().layout_no_wrap(text, font, egui::Color32::WHITE);
            let bg = egui::Rect::from_min_size(at, galley.size()).expand(3.0);
            let overlay_painter = ui
                .painter()
                .clone()
                .with_layer_id(egui::LayerId::new(egui::Order::Foreground, egui::Id::unique("viewport-hover")));
            overlay_painter.rect_filled(bg, 3.0, egui::Color32::from_black_alpha(170));
            overlay_painter.galley(at, galley, egui::Color32::WHITE);
        }
        if !self.has_gpu {
            self.gizmo_ui(ui, w, &area);
            return;
        }
        let (solids, wire) = self.solids_drawn(w);
        let mut overlay = self.overlay(w);
        overlay.segments.extend(wire.iter().cloned());
        let mut options = self.render_options(w);
        if stale {
            options = stale_look(options);
        }
        if self.plate_backdrop_ui(ui, w, area.rect) {
            // The plate is painted behind: the cloth comes over it with alpha.
            options.ground = None;
            options.transparent = true;
        }
        let frame = ViewportFrame {
            mesh: w.shown.mesh().clone(),
            camera: self.camera,
            options,
            overlay: Arc::new(overlay),
            ghosts: w.shown.ghosts().clone(),
            solids,
            size_px: area.size_px,
        };
        ui.painter().add(egui_wgpu::Callback::new_paint_callback(area.rect, frame));
        if w.session.through_camera()
            && let Some(camera) = &w.doc.scene().camera
        {
            self::shot_view::paint_frame(ui.painter(), camera, area.rect);
        }
        self.gizmo_ui(ui, w, &area);
        self.plate_note_ui(ui, w, area.rect);
    }

    /// The translate gizmo, painted on the viewport's own layer after the 3D
    /// view: over the cloth, but under every window and modal dialog (on a
    /// foreground layer of its own it showed through the Save dialog).
    fn gizmo_ui(&self, ui: &egui::Ui, w: &Workspace, area: &ViewportArea) {
        let Some(gizmo) = self.gizmo(w, area.size_px) else {
            return;
        };
        let dragged = self.pin_drag.as_ref().filter(|d| d.by_gizmo).and_then(|d| d.lock);
        let dragged = dragged.or(self.collider_drag.as_ref().filter(|d| d.by_gizmo).and_then(|d| d.lock));
        let hovered = area.response.hover_pos().and_then(|p| gizmo.axis_at(p));
        gizmo.paint(ui.painter(), dragged.or(hovered));
    }

    /// The translate gizmo at the selected pins' centre: where the pins are
    /// drawn (the evaluated cloth), or during a drag where the key now holds
    /// them. With no pin selected, at the selected collider's middle. `None`
    /// with nothing selected, pins (or colliders) hidden or another grid shown.
    pub fn gizmo(&self, w: &Workspace, size_px: (u32, u32)) -> Option<Gizmo> {
        if w.session.selection().is_empty() {
            let index = self.selected_collider_shown(w)?;
            let middle = picking::collider_middle(&w.doc.scene().colliders[index], w.frame())?;
            return Gizmo::at(middle, &self.camera, self.rect, size_px);
        }
        if !self.toggles.pins || !w.shown_grid_is_current() {
            return None;
        }
        let key = &w.doc.scene().keys[w.edit_key_index()];
        let cols = w.shown.scene().cloth.cols();
        let selected = key.pins.iter().filter(|p| w.session.selection().contains(&p.grid));
        let points: Vec<glam::Vec3> = match &self.pin_drag {
            Some(_) => selected.map(|p| glam::DVec3::new(p.pos.0, p.pos.1, p.pos.2).as_vec3()).collect(),
            None => selected
                .filter_map(|p| w.shown.mesh().positions.get(p.grid.1 as usize * cols + p.grid.0 as usize).copied())
                .collect(),
        };
        if points.is_empty() {
            return None;
        }
        let centre = points.iter().copied().sum::<glam::Vec3>() / points.len() as f32;
        Gizmo::at(centre, &self.camera, self.rect, size_px)
    }

    /// The selected collider, if it is drawn (enabled, colliders not hidden).
    pub fn selected_collider_shown(&self, w: &Workspace) -> Option<usize> {
        let index = w.session.selected_collider()?;
        let collider = w.doc.scene().colliders.get(index)?;
        (collider.enabled() && self.toggles.colliders != SolidLook::Hidden).then_some(index)
    }

    /// Leaves the shot camera and frames the cloth on screen (F).
    pub fn frame_all(&mut self, w: &mut Workspace, aspect: f32) {
        w.session.look_through_camera(false);
        if let Some(orbit) = self.orbit_before_shot.take() {
            self.camera = orbit;
        }
        self.frame_cloth(w, aspect);
    }

    /// Frames the cloth on screen with the references and colliders it
    /// touches at the playhead, keeping the camera's angles, with room round
    /// it for the pins' handles and the gizmo's arrows.
    fn frame_cloth(&mut self, w: &Workspace, aspect: f32) {
        if let Some((min, max)) = cloth_and_touched(w.shown.scene(), w.frame(), &w.shown.mesh().positions) {
            let half_pt = 0.5 * self.rect.width().min(self.rect.height());
            let fill = if half_pt.is_finite() && half_pt > 2.0 * FRAMED_ROOM_PT {
                (1.0 - FRAMED_ROOM_PT / half_pt).min(FRAMED_FILL)
            } else {
                FRAMED_FILL
            };
            self.camera.frame_bounds_filling(min, max, aspect, fill);
        }
    }

    /// Whether any point of the shown cloth is in view.
    fn sees_cloth(&self, w: &Workspace, aspect: f32) -> bool {
        self.camera.sees_any_of(w.shown.mesh().positions.iter().copied(), aspect)
    }

    /// Whether a saved view holds the cloth and what it touches at the
    /// playhead whole, as a render of that view must. A view that follows
    /// the cloth frames part of its way on purpose: seeing the cloth is
    /// enough there.
    fn holds_what_is_framed(&self, w: &Workspace, aspect: f32) -> bool {
        if w.session.follow() {
            return self.sees_cloth(w, aspect);
        }
        view_holds(&self.camera, w.shown.scene(), w.frame(), &w.shown.mesh().positions, aspect)
    }

    /// With Follow on, moves the camera's target by as much as the cloth's
    /// centre moved since the playhead was last elsewhere, so orbit and pan
    /// offsets are kept. An edit at the same frame (a pin dragged) moves the
    /// centre without moving the camera, so the pin stays under the mouse.
    fn follow_cloth(&mut self, w: &Workspace) {
        let centre = bounds(&w.shown.mesh().positions).map(|(min, max)| (min + max) * 0.5);
        let frame = w.frame();
        match (w.session.follow(), centre, self.follow_anchor) {
            (true, Some(centre), Some((anchor_frame, anchor))) => {
                if anchor_frame != frame {
                    self.camera.target += centre - anchor;
                }
                self.follow_anchor = Some((frame, centre));
            }
            (true, Some(centre), None) => self.follow_anchor = Some((frame, centre)),
            _ => self.follow_anchor = None,
        }
    }

    fn overlay(&self, w: &mut Workspace) -> Overlay {
        let network = self.stage == Stage::Catenaries;
        let show = SceneOverlays {
            wireframe: false,
            // Dragged pins are drawn below, where the mouse put them.
            pins: self.toggles.pins && self.pin_drag.is_none(),
            catenaries: self.toggles.catenaries || network,
            triangulation: self.toggles.triangulation || network,
            hide_colliders: true,
            hide_references: true,
            view_camera: true,
            ..SceneOverlays::default()
        };
        let session = &w.session;
        let state = |grid: (u32, u32)| {
            if session.selection().contains(&grid) {
                PinState::Selected
            } else if session.hovered() == Some(grid) || session.grid_hovered() == Some(grid) {
                PinState::Hovered
            } else {
                PinState::Normal
            }
        };
        let mut overlay = w.shown.key_overlay(session.frame(), show, state);
        let scene = w.shown.scene();
        let key = scene.key_in_effect(session.frame());
        if self.toggles.pins {
            if let Some(drag) = &self.pin_drag
                && let Some(axis) = drag.lock
            {
                // The locked axis as a line through the dragged pin, in the usual X/Y/Z colours.
                let color = match axis {
                    AxisLock::X => [0.9, 0.25, 0.2, 0.9],
                    AxisLock::Y => [0.35, 0.85, 0.25, 0.9],
                    AxisLock::Z => [0.25, 0.45, 0.95, 0.9],
                };
                let reach = axis.vector() * self.camera.distance_m * 2.0;
                overlay.segments.push(Segment { a: drag.anchor - reach, b: drag.anchor + reach, width_px: 1.5, color });
            }
            if self.pin_drag.is_some() {
                // Dragged pins are drawn where the mouse put them, before the cloth catches up.
                let doc_key = &w.doc.scene().keys[w.edit_key_index()];
                for pin in &doc_key.pins {
                    let center = glam::Vec3::new(pin.pos.0 as f32, pin.pos.1 as f32, pin.pos.2 as f32);
                    let fill = if session.selection().contains(&pin.grid) { colors::PIN_SELECTED } else { colors::PIN };
                    overlay.markers.push(Marker { center, radius_px: PIN_RADIUS_PX, fill, ring: colors::PIN_RING });
                }
            }
        }
        self.add_layer_arrow(w, &mut overlay);
        self.add_collider_outlines(w, &mut overlay);
        let highlight = session.hovered().or(session.grid_hovered());
        if let Some((i, j)) = highlight
            && !key.pins.iter().any(|p| p.grid == (i, j))
            && let Some(&center) = w.shown.mesh().positions.get(j as usize * scene.cloth.cols() + i as usize)
            && w.shown_grid_is_current()
        {
            overlay.markers.push(Marker {
                center,
                radius_px: 4.0,
                fill: [1.0, 1.0, 1.0, 0.9],
                ring: colors::PIN_HOVERED,
            });
        }
        overlay
    }

    /// The selected collider outlined in the selection colour, the one under
    /// the mouse in white.
    fn add_collider_outlines(&self, w: &Workspace, overlay: &mut Overlay) {
        let scene = w.doc.scene();
        let hovered = self.hovered_collider.filter(|i| Some(*i) != w.session.selected_collider());
        let outlined = [(self.selected_collider_shown(w), COLLIDER_SELECTED, 2.0), (hovered, COLLIDER_HOVERED, 1.5)];
        for (index, color, width_px) in outlined {
            let Some(shape) = index.and_then(|i| scene.colliders.get(i)).and_then(|c| shape_at(c, w.frame())) else {
                continue;
            };
            for [a, b] in shape.outline() {
                overlay.segments.push(Segment { a: a.as_vec3(), b: b.as_vec3(), width_px, color });
            }
        }
    }

    /// The selected layer's direction as an arrow over the cloth: a sway's or
    /// the gusts' world direction from the cloth's centre, a wave's direction
    /// of travel along the surface at the centre.
    fn add_layer_arrow(&self, w: &Workspace, overlay: &mut Overlay) {
        let Some(layer) = w.session.selected_layer().and_then(|i| w.shown.scene().layers.get(i)) else { return };
        let mesh = w.shown.mesh();
        let (cols, rows) = (mesh.cols, mesh.rows);
        if cols < 3 || rows < 3 || mesh.positions.len() != cols * rows {
            return;
        }
        let at = |i: usize, j: usize| mesh.positions[j * cols + i];
        let (ci, cj) = (cols / 2, rows / 2);
        let centre = at(ci, cj);
        let direction = match layer {
            Layer::Sway(l) => glam::DVec3::new(l.direction.0, l.direction.1, l.direction.2).as_vec3(),
            Layer::Gusts(l) => glam::DVec3::new(l.direction.0, l.direction.1, l.direction.2).as_vec3(),
            Layer::Wave(l) => {
                let angle = crate::animate::track::sample(&l.direction_deg, w.session.frame()).to_radians() as f32;
                let along_u = (at(ci + 1, cj) - at(ci - 1, cj)).normalize_or_zero();
                let along_v = (at(ci, cj + 1) - at(ci, cj - 1)).normalize_or_zero();
                along_u * angle.cos() + along_v * angle.sin()
            }
            Layer::FollowThrough(_) => return,
        };
        let Some(direction) = direction.try_normalize() else { return };
        let size = bounds(&mesh.positions).map_or(1.0, |(lo, hi)| (hi - lo).max_element());
        let tip = centre + direction * size * 0.45;
        let side = direction.cross(self.camera.backward()).normalize_or_zero() * size * 0.05;
        let back = tip - direction * size * 0.08;
        let color = [0.2, 0.85, 1.0, 1.0];
        for (a, b) in [(centre, tip), (tip, back + side), (tip, back - side)] {
            overlay.segments.push(Segment { a, b, width_px: 3.0, color });
        }
    }

    /// The colliders and references at the playhead as the View asks
    /// (solids for Shaded and See-through, lines for Wire): the document's,
    /// so a collider being dragged or typed is drawn where it is now, before
    /// the cloth has been shaped round it.
    fn solids_drawn(&mut self, w: &Workspace) -> DrawnSolids {
        let look = self.toggles.colliders;
        let opacity = match look {
            SolidLook::Shaded => 1.0,
            SolidLook::SeeThrough => 0.35,
            SolidLook::Wire | SolidLook::Hidden => 0.0,
        };
        let colliders = &w.doc.scene().colliders;
        let meshes = colliders
            .iter()
            .map(|c| match c {
                crate::scene::Collider::Mesh(m) => m.solid.0.as_ref().map(|solid| Arc::as_ptr(solid) as usize),
                _ => None,
            })
            .collect();
        let scene = w.doc.scene();
        let rigs = scene.references.iter().map(|r| r.rig.0.as_ref().map(|rig| Arc::as_ptr(rig) as usize)).collect();
        let key = SolidsKey {
            colliders: colliders.clone(),
            meshes,
            references: scene.references.clone(),
            rigs,
            frame_bits: w.frame().to_bits(),
            fps_bits: scene.timeline.fps.to_bits(),
            look,
            reference_look: self.toggles.references,
        };
        if let Some((cached, (solids, wire))) = &self.solids_cache
            && *cached == key
        {
            return (solids.clone(), wire.clone());
        }
        let mut solids = Vec::new();
        if opacity > 0.0 {
            solids.push(collider_solids(scene, w.frame(), opacity));
        }
        // Posed once: drawn shaded, see-through, or as lines below.
        let mut reference_lines = Vec::new();
        if self.toggles.references != SolidLook::Hidden {
            let references = reference_solids(scene, w.frame(), 1.0);
            match self.toggles.references {
                SolidLook::Shaded => solids.extend(references),
                SolidLook::SeeThrough => {
                    solids.extend(references.into_iter().map(|s| Solids { opacity: s.opacity * 0.35, ..s }))
                }
                SolidLook::Wire | SolidLook::Hidden => reference_lines = references,
            }
        }
        let solids = Arc::new(solids);
        let mut wire = Vec::new();
        if look == SolidLook::Wire {
            // A mesh by its triangles' edges; a primitive by its outline (a
            // ball's tessellation would be a dense net).
            let segment = |a: glam::DVec3, b: glam::DVec3| Segment {
                a: a.as_vec3(),
                b: b.as_vec3(),
                width_px: 1.0,
                color: COLLIDER_WIRE,
            };
            let enabled = scene.colliders.iter().filter(|c| c.enabled());
            for shape in enabled.filter_map(|c| animate::colliders_at::shape_at(c, w.frame())) {
                if !matches!(shape, crate::world::ColliderShape::Mesh { .. }) {
                    wire.extend(shape.outline().into_iter().map(|[a, b]| segment(a, b)));
                    continue;
                }
                let mesh = shape.triangles();
                let at = |i: u32| mesh.positions[i as usize];
                for t in mesh.indices.chunks_exact(3) {
                    for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                        wire.push(segment(at(a), at(b)));
                    }
                }
            }
        }
        for set in reference_lines {
            let at = |i: u32| set.positions[i as usize];
            for t in set.indices.chunks_exact(3) {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    wire.push(Segment { a: at(a), b: at(b), width_px: 1.0, color: REFERENCE_WIRE });
                }
            }
        }
        let wire = Arc::new(wire);
        self.solids_cache = Some((key, (solids.clone(), wire.clone())));
        (solids, wire)
    }

    fn render_options(&self, w: &Workspace) -> RenderOptions {
        let texture = if self.toggles.texture { w.shown.scene().cloth.texture } else { ClothTexture::Plain };
        RenderOptions {
            wireframe: self.toggles.wireframe || self.stage == Stage::Catenaries,
            ground: self.toggles.ground.then_some(self.ground),
            style: self.style(w),
            ..RenderOptions::default()
        }
        .with_texture(texture)
    }

    /// The view bar over the viewport: stage, toggles, style and looks, in
    /// rows that wrap. Every control is always there (greyed where it does
    /// not apply), so nothing in the bar moves when the scene changes.
    pub fn view_bar_ui(&mut self, ui: &mut egui::Ui, w: &mut Workspace) {
        ui.horizontal_wrapped(|ui| {
            egui::ComboBox::from_label("Stage").selected_text(self.stage.label()).show_ui(ui, |ui| {
                for stage in Stage::ALL {
                    ui.selectable_value(&mut self.stage, stage, stage.label());
                }
            });
            ui.separator();
            ui.toggle_value(&mut self.toggles.texture, "Texture");
            ui.toggle_value(&mut self.toggles.wireframe, "Wireframe");
            ui.toggle_value(&mut self.toggles.pins, "Pins");
            ui.toggle_value(&mut self.toggles.catenaries, "Catenaries");
            ui.toggle_value(&mut self.toggles.triangulation, "Triangulation");
            ui.toggle_value(&mut self.toggles.ground, "Ground");
            ui.toggle_value(&mut self.toggles.onion, "Onion skin")
                .on_hover_text("Ghosts of earlier (blue) and later (orange) frames");
            let mut follow = w.session.follow();
            ui.toggle_value(&mut follow, "Follow").on_hover_text("The camera travels with the cloth (F frames it)");
            w.session.set_follow(follow);
            let hint = "Look through the shot camera (orbiting leaves it)";
            let missing = "The scene has no shot camera: View ▸ Add camera from view adds one";
            let mut through = w.session.through_camera();
            toggle_if_ui(ui, w.doc.scene().camera.is_some(), &mut through, "Camera", hint, missing);
            w.session.look_through_camera(through);
            let hint = "The background plate behind the cloth, through the shot camera";
            let missing = "The scene has no plate: the Shot panel's Add plate… adds one";
            toggle_if_ui(ui, w.doc.scene().plate.is_some(), &mut self.toggles.plate, "Plate", hint, missing);
            ui.separator();
            self.style_ui(ui);
            ui.separator();
            egui::ComboBox::from_label("Colliders").selected_text(self.toggles.colliders.label()).show_ui(ui, |ui| {
                for look in SolidLook::ALL {
                    ui.selectable_value(&mut self.toggles.colliders, look, look.label());
                }
            });
            ui.add_enabled_ui(!w.doc.scene().references.is_empty(), |ui| {
                egui::ComboBox::from_label("References").selected_text(self.toggles.references.label()).show_ui(
                    ui,
                    |ui| {
                        for look in SolidLook::ALL {
                            ui.selectable_value(&mut self.toggles.references, look, look.label());
                        }
                    },
                );
            });
            // Label and widget one by one, so the bar wraps between them rather than past its edge.
            let plate_on = w.doc.scene().plate.is_some() && self.toggles.plate;
            // A slider is a row of its own inside: start a new row when the label and it do not fit.
            if ui.max_rect().right() - ui.cursor().min.x < ui.spacing().slider_width + 110.0 {
                ui.end_row();
            }
            let label = ui.add_enabled(plate_on, egui::Label::new("Plate")).id;
            let slider = egui::Slider::new(&mut self.plate_view.opacity, 0.0..=1.0).fixed_decimals(2);
            ui.add_enabled(plate_on, slider)
                .labelled_by(label)
                .on_hover_text("How much of the plate the viewport shows (renders use the scene's plate opacity)");
            let onion = self.toggles.onion;
            let label = ui.add_enabled(onion, egui::Label::new("Ghosts")).id;
            let drag = number_field(ui.ctx(), &mut self.toggles.onion_frames).range(1..=8);
            ui.add_enabled(onion, drag).labelled_by(label).on_hover_text("Ghosts on each side of the playhead");
            let label = ui.add_enabled(onion, egui::Label::new("every")).id;
            let drag = number_field(ui.ctx(), &mut self.toggles.onion_spacing).range(1..=48).suffix(" frames");
            ui.add_enabled(onion, drag).labelled_by(label);
        });
    }
}

/// A toggle for `value` when `available`; otherwise the same button greyed
/// and shown off (whatever `value` holds), saying why on hover.
fn toggle_if_ui(ui: &mut egui::Ui, available: bool, value: &mut bool, label: &str, hint: &str, missing: &str) {
    if available {
        ui.toggle_value(value, label).on_hover_text(hint);
    } else {
        ui.add_enabled(false, egui::Button::new(label).selected(false)).on_disabled_hover_text(missing);
    }
}
