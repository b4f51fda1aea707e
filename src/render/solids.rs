//! Solid shapes drawn beside the cloth (the scene's colliders): triangles in
//! world space with one colour, shaded like the cloth, opaque or see-through.
//! What they stand for is the caller's business.

use std::sync::Arc;

use glam::Vec3;

use crate::image::RgbaImage;

/// Triangles with a normal per vertex, wound counter-clockwise seen from
/// outside, drawn in one colour, or in a texture tinted by it.
#[derive(Clone, Debug, PartialEq)]
pub struct Solids {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
    /// Linear RGB.
    pub color: [f32; 3],
    /// 1 draws them opaque and casting shadows; less blends them over what is behind.
    pub opacity: f32,
    /// A colour texture (sRGB) over the triangles, with `uvs` a point per
    /// vertex ((0, 0) the image's top left); none draws `color` alone.
    pub texture: Option<SolidTexture>,
    pub uvs: Vec<[f32; 2]>,
}

/// A texture shared by reference: two are equal when they are the same
/// texture (comparing pixels every frame would cost more than drawing).
#[derive(Clone, Debug)]
pub struct SolidTexture(pub Arc<RgbaImage>);

impl PartialEq for SolidTexture {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Solids {
    /// Nothing to draw.
    pub const NONE: Solids = Solids {
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
        color: [0.0; 3],
        opacity: 1.0,
        texture: None,
        uvs: Vec::new(),
    };

    /// The colour props get unless the caller says otherwise: a warm light grey,
    /// darker than the default cloth so the two read apart.
    pub const PROP_COLOR: [f32; 3] = [0.34, 0.30, 0.26];

    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }
}
