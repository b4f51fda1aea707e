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

use eframe::egui::{DragValue, Slider, emath::Numeric};

/// A number field for `value`: drag to change it, click to type.
pub fn number_field<N: Numeric>(value: &mut N) -> DragValue<'_> {
    DragValue::new(value).update_while_editing(false)
}

/// A slider over `range` with a number field beside it.
pub fn number_slider<N: Numeric>(value: &mut N, range: RangeInclusive<N>) -> Slider<'_> {
    Slider::new(value, range).update_while_editing(false)
}
