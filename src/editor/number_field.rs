//! The editor's one numeric field: every number a user types goes through
//! [`number_field`] (or [`number_slider`], whose text box is the same field).
//!
//! A typed value is committed once, to the field it was typed into, when
//! the user presses Enter or Tab or clicks elsewhere; Escape restores the
//! value the field had. While typing nothing changes, so typing `65` into
//! the grid size relaxes the cloth once (not at 6 and again at 65) and
//! leaves one undo step. Dragging the field still changes the value live.
//! That Tab never carries the text into the next field, even when typing
//! and Tab arrive in one frame, is [`super::typing_pace`]'s part.

use std::cell::RefCell;
use std::ops::RangeInclusive;

use eframe::egui::{DragValue, Slider, emath::Numeric};

/// A number field for `value`: drag to change it, click to type.
pub fn number_field<N: Numeric>(value: &mut N) -> DragValue<'_> {
    DragValue::new(value).update_while_editing(false).custom_parser(parse_typed)
}

/// A slider over `range` with a number field beside it.
pub fn number_slider<N: Numeric>(value: &mut N, range: RangeInclusive<N>) -> Slider<'_> {
    Slider::new(value, range).update_while_editing(false).custom_parser(parse_typed)
}

thread_local! {
    /// The last typed text that was no number, until [`take_refused`] says so.
    static REFUSED: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// What a user typed as a number: egui's reading (spaces ignored, `−` as
/// `-`) with a unit the field shows after it left off (`1.5 m`, `40°`,
/// `10 %`, `35 mm`). Text that is still no number is kept for
/// [`take_refused`], so the editor can say why the field kept its value
/// instead of dropping the typing silently.
pub fn parse_typed(text: &str) -> Option<f64> {
    let compact: String = text.chars().filter(|c| !c.is_whitespace()).map(|c| if c == '−' { '-' } else { c }).collect();
    let number = compact.trim_end_matches(|c: char| c.is_alphabetic() || c == '%' || c == '°');
    let parsed = number.parse::<f64>().ok().filter(|v| v.is_finite());
    if parsed.is_none() {
        REFUSED.with(|refused| *refused.borrow_mut() = Some(text.trim().to_owned()));
    }
    parsed
}

/// The text last typed into a number field that was no number (the field
/// kept its value), once.
pub fn take_refused() -> Option<String> {
    REFUSED.with(|refused| refused.borrow_mut().take())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_numbers_read_with_or_without_their_unit() {
        assert_eq!(parse_typed("1.5"), Some(1.5));
        assert_eq!(parse_typed(" 1.5 m "), Some(1.5));
        assert_eq!(parse_typed("−0.25"), Some(-0.25));
        assert_eq!(parse_typed("40°"), Some(40.0));
        assert_eq!(parse_typed("10 %"), Some(10.0));
        assert_eq!(parse_typed("35 mm"), Some(35.0));
        assert_eq!(parse_typed("1e-5"), Some(1e-5));
        assert_eq!(take_refused(), None, "nothing refused yet");
        assert_eq!(parse_typed("1.51.000"), None);
        assert_eq!(parse_typed("inf"), None, "not a finite number");
        assert_eq!(take_refused().as_deref(), Some("inf"), "the last refusal");
        assert_eq!(take_refused(), None, "said once");
    }
}
