//! Where a value starts in the RON text.
//!
//! serde and ron report positions for syntax and type errors, but not for
//! values that parsed fine and then fail validation (a pin outside the grid,
//! an elasticity of 0.5). This module is a minimal RON scanner — strings, raw
//! strings, chars, `//` and nested `/* */` comments, `()`, `[]`, `{}`,
//! identifiers, numbers and `name:` fields — that maps a value path such as
//! `keys[0].pins[2].grid` or `layers[1].magnitude` to the line and column where
//! that value starts.
//!
//! Paths are field names joined by `.` with `[n]` for the n-th element of a
//! list or tuple (`keys[0].ease[0]` is the first number of `Bezier(…)`).
//! Variant names and newtype wrappers are stepped through transparently, so
//! `layers[0].magnitude` finds the field inside `Sway((magnitude: …))`.
//!
//! The scanner never panics and never recurses, whatever the input.

use std::fmt;

/// A place in the text: 1-based line and 1-based column counted in characters
/// (the same convention as ron's error positions).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TextPosition {
    pub line: usize,
    pub col: usize,
}

impl fmt::Display for TextPosition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.col)
    }
}

/// The position just after `prefix`, i.e. of the character at `prefix.len()`.
pub(crate) fn position_after(prefix: &str) -> TextPosition {
    let line = 1 + prefix.matches('\n').count();
    let last_line = prefix.rsplit('\n').next().unwrap_or("");
    TextPosition { line, col: 1 + last_line.chars().count() }
}

/// What a token is; enough structure to walk values, not to parse RON.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TokenKind {
    Open(char),
    Close(char),
    Comma,
    Colon,
    Ident,
    Number,
    /// A string, raw string, byte string or char literal.
    Literal,
    /// Any other single character (`#`, `!`, stray punctuation).
    Other,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Token {
    pub kind: TokenKind,
    /// Byte range in the text.
    pub start: usize,
    pub end: usize,
    pub pos: TextPosition,
}

/// A scanned text: its tokens and, for each opening bracket, the index of its
/// matching closing bracket (if any).
pub(crate) struct Scanned<'a> {
    pub text: &'a str,
    pub tokens: Vec<Token>,
    matching: Vec<Option<usize>>,
}

impl<'a> Scanned<'a> {
    pub fn new(text: &'a str) -> Self {
        let tokens = tokenize(text);
        let matching = match_brackets(&tokens);
        Scanned { text, tokens, matching }
    }

