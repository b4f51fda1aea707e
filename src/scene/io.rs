//! Reading and writing scene files: parse + validate, load, atomic save.

use std::path::Path;

use super::error::SceneError;
use super::format::to_ron_string;
use super::locate::{has_tokens, locate};
use super::mesh_files::read_meshes;
use super::read_capped::read_capped;
use super::reference_files::read_references;
use super::types::Scene;
use crate::atomic_file::write_atomically;

const SCENE_START: &str = "a scene starts with `(version: 1, cloth: …, keys: […])`";

/// Parses and validates scene text. `file_label` names the text in messages
/// (`tent.ron:14:17: …`). The first problem is reported with its line and
/// column when known. A leading byte-order mark is ignored. Never panics,
/// whatever the text.
pub fn parse(text: &str, file_label: &str) -> Result<Scene, SceneError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(SceneError::invalid(file_label, None, format!("the file is empty: {SCENE_START}")));
    }
    if !has_tokens(text) {
        return Err(SceneError::invalid(file_label, None, format!("the file holds only comments: {SCENE_START}")));
    }
    // `view: (…)` reads like `view: Some((…))`: an optional block is written the way it looks.
    let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let scene: Scene = options.from_str(text).map_err(|error| SceneError::from_ron(file_label, text, &error))?;
    if let Err(issues) = scene.validate()
        && let Some(first) = issues.first()
    {
        return Err(SceneError::invalid(file_label, locate(text, &first.path), first.message.clone()));
    }
    Ok(scene)
}

/// Like [`parse`] for raw bytes: bytes that are not UTF-8 are an error
/// pointing at the first bad byte, never a panic.
pub fn parse_bytes(bytes: &[u8], file_label: &str) -> Result<Scene, SceneError> {
    let text = std::str::from_utf8(bytes).map_err(|error| SceneError::not_utf8(file_label, bytes, &error))?;
    parse(text, file_label)
}

/// Largest scene file [`load`] reads, in bytes (64 MiB; the largest example
/// scene is a few kilobytes).
pub const MAX_SCENE_FILE_BYTES: u64 = 64 * 1024 * 1024;

/// Reads, parses and validates the scene file at `path`, and reads the mesh
/// files its colliders and references name (relative to it). Messages name the
/// file as `path` displays (`scenes/tent.ron:14:17: …`). Only a regular file
/// is read (a FIFO, a device or a folder is refused unopened), and one larger
/// than [`MAX_SCENE_FILE_BYTES`] is refused without being read whole.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes = read_capped(path, MAX_SCENE_FILE_BYTES)?;
    let mut scene = parse_bytes(&bytes, &path.display().to_string())?;
    // The bytes are UTF-8: `parse_bytes` checked.
    let text = std::str::from_utf8(&bytes).unwrap_or_default();
    read_meshes(&mut scene, path, text)?;
    read_references(&mut scene, path, text)?;
    Ok(scene)
}

