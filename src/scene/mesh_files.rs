//! Reading the files mesh colliders name: OBJ (`.obj`) and glTF 2.0 (`.glb`,
//! or `.gltf` with its buffers in `.bin` files beside it), as one solid in
//! the file's own units and axes (glTF's node transforms applied).
//!
//! A scene names a mesh file relative to itself; [`read_meshes`] reads every
//! one a scene names and gives the first problem its line and column in the
//! scene file, like any other mistake.

use std::collections::HashMap;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use super::colliders::Collider;
use super::error::SceneError;
use super::gltf_structure::{
    check_accessor_types, check_accessors, check_animation_targets, check_images, check_node_trees, read_gltf,
    scene_nodes,
};
use super::loaded::Loaded;
use super::locate::locate;
use super::read_capped::{read_capped, read_prefix};
use super::types::Scene;
use crate::world::MeshSolid;

/// Largest mesh file (or glTF buffer) read, in bytes.
pub const MAX_MESH_FILE_BYTES: u64 = 512 * 1024 * 1024;

/// Reads the file of every mesh collider of `scene`, whose file is
/// `scene_file` and whose text is `text` (for positions in messages), and
/// keeps each solid in its collider. Disabled colliders are read too, so
/// switching one on never fails later.
pub fn read_meshes(scene: &mut Scene, scene_file: &Path, text: &str) -> Result<(), SceneError> {
    let folder = scene_file.parent().unwrap_or(Path::new(""));
    let label = scene_file.display().to_string();
    // A file several colliders name (four chairs) is read once.
    let mut read: HashMap<PathBuf, Arc<MeshSolid>> = HashMap::new();
    for (index, collider) in scene.colliders.iter_mut().enumerate() {
        let what = collider.label(index);
        let Collider::Mesh(mesh) = collider else { continue };
        let path = folder.join(&mesh.file);
        let solid = match read.get(&path) {
            Some(solid) => Arc::clone(solid),
            None => {
                let solid = Arc::new(read_mesh(&path).map_err(|why| {
                    let at = locate(text, &format!("colliders[{index}].file"));
                    SceneError::invalid(&label, at, format!("{what}: cannot use {:?}: {why}", mesh.file))
                })?);
                read.insert(path, Arc::clone(&solid));
                solid
            }
        };
        mesh.solid = Loaded(Some(solid));
    }
    Ok(())
}

/// How a scene in `scene_folder` names the file at `file`: a path relative
/// to the folder (with `..` where needed) when both are absolute or both
/// relative, else `file` as it is. A scene moved with its meshes keeps them.
pub fn relative_path(scene_folder: &Path, file: &Path) -> PathBuf {
    if scene_folder.is_absolute() != file.is_absolute() {
        return file.to_path_buf();
    }
    let (from, to): (Vec<_>, Vec<_>) = (scene_folder.components().collect(), file.components().collect());
    let shared = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    // Different roots (another drive) share nothing to walk up from.
    if shared == 0 && file.is_absolute() {
        return file.to_path_buf();
    }
    let mut relative = PathBuf::new();
    for _ in shared..from.len() {
        relative.push("..");
    }
    to[shared..].iter().for_each(|part| relative.push(part));
    relative
}

/// Renames every file `scene` names (mesh colliders', references', the plate's) for a
/// scene file moving from the folder `from` to the folder `to` (a Save As
/// elsewhere), so each still names the same file: relative to `to` where it
/// can be, else absolute.
pub fn move_referenced_files(scene: &mut Scene, from: &Path, to: &Path) {
    let moved = |file: &mut String| *file = relative_path(to, &from.join(&*file)).display().to_string();
    for collider in &mut scene.colliders {
        if let Collider::Mesh(mesh) = collider {
            moved(&mut mesh.file);
        }
    }
    scene.references.iter_mut().for_each(|reference| moved(&mut reference.file));
    if let Some(plate) = &mut scene.plate {
        moved(&mut plate.file);
    }
}

