//! Reading the glTF 2.0 files a scene's references name into rigs: nodes,
//! skins, the triangle meshes and cameras of the default scene, and
//! animations.
//!
//! What Drape does not read is said, not guessed at: a file that needs an
//! extension, a skinned mesh without joints, an animation name the file
//! lacks. Lines and points are not surfaces and are left out; lights are
//! not read. A mesh takes its material's base colour and base-colour
//! texture (PNG or JPEG). A camera is kept with the node it hangs on, so
//! the shot camera can follow it (`camera.from_reference`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};

use super::error::SceneError;
use super::gltf_structure::{read_gltf, scene_nodes};
use super::loaded::Loaded;
use super::locate::locate;
use super::mesh_files::{gltf_buffers, read_file_bytes};
use super::references::Attachment;
use super::types::Scene;
use crate::image::RgbaImage;
use crate::world::rig::{
    Channel, Clip, Influences, Interpolation, Projection, Property, Rig, RigCamera, RigMesh, RigNode, Skin, Trs,
};

/// Most vertices all the meshes of one referenced file may have together.
pub const MAX_REFERENCE_VERTICES: usize = 4_000_000;

/// Reads the file of every reference of `scene`, whose file is `scene_file`
/// and whose text is `text` (for positions in messages), and keeps each rig
/// in its reference. Hidden references are read too, so showing one never
/// fails later. A named animation the file lacks is an error at its name,
/// and so is an attached pin naming a node or triangle the file lacks, and
/// a shot camera following a camera the file lacks or one that is not a
/// perspective camera.
pub fn read_references(scene: &mut Scene, scene_file: &Path, text: &str) -> Result<(), SceneError> {
    let folder = scene_file.parent().unwrap_or(Path::new(""));
    let label = scene_file.display().to_string();
    let mut read: HashMap<PathBuf, Arc<Rig>> = HashMap::new();
    for (index, reference) in scene.references.iter_mut().enumerate() {
        let what = reference.label(index);
        let path = folder.join(&reference.file);
        let rig = match read.get(&path) {
            Some(rig) => Arc::clone(rig),
            None => {
                let rig = Arc::new(read_rig(&path).map_err(|why| {
                    let at = locate(text, &format!("references[{index}].file"));
                    SceneError::invalid(&label, at, format!("{what}: cannot use {:?}: {why}", reference.file))
                })?);
                read.insert(path, Arc::clone(&rig));
                rig
            }
        };
        if let Some(name) = &reference.animation
            && rig.clip_named(name).is_none()
        {
            let names: Vec<String> = rig.clips().iter().map(|c| format!("{:?}", c.name)).collect();
            let has = if names.is_empty() { "it has none".to_owned() } else { format!("it has {}", names.join(", ")) };
            let at = locate(text, &format!("references[{index}].animation"));
            let message = format!("{what}: {:?} has no animation {name:?} ({has})", reference.file);
            return Err(SceneError::invalid(&label, at, message));
        }
        reference.rig = Loaded(Some(rig));
    }
    check_attachments(scene, &label, text)?;
    check_shot_camera(scene, &label, text)
}

/// The reference's camera the shot camera follows is in its file and is a
/// perspective camera; the message lists the cameras that are.
fn check_shot_camera(scene: &Scene, label: &str, text: &str) -> Result<(), SceneError> {
    let Some(from) = scene.camera.as_ref().and_then(|c| c.from_reference.as_ref()) else { return Ok(()) };
    let Some(reference) = scene.references.iter().find(|r| r.name == from.reference) else { return Ok(()) };
    let Some(rig) = reference.rig.0.as_deref() else { return Ok(()) };
    let perspective: Vec<String> = rig
        .cameras()
        .iter()
        .filter(|c| matches!(c.projection, Projection::Perspective { .. }))
        .map(|c| format!("{:?}", c.name))
        .collect();
    let has = if perspective.is_empty() {
        "it has no perspective camera".to_owned()
    } else {
        format!("it has {}", perspective.join(", "))
    };
    let what = format!("camera: from_reference names camera {:?} of {:?}", from.camera, reference.file);
    let message = match rig.camera_named(&from.camera).map(|c| c.projection) {
        None => format!("{what}, which has no such camera ({has})"),
        Some(Projection::Orthographic) => {
            format!("{what}, which is orthographic: the shot camera sees in perspective ({has})")
        }
        Some(Projection::Perspective { .. }) => return Ok(()),
    };
    Err(SceneError::invalid(label, locate(text, "camera.from_reference.camera"), message))
}