    pub fn token_text(&self, index: usize) -> &'a str {
        let t = &self.tokens[index];
        self.text.get(t.start..t.end).unwrap_or("")
    }

    fn kind(&self, index: usize) -> Option<TokenKind> {
        self.tokens.get(index).map(|t| t.kind)
    }

    /// Index of the token just after the value that starts at `index`.
    pub fn value_end(&self, index: usize) -> usize {
        match self.kind(index) {
            Some(TokenKind::Open(_)) => self.after_group(index),
            Some(TokenKind::Ident) if matches!(self.kind(index + 1), Some(TokenKind::Open(_))) => {
                self.after_group(index + 1)
            }
            Some(_) => index + 1,
            None => index,
        }
    }

    fn after_group(&self, open: usize) -> usize {
        self.matching[open].map_or(self.tokens.len(), |close| close + 1)
    }

    /// The opening bracket of the value at `index`: the value itself, or the
    /// bracket after a struct or variant name (`Sway(`, `Bezier(`).
    pub fn value_group(&self, index: usize) -> Option<usize> {
        match self.kind(index)? {
            TokenKind::Open(_) => Some(index),
            TokenKind::Ident if matches!(self.kind(index + 1), Some(TokenKind::Open(_))) => Some(index + 1),
            _ => None,
        }
    }

    /// The top-level entries of the group opened at `open`.
    pub fn entries(&self, open: usize) -> Vec<Entry<'a>> {
        let end = self.matching[open].unwrap_or(self.tokens.len());
        let mut entries = Vec::new();
        let mut i = open + 1;
        while i < end {
            match self.tokens[i].kind {
                TokenKind::Comma => {
                    i += 1;
                    continue;
                }
                TokenKind::Close(_) => break,
                _ => {}
            }
            let (name, value) = if self.tokens[i].kind == TokenKind::Ident && self.kind(i + 1) == Some(TokenKind::Colon)
            {
                let name = self.token_text(i);
                (Some(name.strip_prefix("r#").unwrap_or(name)), i + 2)
            } else {
                (None, i)
            };
            entries.push(Entry { name, value });
            // Skip to the comma that ends this entry.
            let mut j = value;
            while j < end {
                match self.tokens[j].kind {
                    TokenKind::Comma | TokenKind::Close(_) => break,
                    TokenKind::Open(_) => j = self.after_group(j),
                    _ => j += 1,
                }
            }
            i = j.max(i + 1);
        }
        entries
    }

    /// The index of the token where the document's value starts, after any
    /// `#![enable(…)]` attributes.
    fn root(&self) -> Option<usize> {
        let mut i = 0;
        while self.kind(i) == Some(TokenKind::Other) && self.token_text(i) == "#" {
            i += 1;
            if self.kind(i) == Some(TokenKind::Other) && self.token_text(i) == "!" {
                i += 1;
            }
            if let Some(TokenKind::Open(_)) = self.kind(i) {
                i = self.after_group(i);
            }
        }
        (i < self.tokens.len()).then_some(i)
    }

    fn field(&self, value: usize, name: &str) -> Option<usize> {
        let mut value = value;
        // Step through newtype wrappers such as `Sway((…))` (bounded, no recursion).
        for _ in 0..8 {
            let entries = self.entries(self.value_group(value)?);
            if let Some(entry) = entries.iter().find(|e| e.name == Some(name)) {
                return Some(entry.value);
            }
            match entries.as_slice() {
                [only] if only.name.is_none() && self.value_group(only.value).is_some() => {
                    value = only.value;
                }
                _ => return None,
            }
        }
        None
    }

    fn element(&self, value: usize, index: usize) -> Option<usize> {
        let entries = self.entries(self.value_group(value)?);
        entries.get(index).map(|e| e.value)
    }

    /// Where the value at `path` starts; if part of the path is missing, where
    /// the nearest enclosing value that exists starts. `None` only when the text
    /// holds no value at all.
    pub fn locate(&self, path: &str) -> Option<TextPosition> {
        let mut current = self.root()?;
        for segment in parse_path(path) {
            let next = match segment {
                Segment::Field(name) => self.field(current, name),
                Segment::Index(index) => self.element(current, index),
            };
            match next {
                Some(next) if next < self.tokens.len() => current = next,
                _ => break,
            }
        }
        Some(self.tokens[current].pos)
    }
}

/// One `name: value` or bare `value` inside a group.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry<'a> {
    pub name: Option<&'a str>,
    /// Token index where the value starts.
    pub value: usize,
}

/// Where the value at `path` (e.g. `keys[0].pins[2].grid`) starts in `text`,
/// falling back to the nearest enclosing value found; `None` only if the text
/// holds no value at all.
pub fn locate(text: &str, path: &str) -> Option<TextPosition> {
    Scanned::new(text).locate(path)
}

/// The token at or after a position, for error messages ("found `x`").
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Found {
    /// The token's text, shortened to a few dozen characters.
    pub text: String,
    pub kind: TokenKind,
    /// Where the token starts.
    pub pos: TextPosition,
    /// Just after the token before it, if any (where a missing comma belongs).
    pub after_previous: Option<TextPosition>,
    /// The innermost bracket still open before the token, and where it opened.
    pub open_bracket: Option<(char, TextPosition)>,
}

