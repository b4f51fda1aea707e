//! One animatable number in a panel (a collider's or a reference's): its
//! label, its value at the playhead and the diamond that keys it there.
//! Editing a keyed number keys it at the playhead; a constant changes (or,
//! with auto-key, is keyed); a drag is one undo step.

use eframe::egui;

use crate::animate::track::sample;
use crate::editor::icons::{Icon, icon_button};
use crate::editor::number_field::number_field;
use crate::editor::param_edit::{key_at, set_at_keying, toggle_key};
use crate::editor::workspace::Workspace;
use crate::scene::{Param, Scene};

/// What a number field allows and how fast it drags.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NumberRange {
    pub min: f64,
    pub max: f64,
    pub speed: f64,
    pub unit: &'static str,
}

/// Who owns a row's number, for its diamond's name and its undo steps.
#[derive(Clone, Copy, Debug)]
pub struct Owner {
    /// Before the label in the diamond's name ("" gives "Key centre x").
    pub diamond_prefix: &'static str,
    /// Capitalised, before the label in the edit's undo step ("Collider").
    pub noun: &'static str,
}

/// A number a panel shows as a row, keyed or constant.
pub struct KeyedNumber<'a> {
    pub owner: Owner,
    pub label: &'a str,
    /// The number as the scene holds it now.
    pub param: &'a Param,
    pub range: NumberRange,
}

impl KeyedNumber<'_> {
    /// The label, value field and key diamond at `frame` (three cells of a
    /// grid row). Editing keys the number at `frame`, or changes a constant,
    /// in the scene's number `param_of` finds.
    pub fn row_ui(
        self,
        ui: &mut egui::Ui,
        w: &mut Workspace,
        frame: i32,
        param_of: impl Fn(&mut Scene) -> Option<&mut Param>,
    ) {
        let KeyedNumber { owner, label: label_text, param, range } = self;
        let keyed_here = key_at(param, frame).is_some();
        let keyed = matches!(param, Param::Keys(_));
        let mut value = sample(param, f64::from(frame));
        let label = ui.label(label_text).id;
        let field = number_field(ui.ctx(), &mut value)
            .range(range.min..=range.max)
            .speed(range.speed)
            .max_decimals(4)
            .suffix(range.unit);
        let response = ui.add(field).labelled_by(label);
        let hint = if keyed { "Keyed: click to add or remove the key at this frame" } else { "Key this number here" };
        let name = format!("Key {}{label_text}", owner.diamond_prefix);
        let toggle = icon_button(ui, Icon::Diamond { filled: keyed_here }, true, &name).on_hover_text(hint);
        let what = format!("{} {label_text}", owner.noun);
        if response.drag_started() {
            w.doc.begin_gesture(&what);
        }
        if response.changed() {
            let auto_key = w.session.auto_key();
            w.apply(&what, |s| {
                if let Some(p) = param_of(s) {
                    set_at_keying(p, frame, value, auto_key);
                }
            });
        }
        if toggle.clicked() {
            w.apply(&format!("Key {} number", owner.noun.to_lowercase()), |s| {
                if let Some(p) = param_of(s) {
                    toggle_key(p, frame);
                }
            });
        }
    }
}
