//! How clicks and boxes change the pin selection, the same in the viewport
//! and the grid editor, as in Blender and Maya: a click selects what it hits
//! (and nothing else), Shift adds, Ctrl toggles, a click on nothing clears,
//! a box selects what it holds (Shift adds it, Ctrl toggles it).

use eframe::egui::Modifiers;

/// What a click or box does to the selection, from the modifiers held.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pick {
    /// No modifier: the picked pins become the selection.
    Replace,
    /// Shift: the picked pins join the selection.
    Add,
    /// Ctrl (Cmd on a Mac): each picked pin switches in or out.
    Toggle,
}

impl Pick {
    pub fn from_modifiers(modifiers: Modifiers) -> Pick {
        if modifiers.command {
            Pick::Toggle
        } else if modifiers.shift {
            Pick::Add
        } else {
            Pick::Replace
        }
    }
}

/// Applies a pick of `points` (one pin clicked, or a box's pins) to `selection`.
pub fn pick(selection: &mut Vec<(u32, u32)>, points: &[(u32, u32)], how: Pick) {
    match how {
        Pick::Replace => {
            selection.clear();
            selection.extend(points.iter().copied());
        }
        Pick::Add => {
            for point in points {
                if !selection.contains(point) {
                    selection.push(*point);
                }
            }
        }
        Pick::Toggle => {
            for point in points {
                match selection.iter().position(|p| p == point) {
                    Some(at) => {
                        selection.remove(at);
                    }
                    None => selection.push(*point),
                }
            }
        }
    }
}

/// A click that hit no pin or cloth point: clears the selection unless
/// Shift or Ctrl says the user is adding to it.
pub fn click_on_nothing(selection: &mut Vec<(u32, u32)>, how: Pick) {
    if how == Pick::Replace {
        selection.clear();
    }
}

/// The selection after a new pin at `point` is made by a click: a plain or
/// Ctrl+click pins without selecting and leaves the selection as it was
/// (the user pinned, and picked nothing, so the pin fields keep showing
/// what they showed); Shift+click pins and adds the pin.
pub fn after_pinning(selection: &mut Vec<(u32, u32)>, point: (u32, u32), how: Pick) {
    if how == Pick::Add {
        pick(selection, &[point], Pick::Add);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: (u32, u32) = (0, 0);
    const B: (u32, u32) = (32, 0);
    const C: (u32, u32) = (16, 16);

    #[test]
    fn modifiers_choose_the_pick() {
        assert_eq!(Pick::from_modifiers(Modifiers::NONE), Pick::Replace);
        assert_eq!(Pick::from_modifiers(Modifiers::SHIFT), Pick::Add);
        assert_eq!(Pick::from_modifiers(Modifiers::COMMAND), Pick::Toggle);
        assert_eq!(Pick::from_modifiers(Modifiers::COMMAND | Modifiers::SHIFT), Pick::Toggle);
    }

    #[test]
    fn click_selects_shift_adds_ctrl_toggles() {
        let mut selection = vec![C];
        pick(&mut selection, &[A], Pick::Replace);
        assert_eq!(selection, [A]);
        pick(&mut selection, &[B], Pick::Add);
        pick(&mut selection, &[B], Pick::Add);
        assert_eq!(selection, [A, B], "Shift+click twice adds once, never takes out");
        pick(&mut selection, &[A], Pick::Toggle);
        assert_eq!(selection, [B]);
        pick(&mut selection, &[A, C], Pick::Toggle);
        assert_eq!(selection, [B, A, C]);
        click_on_nothing(&mut selection, Pick::Add);
        assert_eq!(selection.len(), 3);
        click_on_nothing(&mut selection, Pick::Replace);
        assert!(selection.is_empty());
    }

    #[test]
    fn pinning_two_corners_then_clicking_and_shift_clicking_them_selects_both() {
        // New pins are not selected, and the selection stays as it was.
        let mut selection = vec![C];
        after_pinning(&mut selection, A, Pick::Replace);
        after_pinning(&mut selection, B, Pick::Replace);
        assert_eq!(selection, [C], "a plain click pins without selecting or clearing");
        pick(&mut selection, &[A], Pick::Replace);
        pick(&mut selection, &[B], Pick::Add);
        assert_eq!(selection, [A, B]);
        after_pinning(&mut selection, C, Pick::Add);
        assert_eq!(selection, [A, B, C], "Shift+click pins and adds");
        after_pinning(&mut selection, (1, 1), Pick::Toggle);
        assert_eq!(selection, [A, B, C]);
    }
}
