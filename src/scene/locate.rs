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
    let mut current = root(text)?;
    for segment in parse_path(path) {
        let next = match segment {
            Segment::Field(name) => field(text, current, name),
            Segment::Index(index) => element(text, current, index),
        };
        match next {
            Some(next) => current = next,
            None => break,
        }
    }
    Some(current.pos)
}

/// The token where the document's value starts, after any `#![enable(…)]`
/// attributes.
fn root(text: &str) -> Option<Token> {
    let mut tokens = Tokens::new(text);
    let mut token = tokens.next()?;
    while token.kind == TokenKind::Other && token_text(text, &token) == "#" {
        token = tokens.next()?;
        if token.kind == TokenKind::Other && token_text(text, &token) == "!" {
            token = tokens.next()?;
        }
        if let TokenKind::Open(open) = token.kind {
            skip_group(&mut tokens, open);
            token = tokens.next()?;
        }
    }
    Some(token)
}

fn token_text<'a>(text: &'a str, token: &Token) -> &'a str {
    text.get(token.start..token.end).unwrap_or("")
}

/// The tokens inside the group of the value starting at `value`: the value
/// itself, or the bracket after a struct or variant name (`Sway(`, `Bezier(`).
fn group_inside<'a>(text: &'a str, value: &Token) -> Option<Tokens<'a>> {
    let mut tokens = Tokens::after(text, value);
    match value.kind {
        TokenKind::Open(_) => Some(tokens),
        TokenKind::Ident => matches!(tokens.next()?.kind, TokenKind::Open(_)).then_some(tokens),
        _ => None,
    }
}

/// Moves past the bracket that closes a group opened by `open`, whose
/// opening bracket `tokens` just gave. A closing bracket of the wrong kind
/// closes nothing.
fn skip_group(tokens: &mut Tokens, open: char) {
    let mut open_brackets = vec![open];
    for token in tokens {
        match token.kind {
            TokenKind::Open(c) => open_brackets.push(c),
            TokenKind::Close(c) if open_brackets.last().is_some_and(|&o| closing(o) == c) => {
                open_brackets.pop();
                if open_brackets.is_empty() {
                    return;
                }
            }
            _ => {}
        }
    }
}

/// Gives each top-level entry of a group (`inside`: its tokens after the
/// opening bracket) to `visit` as its name, if any, and its first token,
/// until `visit` returns true or the group ends.
fn visit_entries(text: &str, mut inside: Tokens, mut visit: impl FnMut(Option<&str>, Token) -> bool) {
    while let Some(token) = inside.next() {
        match token.kind {
            TokenKind::Comma => continue,
            TokenKind::Close(_) => return,
            _ => {}
        }
        let mut after_name = inside.clone();
        let (name, value) = match after_name.next() {
            Some(colon) if token.kind == TokenKind::Ident && colon.kind == TokenKind::Colon => {
                inside = after_name;
                let name = token_text(text, &token);
                let Some(value) = inside.next() else { return };
                (Some(name.strip_prefix("r#").unwrap_or(name)), value)
            }
            _ => (None, token),
        };
        if visit(name, value) {
            return;
        }
        // Skip to the comma that ends this entry.
        let mut at = Some(value);
        while let Some(token) = at {
            match token.kind {
                TokenKind::Comma => break,
                TokenKind::Close(_) => return,
                TokenKind::Open(open) => skip_group(&mut inside, open),
                _ => {}
            }
            at = inside.next();
        }
    }
}

fn field(text: &str, value: Token, name: &str) -> Option<Token> {
    let mut value = value;
    // Step through newtype wrappers such as `Sway((…))` (bounded, no recursion).
    for _ in 0..8 {
        let inside = group_inside(text, &value)?;
        let (mut found, mut count, mut first) = (None, 0, None);
        visit_entries(text, inside, |entry_name, entry_value| {
            count += 1;
            first = first.or(Some((entry_name.is_none(), entry_value)));
            if entry_name == Some(name) {
                found = Some(entry_value);
            }
            found.is_some()
        });
        if found.is_some() {
            return found;
        }
        match first {
            Some((true, only)) if count == 1 && group_inside(text, &only).is_some() => value = only,
            _ => return None,
        }
    }
    None
}