/// What stands at `at` in `text` (the first token starting there or later).
pub(crate) fn found_at(text: &str, at: TextPosition) -> Option<Found> {
    let tokens = tokenize(text);
    let offset = byte_offset(text, at)?;
    // The token that contains the position, else the next one.
    let index = tokens
        .iter()
        .position(|t| t.start <= offset && offset < t.end)
        .or_else(|| tokens.iter().position(|t| t.start >= offset))?;
    let token = tokens[index];
    let full = text.get(token.start..token.end).unwrap_or("");
    let mut shown: String = full.chars().take(30).collect();
    if shown.len() < full.len() {
        shown.push('…');
    }
    Some(Found {
        text: shown,
        kind: token.kind,
        pos: token.pos,
        after_previous: index
            .checked_sub(1)
            .map(|previous| position_after(text.get(..tokens[previous].end).unwrap_or(""))),
        open_bracket: innermost_open(&tokens[..index]),
    })
}

/// The byte offset of a position, if it lies within the text (or at its end).
pub(crate) fn byte_offset(text: &str, at: TextPosition) -> Option<usize> {
    let mut line_start = 0;
    for _ in 1..at.line {
        line_start += text.get(line_start..)?.find('\n')? + 1;
    }
    let line = text.get(line_start..)?;
    let line = &line[..line.find('\n').unwrap_or(line.len())];
    let col = at.col.checked_sub(1)?;
    match line.char_indices().nth(col) {
        Some((offset, _)) => Some(line_start + offset),
        None if col == line.chars().count() => Some(line_start + line.len()),
        None => None,
    }
}

/// The innermost bracket left open at the end of `text`.
pub(crate) fn unclosed_bracket(text: &str) -> Option<(char, TextPosition)> {
    innermost_open(&tokenize(text))
}

fn innermost_open(tokens: &[Token]) -> Option<(char, TextPosition)> {
    let mut stack: Vec<(char, TextPosition)> = Vec::new();
    for token in tokens {
        match token.kind {
            TokenKind::Open(c) => stack.push((c, token.pos)),
            TokenKind::Close(c) if stack.last().is_some_and(|&(open, _)| closing(open) == c) => {
                stack.pop();
            }
            _ => {}
        }
    }
    stack.pop()
}

/// The closing bracket for an opening one.
pub(crate) fn closing(open: char) -> char {
    match open {
        '(' => ')',
        '[' => ']',
        _ => '}',
    }
}

#[derive(Debug, PartialEq)]
enum Segment<'p> {
    Field(&'p str),
    Index(usize),
}

/// Splits `keys[0].pins[2].grid` into segments; stops at anything malformed.
fn parse_path(path: &str) -> Vec<Segment<'_>> {
    let mut segments = Vec::new();
    let mut rest = path;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix('[') {
            let Some(close) = after.find(']') else { break };
            let Ok(index) = after[..close].trim().parse() else { break };
            segments.push(Segment::Index(index));
            rest = &after[close + 1..];
        } else if let Some(after) = rest.strip_prefix('.') {
            rest = after;
        } else {
            let end = rest.find(['.', '[']).unwrap_or(rest.len());
            segments.push(Segment::Field(&rest[..end]));
            rest = &rest[end..];
        }
    }
    segments
}

fn is_ident_start(c: char) -> bool {
    c == '_' || c.is_alphabetic()
}

