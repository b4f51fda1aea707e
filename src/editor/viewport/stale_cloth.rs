//! The cloth on screen while its new shape is being solved (a collider or
//! pin dragged, a value typed): the old shape is no answer for the new
//! scene, so after a moment it is drawn grey and untextured, and the status
//! bar says the cloth is updating. A solve that finishes sooner never
//! flashes grey.

use std::time::{Duration, Instant};

use eframe::egui;

use crate::render::{RenderOptions, Style};
use crate::scene::ClothTexture;

/// How long the cloth may lag the document before it is drawn as stale.
pub const STALE_AFTER: Duration = Duration::from_millis(250);

/// The stale cloth's grey, front and back: dark enough that, lit, it reads
/// as dimmed beside any fabric rather than as a pale cloth of its own.
const STALE_FRONT: [f32; 3] = [0.22, 0.23, 0.25];
const STALE_BACK: [f32; 3] = [0.15, 0.16, 0.17];

/// Whether the cloth shown lags the document, and since when.
#[derive(Default)]
pub struct StaleCloth {
    behind_since: Option<Instant>,
    /// Whether the last frame drew the cloth as stale.
    drawn_stale: bool,
}

impl StaleCloth {
    /// Whether the last frame drew the cloth as stale.
    pub fn drawn_stale(&self) -> bool {
        self.drawn_stale
    }

    /// Notes whether the cloth shown is `behind` the document this frame
    /// and whether it is drawn as stale: once it has lagged for
    /// [`STALE_AFTER`], or at once while it is `unsolved` (where its solve
    /// starts, never drawn as if it were the answer). Asks for a frame then,
    /// so the grey shows without waiting for the mouse.
    pub fn update(&mut self, behind: bool, unsolved: bool, ctx: &egui::Context) -> bool {
        let since = match (behind, self.behind_since) {
            (false, _) => None,
            (true, None) => Some(Instant::now()),
            (true, Some(since)) => Some(since),
        };
        self.behind_since = since;
        let lagged = since.map(|s| s.elapsed());
        self.drawn_stale = unsolved || lagged.is_some_and(|d| d >= STALE_AFTER);
        if let Some(lagged) = lagged.filter(|_| !self.drawn_stale) {
            ctx.request_repaint_after(STALE_AFTER.saturating_sub(lagged));
        }
        self.drawn_stale
    }
}

/// `options` drawing the cloth as stale: grey on both sides, untextured, lit.
pub fn stale_look(options: RenderOptions) -> RenderOptions {
    RenderOptions {
        texture: ClothTexture::Plain,
        front_tint: STALE_FRONT,
        back_tint: STALE_BACK,
        // The toon style's own colours would replace the grey.
        style: Style::Lit,
        ..options
    }
}