/// The followed node, and every attached pin's node or triangle, are in
/// their reference's file.
fn check_attachments(scene: &Scene, label: &str, text: &str) -> Result<(), SceneError> {
    if let Some(follow) = &scene.follow
        && let Some(reference) = scene.references.iter().find(|r| r.name == follow.reference)
        && let Some(rig) = reference.rig.0.as_deref()
        && rig.node_named(&follow.node).is_none()
    {
        let message =
            format!("the cloth follows node {:?} of {:?}, which has no such node", follow.node, reference.file);
        return Err(SceneError::invalid(label, locate(text, "follow.node"), message));
    }
    for (k, key) in scene.keys.iter().enumerate() {
        for (p, pin) in key.pins.iter().enumerate() {
            let Some(attachment) = &pin.attach else { continue };
            let Some(reference) = scene.references.iter().find(|r| r.name == attachment.reference()) else { continue };
            let Some(rig) = reference.rig.0.as_deref() else { continue };
            let what =
                format!("pin {:?} in the key at frame {} is attached to {:?}", pin.grid, key.frame, reference.file);
            let problem = match attachment {
                Attachment::Node(node) if rig.node_named(&node.node).is_none() => {
                    Some(("node", format!("{what}, which has no node {:?}", node.node)))
                }
                Attachment::Surface(surface) => match rig.meshes().get(surface.mesh) {
                    None => Some((
                        "mesh",
                        format!("{what}, which has {} meshes (mesh {} asked for)", rig.meshes().len(), surface.mesh),
                    )),
                    Some(mesh) if surface.triangle >= mesh.indices.len() / 3 => Some((
                        "triangle",
                        format!(
                            "{what}, whose mesh {} has {} triangles (triangle {} asked for)",
                            surface.mesh,
                            mesh.indices.len() / 3,
                            surface.triangle
                        ),
                    )),
                    Some(_) => None,
                },
                Attachment::Node(_) => None,
            };
            if let Some((field, message)) = problem {
                let at = locate(text, &format!("keys[{k}].pins[{p}].attach.{field}"));
                return Err(SceneError::invalid(label, at, message));
            }
        }
    }
    Ok(())
}

/// The rig in the glTF file at `path`, or why not, in a user's words.
pub fn read_rig(path: &Path) -> Result<Rig, String> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("glb" | "gltf")) {
        return Err("a reference is a glTF 2.0 file: .glb, or .gltf with its .bin".to_owned());
    }
    let bytes = read_file_bytes(path)?;
    rig_from_bytes(&bytes, path.parent().unwrap_or(Path::new("")))
}

/// The rig in a glTF file's `bytes` (JSON or GLB), its `.bin` buffers and
/// image files looked for in `folder`.
pub fn rig_from_bytes(bytes: &[u8], folder: &Path) -> Result<Rig, String> {
    let gltf = read_gltf(bytes)?;
    if let Some(needed) = gltf.document.extensions_required().next() {
        return Err(format!("it needs the extension {needed}, which Drape does not read"));
    }
    let buffers = gltf_buffers(&gltf, folder)?;
    let document = &gltf.document;
    let nodes = read_nodes(document);
    let skins = read_skins(document, &buffers)?;
    let images = read_images(document, &buffers, folder)?;
    let meshes = read_meshes(document, &buffers, &images)?;
    let clips = read_clips(document, &buffers, &nodes)?;
    let cameras = read_cameras(document);
    Rig::new(nodes, meshes, skins, clips)?.with_cameras(cameras)
}