fn element(text: &str, value: Token, index: usize) -> Option<Token> {
    let inside = group_inside(text, &value)?;
    let (mut found, mut count) = (None, 0);
    visit_entries(text, inside, |_, entry_value| {
        if count == index {
            found = Some(entry_value);
        }
        count += 1;
        found.is_some()
    });
    found
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
    let offset = byte_offset(text, at)?;
    let mut open_brackets = OpenBrackets::default();
    let mut previous: Option<Token> = None;
    // The token that contains the position, else the next one: the first that ends past it.
    for token in Tokens::new(text) {
        if token.end > offset {
            let full = token_text(text, &token);
            let mut shown: String = full.chars().take(30).collect();
            if shown.len() < full.len() {
                shown.push('…');
            }
            return Some(Found {
                text: shown,
                kind: token.kind,
                pos: token.pos,
                after_previous: previous.map(|p| position_after(text.get(..p.end).unwrap_or(""))),
                open_bracket: open_brackets.innermost(),
            });
        }
        open_brackets.step(&token);
        previous = Some(token);
    }
    None
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
    let mut open_brackets = OpenBrackets::default();
    Tokens::new(text).for_each(|token| open_brackets.step(&token));
    open_brackets.innermost()
}

/// The brackets still open at a point of a walk through the tokens.
#[derive(Default)]
struct OpenBrackets(Vec<(char, TextPosition)>);

impl OpenBrackets {
    fn step(&mut self, token: &Token) {
        match token.kind {
            TokenKind::Open(c) => self.0.push((c, token.pos)),
            TokenKind::Close(c) if self.0.last().is_some_and(|&(open, _)| closing(open) == c) => {
                self.0.pop();
            }
            _ => {}
        }
    }

    fn innermost(&self) -> Option<(char, TextPosition)> {
        self.0.last().copied()
    }
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
    Tokens::new(text).collect()
}

/// Whether the text holds anything but whitespace and comments; stops at
/// the first token.
pub(crate) fn has_tokens(text: &str) -> bool {
    Tokens::new(text).next().is_some()
}

/// Where a `/*` comment starts that is never closed, if any.
pub(crate) fn unclosed_comment(text: &str) -> Option<TextPosition> {
    let mut tokens = Tokens::new(text);
    tokens.by_ref().for_each(drop);
    tokens.unclosed_comment
}

/// The tokens of a text, scanned one at a time: walking a text holds
/// nothing but the token at hand, however long the text. Walks byte
/// offsets, decoding one char at a time.
#[derive(Clone)]
pub(crate) struct Tokens<'a> {
    text: &'a str,
    /// Byte offset of the next char to scan, and its line and column.
    offset: usize,
    line: usize,
    col: usize,
    /// Where a `/*` comment that is never closed starts, once scanned.
    pub unclosed_comment: Option<TextPosition>,
}

impl<'a> Tokens<'a> {
    pub fn new(text: &'a str) -> Self {
        Tokens { text, offset: 0, line: 1, col: 1, unclosed_comment: None }
    }

    /// The tokens after `token` (one of this text's).
    pub fn after(text: &'a str, token: &Token) -> Self {
        let (mut line, mut col) = (token.pos.line, token.pos.col);
        for c in text.get(token.start..token.end).unwrap_or("").chars() {
            if c == '\n' {
                line += 1;
                col = 1;
            } else {
                col += 1;
            }
        }
        Tokens { text, offset: token.end, line, col, unclosed_comment: None }
    }
}

