//! The toon style's settings (`cloth.toon` in the scene): how many flat tone
//! bands the key light makes, the ink drawn on the silhouette, the open
//! border and sharp creases, and optional front and back colours. The style
//! itself is chosen where the picture is made (`drape render --style toon`,
//! View ▸ Style ▸ Toon); these settings only say how it looks.
//!
//! Colours are **sRGB** components in 0..1 (what a colour picker shows, e.g.
//! `(0.08, 0.06, 0.05)` for a warm near-black), turned linear where the
//! picture is drawn.

use serde::{Deserialize, Serialize};

/// Fewest and most flat tone bands.
pub const MIN_TOON_BANDS: u32 = 2;
pub const MAX_TOON_BANDS: u32 = 3;
/// Widest ink line, in pixels.
pub const MAX_INK_WIDTH_PX: f64 = 32.0;
/// Largest crease threshold: the angle between two faces' normals never exceeds it.
pub const MAX_CREASE_DEG: f64 = 180.0;

/// An sRGB colour, each component in 0..1.
pub type SrgbColor = (f64, f64, f64);

/// How the toon style draws the cloth. Every field has a default, so
/// `toon: (bands: 2)` is a whole setting.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ToonSettings {
    /// Flat tones from the key light: 2 (lit, shadow) or 3 (lit, half, shadow).
    pub bands: u32,
    /// Width of the ink lines in pixels, 0 (no ink) to [`MAX_INK_WIDTH_PX`].
    pub ink_width_px: f64,
    /// The ink's colour, sRGB 0..1.
    pub ink_color: SrgbColor,
    /// An edge where the two faces' normals differ by more than this many
    /// degrees is a crease and gets ink; 0 inks every bend, 180 none.
    pub crease_deg: f64,
    /// The front's colour, sRGB 0..1, multiplying the texture; none: the
    /// cloth's usual front tint (white on a textured cloth).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub front: Option<SrgbColor>,
    /// The back's colour, as `front`; none: the usual back tint.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub back: Option<SrgbColor>,
}

impl Default for ToonSettings {
    fn default() -> Self {
        ToonSettings {
            bands: 3,
            ink_width_px: 2.0,
            ink_color: (0.06, 0.045, 0.04),
            crease_deg: 40.0,
            front: None,
            back: None,
        }
    }
}

impl ToonSettings {
    /// Whether these are the defaults (the scene file then leaves them out).
    pub fn is_default(&self) -> bool {
        *self == ToonSettings::default()
    }
}

/// One sRGB component (0..1) as linear light; out-of-range values are
/// clamped, NaN reads as 0.
pub fn srgb_to_linear(v: f64) -> f64 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

/// One linear component (0..1) as sRGB; out-of-range values are clamped, NaN reads as 0.
pub fn linear_to_srgb(v: f64) -> f64 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    if v <= 0.0031308 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
}

/// An sRGB colour as linear RGB, as the renderer takes it.
pub fn linear_rgb((r, g, b): SrgbColor) -> [f32; 3] {
    [r, g, b].map(|c| srgb_to_linear(c) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_and_linear_round_trip_and_clamp() {
        for v in [0.0, 0.02, 0.2, 0.5, 1.0] {
            assert!((linear_to_srgb(srgb_to_linear(v)) - v).abs() < 1e-9, "{v}");
        }
        assert!((srgb_to_linear(0.5) - 0.214).abs() < 1e-3);
        assert_eq!(srgb_to_linear(f64::NAN), 0.0);
        assert_eq!(srgb_to_linear(2.0), 1.0);
    }

    #[test]
    fn a_scene_keeps_its_toon_settings_through_a_save_and_leaves_the_defaults_out() {
        let text = "(version: 1, cloth: (size: (1.0, 1.0), grid: (3, 3), toon: (bands: 2, front: (0.9, 0.8, 0.7))), \
                    keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])])";
        let mut scene = crate::scene::parse(text, "toon.ron").unwrap();
        let expected = ToonSettings { bands: 2, front: Some((0.9, 0.8, 0.7)), ..ToonSettings::default() };
        assert_eq!(scene.cloth.toon, expected);
        let saved = crate::scene::to_ron_string(&scene);
        assert_eq!(crate::scene::parse(&saved, "saved.ron").unwrap(), scene);
        assert!(!saved.contains("back"), "an absent colour stays absent:\n{saved}");
        scene.cloth.toon = ToonSettings::default();
        assert!(!crate::scene::to_ron_string(&scene).contains("toon"), "defaults are left out");
    }

    #[test]
    fn a_partial_setting_takes_the_defaults_and_an_unknown_field_is_refused() {
        let toon: ToonSettings = ron::from_str("(bands: 2)").unwrap();
        assert_eq!(toon, ToonSettings { bands: 2, ..ToonSettings::default() });
        let typo = ron::from_str::<ToonSettings>("(bandz: 2)").unwrap_err().to_string();
        assert!(typo.contains("bandz"), "{typo}");
    }
}