/// Every camera on a node of the default scene (or the first), each as
/// often as nodes carry it, in the file's node order, named as
/// [`RigCamera::name`] says.
fn read_cameras(document: &gltf::Document) -> Vec<RigCamera> {
    use gltf::camera::Projection as Lens;
    let Some(scene) = document.default_scene().or_else(|| document.scenes().next()) else {
        return Vec::new();
    };
    let mut in_scene = vec![false; document.nodes().len()];
    for (node, _) in scene_nodes(document, &scene) {
        in_scene[node.index()] = true;
    }
    let mut cameras = Vec::new();
    for node in document.nodes().filter(|n| in_scene[n.index()]) {
        let Some(camera) = node.camera() else { continue };
        let name = [node.name(), camera.name()]
            .into_iter()
            .flatten()
            .find(|n| !n.trim().is_empty())
            .map_or_else(|| format!("camera {}", camera.index() + 1), str::to_owned);
        let projection = match camera.projection() {
            Lens::Perspective(lens) => Projection::Perspective {
                yfov_rad: f64::from(lens.yfov()),
                aspect_ratio: lens.aspect_ratio().map(f64::from),
                znear: f64::from(lens.znear()),
            },
            Lens::Orthographic(_) => Projection::Orthographic,
        };
        cameras.push(RigCamera { name, node: node.index(), projection });
    }
    cameras
}

/// Every node with its parent, rest transform and default morph weights.
fn read_nodes(document: &gltf::Document) -> Vec<RigNode> {
    let mut nodes: Vec<RigNode> = document
        .nodes()
        .map(|node| {
            let (translation, rotation, scale) = node.transform().decomposed();
            let rest = Trs {
                translation: DVec3::from_array(translation.map(f64::from)),
                rotation: DQuat::from_array(rotation.map(f64::from)).normalize(),
                scale: DVec3::from_array(scale.map(f64::from)),
            };
            let targets = node.mesh().and_then(|m| m.primitives().next()).map_or(0, |p| p.morph_targets().len());
            let defaults = node.weights().or_else(|| node.mesh().and_then(|m| m.weights()));
            let morph_weights = match defaults {
                Some(weights) if weights.len() == targets => weights.iter().map(|&w| f64::from(w)).collect(),
                _ => vec![0.0; targets],
            };
            RigNode { name: node.name().unwrap_or_default().to_owned(), parent: None, rest, morph_weights }
        })
        .collect();
    for node in document.nodes() {
        for child in node.children() {
            nodes[child.index()].parent = Some(node.index());
        }
    }
    nodes
}

fn read_skins(document: &gltf::Document, buffers: &[Vec<u8>]) -> Result<Vec<Skin>, String> {
    document
        .skins()
        .map(|skin| {
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            let reader = skin.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let inverse_bind = match reader.read_inverse_bind_matrices() {
                Some(matrices) => matrices.map(|m| DMat4::from_cols_array_2d(&m.map(|c| c.map(f64::from)))).collect(),
                None => vec![DMat4::IDENTITY; joints.len()],
            };
            Ok(Skin { joints, inverse_bind })
        })
        .collect()
}

/// The triangle primitives the default scene (or the first) draws, each
/// with the node that draws it.
fn read_meshes(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    images: &[Arc<RgbaImage>],
) -> Result<Vec<RigMesh>, String> {
    let Some(scene) = document.default_scene().or_else(|| document.scenes().next()) else {
        return Ok(Vec::new());
    };
    let mut meshes = Vec::new();
    let mut vertices = 0usize;
    for (node, _) in scene_nodes(document, &scene) {
        let Some(mesh) = node.mesh() else { continue };
        for primitive in mesh.primitives() {
            let Some(rig_mesh) = read_primitive(&node, &mesh, &primitive, buffers, images)? else { continue };
            vertices += rig_mesh.positions.len();
            if vertices > MAX_REFERENCE_VERTICES {
                return Err(format!("its meshes have over {MAX_REFERENCE_VERTICES} vertices"));
            }
            meshes.push(rig_mesh);
        }
    }
    Ok(meshes)
}

