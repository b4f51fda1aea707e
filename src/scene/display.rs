//! Numbers and names as messages and summaries show them: never hundreds of
//! digits, never a name that fills the screen or moves the terminal's cursor.

/// Longest name, in characters, that messages and summaries show whole.
pub const MAX_SHOWN_NAME_CHARS: usize = 60;

/// `v` in its shortest exact form (`0.25`, `-3`, `1000`), or in scientific
/// form when that would run long: from 1e12 up, or below 1e-6 (`1e308`,
/// `2.5e-9`). Infinities and NaN read `inf`, `-inf`, `NaN`.
pub fn readable_number(v: f64) -> String {
    let magnitude = v.abs();
    if v.is_finite() && v != 0.0 && !(1e-6..1e12).contains(&magnitude) { format!("{v:e}") } else { format!("{v}") }
}

/// A vector as `(x, y, z)`, each number as [`readable_number`] writes it.
pub fn readable_vec3((x, y, z): (f64, f64, f64)) -> String {
    format!("({}, {}, {})", readable_number(x), readable_number(y), readable_number(z))
}

/// A name (a scene's, a layer's) to print on one line: written as
/// [`escaped`] writes it, and cut as [`truncated_name`] cuts it.
pub fn shown_name(name: &str) -> String {
    escaped(&truncated_name(name)).into_owned()
}

/// Text from a file or a user (a name, a path, a quoted token) made safe to
/// print: control characters (line breaks, tabs, NUL, terminal escapes) and
/// the invisible characters that reorder or hide text (bidi controls such as
/// U+202E, zero-width ones, line separators) are written as escapes (`\n`,
/// `\0`, `\u{1b}`, `\u{202e}`), so what a terminal or a label shows is what
/// the text holds. Everything else, accents and scripts included, stays.
pub fn escaped(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(needs_escape) {
        return text.into();
    }
    let mut shown = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            shown.extend(c.escape_debug());
        } else if needs_escape(c) {
            shown.extend(c.escape_unicode());
        } else {
            shown.push(c);
        }
    }
    shown.into()
}

/// Control characters, and the format characters that change how the text
/// around them is shown: bidi marks, embeddings, overrides and isolates,
/// zero-width characters, line and paragraph separators, tags.
fn needs_escape(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{180e}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2028}'..='\u{202e}'
                | '\u{2060}'..='\u{206f}'
                | '\u{feff}'
                | '\u{fff9}'..='\u{fffb}'
                | '\u{e0000}'..='\u{e007f}'
        )
}

/// `name` itself, or when longer than [`MAX_SHOWN_NAME_CHARS`] characters
/// its first ones and `…`, [`MAX_SHOWN_NAME_CHARS`] in all.
pub fn truncated_name(name: &str) -> std::borrow::Cow<'_, str> {
    match name.char_indices().nth(MAX_SHOWN_NAME_CHARS) {
        None => name.into(),
        Some(_) => {
            let (cut, _) = name.char_indices().nth(MAX_SHOWN_NAME_CHARS - 1).expect("longer than the cut");
            format!("{}…", &name[..cut]).into()
        }
    }
}

/// `1536` → `1.5 KiB`, `9663676416` → `9.0 GiB`: binary units with one decimal.
pub fn readable_bytes(bytes: u64) -> String {
    const UNITS: [&str; 6] = ["KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_stay_short() {
        assert_eq!(readable_number(0.25), "0.25");
        assert_eq!(readable_number(-3.0), "-3");
        assert_eq!(readable_number(0.0), "0");
        assert_eq!(readable_number(1e-5), "0.00001");
        assert_eq!(readable_number(999_999_999_999.0), "999999999999");
        assert_eq!(readable_number(1e308), "1e308");
        assert_eq!(readable_number(-f64::MAX), "-1.7976931348623157e308");
        assert_eq!(readable_number(2.5e-9), "2.5e-9");
        assert_eq!(readable_number(f64::NEG_INFINITY), "-inf");
        assert_eq!(readable_number(f64::NAN), "NaN");
    }

    #[test]
    fn names_stay_short_and_on_one_line() {
        assert_eq!(shown_name("Magic carpet"), "Magic carpet");
        assert_eq!(shown_name("a\nb\u{1b}[2J"), "a\\nb\\u{1b}[2J");
        assert_eq!(shown_name("a\u{202e}b\0c"), "a\\u{202e}b\\0c");
        let exact = "x".repeat(MAX_SHOWN_NAME_CHARS);
        assert_eq!(shown_name(&exact), exact);
        let long = "é".repeat(5_000_000);
        let shown = shown_name(&long);
        assert_eq!(shown.chars().count(), MAX_SHOWN_NAME_CHARS);
        assert!(shown.ends_with("é…"), "{shown}");
    }

    #[test]
    fn control_and_bidi_characters_are_escaped_and_the_rest_kept() {
        assert_eq!(escaped("Crêpe café 布 ü"), "Crêpe café 布 ü");
        assert_eq!(escaped("e\u{301}"), "e\u{301}", "a combining accent is no control");
        assert_eq!(escaped("\u{1b}[31m\0\t\r\n\u{7f}\u{9b}"), "\\u{1b}[31m\\0\\t\\r\\n\\u{7f}\\u{9b}");
        assert_eq!(
            escaped("\u{202e}\u{2066}\u{200f}\u{200b}\u{2028}\u{feff}\u{e0041}"),
            "\\u{202e}\\u{2066}\\u{200f}\\u{200b}\\u{2028}\\u{feff}\\u{e0041}"
        );
        assert!(matches!(escaped("plain"), std::borrow::Cow::Borrowed(_)));
    }

    #[test]
    fn bytes_read_in_binary_units() {
        assert_eq!(readable_bytes(0), "0 bytes");
        assert_eq!(readable_bytes(1023), "1023 bytes");
        assert_eq!(readable_bytes(1536), "1.5 KiB");
        assert_eq!(readable_bytes(9 << 30), "9.0 GiB");
        assert_eq!(readable_bytes(u64::MAX), "16.0 EiB");
    }
}
