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

use std::ops::RangeInclusive;

use eframe::egui::{self, DragValue, Id, Slider, emath::Numeric};

/// A number field for `value`: drag to change it, click to type.
pub fn number_field<'a, N: Numeric>(ctx: &egui::Context, value: &'a mut N) -> DragValue<'a> {
    DragValue::new(value).update_while_editing(false).custom_parser(typed_parser(ctx))
}

/// A slider over `range` with a number field beside it.
pub fn number_slider<'a, N: Numeric>(ctx: &egui::Context, value: &'a mut N, range: RangeInclusive<N>) -> Slider<'a> {
    Slider::new(value, range).update_while_editing(false).custom_parser(typed_parser(ctx))
}

/// Where the window keeps the last typed text that was no number, until
/// [`take_refused`] says so.
fn refused_id() -> Id {
    Id::unique("number_field refused")
}

/// Reads typed text with [`parse_typed`]; text that is still no number is
/// kept in the window's memory for [`take_refused`], so the editor can say
/// why the field kept its value instead of dropping the typing silently.
fn typed_parser(ctx: &egui::Context) -> impl Fn(&str) -> Option<f64> + use<> {
    let ctx = ctx.clone();
    move |text| {
        let parsed = parse_typed(text);
        if parsed.is_none() {
            ctx.data_mut(|data| data.insert_temp(refused_id(), text.trim().to_owned()));
        }
        parsed
    }
}

/// What a user typed as a number: egui's reading (spaces ignored, `−` as
/// `-`) with a unit the field shows after it left off (`1.5 m`, `40°`,
/// `10 %`, `35 mm`).
pub fn parse_typed(text: &str) -> Option<f64> {
    let compact: String = text.chars().filter(|c| !c.is_whitespace()).map(|c| if c == '−' { '-' } else { c }).collect();
    let number = compact.trim_end_matches(|c: char| c.is_alphabetic() || c == '%' || c == '°');
    number.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The text last typed into a number field of this window that was no
/// number (the field kept its value), once.
pub fn take_refused(ctx: &egui::Context) -> Option<String> {
    ctx.data_mut(|data| data.remove_temp::<String>(refused_id()))
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
        assert_eq!(parse_typed("1.51.000"), None);
        assert_eq!(parse_typed("inf"), None, "not a finite number");
    }

    #[test]
    fn text_that_is_no_number_is_kept_for_the_window_once() {
        let ctx = egui::Context::default();
        let parse = typed_parser(&ctx);
        assert_eq!(parse(" 1.5 m "), Some(1.5));
        assert_eq!(take_refused(&ctx), None, "nothing refused yet");
        assert_eq!(parse("1.51.000"), None);
        assert_eq!(parse(" inf "), None);
        assert_eq!(take_refused(&ctx).as_deref(), Some("inf"), "the last refusal");
        assert_eq!(take_refused(&ctx), None, "said once");
    }
}