impl Iterator for Tokens<'_> {
    type Item = Token;

    fn next(&mut self) -> Option<Token> {
        let text = self.text;
        let n = text.len();
        let bytes = text.as_bytes();
        let at = |i: usize| text.get(i..).and_then(|rest| rest.chars().next());
        // The offset of the char after the one at `i` (`n` at the end).
        let next = |i: usize| at(i).map_or(n, |c| i + c.len_utf8());
        let (mut i, mut line, mut col) = (self.offset, self.line, self.col);
        let mut found = None;
        while i < n && found.is_none() {
            let Some(c) = at(i) else { break };
            let pos = TextPosition { line, col };
            let start = i;
            let (kind, end) = if c.is_whitespace() {
                (None, next(i))
            } else if c == '/' && at(i + 1) == Some('/') {
                let end = text[i..].find('\n').map_or(n, |k| i + k);
                (None, end)
            } else if c == '/' && at(i + 1) == Some('*') {
                let mut depth = 1usize;
                let mut j = i + 2;
                while j < n && depth > 0 {
                    if bytes[j] == b'/' && bytes.get(j + 1) == Some(&b'*') {
                        depth += 1;
                        j += 2;
                    } else if bytes[j] == b'*' && bytes.get(j + 1) == Some(&b'/') {
                        depth -= 1;
                        j += 2;
                    } else {
                        j = next(j);
                    }
                }
                if depth > 0 {
                    self.unclosed_comment = Some(pos);
                }
                (None, j.min(n))
            } else if let Some(end) = scan_string(text, i) {
                (Some(TokenKind::Literal), end)
            } else if c == '\'' {
                // A char literal such as 'a' or '\''; a stray quote is one char.
                let escaped = at(next(i)) == Some('\\');
                let mut j = if escaped { next(next(next(i))) } else { next(next(i)) };
                // At most 12 chars from the opening quote.
                let mut looked = if escaped { 3 } else { 2 };
                while j < n && looked < 12 && bytes[j] != b'\'' {
                    j = next(j);
                    looked += 1;
                }
                if at(j) == Some('\'') { (Some(TokenKind::Literal), j + 1) } else { (Some(TokenKind::Other), next(i)) }
            } else if c == 'r' && at(i + 1) == Some('#') && at(i + 2).is_some_and(is_ident_start) {
                // Raw identifier r#name.
                (Some(TokenKind::Ident), ident_end(text, i + 2))
            } else if is_ident_start(c) {
                (Some(TokenKind::Ident), ident_end(text, i))
            } else if c.is_ascii_digit()
                || (matches!(c, '+' | '-' | '.')
                    && at(i + 1).is_some_and(|d| d.is_ascii_digit() || d == '.' || is_ident_start(d)))
            {
                let mut j = i + 1;
                while let Some(d) = at(j) {
                    // A char before `j` that is not ASCII ends in a byte that is never `e`.
                    let exponent_sign = matches!(d, '+' | '-') && matches!(bytes[j - 1], b'e' | b'E');
                    if is_ident_continue(d) || d == '.' || exponent_sign {
                        j += d.len_utf8();
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
                (Some(kind), next(i))
            };
            if let Some(kind) = kind {
                found = Some(Token { kind, start, end, pos });
            }
            // Move to `end`, keeping line and column in step.
            let end = end.clamp(next(i), n);
            for c in text[i..end].chars() {
                if c == '\n' {
                    line += 1;
                    col = 1;
                } else {
                    col += 1;
                }
            }
            i = end;
        }
        (self.offset, self.line, self.col) = (i, line, col);
        found
    }
}

/// The offset just after the identifier whose first char is at `start`.
fn ident_end(text: &str, start: usize) -> usize {
    let mut chars = text[start..].char_indices();
    chars.next();
    chars.find(|&(_, c)| !is_ident_continue(c)).map_or(text.len(), |(k, _)| start + k)
}

/// If a (raw/byte) string starts at byte offset `i`, the offset just after it.
fn scan_string(text: &str, i: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let at = |k: usize| bytes.get(k).copied();
    let mut j = i;
    if at(j) == Some(b'b') {
        j += 1;
    }
    let raw = at(j) == Some(b'r');
    if raw {
        j += 1;
        let mut hashes = 0;
        while at(j) == Some(b'#') {
            hashes += 1;
            j += 1;
        }
        if at(j) != Some(b'"') {
            return None;
        }
        j += 1;
        // Find `"` followed by `hashes` × `#`; both are ASCII, never inside another char's bytes.
        while j < bytes.len() {
            if bytes[j] == b'"' && (1..=hashes).all(|h| at(j + h) == Some(b'#')) {
                return Some(j + 1 + hashes);
            }
            j += 1;
        }
        return Some(bytes.len());
    }
    if at(j) != Some(b'"') {
        return None;
    }
    j += 1;
    while j < bytes.len() {
        match bytes[j] {
            // The escaped char may be several bytes: the scan goes on at its next byte, never a quote.
            b'\\' => j += 2,
            b'"' => return Some(j + 1),
            _ => j += 1,
        }
    }
    Some(bytes.len())
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
