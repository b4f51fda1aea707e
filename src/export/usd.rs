//! USD as text (`.usda`): the cloth as a UsdGeomMesh with time-sampled points.
//!
//! The stage is Y up in metres (`upAxis = "Y"`, `metersPerUnit = 1`); one
//! time code is one frame (`timeCodesPerSecond` = `framesPerSecond` = the
//! scene's fps) and `startTimeCode`/`endTimeCode` are the exported range, so
//! frame F of the scene is time code F. Under `/NAME` (an Xform named after
//! the scene) the Mesh `cloth` has the grid's triangles (`faceVertexCounts`,
//! `faceVertexIndices`, vertex order `j·cols + i`), `orientation =
//! "rightHanded"` (the mesh's triangles run counter-clockwise seen from the
//! side the normals point to), `doubleSided = 1`, no subdivision,
//! `points.timeSamples`, `normals.timeSamples` (interpolation `vertex`),
//! `extent.timeSamples`, `primvars:st` (interpolation `vertex`, with v up as
//! USD's texture coordinates have it: `st = (u, 1 − v)`) and
//! `primvars:displayColor` (the renderer's cloth colour, white when textured).
//! The layer's `doc` string names the scene exactly, written with USD's
//! string escapes ([`usd_string`]); the prim name is the name reduced to an
//! identifier ([`prim_name`]).
//!
//! The points and the normals are two separate blocks, each with every
//! frame, so the frames are evaluated twice: once for the points (and their
//! extents), once for the normals.

use std::fmt::Write as _;
use std::io::{self, Write};

use glam::Vec3;

use super::job::Job;
use crate::look;

/// Writes the whole stage, streaming the frames.
pub(crate) fn write(job: &mut Job, out: &mut dyn Write) -> io::Result<()> {
    let scene = job.source.scene();
    let prim = prim_name(job.name_or("Cloth"));
    let fps = job.fps();
    writeln!(out, "#usda 1.0")?;
    writeln!(out, "(")?;
    writeln!(out, "    defaultPrim = \"{prim}\"")?;
    // The name as it is, quotes, line breaks and all: the string escapes keep it one literal.
    let named = if scene.name.trim().is_empty() { String::new() } else { format!(" of \"{}\"", scene.name) };
    let doc = format!("Drape cloth animation{named}: frames {}..{} at {fps} fps, metres, Y up", job.first, job.last);
    writeln!(out, "    doc = {}", usd_string(&doc))?;
    writeln!(out, "    endTimeCode = {}", job.last)?;
    writeln!(out, "    framesPerSecond = {fps}")?;
    writeln!(out, "    metersPerUnit = 1")?;
    writeln!(out, "    startTimeCode = {}", job.first)?;
    writeln!(out, "    timeCodesPerSecond = {fps}")?;
    writeln!(out, "    upAxis = \"Y\"")?;
    writeln!(out, ")")?;
    writeln!(out)?;
    writeln!(out, "def Xform \"{prim}\" (")?;
    writeln!(out, "    kind = \"component\"")?;
    writeln!(out, ")")?;
    writeln!(out, "{{")?;
    writeln!(out, "    def Mesh \"cloth\"")?;
    writeln!(out, "    {{")?;
    writeln!(out, "        uniform bool doubleSided = 1")?;
    writeln!(out, "        uniform token orientation = \"rightHanded\"")?;
    writeln!(out, "        uniform token subdivisionScheme = \"none\"")?;

    let base = job.source.mesh(job.first);
    let mut line = String::new();
    line.push_str("        int[] faceVertexCounts = [");
    for k in 0..base.triangle_count() {
        line.push_str(if k == 0 { "3" } else { ", 3" });
    }
    line.push(']');
    writeln!(out, "{line}")?;
    line.clear();
    line.push_str("        int[] faceVertexIndices = [");
    for (k, index) in base.indices.iter().enumerate() {
        if k > 0 {
            line.push_str(", ");
        }
        let _ = write!(line, "{index}");
    }
    line.push(']');
    writeln!(out, "{line}")?;
    line.clear();
    line.push_str("        texCoord2f[] primvars:st = [");
    for (k, uv) in base.uvs.iter().enumerate() {
        if k > 0 {
            line.push_str(", ");
        }
        let _ = write!(line, "({}, {})", uv.x, 1.0 - uv.y);
    }
    line.push_str("] (");
    writeln!(out, "{line}")?;
    writeln!(out, "            interpolation = \"vertex\"")?;
    writeln!(out, "        )")?;
    let [r, g, b] = look::front_tint(scene.cloth.texture);
    writeln!(out, "        color3f[] primvars:displayColor = [({r}, {g}, {b})] (")?;
    writeln!(out, "            interpolation = \"constant\"")?;
    writeln!(out, "        )")?;

    // Pass 1: the points, and each frame's extent.
    let mut extents = Vec::with_capacity(job.frame_count());
    writeln!(out, "        point3f[] points.timeSamples = {{")?;
    job.for_each_frame(|_, frame, mesh| {
        let (min, max) =
            mesh.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        extents.push((frame, min, max));
        write_sample(out, &mut line, frame, &mesh.positions)
    })?;
    writeln!(out, "        }}")?;
    writeln!(out, "        float3[] extent.timeSamples = {{")?;
    for (frame, min, max) in extents {
        writeln!(out, "            {frame}: [{}, {}],", tuple(min), tuple(max))?;
    }
    writeln!(out, "        }}")?;

    // Pass 2: the normals.
    writeln!(out, "        normal3f[] normals (")?;
    writeln!(out, "            interpolation = \"vertex\"")?;
    writeln!(out, "        )")?;
    writeln!(out, "        normal3f[] normals.timeSamples = {{")?;
    job.for_each_frame(|_, frame, mesh| write_sample(out, &mut line, frame, &mesh.normals))?;
    writeln!(out, "        }}")?;
    writeln!(out, "    }}")?;
    writeln!(out, "}}")?;
    Ok(())
}

