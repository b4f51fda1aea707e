//! Keeps typing and focus moves in separate frames, so a typed value lands
//! in the field it was typed into.
//!
//! egui moves keyboard focus while it draws a frame: a Tab (or a click
//! elsewhere) takes focus from a field as soon as that field is drawn, and
//! the field then no longer reads the frame's text events. When typing and
//! Tab arrive in one frame (a slow display, a fast typist, a test), the
//! typed text went to the *next* field instead. [`TypingPace`] cuts a
//! frame's events where typing meets a focus move and holds the rest for
//! the next frame, so each frame either types or moves focus, in the order
//! the user did it. Nothing is dropped or reordered.

use eframe::egui::{Event, Key, RawInput};

/// Events held back for the next frame.
#[derive(Default)]
pub struct TypingPace {
    held: Vec<Event>,
}

impl TypingPace {
    /// Puts the held events in front of `raw`'s new ones, then keeps only
    /// the first run that does not mix typing with a focus move; the rest
    /// is held. Returns whether events are held (the caller asks for
    /// another frame).
    pub fn pace(&mut self, raw: &mut RawInput) -> bool {
        if !self.held.is_empty() {
            let new = std::mem::take(&mut raw.events);
            raw.events = std::mem::take(&mut self.held);
            raw.events.extend(new);
        }
        let cut = first_cut(&raw.events);
        if cut < raw.events.len() {
            self.held = raw.events.split_off(cut);
        }
        !self.held.is_empty()
    }

    /// Whether events wait for the next frame.
    pub fn holds_events(&self) -> bool {
        !self.held.is_empty()
    }
}

/// What an event does to a text field: types into it, moves focus away
/// from it, or neither (pointer motion, releases, window events).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Typing,
    FocusMove,
    Other,
}

fn kind(event: &Event) -> Kind {
    match event {
        Event::Key { key: Key::Tab, pressed: true, .. } => Kind::FocusMove,
        Event::PointerButton { pressed: true, .. } => Kind::FocusMove,
        Event::Key { pressed: true, .. } | Event::Text(_) | Event::Paste(_) | Event::Copy | Event::Cut => Kind::Typing,
        Event::Ime(_) => Kind::Typing,
        _ => Kind::Other,
    }
}

/// The index of the first event that must wait for the next frame: the
/// first focus move after typing, the first typing after a focus move, or a
/// second Tab (egui moves focus once a frame); `events.len()` when the
/// frame may take them all.
fn first_cut(events: &[Event]) -> usize {
    let mut seen = Kind::Other;
    let mut tabbed = false;
    for (i, event) in events.iter().enumerate() {
        let k = kind(event);
        if k == Kind::Other {
            continue;
        }
        let tab = matches!(event, Event::Key { key: Key::Tab, pressed: true, .. });
        if (seen != Kind::Other && k != seen) || (tab && tabbed) {
            return i;
        }
        seen = k;
        tabbed |= tab;
    }
    events.len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::egui::{Modifiers, PointerButton, pos2};

    fn key(key: Key, pressed: bool) -> Event {
        Event::Key { key, physical_key: None, pressed, repeat: false, modifiers: Modifiers::NONE }
    }

    fn text(s: &str) -> Event {
        Event::Text(s.to_owned())
    }

    fn press() -> Event {
        Event::PointerButton {
            pos: pos2(1.0, 1.0),
            button: PointerButton::Primary,
            pressed: true,
            modifiers: Modifiers::NONE,
        }
    }

    fn frames(mut events: Vec<Event>) -> Vec<Vec<Event>> {
        let mut pace = TypingPace::default();
        let mut out = Vec::new();
        loop {
            let mut raw = RawInput { events: std::mem::take(&mut events), ..Default::default() };
            let held = pace.pace(&mut raw);
            out.push(raw.events);
            if !held {
                return out;
            }
        }
    }

    #[test]
    fn typing_alone_stays_in_one_frame() {
        let events = vec![text("3"), text("0"), key(Key::Backspace, true), key(Key::Backspace, false)];
        assert_eq!(frames(events.clone()), vec![events]);
    }

    #[test]
    fn text_then_tab_then_text_takes_three_frames_in_order() {
        let events = vec![text("30"), key(Key::Tab, true), key(Key::Tab, false), text("24"), key(Key::Enter, true)];
        let got = frames(events);
        assert_eq!(
            got,
            vec![
                vec![text("30")],
                vec![key(Key::Tab, true), key(Key::Tab, false)],
                vec![text("24"), key(Key::Enter, true)],
            ]
        );
    }

    #[test]
    fn a_click_after_typing_waits_for_the_typing() {
        let release = Event::PointerButton {
            pos: pos2(1.0, 1.0),
            button: PointerButton::Primary,
            pressed: false,
            modifiers: Modifiers::NONE,
        };
        let moved = Event::PointerMoved(pos2(1.0, 1.0));
        let got = frames(vec![text("7"), moved.clone(), press(), release.clone()]);
        assert_eq!(got, vec![vec![text("7"), moved], vec![press(), release]]);
    }

    #[test]
    fn new_events_queue_behind_held_ones() {
        let mut pace = TypingPace::default();
        let mut raw = RawInput { events: vec![text("1"), key(Key::Tab, true)], ..Default::default() };
        assert!(pace.pace(&mut raw));
        assert_eq!(raw.events, vec![text("1")]);
        let mut raw = RawInput { events: vec![text("2")], ..Default::default() };
        assert!(pace.pace(&mut raw));
        assert_eq!(raw.events, vec![key(Key::Tab, true)]);
        let mut raw = RawInput::default();
        assert!(!pace.pace(&mut raw));
        assert_eq!(raw.events, vec![text("2")]);
        assert!(!pace.holds_events());
    }

    #[test]
    fn each_tab_gets_its_own_frame_and_clicks_share_one() {
        let tab = || key(Key::Tab, true);
        let got = frames(vec![tab(), press(), tab(), press(), press()]);
        assert_eq!(got, vec![vec![tab(), press()], vec![tab(), press(), press()]]);
    }
}
