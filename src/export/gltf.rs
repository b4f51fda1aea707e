//! glTF 2.0: the cloth as one mesh whose animation is a morph target per frame.
//!
//! The base mesh is the first exported frame (positions, normals, UVs,
//! triangles wound counter-clockwise seen from the front, as glTF expects).
//! Target k holds frame k's POSITION and NORMAL minus the base's, so target 0
//! is all zeros. The node's weights are animated with one keyframe per frame
//! at `t = (frame − first) / fps` seconds and one-hot weights (target k is 1 at
//! keyframe k, every other target 0). The sampler is LINEAR: at each frame's
//! time it reproduces that frame exactly, and between two frames it blends
//! their positions linearly, so a viewer running at another rate than the
//! scene (a 60 Hz display, a host timeline at 30 fps) shows smooth motion
//! rather than held frames. The scene's fps and frame range are also recorded
//! in `asset.extras`.
//!
//! The material is double-sided (cloth is seen from both sides): with the
//! scene's texture as `baseColorTexture` when it has one, else the renderer's
//! plain cloth colour. The node and mesh are named after the scene.
//!
//! `.glb` holds everything, texture included, in one file. `.gltf` writes
//! `NAME.gltf` with `NAME.bin` (the binary buffer) and `NAME_texture.png`
//! beside it. Every length is known before the first byte of binary data
//! (vertex count × frames × 24 bytes for the targets), but the accessor bounds
//! the format requires for morph positions are not, so the frames are
//! evaluated twice: once to measure the bounds, once to stream the data.
//!
//! One target per frame makes the weights frames × frames floats (58 KB for
//! 121 frames, 4 MB for 1000), streamed a keyframe at a time like the rest.

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde_json::{Value, json};

use super::error::ExportError;
use super::job::Job;
use super::output::{check_directory, write_around};
use crate::atomic_file::{is_special_file, write_atomically};
use crate::look::{self, texture_png};
use crate::scene::ClothTexture;

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// What the first pass learns: the base mesh and each target's position bounds.
struct Measured {
    base_positions: Vec<Vec3>,
    base_normals: Vec<Vec3>,
    /// Per frame: min and max of the position deltas.
    delta_bounds: Vec<(Vec3, Vec3)>,
}

/// Byte offsets of the parts of the binary buffer, in order.
struct Layout {
    vertices: usize,
    frames: usize,
    indices: usize,
    image_len: usize,
    positions: usize,
    normals: usize,
    uvs: usize,
    image: usize,
    targets: usize,
    times: usize,
    weights: usize,
    total: usize,
}

impl Layout {
    fn new(vertices: usize, index_count: usize, image_len: usize, frames: usize) -> Layout {
        let positions = index_count * 4;
        let normals = positions + vertices * 12;
        let uvs = normals + vertices * 12;
        let image = uvs + vertices * 8;
        let targets = image + padded4(image_len);
        let times = targets + frames * vertices * 24;
        let weights = times + frames * 4;
        let total = weights + frames * frames * 4;
        Layout {
            vertices,
            frames,
            indices: 0,
            image_len,
            positions,
            normals,
            uvs,
            image,
            targets,
            times,
            weights,
            total,
        }
    }
}

fn padded4(n: usize) -> usize {
    n.div_ceil(4) * 4
}

/// The position delta of one vertex, rounded once from the exact difference.
fn delta(p: Vec3, base: Vec3) -> Vec3 {
    (p.as_dvec3() - base.as_dvec3()).as_vec3()
}

