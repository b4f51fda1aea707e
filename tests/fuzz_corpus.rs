//! Replays the fuzz targets' kept inputs (`fuzz/seeds/TARGET` and every
//! input a fuzzer once failed on, `fuzz/regressions/TARGET`) through the
//! same checks `cargo +nightly fuzz run TARGET` runs, on a stable compiler.

use std::path::{Path, PathBuf};

use drape::scene::fuzz;

/// Every file kept for `target`, sorted; at least one seed.
fn kept_inputs(target: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for folder in ["fuzz/seeds", "fuzz/regressions"] {
        let Ok(entries) = std::fs::read_dir(Path::new(folder).join(target)) else { continue };
        files.extend(entries.map(|entry| entry.unwrap().path()).filter(|path| path.is_file()));
    }
    files.sort();
    assert!(!files.is_empty(), "no seeds for the fuzz target {target}: run fuzz/make_seeds.sh");
    files
}

fn replay(target: &str, check: fn(&[u8])) {
    for path in kept_inputs(target) {
        let bytes = std::fs::read(&path).unwrap();
        eprintln!("{target}: {}", path.display());
        check(&bytes);
    }
}

#[test]
fn scene_text_inputs_replay() {
    replay("scene_text", fuzz::scene_text);
}

#[test]
fn gltf_file_inputs_replay() {
    replay("gltf_file", fuzz::gltf_file);
    // The walker is too large a seed to fuzz from quickly, but is checked here.
    fuzz::gltf_file(&std::fs::read("assets/walker.glb").unwrap());
}

#[test]
fn obj_file_inputs_replay() {
    replay("obj_file", fuzz::obj_file);
}

#[test]
fn image_file_inputs_replay() {
    replay("image_file", fuzz::image_file);
}

#[test]
fn the_seeds_are_accepted_where_they_are_valid() {
    // A replay that rejects everything would check nothing past the first error.
    let scene = std::fs::read("fuzz/seeds/scene_text/tent.ron").unwrap();
    assert!(drape::scene::parse_bytes(&scene, "tent.ron").is_ok());
    let folder = Path::new("fuzz/seeds/gltf_file");
    let rig = drape::scene::rig_from_bytes(&std::fs::read(folder.join("tiny_rig.glb")).unwrap(), folder).unwrap();
    assert_eq!((rig.nodes().len(), rig.skins().len(), rig.clips().len(), rig.meshes().len()), (4, 1, 1, 1));
    let table = std::fs::read("fuzz/seeds/obj_file/table.obj").unwrap();
    assert!(drape::scene::mesh_from_bytes(&table, Some("obj"), Path::new("")).is_ok());
    let image = std::fs::read("fuzz/seeds/image_file/checker.png").unwrap();
    assert!(drape::image::RgbaImage::decode(&image, None).is_ok());
}
