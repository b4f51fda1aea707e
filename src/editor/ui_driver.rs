//! Test support: drives a piece of egui UI through frames the way a user
//! would, finding widgets by their accessible labels as egui_kittest does,
//! with nothing but an `egui::Context` (no window, no GPU).

use eframe::egui::accesskit::{self, NodeId, Role};
use eframe::egui::{self, Event, Key, Modifiers, Pos2, RawInput, Rect, vec2};

/// Shows `state` with `show` every frame until it returns an outcome.
pub(crate) struct UiDriver<S, O> {
    pub state: S,
    show: fn(&mut S, &egui::Context) -> Option<O>,
    ctx: egui::Context,
    outcome: Option<O>,
    /// The accessibility tree of the last frame.
    nodes: Vec<(NodeId, accesskit::Node)>,
    time: f64,
}

impl<S, O: Clone> UiDriver<S, O> {
    pub fn new(state: S, show: fn(&mut S, &egui::Context) -> Option<O>) -> Self {
        let ctx = egui::Context::default();
        ctx.enable_accesskit();
        let mut driver = UiDriver { state, show, ctx, outcome: None, nodes: Vec::new(), time: 0.0 };
        // A modal's first frame only measures it: nothing is shown yet.
        driver.frame(Vec::new());
        driver
    }

    /// Runs a frame with `events`, then one without so the screen shows what
    /// they changed (egui code acts on input after drawing); returns the
    /// outcome so far.
    pub fn frame(&mut self, events: Vec<Event>) -> Option<O> {
        self.run(events);
        self.run(Vec::new())
    }

    fn run(&mut self, events: Vec<Event>) -> Option<O> {
        self.time += 0.05;
        let input = RawInput {
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, vec2(1024.0, 768.0))),
            time: Some(self.time),
            events,
            ..RawInput::default()
        };
        let (state, show, outcome) = (&mut self.state, self.show, &mut self.outcome);
        let output = self.ctx.run_pass(input, |ctx| {
            if outcome.is_none() {
                *outcome = show(state, ctx);
            }
        });
        self.nodes = output.platform_output.accesskit_update.map(|u| u.nodes).unwrap_or_default();
        self.outcome.clone()
    }

    /// The widget named `label`: by its own label, or by a visible label it
    /// is `labelled_by` (a text field beside its caption).
    pub fn find(&self, label: &str) -> Option<(NodeId, &accesskit::Node)> {
        let labels: Vec<NodeId> =
            self.nodes.iter().filter(|(_, n)| text_of(n) == Some(label)).map(|(id, _)| *id).collect();
        let labelled = self.nodes.iter().find(|(_, n)| n.labelled_by().iter().any(|l| labels.contains(l)));
        labelled
            .or_else(|| self.nodes.iter().find(|(id, n)| labels.contains(id) && n.role() != Role::Label))
            .map(|(id, n)| (*id, n))
    }

    pub fn exists(&self, label: &str) -> bool {
        self.find(label).is_some()
    }

    /// A mouse click at the widget's centre (which also takes keyboard focus
    /// from a text field, as a real click does).
    pub fn click(&mut self, label: &str) -> Option<O> {
        self.clicks(label, 1)
    }

    /// Two clicks in quick succession at the widget's centre.
    pub fn double_click(&mut self, label: &str) -> Option<O> {
        self.clicks(label, 2)
    }

    fn clicks(&mut self, label: &str, count: usize) -> Option<O> {
        let (_, node) = self.find(label).unwrap_or_else(|| panic!("no widget labelled {label:?}"));
        let bounds = node.bounds().expect("widget bounds");
        let pos = Pos2::new(((bounds.x0 + bounds.x1) / 2.0) as f32, ((bounds.y0 + bounds.y1) / 2.0) as f32);
        let button = |pressed| Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        };
        // A pause first, so an earlier click does not pair with these.
        self.time += 1.0;
        self.frame(vec![Event::PointerMoved(pos)]);
        for _ in 0..count {
            self.frame(vec![button(true), button(false)]);
        }
        self.outcome.clone()
    }

    /// Gives the widget keyboard focus, as Tab would.
    pub fn focus(&mut self, label: &str) -> Option<O> {
        let (target, _) = self.find(label).unwrap_or_else(|| panic!("no widget labelled {label:?}"));
        let request = accesskit::ActionRequest {
            action: accesskit::Action::Focus,
            target_tree: accesskit::TreeId::ROOT,
            target_node: target,
            data: None,
        };
        self.frame(vec![Event::AccessKitActionRequest(request)])
    }

    pub fn type_text(&mut self, text: &str) -> Option<O> {
        self.frame(vec![Event::Text(text.to_owned())])
    }

    pub fn press(&mut self, key: Key) -> Option<O> {
        self.press_with(Modifiers::NONE, key)
    }

    pub fn press_with(&mut self, modifiers: Modifiers, key: Key) -> Option<O> {
        let event = |pressed| Event::Key { key, physical_key: None, pressed, repeat: false, modifiers };
        self.frame(vec![event(true), event(false)])
    }

    /// The text in the widget named `label` (a text field's contents).
    pub fn value_of(&self, label: &str) -> Option<String> {
        self.find(label).and_then(|(_, node)| node.value().map(str::to_owned))
    }

    /// Whether some text on screen contains `fragment`.
    pub fn shows(&self, fragment: &str) -> bool {
        self.nodes.iter().any(|(_, n)| {
            n.value().is_some_and(|v| v.contains(fragment)) || n.label().is_some_and(|l| l.contains(fragment))
        })
    }
}

/// The text naming a node: a `Role::Label` node keeps its text in `value`.
fn text_of(node: &accesskit::Node) -> Option<&str> {
    if node.role() == Role::Label { node.value() } else { node.label() }
}