/// The solid in the mesh file at `path`, or why not, in a user's words.
pub fn read_mesh(path: &Path) -> Result<MeshSolid, String> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("obj" | "glb" | "gltf")) {
        return Err("Drape reads meshes from .obj, .glb and .gltf files".to_owned());
    }
    let bytes = read_file_bytes(path)?;
    mesh_from_bytes(&bytes, extension.as_deref(), path.parent().unwrap_or(Path::new("")))
}

/// The solid in a mesh file's `bytes`, read as its `extension` says (`obj`,
/// `glb` or `gltf`), a glTF's `.bin` buffers looked for in `folder`.
pub fn mesh_from_bytes(bytes: &[u8], extension: Option<&str>, folder: &Path) -> Result<MeshSolid, String> {
    let (vertices, triangles) = match extension {
        Some("obj") => obj_triangles(bytes)?,
        Some("glb" | "gltf") => gltf_triangles(bytes, folder)?,
        _ => return Err("Drape reads meshes from .obj, .glb and .gltf files".to_owned()),
    };
    MeshSolid::new(&vertices, &triangles).map_err(|why| format!("the mesh is not a solid: {why}"))
}

/// The bytes of the file at `path` (up to [`MAX_MESH_FILE_BYTES`]), or why not, in a user's words.
pub(super) fn read_file_bytes(path: &Path) -> Result<Vec<u8>, String> {
    read_capped(path, MAX_MESH_FILE_BYTES).map_err(|error| match error {
        SceneError::Read { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            format!("there is no such file ({})", path.display())
        }
        SceneError::TooLarge { .. } => format!("the file is over {} MiB", MAX_MESH_FILE_BYTES / (1024 * 1024)),
        other => other.to_string(),
    })
}

/// Every face of an OBJ, fanned into triangles; materials are not read.
fn obj_triangles(bytes: &[u8]) -> Result<(Vec<DVec3>, Vec<[u32; 3]>), String> {
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..tobj::LoadOptions::default() };
    let (models, _) =
        tobj::load_obj_buf(&mut BufReader::new(bytes), &options, |_| Err(tobj::LoadError::OpenFileFailed))
            .map_err(|error| format!("not a readable OBJ file ({error})"))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in &models {
        let base = vertices.len() as u32;
        let mesh = &model.mesh;
        vertices.extend(mesh.positions.chunks_exact(3).map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into())));
        triangles.extend(mesh.indices.chunks_exact(3).map(|t| [t[0] + base, t[1] + base, t[2] + base]));
    }
    Ok((vertices, triangles))
}

/// The bytes of every buffer of `gltf`: its binary chunk, or `.bin` files in
/// `folder`, each read only as far as its declared length, all of them
/// together at most [`MAX_MESH_FILE_BYTES`]; then its structure checked
/// ([`check_node_trees`], [`check_accessors`], [`check_animation_targets`],
/// [`check_images`], [`check_accessor_types`]), so walking and reading it is
/// safe.
pub(super) fn gltf_buffers(gltf: &gltf::Gltf, folder: &Path) -> Result<Vec<Vec<u8>>, String> {
    check_node_trees(&gltf.document)?;
    let mut buffers = Vec::new();
    let mut total_bytes = 0u64;
    for buffer in gltf.document.buffers() {
        total_bytes = total_bytes.saturating_add(buffer.length() as u64);
        if total_bytes > MAX_MESH_FILE_BYTES {
            return Err(format!("its buffers declare over {} MiB", MAX_MESH_FILE_BYTES / (1024 * 1024)));
        }
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or("its binary chunk is missing")?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                return Err("buffers embedded as data URIs are not read: export a .glb, or .gltf with a .bin".into());
            }
            gltf::buffer::Source::Uri(uri) => {
                let path: PathBuf = folder.join(uri);
                read_prefix(&path, buffer.length() as u64).map_err(|error| {
                    let why = error.message();
                    format!("cannot read its buffer {uri:?}: {why}")
                })?
            }
        };
        if data.len() < buffer.length() {
            return Err(format!("buffer {} is shorter than the file says", buffer.index()));
        }
        buffers.push(data);
    }
    check_accessors(&gltf.document, &buffers)?;
    check_animation_targets(&gltf.document)?;
    check_images(&gltf.document)?;
    check_accessor_types(&gltf.document)?;
    Ok(buffers)
}