/// Writes `output` as `.glb` (`binary`) or `.gltf` with its side files.
pub(crate) fn write(job: &mut Job, output: &Path, binary: bool) -> Result<Vec<PathBuf>, ExportError> {
    check_directory(output)?;
    if !binary && is_special_file(output) {
        return Err(ExportError::SideFilesBesideSpecialFile { path: output.to_path_buf() });
    }
    let scene = job.source.scene();
    let png = texture_png(scene.cloth.texture);
    // A .glb carries the texture in its buffer; a .gltf beside it.
    let embedded_png = if binary { png } else { None };
    // Every mesh of the grid has these counts (two triangles a cell).
    let (cols, rows) = (scene.cloth.cols(), scene.cloth.rows());
    let index_count = (cols - 1) * (rows - 1) * 6;
    let image_len = embedded_png.map_or(0, <[u8]>::len);
    let vertices = cols * rows;
    let layout = Layout::new(vertices, index_count, image_len, job.frame_count());
    // The buffer's length is known before any frame is evaluated: a .glb too
    // large for its 32-bit length is refused at once, not after the first pass.
    if binary && layout.total as u64 > u64::from(u32::MAX) {
        return Err(ExportError::TooLarge { path: output.to_path_buf(), size_bytes: layout.total as u64 });
    }
    let measured = measure(job).map_err(|e| ExportError::write(output, e))?;
    let (bin_path, png_path) = side_files(output);
    let (buffer_uri, image_uri) =
        if binary { (None, None) } else { (Some(uri_of(&bin_path)), png.map(|_| uri_of(&png_path))) };
    let document = document(job, &measured, &layout, buffer_uri, image_uri);
    let json = serde_json::to_vec(&document).map_err(|e| ExportError::write(output, io::Error::other(e)))?;

    if binary {
        let json_len = padded4(json.len());
        let total = 12 + 8 + json_len as u64 + 8 + layout.total as u64;
        if total > u64::from(u32::MAX) {
            return Err(ExportError::TooLarge { path: output.to_path_buf(), size_bytes: total });
        }
        write_atomically(output, |w| {
            w.write_all(b"glTF")?;
            w.write_all(&2u32.to_le_bytes())?;
            w.write_all(&(total as u32).to_le_bytes())?;
            w.write_all(&(json_len as u32).to_le_bytes())?;
            w.write_all(b"JSON")?;
            w.write_all(&json)?;
            w.write_all(&b"   "[..json_len - json.len()])?;
            w.write_all(&(layout.total as u32).to_le_bytes())?;
            w.write_all(b"BIN\0")?;
            write_buffer(job, &measured, &layout, embedded_png, w)
        })
        .map_err(|e| ExportError::write(output, e))?;
        return Ok(vec![output.to_path_buf()]);
    }

    let stream_bin = |job: &mut Job| {
        write_atomically(&bin_path, |w| write_buffer(job, &measured, &layout, None, w))
            .map_err(|e| ExportError::write(&bin_path, e))
    };
    match png {
        Some(png) => write_around(&png_path, png, || write_around(output, &json, || stream_bin(job)))?,
        None => write_around(output, &json, || stream_bin(job))?,
    }
    let mut files = vec![output.to_path_buf(), bin_path];
    files.extend(png.map(|_| png_path));
    Ok(files)
}

/// The files beside a `.gltf`: its buffer `NAME.bin` and its texture
/// `NAME_texture.png` (written when the cloth has a texture).
pub(crate) fn side_files(output: &Path) -> (PathBuf, PathBuf) {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "cloth".into());
    (output.with_file_name(format!("{stem}.bin")), output.with_file_name(format!("{stem}_texture.png")))
}

/// First pass: the base mesh and the bounds of every target's position deltas.
fn measure(job: &mut Job) -> io::Result<Measured> {
    let mut measured = Measured { base_positions: Vec::new(), base_normals: Vec::new(), delta_bounds: Vec::new() };
    job.for_each_frame(|index, _, mesh| {
        if index == 0 {
            measured.base_positions = mesh.positions.clone();
            measured.base_normals = mesh.normals.clone();
        }
        let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for (p, base) in mesh.positions.iter().zip(&measured.base_positions) {
            let d = delta(*p, *base);
            min = min.min(d);
            max = max.max(d);
        }
        measured.delta_bounds.push((min, max));
        Ok(())
    })?;
    Ok(measured)
}

/// Second pass: the binary buffer in [`Layout`] order, the targets streamed frame by frame.
fn write_buffer(
    job: &mut Job,
    measured: &Measured,
    layout: &Layout,
    png: Option<&[u8]>,
    w: &mut dyn Write,
) -> io::Result<()> {
    let mut bytes: Vec<u8> = Vec::with_capacity(layout.vertices * 24);
    let base = job.source.mesh(job.first);
    for index in &base.indices {
        bytes.extend_from_slice(&index.to_le_bytes());
    }
    w.write_all(&bytes)?;
    write_vec3s(w, &mut bytes, measured.base_positions.iter().copied())?;
    write_vec3s(w, &mut bytes, measured.base_normals.iter().copied())?;
    bytes.clear();
    for uv in &job.source.mesh(job.first).uvs {
        bytes.extend_from_slice(&uv.x.to_le_bytes());
        bytes.extend_from_slice(&uv.y.to_le_bytes());
    }
    w.write_all(&bytes)?;
    if let Some(png) = png {
        w.write_all(png)?;
        w.write_all(&[0u8; 3][..padded4(png.len()) - png.len()])?;
    } else {
        // A .gltf keeps the texture in its own file; its bytes are not in the buffer.
        debug_assert_eq!(layout.targets, layout.image);
    }
    job.for_each_frame(|_, _, mesh| {
        let positions = mesh.positions.iter().zip(&measured.base_positions).map(|(p, b)| delta(*p, *b));
        write_vec3s(w, &mut bytes, positions)?;
        let normals = mesh.normals.iter().zip(&measured.base_normals).map(|(n, b)| delta(*n, *b));
        write_vec3s(w, &mut bytes, normals)
    })?;
    let fps = job.fps();
    bytes.clear();
    for k in 0..layout.frames {
        bytes.extend_from_slice(&key_time_secs(k, fps).to_le_bytes());
    }
    w.write_all(&bytes)?;
    for k in 0..layout.frames {
        bytes.clear();
        for target in 0..layout.frames {
            bytes.extend_from_slice(&(if target == k { 1.0f32 } else { 0.0 }).to_le_bytes());
        }
        w.write_all(&bytes)?;
    }
    Ok(())
}