/// One time sample: `F: [(x, y, z), …],` on one line.
fn write_sample(out: &mut dyn Write, line: &mut String, frame: i32, values: &[Vec3]) -> io::Result<()> {
    line.clear();
    let _ = write!(line, "            {frame}: [");
    for (k, v) in values.iter().enumerate() {
        if k > 0 {
            line.push_str(", ");
        }
        line.push_str(&tuple(*v));
    }
    line.push_str("],");
    writeln!(out, "{line}")
}

/// `(x, y, z)` with each f32 in its shortest form that reads back exactly.
fn tuple(v: Vec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

/// `text` as a USD string literal: in double quotes, with `\\`, `\"`, `\n`,
/// `\r` and `\t` escaped, and every other control character and line or
/// paragraph separator written as `\xHH` escapes of its UTF-8 bytes, so the
/// literal stays on one line and USD reads back exactly `text`.
pub fn usd_string(text: &str) -> String {
    let mut quoted = String::with_capacity(text.len() + 2);
    quoted.push('"');
    for c in text.chars() {
        match c {
            '\\' => quoted.push_str("\\\\"),
            '"' => quoted.push_str("\\\""),
            '\n' => quoted.push_str("\\n"),
            '\r' => quoted.push_str("\\r"),
            '\t' => quoted.push_str("\\t"),
            c if c.is_control() || c == '\u{2028}' || c == '\u{2029}' => {
                for byte in c.encode_utf8(&mut [0; 4]).bytes() {
                    let _ = write!(quoted, "\\x{byte:02x}");
                }
            }
            c => quoted.push(c),
        }
    }
    quoted.push('"');
    quoted
}

/// A USD prim name from a scene name: letters, digits and `_`, not starting
/// with a digit (`Magic carpet` → `Magic_carpet`).
pub fn prim_name(name: &str) -> String {
    let mut prim: String =
        name.trim().chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).collect();
    if prim.is_empty() {
        prim.push_str("Cloth");
    }
    if prim.starts_with(|c: char| c.is_ascii_digit()) {
        prim.insert(0, '_');
    }
    prim
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_are_escaped_onto_one_line() {
        assert_eq!(usd_string("Magic carpet"), "\"Magic carpet\"");
        assert_eq!(usd_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
        assert_eq!(usd_string("l1\nl2\r\tx"), "\"l1\\nl2\\r\\tx\"");
        assert_eq!(
            usd_string("nul\0 del\u{7f} nel\u{85} ls\u{2028}"),
            "\"nul\\x00 del\\x7f nel\\xc2\\x85 ls\\xe2\\x80\\xa8\""
        );
        assert_eq!(usd_string("é ü ✓"), "\"é ü ✓\"");
    }

    #[test]
    fn prim_names_are_identifiers() {
        assert_eq!(prim_name("Magic carpet"), "Magic_carpet");
        assert_eq!(prim_name("3 flags!"), "_3_flags_");
        assert_eq!(prim_name(" "), "Cloth");
    }
}