/// One primitive as a rig mesh; None for lines and points.
fn read_primitive(
    node: &gltf::Node,
    mesh: &gltf::Mesh,
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    images: &[Arc<RgbaImage>],
) -> Result<Option<RigMesh>, String> {
    use gltf::mesh::Mode;
    let name = mesh.name().unwrap_or_default().to_owned();
    let what = format!("mesh {name:?}");
    let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let Some(positions) = reader.read_positions() else { return Ok(None) };
    let positions: Vec<DVec3> = positions.map(|p| DVec3::from_array(p.map(f64::from))).collect();
    let count = positions.len() as u32;
    let listed: Vec<u32> = match reader.read_indices() {
        Some(indices) => indices.into_u32().collect(),
        None => (0..count).collect(),
    };
    let indices = match primitive.mode() {
        Mode::Triangles => listed.chunks_exact(3).flatten().copied().collect(),
        Mode::TriangleStrip => (2..listed.len())
            .flat_map(|k| {
                let (a, b, c) = (listed[k - 2], listed[k - 1], listed[k]);
                if k % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => (2..listed.len()).flat_map(|k| [listed[0], listed[k - 1], listed[k]]).collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => return Ok(None),
    };
    let skin = node.skin().map(|s| s.index());
    let mut influences = Influences::default();
    if skin.is_some() {
        let mut sets = Vec::new();
        for set in 0.. {
            let (Some(joints), Some(weights)) = (reader.read_joints(set), reader.read_weights(set)) else { break };
            let joints: Vec<[u16; 4]> = joints.into_u16().collect();
            let weights: Vec<[f32; 4]> = weights.into_f32().collect();
            if joints.len() != positions.len() || weights.len() != positions.len() {
                return Err(format!("{what}: JOINTS_{set} or WEIGHTS_{set} does not cover every vertex"));
            }
            sets.push((joints, weights));
        }
        if sets.is_empty() {
            return Err(format!("{what} is skinned but has no JOINTS_0 and WEIGHTS_0"));
        }
        influences.start.push(0);
        for v in 0..positions.len() {
            for (joints, weights) in &sets {
                for (&joint, &weight) in joints[v].iter().zip(&weights[v]) {
                    if weight != 0.0 {
                        influences.joint.push(joint);
                        influences.weight.push(f64::from(weight));
                    }
                }
            }
            influences.start.push(influences.joint.len() as u32);
        }
    }
    let morph_targets = reader
        .read_morph_targets()
        .map(|(moves, _, _)| match moves {
            Some(moves) => moves.map(|d| DVec3::from_array(d.map(f64::from))).collect(),
            None => vec![DVec3::ZERO; positions.len()],
        })
        .collect();
    let pbr = primitive.material().pbr_metallic_roughness();
    let color = pbr.base_color_factor();
    // The base-colour texture, where the primitive has the coordinates it names.
    let textured = pbr.base_color_texture().and_then(|info| {
        let uvs: Vec<[f32; 2]> = reader.read_tex_coords(info.tex_coord())?.into_f32().collect();
        let image = images.get(info.texture().source().index())?;
        (uvs.len() == positions.len()).then(|| (Arc::clone(image), uvs))
    });
    let (texture, uvs) = textured.map_or((None, Vec::new()), |(image, uvs)| (Some(image), uvs));
    let node = node.index();
    Ok(Some(RigMesh { name, node, skin, positions, indices, influences, morph_targets, color, texture, uvs }))
}

/// Every image of the file decoded (PNG or JPEG, from a buffer or a file
/// beside it), in the file's order.
fn read_images(document: &gltf::Document, buffers: &[Vec<u8>], folder: &Path) -> Result<Vec<Arc<RgbaImage>>, String> {
    use gltf::image::Source;
    let mut images = Vec::new();
    for image in document.images() {
        let what = format!("image {} ({:?})", image.index(), image.name().unwrap_or_default());
        let (bytes, mime_type): (Vec<u8>, Option<&str>) = match image.source() {
            Source::View { view, mime_type } => {
                let data = buffers.get(view.buffer().index()).ok_or(format!("{what} names a missing buffer"))?;
                let bytes = data
                    .get(view.offset()..view.offset() + view.length())
                    .ok_or(format!("{what} lies outside its buffer"))?;
                (bytes.to_vec(), Some(mime_type))
            }
            Source::Uri { uri, .. } if uri.starts_with("data:") => {
                return Err(format!("{what} is embedded as a data URI, which Drape does not read: export a .glb"));
            }
            Source::Uri { uri, mime_type } => {
                (read_file_bytes(&folder.join(uri)).map_err(|why| format!("{what} ({uri:?}): {why}"))?, mime_type)
            }
        };
        let texture = RgbaImage::decode(&bytes, mime_type).map_err(|why| format!("{what}: {why}"))?;
        images.push(Arc::new(texture));
    }
    Ok(images)
}

/// Every animation, its channels' samplers read out in full.
fn read_clips(document: &gltf::Document, buffers: &[Vec<u8>], nodes: &[RigNode]) -> Result<Vec<Clip>, String> {
    use gltf::animation::util::ReadOutputs;
    let mut clips = Vec::new();
    for animation in document.animations() {
        let name = animation.name().map_or_else(|| format!("animation {}", animation.index() + 1), str::to_owned);
        let mut channels = Vec::new();
        for channel in animation.channels() {
            let node = channel.target().node().index();
            let reader = channel.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let (Some(inputs), Some(outputs)) = (reader.read_inputs(), reader.read_outputs()) else {
                return Err(format!("animation {name:?} has a channel whose keys cannot be read"));
            };
            let times_secs: Vec<f64> = inputs.map(f64::from).collect();
            let (property, width, values): (Property, usize, Vec<f64>) = match outputs {
                ReadOutputs::Translations(v) => (Property::Translation, 3, v.flatten().map(f64::from).collect()),
                ReadOutputs::Rotations(v) => (Property::Rotation, 4, v.into_f32().flatten().map(f64::from).collect()),
                ReadOutputs::Scales(v) => (Property::Scale, 3, v.flatten().map(f64::from).collect()),
                ReadOutputs::MorphTargetWeights(v) => {
                    let width = nodes.get(node).map_or(0, |n| n.morph_weights.len());
                    (Property::MorphWeights, width, v.into_f32().map(f64::from).collect())
                }
            };
            let interpolation = match channel.sampler().interpolation() {
                gltf::animation::Interpolation::Linear => Interpolation::Linear,
                gltf::animation::Interpolation::Step => Interpolation::Step,
                gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
            channels.push(Channel { node, property, interpolation, times_secs, values, width });
        }
        clips.push(Clip { name, channels });
    }
    Ok(clips)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_and_jpeg_textures_decode_and_other_images_say_what_is_read() {
        // An 8 × 8 JPEG of one red, made by tests/data/textures/make_textures.sh.
        let jpeg = RgbaImage::decode(include_bytes!("../../tests/data/textures/red.jpg"), None).unwrap();
        assert_eq!((jpeg.width, jpeg.height, jpeg.pixels.len()), (8, 8, 256));
        let [r, g, b, a] = [jpeg.pixels[0], jpeg.pixels[1], jpeg.pixels[2], jpeg.pixels[3]].map(i32::from);
        assert!((r - 0xe0).abs() <= 3 && (g - 0x10).abs() <= 3 && (b - 0x10).abs() <= 3 && a == 255, "{r} {g} {b} {a}");
        let mut png = Vec::new();
        let image = RgbaImage { width: 1, height: 2, pixels: vec![1, 2, 3, 255, 4, 5, 6, 128] };
        let mut encoder = png::Encoder::new(&mut png, 1, 2);
        encoder.set_color(png::ColorType::Rgba);
        encoder.write_header().unwrap().write_image_data(&image.pixels).unwrap();
        let decoded = RgbaImage::decode(&png, Some("image/png")).unwrap();
        assert_eq!((decoded.width, decoded.height, decoded.pixels), (1, 2, image.pixels));
        assert!(RgbaImage::decode(b"GIF89a", Some("image/gif")).unwrap_err().contains("only PNG and JPEG"));
        assert!(RgbaImage::decode(&[0xFF, 0xD8, 0, 0], None).unwrap_err().contains("not a readable JPEG"));
    }
}