/// Every triangle primitive of the default scene (or the first) of a glTF,
/// placed by its nodes' transforms.
fn gltf_triangles(bytes: &[u8], folder: &Path) -> Result<(Vec<DVec3>, Vec<[u32; 3]>), String> {
    let gltf = read_gltf(bytes)?;
    let buffers = gltf_buffers(&gltf, folder)?;
    let scene = gltf.document.default_scene().or_else(|| gltf.document.scenes().next()).ok_or("it has no scene")?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (node, world) in scene_nodes(&gltf.document, &scene) {
        let Some(mesh) = node.mesh() else { continue };
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let Some(positions) = reader.read_positions() else { continue };
            let base = vertices.len() as u32;
            vertices
                .extend(positions.map(|p| world.transform_point3(DVec3::new(p[0].into(), p[1].into(), p[2].into()))));
            let count = vertices.len() as u32 - base;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(indices) => indices.into_u32().collect(),
                None => (0..count).collect(),
            };
            if let Some(bad) = indices.iter().find(|&&i| i >= count) {
                return Err(format!("mesh {:?} names vertex {bad} of {count}", mesh.name().unwrap_or("")));
            }
            // A mirroring transform turns the winding inside out.
            let flip = world.determinant() < 0.0;
            triangles.extend(indices.chunks_exact(3).map(|t| {
                let [a, b, c] = [t[0] + base, t[1] + base, t[2] + base];
                if flip { [a, c, b] } else { [a, b, c] }
            }));
        }
    }
    Ok((vertices, triangles))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `bytes` written to a file named `name` in a fresh folder, read back as a mesh.
    fn read_written(name: &str, bytes: &[u8]) -> Result<MeshSolid, String> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        read_mesh(&path)
    }

    #[test]
    fn files_that_hold_no_solid_say_why() {
        let error = |name: &str, bytes: &[u8]| read_written(name, bytes).unwrap_err();
        assert!(error("empty.obj", b"").contains("no triangles"), "{}", error("empty.obj", b""));
        assert!(error("points.obj", b"v 0 0 0\nv 1 0 0\n").contains("no triangles"));
        assert!(error("flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").contains("no area"));
        assert!(error("chair.fbx", b"binary").contains(".obj, .glb and .gltf"));
        assert!(error("chair.glb", b"not a gltf").contains("not a readable glTF file"));
        let data_uri = br#"{"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4, "uri": "data:application/octet-stream;base64,AAAAAA=="}]}"#;
        assert!(error("inline.gltf", data_uri).contains("data URIs"), "{}", error("inline.gltf", data_uri));
        let no_bin = br#"{"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4, "uri": "missing.bin"}]}"#;
        assert!(error("outside.gltf", no_bin).contains("cannot read its buffer \"missing.bin\""));
        let no_scene = br#"{"asset": {"version": "2.0"}}"#;
        assert!(error("empty.gltf", no_scene).contains("no scene"), "{}", error("empty.gltf", no_scene));
    }

    #[test]
    fn mesh_files_are_named_relative_to_the_scene() {
        let p = |s: &str| PathBuf::from(s);
        assert_eq!(relative_path(Path::new("/shots/a"), Path::new("/shots/a/chair.obj")), p("chair.obj"));
        assert_eq!(relative_path(Path::new("/shots/a"), Path::new("/shots/props/chair.obj")), p("../props/chair.obj"));
        assert_eq!(relative_path(Path::new("scenes"), Path::new("assets/chair.obj")), p("../assets/chair.obj"));
        assert_eq!(relative_path(Path::new("/shots"), Path::new("props/chair.obj")), p("props/chair.obj"));
        assert_eq!(relative_path(Path::new(""), Path::new("chair.obj")), p("chair.obj"));
    }
}
