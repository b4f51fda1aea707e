//! Wavefront OBJ: positions, UVs, normals and triangles in vertex order `j·cols + i`.

use std::io::{self, Write};

use crate::mesh::Mesh;

/// Writes `mesh` as one OBJ object named `name` (1-based indices, `f v/vt/vn`).
/// The name is written as [`object_name`] makes it: always one line, so no
/// name adds or changes geometry.
pub fn write_obj(mesh: &Mesh, name: &str, out: &mut dyn Write) -> io::Result<()> {
    writeln!(out, "# Drape cloth: {} × {} grid, vertex order j·cols + i", mesh.cols, mesh.rows)?;
    writeln!(out, "o {}", object_name(name))?;
    for p in &mesh.positions {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for t in &mesh.uvs {
        // OBJ's v runs upwards; our v = 0 is the top edge.
        writeln!(out, "vt {} {}", t.x, 1.0 - t.y)?;
    }
    for n in &mesh.normals {
        writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    for tri in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [tri[0] + 1, tri[1] + 1, tri[2] + 1];
        writeln!(out, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
    }
    Ok(())
}

/// A scene name as an OBJ object name, which runs to the end of its line:
/// line breaks, NULs, tabs and every other control or non-space whitespace
/// character become spaces, spaces at either end go, a trailing `\` (a line
/// continuation to some readers) is dropped, and an empty name becomes `cloth`.
pub fn object_name(name: &str) -> String {
    let one_line: String = name.chars().map(|c| if c.is_control() || c.is_whitespace() { ' ' } else { c }).collect();
    let trimmed = one_line.trim().trim_end_matches('\\').trim_end();
    if trimmed.is_empty() { "cloth".to_string() } else { trimmed.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn writes_every_element_once() {
        let positions: Vec<DVec3> = (0..6).map(|k| DVec3::new((k % 3) as f64, -((k / 3) as f64), 0.0)).collect();
        let mesh = Mesh::from_grid(3, 2, &positions);
        let mut buf = Vec::new();
        write_obj(&mesh, "curtain", &mut buf).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let count = |prefix: &str| text.lines().filter(|l| l.starts_with(prefix)).count();
        assert_eq!((count("v "), count("vt "), count("vn "), count("f ")), (6, 6, 6, 4));
        assert!(text.contains("o curtain"));
        assert!(text.contains("v 2 -1 0"));
        assert!(text.contains("f 1/1/1 4/4/4 2/2/2"));
    }

    #[test]
    fn names_stay_on_their_line() {
        assert_eq!(object_name("Cur\nv 1e30 1e30 1e30\nf 1 2 3"), "Cur v 1e30 1e30 1e30 f 1 2 3");
        assert_eq!(object_name("a\0b\r\nc\u{2028}d\u{85}e\tf"), "a b  c d e f");
        assert_eq!(object_name("ends in \\\\"), "ends in");
        assert_eq!(object_name(" \n "), "cloth");
        assert_eq!(object_name("Magic carpet"), "Magic carpet");
    }
}
