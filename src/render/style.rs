//! How the cloth is drawn: today's lit look, or a hand-drawn toon look
//! (flat tone bands from the key light, the texture kept, ink on the
//! silhouette, the open border and sharp creases; see [`super::ink`]).

use crate::scene::{ToonSettings, linear_rgb};

/// The drawing style of the cloth (and of opaque colliders and references,
/// which take its bands but no ink). Ghosts look the same in both.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Style {
    /// Two-sided lighting with a key, fill, sky, rim and sheen.
    #[default]
    Lit,
    Toon(ToonLook),
}

/// The toon style's look, colours linear RGB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToonLook {
    /// Flat tones from the key light, 2 or 3 (other values are clamped).
    pub bands: u32,
    /// Ink line width in pixels; 0 or less draws no ink.
    pub ink_width_px: f32,
    pub ink_color: [f32; 3],
    /// Edges whose faces' normals differ by more than this are inked.
    pub crease_deg: f32,
    /// The front's and back's colours; none: the options' tints.
    pub front: Option<[f32; 3]>,
    pub back: Option<[f32; 3]>,
}

impl Default for ToonLook {
    fn default() -> Self {
        ToonLook::from_settings(&ToonSettings::default())
    }
}

impl ToonLook {
    /// A scene's toon settings (sRGB) as a look (linear).
    pub fn from_settings(settings: &ToonSettings) -> ToonLook {
        ToonLook {
            bands: settings.bands.clamp(2, 3),
            ink_width_px: settings.ink_width_px as f32,
            ink_color: linear_rgb(settings.ink_color),
            crease_deg: settings.crease_deg as f32,
            front: settings.front.map(linear_rgb),
            back: settings.back.map(linear_rgb),
        }
    }
}

impl Style {
    /// The toon look, when the style is toon.
    pub fn toon(&self) -> Option<&ToonLook> {
        match self {
            Style::Lit => None,
            Style::Toon(look) => Some(look),
        }
    }

    /// The number of tone bands the shaders use: 0 for the lit style.
    pub fn bands(&self) -> u32 {
        self.toon().map_or(0, |look| look.bands.clamp(2, 3))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_become_a_linear_look_with_bands_clamped() {
        let settings = ToonSettings { bands: 7, ink_color: (0.5, 0.0, 1.0), ..ToonSettings::default() };
        let look = ToonLook::from_settings(&settings);
        assert_eq!(look.bands, 3);
        assert!((look.ink_color[0] - 0.214).abs() < 1e-3 && look.ink_color[2] == 1.0);
        assert_eq!(Style::Toon(look).bands(), 3);
        assert_eq!(Style::Lit.bands(), 0);
    }
}