fn is_ident_continue(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

/// Splits RON text into tokens, skipping whitespace and comments. Unterminated
/// strings and comments run to the end of the text.
pub(crate) fn tokenize(text: &str) -> Vec<Token> {
    scan(text).0
}

/// Where a `/*` comment starts that is never closed, if any.
pub(crate) fn unclosed_comment(text: &str) -> Option<TextPosition> {
    scan(text).1
}

/// Tokens, and the start of an unclosed block comment.
fn scan(text: &str) -> (Vec<Token>, Option<TextPosition>) {
    let mut unclosed_comment = None;
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let n = chars.len();
    let at = |i: usize| chars.get(i).map(|&(_, c)| c);
    let byte = |i: usize| chars.get(i).map_or(text.len(), |&(b, _)| b);

    let mut tokens = Vec::new();
    let (mut line, mut col) = (1, 1);
    let mut i = 0;
    while i < n {
        let c = chars[i].1;
        let pos = TextPosition { line, col };
        let start = i;
        let (kind, end) = if c.is_whitespace() {
            (None, i + 1)
        } else if c == '/' && at(i + 1) == Some('/') {
            let mut j = i + 2;
            while j < n && chars[j].1 != '\n' {
                j += 1;
            }
            (None, j)
        } else if c == '/' && at(i + 1) == Some('*') {
            let mut depth = 1usize;
            let mut j = i + 2;
            while j < n && depth > 0 {
                if chars[j].1 == '/' && at(j + 1) == Some('*') {
                    depth += 1;
                    j += 2;
                } else if chars[j].1 == '*' && at(j + 1) == Some('/') {
                    depth -= 1;
                    j += 2;
                } else {
                    j += 1;
                }
            }
            if depth > 0 {
                unclosed_comment = Some(pos);
            }
            (None, j)
        } else if let Some(end) = scan_string(&chars, i) {
            (Some(TokenKind::Literal), end)
        } else if c == '\'' {
            // A char literal such as 'a' or '\''; a stray quote is one char.
            let mut j = i + 1;
            if at(j) == Some('\\') {
                j += 2;
            } else {
                j += 1;
            }
            while j < n && j < i + 12 && chars[j].1 != '\'' {
                j += 1;
            }
            if at(j) == Some('\'') { (Some(TokenKind::Literal), j + 1) } else { (Some(TokenKind::Other), i + 1) }
        } else if c == 'r' && at(i + 1) == Some('#') && at(i + 2).is_some_and(is_ident_start) {
            // Raw identifier r#name.
            let mut j = i + 2;
            while j < n && is_ident_continue(chars[j].1) {
                j += 1;
            }
            (Some(TokenKind::Ident), j)
        } else if is_ident_start(c) {
            let mut j = i + 1;
            while j < n && is_ident_continue(chars[j].1) {
                j += 1;
            }
            (Some(TokenKind::Ident), j)
        } else if c.is_ascii_digit()
            || (matches!(c, '+' | '-' | '.')
                && at(i + 1).is_some_and(|d| d.is_ascii_digit() || d == '.' || is_ident_start(d)))
        {
            let mut j = i + 1;
            while j < n {
                let d = chars[j].1;
                let exponent_sign = matches!(d, '+' | '-') && matches!(chars[j - 1].1, 'e' | 'E');
                if is_ident_continue(d) || d == '.' || exponent_sign {
                    j += 1;
                } else {
                    break;
                }
            }
            (Some(TokenKind::Number), j)
        } else {
            let kind = match c {
                '(' | '[' | '{' => TokenKind::Open(c),
                ')' | ']' | '}' => TokenKind::Close(c),
                ',' => TokenKind::Comma,
                ':' => TokenKind::Colon,
                _ => TokenKind::Other,
            };
            (Some(kind), i + 1)
        };
        if let Some(kind) = kind {
            tokens.push(Token { kind, start: byte(start), end: byte(end), pos });
        }
        // Move to `end`, keeping line and column in step.
        let end = end.clamp(i + 1, n);
        while i < end {
            if chars[i].1 == '\n' {
                line += 1;
                col = 1;
            } else {
                col += 1;
            }
            i += 1;
        }
    }
    (tokens, unclosed_comment)
}

/// If a (raw/byte) string starts at char index `i`, the char index just after it.
fn scan_string(chars: &[(usize, char)], i: usize) -> Option<usize> {
    let at = |k: usize| chars.get(k).map(|&(_, c)| c);
    let mut j = i;
    if at(j) == Some('b') {
        j += 1;
    }
    let raw = at(j) == Some('r');
    if raw {
        j += 1;
        let mut hashes = 0;
        while at(j) == Some('#') {
            hashes += 1;
            j += 1;
        }
        if at(j) != Some('"') {
            return None;
        }
        j += 1;
        // Find `"` followed by `hashes` × `#`.
        while j < chars.len() {
            if chars[j].1 == '"' && (1..=hashes).all(|h| at(j + h) == Some('#')) {
                return Some(j + 1 + hashes);
            }
            j += 1;
        }
        return Some(chars.len());
    }
    if at(j) != Some('"') {
        return None;
    }
    j += 1;
    while j < chars.len() {
        match chars[j].1 {
            '\\' => j += 2,
            '"' => return Some(j + 1),
            _ => j += 1,
        }
    }
    Some(chars.len())
}

/// For each opening bracket, the index of its matching closing bracket. A
/// closing bracket of the wrong kind closes nothing and is left alone.
fn match_brackets(tokens: &[Token]) -> Vec<Option<usize>> {
    let mut matching = vec![None; tokens.len()];
    let mut stack: Vec<(usize, char)> = Vec::new();
    for (index, token) in tokens.iter().enumerate() {
        match token.kind {
            TokenKind::Open(c) => stack.push((index, c)),
            TokenKind::Close(c) => {
                let want = match c {
                    ')' => '(',
                    ']' => '[',
                    _ => '{',
                };
                if let Some(&(open, kind)) = stack.last()
                    && kind == want
                {
                    stack.pop();
                    matching[open] = Some(index);
                }
            }
            _ => {}
        }
    }
    matching
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pos(line: usize, col: usize) -> Option<TextPosition> {
        Some(TextPosition { line, col })
    }

    const SCENE: &str = r#"// a comment with (brackets] and "quotes
/* block /* nested ) */ still comment */
(
    version: 1,
    name: "Cur(tain, \"x\"",
    cloth: (size: (2.0, 1.5), grid: (33, 25)),
    keys: [
        (
            frame: 0,
            pins: [
                (grid: (0, 0),  pos: (-1.0, 2.0, 0.0)),
                (grid: (32, 0), pos: ( 1.0, 2.0, 0.0)),
            ],
            ease: Bezier(0.1, 0.2, 1.5, 1.0),
        ),
    ],
    layers: [
        Sway((name: "breeze", magnitude: 0.2, direction: (0.0, 0.0, 1.0))),
        Wave((magnitude: [(frame: 0, value: 0.0), (frame: 48, value: 0.05, ease: EaseIn)],
              r#phase: 0.0, axis: Fixed((0.0, 1.0, 0.0)))),
    ],
)
"#;

    #[test]
    fn finds_fields_and_elements() {
        assert_eq!(locate(SCENE, ""), pos(3, 1));
        assert_eq!(locate(SCENE, "version"), pos(4, 14));
        assert_eq!(locate(SCENE, "name"), pos(5, 11));
        assert_eq!(locate(SCENE, "cloth.grid"), pos(6, 37));
        assert_eq!(locate(SCENE, "cloth.grid[1]"), pos(6, 42));
        assert_eq!(locate(SCENE, "keys[0].frame"), pos(9, 20));
        assert_eq!(locate(SCENE, "keys[0].pins[1].grid"), pos(12, 24));
        assert_eq!(locate(SCENE, "keys[0].pins[0].pos"), pos(11, 38));
        assert_eq!(locate(SCENE, "keys[0].ease"), pos(14, 19));
        assert_eq!(locate(SCENE, "keys[0].ease[2]"), pos(14, 36));
    }

    #[test]
    fn steps_through_variants_and_param_keys() {
        assert_eq!(locate(SCENE, "layers[0]"), pos(18, 9));
        assert_eq!(locate(SCENE, "layers[0].magnitude"), pos(18, 42));
        assert_eq!(locate(SCENE, "layers[0].direction"), pos(18, 58));
        assert_eq!(locate(SCENE, "layers[1].magnitude[1].value"), pos(19, 70));
        assert_eq!(locate(SCENE, "layers[1].magnitude[1].ease"), pos(19, 82));
        assert_eq!(locate(SCENE, "layers[1].phase"), pos(20, 24));
        assert_eq!(locate(SCENE, "layers[1].axis"), pos(20, 35));
    }

    #[test]
    fn falls_back_to_the_nearest_enclosing_value() {
        // `elasticity` is absent: the key itself.
        assert_eq!(locate(SCENE, "keys[0].elasticity"), pos(8, 9));
        assert_eq!(locate(SCENE, "keys[3].frame"), pos(7, 11));
        assert_eq!(locate(SCENE, "timeline.fps"), pos(3, 1));
        assert_eq!(locate("", "version"), None);
        assert_eq!(locate("  // only a comment", "version"), None);
    }

    #[test]
    fn skips_attributes_and_counts_columns_in_chars() {
        let text = "#![enable(implicit_some)]\n(name: \"é\", version: 2)";
        assert_eq!(locate(text, "version"), pos(2, 22));
    }

    #[test]
    fn survives_unbalanced_and_unterminated_input() {
        for text in ["(", ")", "(a: [1, 2", "(a: \"unterminated", "/* open", "(a: r##\"x\"#)", "'", "-", "r#"] {
            let _ = locate(text, "a[1].b");
            let _ = locate(text, "a");
        }
        assert_eq!(locate("(a: [1, 2", "a[1]"), pos(1, 9));
        assert_eq!(locate("(a: r#\"x)\"#, b: 'x', c: 3)", "c"), pos(1, 25));
    }

    #[test]
    fn numbers_with_signs_and_exponents_are_one_token() {
        let tokens = tokenize("(-1.5e-3, +inf, .5, 0x1F)");
        let kinds: Vec<_> = tokens.iter().map(|t| t.kind).collect();
        use TokenKind::*;
        assert_eq!(kinds, [Open('('), Number, Comma, Number, Comma, Number, Comma, Number, Close(')')]);
    }

    #[test]
    fn byte_offsets_and_found_tokens() {
        let text = "(a: 1,\n é: -3)";
        assert_eq!(byte_offset(text, TextPosition { line: 1, col: 1 }), Some(0));
        assert_eq!(byte_offset(text, TextPosition { line: 2, col: 5 }), Some(12));
        assert_eq!(byte_offset(text, TextPosition { line: 2, col: 8 }), Some(15));
        assert_eq!(byte_offset(text, TextPosition { line: 2, col: 9 }), None);
        assert_eq!(byte_offset(text, TextPosition { line: 3, col: 1 }), None);
        assert_eq!(byte_offset(text, TextPosition { line: 1, col: 0 }), None);
        let found = found_at(text, TextPosition { line: 2, col: 6 }).unwrap();
        assert_eq!(found.text, "-3");
        assert_eq!(found.open_bracket, Some(('(', TextPosition { line: 1, col: 1 })));
        assert_eq!(unclosed_bracket("(a: [1, (2)"), Some(('[', TextPosition { line: 1, col: 5 })));
        assert_eq!(unclosed_bracket("(a: [1, (2)])"), None);
        assert_eq!(unclosed_comment("(a: /* x */ 1, /* b /* c */"), Some(TextPosition { line: 1, col: 16 }));
        assert_eq!(unclosed_comment("(a: \"/*\", /* /* */ */)"), None);
    }

    #[test]
    fn position_after_counts_lines_and_chars() {
        assert_eq!(position_after(""), TextPosition { line: 1, col: 1 });
        assert_eq!(position_after("ab\ncé"), TextPosition { line: 2, col: 3 });
    }
}
