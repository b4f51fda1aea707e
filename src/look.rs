//! How the cloth looks wherever it appears: the built-in textures (the PNGs
//! in `assets/`, drawn by `assets/make_textures.py`) and the tints of a plain
//! or textured cloth. `render` draws with them and the exporters write them
//! as the cloth's material, so a picture and an export agree.

use crate::scene::ClothTexture;

const CARPET_PNG: &[u8] = include_bytes!("../assets/carpet.png");
const CHECKER_PNG: &[u8] = include_bytes!("../assets/checker.png");

/// Linear RGB of a plain cloth's front and back.
pub const PLAIN_FRONT_TINT: [f32; 3] = [0.52, 0.45, 0.37];
pub const PLAIN_BACK_TINT: [f32; 3] = [0.3, 0.25, 0.21];
/// Linear RGB of a textured cloth: white lets the picture show, the back a shade darker.
pub const TEXTURED_FRONT_TINT: [f32; 3] = [1.0, 1.0, 1.0];
pub const TEXTURED_BACK_TINT: [f32; 3] = [0.55, 0.52, 0.5];

/// The PNG of a built-in texture as shipped in `assets/`; `None` for a plain cloth.
pub fn texture_png(texture: ClothTexture) -> Option<&'static [u8]> {
    match texture {
        ClothTexture::Plain => None,
        ClothTexture::Carpet => Some(CARPET_PNG),
        ClothTexture::Checker => Some(CHECKER_PNG),
    }
}

/// The front tint of a cloth with `texture`: the colour exporters give its material.
pub fn front_tint(texture: ClothTexture) -> [f32; 3] {
    if texture == ClothTexture::Plain { PLAIN_FRONT_TINT } else { TEXTURED_FRONT_TINT }
}