/// Writes the scene to `path` atomically: the text goes to a new temporary file
/// in the same directory, which is flushed to disk and then renamed over
/// `path` (on Unix the directory is then synced, best effort). On any failure
/// the previous file at `path` is left as it was and the temporary file is
/// removed. An existing file's permissions carry over. A symlink at `path` is
/// followed: the file it points to is replaced and the link stays (see
/// [`write_atomically`]).
pub fn save(scene: &Scene, path: &Path) -> Result<(), SceneError> {
    let text = to_ron_string(scene);
    write_atomically(path, |w| w.write_all(text.as_bytes()))
        .map_err(|source| SceneError::Write { path: path.to_owned(), source })
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = "(version: 1, cloth: (size: (1.0, 1.0), grid: (2, 2)), \
                           keys: [(frame: 0, pins: [(grid: (0, 0), pos: (0.0, 1.0, 0.0))])])";

    /// `MINIMAL` with `layers: [LAYER]` added.
    fn with_layer(layer: &str) -> String {
        format!("{}, layers: [{layer}])", &MINIMAL[..MINIMAL.len() - 1])
    }

    fn message(text: &str) -> String {
        match parse(text, "t.ron") {
            Ok(_) => "parsed".to_owned(),
            Err(error) => error.to_string(),
        }
    }

    #[test]
    fn syntax_errors_point_where_the_fix_goes() {
        assert_eq!(
            message("(version: 1\n  // comment\n   cloth: (size: (1.0, 1.0), grid: (2, 2)))"),
            "t.ron:1:12: expected a comma before `cloth`"
        );
        assert_eq!(
            message(&MINIMAL[..MINIMAL.len() - 1]),
            "t.ron:1:119: unexpected end of file: the `(` at 1:1 is never closed (a `)` is missing)"
        );
        assert_eq!(
            message("(version: 1, keys: [(frame: 0, pins: [) ])"),
            "t.ron:1:39: `)` does not close the `[` at 1:38: is a `]` missing?"
        );
        assert_eq!(message("(version: 1, /* unclosed"), "t.ron:1:14: a `/*` comment is never closed");
        assert_eq!(message("(version: 1, name: \"abc"), "t.ron:1:20: the string has no closing `\"`");
        assert_eq!(
            message(&format!("{MINIMAL} trailing")),
            "t.ron:1:121: unexpected text after the end of the scene, found `trailing`"
        );
    }

    #[test]
    fn type_errors_say_what_was_expected() {
        assert_eq!(
            message(&with_layer("Sway((magnitude: (frame: 0, value: 1.0), direction: (1.0, 0.0, 0.0)))")),
            "t.ron:1:147: expected a number or a list of keys like [(frame: 0, value: 1.0)] but found `(…)`"
        );
        assert_eq!(
            message(&with_layer("Sway((magnitude: [(frame: 0, valu: 1.0)], direction: (1.0, 0.0, 0.0)))")),
            "t.ron:1:159: unknown field `valu` in parameter key (expected one of: frame, value, ease)"
        );
        assert_eq!(
            message(&with_layer("Swirl((magnitude: 1.0))")),
            "t.ron:1:130: unknown layer `Swirl` (expected one of: Sway, Wave, Gusts, FollowThrough)"
        );
        assert_eq!(
            message(&with_layer("Noise((ampltude: 0.1, direction: (1.0, 0.0, 0.0)))")),
            "t.ron:1:137: unknown field `ampltude` in Gusts layer (expected one of: name, enabled, weight, \
             amplitude, scale, speed, direction, turbulence, octaves, seed, falloff)"
        );
        assert_eq!(
            message(&with_layer("Gusts((amplitude: 0.1))")),
            "t.ron:1:151: missing field `direction` in Gusts layer"
        );
        assert_eq!(
            message(&with_layer("Wave((magnitude: 1.0, axis: Fixed((1.0, 0.0))))")),
            "t.ron:1:173: expected a tuple of 3 numbers like `(0, 0, 0)` but found 2 elements"
        );
        assert_eq!(
            message(&with_layer("Sway((enabled: 1, magnitude: 1.0, direction: (1.0, 0.0, 0.0)))")),
            "t.ron:1:145: expected true or false, found `1`"
        );
        assert_eq!(
            message("(version: 1, cloth: (size: (1.0, 1.0), grid: (2, 2), grid: (3, 3)))"),
            "t.ron:1:54: field `grid` is given twice in cloth"
        );
        assert_eq!(message("(version: 1, cloth: 5)"), "t.ron:1:21: expected `(`, found `5`");
        assert_eq!(
            message("(version: 1, timeline: (start: 99999999999))"),
            "t.ron:1:32: the number 99999999999 is too large for this field"
        );
    }

    #[test]
    fn validation_errors_point_at_the_value() {
        let text = MINIMAL.replace("grid: (0, 0)", "grid: (5, 0)");
        assert_eq!(message(&text), "t.ron:1:87: pin (5, 0) is outside the 2 × 2 grid");
        assert_eq!(
            message(&with_layer("Sway((magnitude: [], direction: (1.0, 0.0, 0.0)))")),
            "t.ron:1:147: Sway layer 1: magnitude has an empty list of keys: write a plain number or at least one key"
        );
    }

    #[test]
    fn empty_files_and_byte_order_marks() {
        assert_eq!(
            message(" \n\t"),
            "t.ron: the file is empty: a scene starts with `(version: 1, cloth: …, keys: […])`"
        );
        assert_eq!(
            message("// just a comment\n/* and another */"),
            "t.ron: the file holds only comments: a scene starts with `(version: 1, cloth: …, keys: […])`"
        );
        assert_eq!(message(&format!("\u{feff}{MINIMAL}")), "parsed");
        assert_eq!(
            message(&format!("\u{feff}{}", MINIMAL.replace("version: 1", "version: 7"))),
            "t.ron:1:11: unsupported scene version 7 (this Drape reads version 1)"
        );
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        assert_eq!(message(&"(".repeat(100_000)), "t.ron:1:2: expected a name, found `(`");
        let deep = with_layer(&format!(
            "Sway((magnitude: {}1.0{}, direction: (1.0, 0.0, 0.0)))",
            "[".repeat(10_000),
            "]".repeat(10_000)
        ));
        assert_eq!(message(&deep), "t.ron:1:148: expected `(`, found `[`");
    }

    #[test]
    fn bytes_that_are_not_utf8_are_an_error() {
        let mut bytes = MINIMAL.as_bytes().to_vec();
        bytes.insert(1, 0xC3);
        let error = parse_bytes(&bytes, "b.ron").unwrap_err();
        assert_eq!(error.to_string(), "b.ron:1:2: the file is not UTF-8 text (invalid byte 0xC3)");
        assert!(parse_bytes(MINIMAL.as_bytes(), "b.ron").is_ok());
    }
}
