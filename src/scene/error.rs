//! Errors from reading, checking and writing scene files, in the user's terms.
//!
//! A problem inside a file reads `FILE:LINE:COL: message` when its place is
//! known and `FILE: message` otherwise, e.g.
//! `tent.ron:14:17: pin (40, 3) is outside the 33 × 25 grid`. The file's
//! name and the message are shown [`escaped`]: a message may quote the
//! file's own text, and neither may move a terminal's cursor or reorder
//! what it shows.

use std::io;
use std::path::PathBuf;

use crate::atomic_file::io_reason;

use super::colliders::Collider;
use super::display::escaped;
use super::layers::Layer;
use super::locate::{
    Found, TextPosition, TokenKind, closing, found_at, position_after, unclosed_bracket, unclosed_comment,
};

/// Why a scene could not be loaded, parsed or saved.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The text is not a valid scene: a syntax error, a value of the wrong
    /// type, a missing or unknown field, or a value validation rejects.
    #[error("{}", located(.file, .position, .message))]
    Invalid {
        /// The file as the user named it (or another label for in-memory text).
        file: String,
        /// Where in the text, when known.
        position: Option<TextPosition>,
        message: String,
    },
    /// The file could not be read.
    #[error("cannot read {}: {}", shown_path(.path), io_reason(.source))]
    Read {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    /// The file is larger than any scene Drape reads; nothing beyond the limit was read.
    #[error("{} is too large for a scene file: over {} MiB", shown_path(.path), .limit_bytes / (1024 * 1024))]
    TooLarge { path: PathBuf, limit_bytes: u64 },
    /// The file could not be written; the previous file, if any, is untouched.
    #[error("cannot write {}: {}", shown_path(.path), io_reason(.source))]
    Write {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
}

impl SceneError {
    /// Where in the file the problem is, when known.
    pub fn position(&self) -> Option<TextPosition> {
        match self {
            SceneError::Invalid { position, .. } => *position,
            _ => None,
        }
    }

    /// The message without the file and position prefix.
    pub fn message(&self) -> String {
        match self {
            SceneError::Invalid { message, .. } => escaped(message).into_owned(),
            SceneError::Read { source, .. } | SceneError::Write { source, .. } => io_reason(source),
            SceneError::TooLarge { limit_bytes, .. } => {
                format!("too large for a scene file: over {} MiB", limit_bytes / (1024 * 1024))
            }
        }
    }

    pub(crate) fn invalid(file: &str, position: Option<TextPosition>, message: impl Into<String>) -> Self {
        SceneError::Invalid { file: file.to_owned(), position, message: message.into() }
    }

    /// A ron parse error, reworded and placed.
    pub(crate) fn from_ron(file: &str, text: &str, error: &ron::error::SpannedError) -> Self {
        let known =
            |p: &ron::error::Position| (p.line > 0 && p.col > 0).then_some(TextPosition { line: p.line, col: p.col });
        let missing_comma = error.code == ron::Error::ExpectedComma;
        // ron's span runs from the last thing it read to where it stopped; for
        // a missing comma, what stands where it stopped is the interesting part.
        let mut position = if missing_comma { known(&error.span.end) } else { known(&error.span.start) };
        let found = position.and_then(|p| found_at(text, p));
        // ron may stop inside a token (after the `-` of `-3`) or before the
        // whitespace ahead of it: point at the token itself.
        if let Some(found) = &found {
            position = Some(found.pos);
        }
        let message = match (&error.code, &found) {
            (ron::Error::Eof, _) | (ron::Error::ExpectedComma, None) => match unclosed_bracket(text) {
                Some((open, at)) => format!(
                    "unexpected end of file: the `{open}` at {at} is never closed (a `{}` is missing)",
                    closing(open)
                ),
                None => describe_ron_error(&ron::Error::Eof),
            },
            // A closing bracket that does not match the innermost open one.
            (_, Some(Found { kind: TokenKind::Close(close), open_bracket: Some((open, at)), .. }))
                if closing(*open) != *close =>
            {
                format!("`{close}` does not close the `{open}` at {at}: is a `{}` missing?", closing(*open))
            }
            // Point where the comma belongs, not at the next line's first word.
            (ron::Error::ExpectedComma, Some(found)) => {
                position = found.after_previous.or(position);
                format!("expected a comma before `{}`", found.text)
            }
            (code, Some(found)) if names_what_was_found(code) => {
                format!("{}, found `{}`", describe_ron_error(code), found.text)
            }
            (ron::Error::IntegerOutOfBounds, Some(found)) if found.text.starts_with('-') => {
                format!("the number {} is out of range here: this field cannot be negative", found.text)
            }
            (ron::Error::IntegerOutOfBounds, Some(found)) => {
                format!("the number {} is too large for this field", found.text)
            }
            (ron::Error::UnclosedBlockComment, _) => {
                position = unclosed_comment(text).or(position);
                describe_ron_error(&error.code)
            }
            (code, _) => describe_ron_error(code),
        };
        Self::invalid(file, position, message)
    }

    /// Bytes that are not UTF-8: the position of the first bad byte.
    pub(crate) fn not_utf8(file: &str, bytes: &[u8], error: &std::str::Utf8Error) -> Self {
        let valid = &bytes[..error.valid_up_to()];
        let prefix = std::str::from_utf8(valid).unwrap_or("");
        let bad = bytes.get(error.valid_up_to()).copied().unwrap_or(0);
        Self::invalid(
            file,
            Some(position_after(prefix)),
            format!("the file is not UTF-8 text (invalid byte 0x{bad:02X})"),
        )
    }
}

/// Errors where "found `…`" helps: ron stopped at an unexpected token.
fn names_what_was_found(code: &ron::Error) -> bool {
    use ron::Error as E;
    matches!(
        code,
        E::ExpectedArray
            | E::ExpectedArrayEnd
            | E::ExpectedBoolean
            | E::ExpectedComma
            | E::ExpectedFloat
            | E::ExpectedInteger
            | E::ExpectedOptionEnd
            | E::ExpectedStructLikeEnd
            | E::ExpectedMap
            | E::ExpectedMapColon
            | E::ExpectedMapEnd
            | E::ExpectedStructLike
            | E::ExpectedNamedStructLike(_)
            | E::ExpectedUnit
            | E::ExpectedString
            | E::ExpectedIdentifier
            | E::TrailingCharacters
    )
}

fn located(file: &str, position: &Option<TextPosition>, message: &str) -> String {
    let (file, message) = (escaped(file), escaped(message));
    match position {
        Some(p) => format!("{file}:{}:{}: {message}", p.line, p.col),
        None => format!("{file}: {message}"),
    }
}

fn shown_path(path: &std::path::Path) -> String {
    escaped(&path.display().to_string()).into_owned()
}

/// The user's word for a struct or enum of the scene file: a layer kind
/// (`Sway`) is "Sway layer".
fn user_name(type_name: &str) -> String {
    if Layer::KINDS.contains(&type_name) {
        return format!("{type_name} layer");
    }
    if Collider::KINDS.contains(&type_name) {
        return format!("{type_name} collider");
    }
    let name = match type_name {
        "Scene" => "the scene",
        "Cloth" => "cloth",
        "Timeline" => "timeline",
        "Key" => "key",
        "Pin" => "pin",
        "RelaxSettings" => "relax",
        "ParamKey" => "parameter key",
        "Ease" => "ease",
        "Layer" => "layer",
        "WaveAxis" => "wave axis",
        "ClothTexture" => "cloth texture",
        "ToonSettings" => "toon",
        "View" => "view",
        "Collider" => "collider",
        other => other,
    };
    name.to_owned()
}

/// Which struct a list of field names belongs to, when ron does not say.
fn struct_from_fields(fields: &[&str]) -> Option<String> {
    if let Some((kind, _)) = Layer::KIND_PARAMS
        .iter()
        .find(|(_, params)| fields.len() == params.len() + 2 && params.iter().all(|spec| fields.contains(&spec.name)))
    {
        return Some(format!("{kind} layer"));
    }
    let has = |f: &str| fields.contains(&f);
    let collider = if has("file") && has("scale") {
        Some("Mesh")
    } else if has("center") && has("size") {
        Some("Box")
    } else if has("center") && has("height") {
        Some("Cylinder")
    } else if has("center") && has("radius") {
        Some("Sphere")
    } else if has("a") && has("b") {
        Some("Capsule")
    } else if has("height") && has("thickness") {
        Some("Ground")
    } else {
        None
    };
    if let Some(kind) = collider {
        return Some(format!("{kind} collider"));
    }
    let name = if has("version") {
        "the scene"
    } else if has("pins") {
        "key"
    } else if has("pos") {
        "pin"
    } else if has("size") {
        "cloth"
    } else if has("fps") {
        "timeline"
    } else if has("iterations") {
        "relax"
    } else if has("value") {
        "parameter key"
    } else if has("yaw_deg") {
        "view"
    } else {
        return None;
    };
    Some(name.to_owned())
}

fn in_struct(outer: &Option<String>, fields: &[&str]) -> String {
    match outer.as_deref().filter(|o| !o.is_empty()).map(user_name).or_else(|| struct_from_fields(fields)) {
        Some(name) => format!(" in {name}"),
        None => String::new(),
    }
}

/// Serde's name for an expected type, in the user's words.
fn expected_in_user_terms(expected: &str) -> String {
    let stripped = expected.trim_start_matches("a ").trim_start_matches("an ");
    match stripped {
        "f64" | "f32" => "a number".to_owned(),
        "u8" | "u16" | "u32" | "u64" | "usize" => "a whole number ≥ 0".to_owned(),
        "i8" | "i16" | "i32" | "i64" | "isize" => "a whole number".to_owned(),
        "bool" | "boolean" => "true or false".to_owned(),
        "string" => "a string in double quotes".to_owned(),
        "sequence" => "a list `[…]`".to_owned(),
        _ => {
            if let Some(name) = stripped.strip_prefix("struct ") {
                format!("a {} `(…)`", user_name(name.trim_matches('`')))
            } else if let Some(name) = stripped.strip_prefix("enum ") {
                format!("a {} name", user_name(name.trim_matches('`')))
            } else if let Some(size) = stripped.strip_prefix("tuple of size ") {
                format!("a tuple of {size} numbers like `({})`", vec!["0"; size.parse().unwrap_or(2).min(4)].join(", "))
            } else {
                expected.to_owned()
            }
        }
    }
}

fn list(names: &[&str]) -> String {
    names.join(", ")
}

/// ron's error codes reworded for someone editing a scene by hand.
pub(crate) fn describe_ron_error(code: &ron::Error) -> String {
    use ron::Error as E;
    match code {
        E::Eof => "unexpected end of file (is a bracket or a value missing?)".to_owned(),
        E::ExpectedArray => "expected a list starting with `[`".to_owned(),
        E::ExpectedArrayEnd => "expected `,` or the closing `]` of the list".to_owned(),
        E::ExpectedBoolean => "expected true or false".to_owned(),
        E::ExpectedComma => "expected a comma".to_owned(),
        E::ExpectedFloat => "expected a number".to_owned(),
        E::FloatUnderscore => "unexpected `_` in a number".to_owned(),
        E::ExpectedInteger => "expected a whole number".to_owned(),
        E::ExpectedOptionEnd | E::ExpectedStructLikeEnd => "expected `,` or the closing `)`".to_owned(),
        E::ExpectedMap => "expected a map starting with `{`".to_owned(),
        E::ExpectedMapColon => "expected `:` after the name".to_owned(),
        E::ExpectedMapEnd => "expected `,` or the closing `}`".to_owned(),
        E::ExpectedDifferentStructName { expected, found } => {
            format!("expected {} but found `{found}`", user_name(expected))
        }
        E::ExpectedStructLike | E::ExpectedNamedStructLike(_) => "expected `(`".to_owned(),
        E::ExpectedUnit => "expected `()`".to_owned(),
        E::ExpectedString => "expected a string in double quotes".to_owned(),
        E::ExpectedStringEnd => "the string has no closing `\"`".to_owned(),
        E::ExpectedIdentifier => "expected a name".to_owned(),
        E::InvalidEscape(what) => format!("invalid escape in a string: {what}"),
        E::IntegerOutOfBounds => "the number is out of range for this field".to_owned(),
        E::InvalidIntegerDigit { digit, base } => {
            format!("invalid digit {digit:?} in a base-{base} number")
        }
        E::NoSuchExtension(name) => format!("unknown RON extension `{name}`"),
        E::UnclosedBlockComment => "a `/*` comment is never closed".to_owned(),
        E::UnclosedLineComment => "the file ends inside a `//` comment".to_owned(),
        E::UnderscoreAtBeginning => "a number cannot start with `_`".to_owned(),
        E::UnexpectedChar(c) => format!("unexpected character {c:?}"),
        E::Utf8Error(_) => "the text is not valid UTF-8".to_owned(),
        E::TrailingCharacters => "unexpected text after the end of the scene".to_owned(),
        E::InvalidValueForType { expected, found } => {
            // ron calls a `(name: value)` struct "a map".
            let found = if found == "a map" { "`(…)`" } else { found.as_str() };
            format!("expected {} but found {found}", expected_in_user_terms(expected))
        }
        E::ExpectedDifferentLength { expected, found } => {
            let found = match found {
                0 => "no elements".to_owned(),
                1 => "one element".to_owned(),
                n => format!("{n} elements"),
            };
            format!("expected {} but found {found}", expected_in_user_terms(expected))
        }
        E::NoSuchEnumVariant { expected, found, outer } => {
            let what = outer.as_deref().map_or_else(|| "variant".to_owned(), user_name);
            // A layer kind's former name still reads, but is not offered.
            let offered: Vec<&str> = expected
                .iter()
                .copied()
                .filter(|name| !Layer::FORMER_KINDS.iter().any(|(old, _)| old == name))
                .collect();
            format!("unknown {what} `{found}` (expected one of: {})", list(&offered))
        }
        E::NoSuchStructField { expected, found, outer } => {
            format!("unknown field `{found}`{} (expected one of: {})", in_struct(outer, expected), list(expected))
        }
        E::MissingStructField { field, outer } => {
            format!("missing field `{field}`{}", in_struct(outer, &[]))
        }
        E::DuplicateStructField { field, outer } => {
            format!("field `{field}` is given twice{}", in_struct(outer, &[]))
        }
        E::InvalidIdentifier(name) => format!("invalid name {name:?}"),
        E::ExceededRecursionLimit => "the brackets are nested too deeply".to_owned(),
        E::Message(text) => lowercase_first(text),
        other => lowercase_first(&other.to_string()),
    }
}

fn lowercase_first(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_with_and_without_position() {
        let with = SceneError::invalid(
            "tent.ron",
            Some(TextPosition { line: 14, col: 17 }),
            "pin (40, 3) is outside the 33 × 25 grid",
        );
        assert_eq!(with.to_string(), "tent.ron:14:17: pin (40, 3) is outside the 33 × 25 grid");
        let without = SceneError::invalid("tent.ron", None, "the file is empty");
        assert_eq!(without.to_string(), "tent.ron: the file is empty");
    }

    #[test]
    fn quoted_text_and_file_names_are_shown_escaped() {
        let error = SceneError::invalid(
            "evil\u{1b}[2J.ron",
            Some(TextPosition { line: 3, col: 9 }),
            "expected `(`, found `\"\0\u{202e}exe\"`",
        );
        assert_eq!(error.to_string(), "evil\\u{1b}[2J.ron:3:9: expected `(`, found `\"\\0\\u{202e}exe\"`");
        assert_eq!(error.message(), "expected `(`, found `\"\\0\\u{202e}exe\"`");
        let unreadable = SceneError::Read { path: "a\nb.ron".into(), source: io::Error::from_raw_os_error(2) };
        assert_eq!(unreadable.to_string(), "cannot read a\\nb.ron: No such file or directory");
    }

    #[test]
    fn io_errors_name_the_path_without_os_error_codes() {
        let error = SceneError::Read { path: "scenes/x.ron".into(), source: io::Error::from_raw_os_error(2) };
        assert_eq!(error.to_string(), "cannot read scenes/x.ron: No such file or directory");
        assert!(std::error::Error::source(&error).is_some());
    }

    #[test]
    fn unknown_and_missing_fields_read_naturally() {
        let unknown = ron::Error::NoSuchStructField {
            expected: &["frame", "pins", "elasticity"],
            found: "elastisity".into(),
            outer: Some("Key".into()),
        };
        assert_eq!(
            describe_ron_error(&unknown),
            "unknown field `elastisity` in key (expected one of: frame, pins, elasticity)"
        );
        let missing = ron::Error::MissingStructField { field: "pins", outer: None };
        assert_eq!(describe_ron_error(&missing), "missing field `pins`");
    }

    #[test]
    fn utf8_errors_point_at_the_bad_byte() {
        let mut bytes = b"(\n  name: \"a".to_vec();
        bytes.extend([0xff, b'"', b')']);
        let error = std::str::from_utf8(&bytes).unwrap_err();
        let error = SceneError::not_utf8("x.ron", &bytes, &error);
        assert_eq!(error.to_string(), "x.ron:2:11: the file is not UTF-8 text (invalid byte 0xFF)");
    }
}
