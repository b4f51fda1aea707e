//! What the fuzz targets (`fuzz/fuzz_targets/`) check on every input, and
//! what `tests/fuzz_corpus.rs` replays over the kept corpus on a stable
//! compiler. Each function returns for any input: a panic is a finding, and
//! so is a hang or an allocation past the fuzzer's limits. What a reader
//! accepts must also survive a round trip.

use std::path::Path;

use crate::image::RgbaImage;

use super::format::to_ron_string;
use super::io::{parse, parse_bytes};
use super::mesh_files::mesh_from_bytes;
use super::reference_files::rig_from_bytes;

/// A folder no input's relative buffer or image names can be found in.
const NO_FOLDER: &str = "/nonexistent-drape-fuzz-folder";

/// Scene text: parsed and validated; an accepted scene, written out and
/// parsed again, is the same scene.
pub fn scene_text(bytes: &[u8]) {
    let Ok(scene) = parse_bytes(bytes, "fuzz.ron") else { return };
    let text = to_ron_string(&scene);
    let again = match parse(&text, "written.ron") {
        Ok(again) => again,
        Err(error) => panic!("an accepted scene does not read back: {error}\n{text}"),
    };
    assert!(again == scene, "an accepted scene reads back different:\n{text}");
}

/// A glTF file (JSON or GLB) as a reference's rig and as a mesh collider's
/// solid; an accepted rig is posed at the start, middle and end of every
/// clip, an accepted solid rebuilt from its own triangles is the same solid.
pub fn gltf_file(bytes: &[u8]) {
    let folder = Path::new(NO_FOLDER);
    if let Ok(rig) = rig_from_bytes(bytes, folder) {
        let _ = rig.rest_pose();
        for (index, clip) in rig.clips().iter().enumerate() {
            let (start_secs, end_secs) = clip.span_secs();
            for t_secs in [start_secs, 0.5 * (start_secs + end_secs), end_secs] {
                let pose = rig.pose(Some(index), t_secs);
                let _ = rig.posed_meshes(&pose);
            }
        }
    }
    if let Ok(solid) = mesh_from_bytes(bytes, Some("glb"), folder) {
        solid_round_trip(&solid);
    }
}

/// An OBJ file as a mesh collider's solid, rebuilt from its own triangles.
pub fn obj_file(bytes: &[u8]) {
    if let Ok(solid) = mesh_from_bytes(bytes, Some("obj"), Path::new(NO_FOLDER)) {
        solid_round_trip(&solid);
    }
}

fn solid_round_trip(solid: &crate::world::MeshSolid) {
    let (vertices, triangles) = solid.triangles();
    let again = match crate::world::MeshSolid::new(&vertices, triangles) {
        Ok(again) => again,
        Err(why) => panic!("an accepted solid does not rebuild from its own triangles: {why}"),
    };
    // Merging vertices and dropping triangles without area leave nothing more to merge or drop.
    assert!(again.triangles() == solid.triangles(), "a solid rebuilt from its own triangles differs");
    let (low, high) = solid.bounds();
    let _ = solid.surface_point(0.5 * (low + high));
}

/// An image file (a plate, a texture): decoded as PNG or JPEG; what decodes
/// is written as a PNG and decodes back to the same pixels.
pub fn image_file(bytes: &[u8]) {
    let Ok(image) = RgbaImage::decode(bytes, None) else { return };
    assert_eq!(image.pixels.len(), image.width as usize * image.height as usize * 4, "pixels and size disagree");
    let mut png_bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut png_bytes, image.width, image.height);
    encoder.set_color(png::ColorType::Rgba);
    let written = encoder.write_header().and_then(|mut writer| writer.write_image_data(&image.pixels));
    if let Err(error) = written {
        panic!("a decoded {} × {} image cannot be written as a PNG: {error}", image.width, image.height);
    }
    let again = match RgbaImage::decode(&png_bytes, None) {
        Ok(again) => again,
        Err(why) => panic!("a written PNG does not decode: {why}"),
    };
    assert!(again.pixels == image.pixels, "a decoded image written as a PNG reads back different");
}