fn write_vec3s(w: &mut dyn Write, bytes: &mut Vec<u8>, values: impl Iterator<Item = Vec3>) -> io::Result<()> {
    bytes.clear();
    for v in values {
        for c in v.to_array() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    w.write_all(bytes)
}

/// The time of the k-th exported frame, in seconds from the first.
fn key_time_secs(k: usize, fps: f64) -> f32 {
    (k as f64 / fps) as f32
}

/// An f32 as a JSON number that reads back as exactly that f32 (its exact
/// value as f64, so bounds compare equal to the data however a reader parses).
fn number(v: f32) -> Value {
    json!(f64::from(v))
}

fn vec3_json(v: Vec3) -> Value {
    json!([number(v.x), number(v.y), number(v.z)])
}

/// The glTF JSON document for `layout`.
fn document(
    job: &Job,
    measured: &Measured,
    layout: &Layout,
    buffer_uri: Option<String>,
    image_uri: Option<String>,
) -> Value {
    let scene = job.source.scene();
    let name = job.name_or("cloth");
    let frames = layout.frames;
    let vertices = layout.vertices;
    let textured = scene.cloth.texture != ClothTexture::Plain;

    let mut buffer_views = vec![
        json!({"name": "indices", "buffer": 0, "byteOffset": layout.indices,
               "byteLength": layout.positions - layout.indices, "target": ELEMENT_ARRAY_BUFFER}),
        json!({"name": "positions", "buffer": 0, "byteOffset": layout.positions,
               "byteLength": vertices * 12, "target": ARRAY_BUFFER}),
        json!({"name": "normals", "buffer": 0, "byteOffset": layout.normals,
               "byteLength": vertices * 12, "target": ARRAY_BUFFER}),
        json!({"name": "uvs", "buffer": 0, "byteOffset": layout.uvs,
               "byteLength": vertices * 8, "target": ARRAY_BUFFER}),
        json!({"name": "morph targets", "buffer": 0, "byteOffset": layout.targets,
               "byteLength": layout.times - layout.targets, "byteStride": 12, "target": ARRAY_BUFFER}),
        json!({"name": "key times", "buffer": 0, "byteOffset": layout.times, "byteLength": frames * 4}),
        json!({"name": "key weights", "buffer": 0, "byteOffset": layout.weights, "byteLength": frames * frames * 4}),
    ];
    let (base_min, base_max) = measured
        .base_positions
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let mut accessors = vec![
        json!({"name": "indices", "bufferView": 0, "componentType": UNSIGNED_INT,
               "count": layout.positions / 4, "type": "SCALAR"}),
        json!({"name": "positions", "bufferView": 1, "componentType": FLOAT, "count": vertices, "type": "VEC3",
               "min": vec3_json(base_min), "max": vec3_json(base_max)}),
        json!({"name": "normals", "bufferView": 2, "componentType": FLOAT, "count": vertices, "type": "VEC3"}),
        json!({"name": "uvs", "bufferView": 3, "componentType": FLOAT, "count": vertices, "type": "VEC2"}),
    ];
    let mut targets = Vec::with_capacity(frames);
    let mut target_names = Vec::with_capacity(frames);
    for (k, (frame, (min, max))) in job.frames().zip(&measured.delta_bounds).enumerate() {
        let offset = k * vertices * 24;
        targets.push(json!({"POSITION": accessors.len(), "NORMAL": accessors.len() + 1}));
        target_names.push(format!("frame {frame}"));
        accessors.push(json!({"bufferView": 4, "byteOffset": offset, "componentType": FLOAT, "count": vertices,
                              "type": "VEC3", "min": vec3_json(*min), "max": vec3_json(*max)}));
        accessors.push(json!({"bufferView": 4, "byteOffset": offset + vertices * 12, "componentType": FLOAT,
                              "count": vertices, "type": "VEC3"}));
    }
    let times = accessors.len();
    accessors.push(json!({"name": "key times", "bufferView": 5, "componentType": FLOAT, "count": frames,
                          "type": "SCALAR", "min": [number(key_time_secs(0, job.fps()))],
                          "max": [number(key_time_secs(frames - 1, job.fps()))]}));
    accessors.push(json!({"name": "key weights", "bufferView": 6, "componentType": FLOAT,
                          "count": frames * frames, "type": "SCALAR"}));

    let mut pbr = json!({"metallicFactor": 0.0, "roughnessFactor": 0.9});
    if textured {
        pbr["baseColorFactor"] = json!([1.0, 1.0, 1.0, 1.0]);
        pbr["baseColorTexture"] = json!({"index": 0, "texCoord": 0});
    } else {
        let [r, g, b] = look::PLAIN_FRONT_TINT;
        pbr["baseColorFactor"] = json!([number(r), number(g), number(b), 1.0]);
    }
    let mut document = json!({
        "asset": {
            "version": "2.0",
            "generator": concat!("Drape ", env!("CARGO_PKG_VERSION")),
            "extras": {"fps": job.fps(), "firstFrame": job.first, "lastFrame": job.last,
                       "units": "metres, Y up"},
        },
        "scene": 0,
        "scenes": [{"name": name, "nodes": [0]}],
        "nodes": [{"name": name, "mesh": 0}],
        "meshes": [{
            "name": name,
            "primitives": [{
                "attributes": {"POSITION": 1, "NORMAL": 2, "TEXCOORD_0": 3},
                "indices": 0,
                "material": 0,
                "mode": 4,
                "targets": targets,
            }],
            "weights": vec![0.0; frames],
            "extras": {"targetNames": target_names},
        }],
        "materials": [{"name": format!("{name} cloth"), "doubleSided": true, "pbrMetallicRoughness": pbr}],
        "animations": [{
            "name": format!("frames {}..{} at {} fps", job.first, job.last, job.fps()),
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
            "samplers": [{"input": times, "output": times + 1, "interpolation": "LINEAR"}],
        }],
        "buffers": [{"byteLength": layout.total}],
        "bufferViews": [],
        "accessors": accessors,
    });
    if let Some(uri) = buffer_uri {
        document["buffers"][0]["uri"] = json!(uri);
    }
    if textured {
        let texture_name = format!("{:?}", scene.cloth.texture).to_lowercase();
        let image = match image_uri {
            Some(uri) => json!({"name": texture_name, "uri": uri}),
            None => {
                buffer_views.push(json!({"name": "texture", "buffer": 0, "byteOffset": layout.image,
                                         "byteLength": layout.image_len}));
                json!({"name": texture_name, "mimeType": "image/png", "bufferView": buffer_views.len() - 1})
            }
        };
        document["images"] = json!([image]);
        // Linear filtering with mipmaps, clamped at the cloth's edges.
        document["samplers"] = json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}]);
        document["textures"] = json!([{"name": texture_name, "sampler": 0, "source": 0}]);
    }
    document["bufferViews"] = json!(buffer_views);
    document
}

/// A relative URI for a file beside the `.gltf`: its name, percent-encoded
/// where URIs need it (spaces, `%`, `#`, …).
fn uri_of(path: &Path) -> String {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut uri = String::new();
    for byte in name.bytes() {
        if byte.is_ascii_alphanumeric() || b"-._~".contains(&byte) {
            uri.push(byte as char);
        } else {
            uri.push_str(&format!("%{byte:02X}"));
        }
    }
    uri
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_are_percent_encoded() {
        assert_eq!(uri_of(Path::new("/a/b/magic carpet#1.bin")), "magic%20carpet%231.bin");
        assert_eq!(uri_of(Path::new("flag.bin")), "flag.bin");
    }

    #[test]
    fn layout_parts_follow_each_other_aligned() {
        let layout = Layout::new(6, 12, 5, 3);
        assert_eq!((layout.positions, layout.normals, layout.uvs, layout.image), (48, 120, 192, 240));
        assert_eq!(layout.targets, 248);
        assert_eq!(layout.times, 248 + 3 * 6 * 24);
        assert_eq!(layout.total, layout.times + 12 + 36);
    }
}
