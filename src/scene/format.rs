//! Writing a scene as RON that reads well by hand.
//!
//! ron's own pretty printer puts every tuple element and struct field on its
//! own line. Instead, the scene is serialised compactly and then laid out like
//! rustfmt would: a bracketed value stays on one line when it fits in
//! [`MAX_LINE_CHARS`], otherwise its entries go one per line, indented by four
//! spaces, each followed by a comma. Newtype wrappers hug their content
//! (`Sway((` … `)),`). Only whitespace changes, so the text parses back to the
//! same scene.

use super::locate::{Scanned, TokenKind};
use super::types::Scene;

/// Lines are kept at most this long where the structure allows.
pub const MAX_LINE_CHARS: usize = 100;
const INDENT: &str = "    ";

/// The scene as pretty RON ending with a newline. Constant parameters are
/// plain numbers; every field is written, defaults included, so the file shows
/// what can be changed. Parses back to an equal [`Scene`] (NaN aside).
pub fn to_ron_string(scene: &Scene) -> String {
    let compact = ron::Options::default()
        .to_string(scene)
        .expect("a Scene always serialises to RON (no maps with non-string keys, no I/O)");
    let mut out = layout(&compact);
    out.push('\n');
    out
}

/// Re-lays out compact RON text (no comments) as described in the module docs.
pub(crate) fn layout(compact: &str) -> String {
    let scanned = Scanned::new(compact);
    let mut layout = Layout { scanned: &scanned, out: String::new() };
    if !scanned.tokens.is_empty() {
        let end = scanned.value_end(0);
        layout.value(0, 0, 0, true);
        // Anything ron wrote after the value (there should be nothing).
        for index in end..scanned.tokens.len() {
            layout.out.push_str(scanned.token_text(index));
        }
    }
    layout.out
}

struct Layout<'s, 'a> {
    scanned: &'s Scanned<'a>,
    out: String,
}

impl Layout<'_, '_> {
    /// The value's text on one line, with `, ` and `: ` spacing.
    fn flat(&self, start: usize, end: usize) -> String {
        let mut text = String::new();
        for index in start..end {
            text.push_str(self.scanned.token_text(index));
            match self.scanned.tokens[index].kind {
                TokenKind::Comma | TokenKind::Colon => text.push(' '),
                _ => {}
            }
        }
        text
    }

    fn column(&self) -> usize {
        self.out.rsplit('\n').next().map_or(0, |line| line.chars().count())
    }

    /// Writes the value starting at token `start`; `trailing` is the number of
    /// characters that will follow it on the line (the comma).
    fn value(&mut self, start: usize, depth: usize, trailing: usize, force_break: bool) {
        let end = self.scanned.value_end(start);
        let flat = self.flat(start, end);
        let fits = self.column() + flat.chars().count() + trailing <= MAX_LINE_CHARS;
        let Some(open) = self.scanned.value_group(start) else {
            self.out.push_str(&flat);
            return;
        };
        // A list of two or more structs or tuples puts each on its own line.
        let entries = self.scanned.entries(open);
        let list_of_groups = self.scanned.tokens[open].kind == TokenKind::Open('[')
            && entries.len() > 1
            && entries.iter().all(|e| self.scanned.value_group(e.value).is_some());
        if fits && !force_break && !list_of_groups {
            self.out.push_str(&flat);
            return;
        }
        for index in start..=open {
            self.out.push_str(self.scanned.token_text(index));
        }
        let close = end - 1;
        match entries.as_slice() {
            [] => {}
            // A newtype wrapper such as `Sway((…))`: hug the inner value.
            [only] if open > start && only.name.is_none() && self.scanned.value_group(only.value).is_some() => {
                self.value(only.value, depth, trailing + 1, force_break);
            }
            _ => {
                let inner = INDENT.repeat(depth + 1);
                for entry in &entries {
                    self.out.push('\n');
                    self.out.push_str(&inner);
                    if entry.name.is_some() {
                        // The name token as written (keeps any `r#` prefix).
                        self.out.push_str(self.scanned.token_text(entry.value - 2));
                        self.out.push_str(": ");
                    }
                    self.value(entry.value, depth + 1, 1, false);
                    self.out.push(',');
                }
                self.out.push('\n');
                self.out.push_str(&INDENT.repeat(depth));
            }
        }
        if close < self.scanned.tokens.len() && matches!(self.scanned.tokens[close].kind, TokenKind::Close(_)) {
            self.out.push_str(self.scanned.token_text(close));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{
        Cloth, ClothTexture, Ease, Key, Layer, Param, ParamKey, Pin, RelaxSettings, Sway, Timeline, View, Wave,
        WaveAxis, parse,
    };

    fn scene() -> Scene {
        let key = |frame: i32, ease: Ease| Key {
            frame,
            pins: vec![Pin::at((0, 0), (-1.0, 2.0, 0.0)), Pin::at((32, 0), (1.0, 2.0, 1e-7))],
            elasticity: 1.25,
            stiffness: 0.0,
            relax: RelaxSettings { iterations: 0, tolerance: 1e-9 },
            ease,
            inbetween_relax: 3,
            thickness: crate::scene::DEFAULT_THICKNESS_M,
            friction: crate::scene::DEFAULT_FRICTION,
            placement: None,
        };
        let animated = Param::Keys(
            Ease::ALL
                .iter()
                .enumerate()
                .map(|(i, &ease)| ParamKey { frame: 10 * i as i32, value: 0.1 * i as f64 - 0.3, ease })
                .collect(),
        );
        Scene {
            name: "Round \"trip\" (ü) // not a comment".into(),
            cloth: Cloth { texture: ClothTexture::Carpet, ..Cloth::new((2.0, 1.5), (33, 25)) },
            timeline: Timeline { fps: 29.97, start: -10, end: 200 },
            keys: Ease::ALL.iter().enumerate().map(|(i, &ease)| key(20 * i as i32, ease)).collect(),
            layers: vec![
                // Fields left out are at their start values; every one is written all the same.
                Layer::Sway(Sway {
                    name: "breeze".into(),
                    enabled: false,
                    weight: Param::Constant(0.75),
                    magnitude: animated.clone(),
                    direction: (0.0, 0.0, 1.0),
                    phase: std::f64::consts::FRAC_PI_2.into(),
                    falloff: 2.0.into(),
                    ..Sway::with_start_values()
                }),
                Layer::Wave(Wave {
                    weight: animated,
                    magnitude: 0.05.into(),
                    frequency: 6.0.into(),
                    speed: (-2.0).into(),
                    direction_deg: 45.0.into(),
                    axis: WaveAxis::Fixed((0.0, 1.0, 0.0)),
                    ..Wave::with_start_values()
                }),
                Layer::Wave(Wave {
                    name: "normal".into(),
                    magnitude: 0.01.into(),
                    frequency: 1.0.into(),
                    speed: 1.0.into(),
                    ..Wave::with_start_values()
                }),
            ],
            view: Some(View {
                target: (0.5, 1.2, -0.25),
                yaw_deg: 30.0,
                pitch_deg: -12.5,
                distance_m: 4.0,
                fov_y_deg: 40.0,
                frame: Some(36),
                follow: true,
                through_camera: true,
            }),
            ..Scene::default()
        }
    }

    #[test]
    fn every_variant_round_trips_and_constants_are_plain_numbers() {
        let scene = scene();
        assert_eq!(scene.validate(), Ok(()));
        let text = to_ron_string(&scene);
        assert_eq!(parse(&text, "round trip").map_err(|e| e.to_string()), Ok(scene), "{text}");
        assert!(text.contains("\n            weight: 0.75,\n"), "{text}");
        assert!(text.contains("\n            magnitude: 0.05,\n"), "{text}");
        assert!(text.contains("axis: Fixed((0.0, 1.0, 0.0)),"), "{text}");
        assert!(text.contains("ease: Bezier(0.42, 0.0, 0.58, 1.0)"), "{text}");
        assert!(text.lines().all(|line| line.chars().count() <= MAX_LINE_CHARS), "{text}");
        assert!(text.ends_with(")\n"));
    }

    #[test]
    fn short_groups_stay_on_one_line() {
        assert_eq!(
            layout("(version:1,cloth:(size:(2.0,1.5),grid:(33,25)))"),
            "(\n    version: 1,\n    cloth: (size: (2.0, 1.5), grid: (33, 25)),\n)"
        );
    }

    #[test]
    fn long_groups_break_and_newtypes_hug() {
        let long = format!("(layers:[Sway((name:\"{}\",magnitude:0.2))])", "x".repeat(90));
        let expected = format!(
            "(\n    layers: [\n        Sway((\n            name: \"{}\",\n            magnitude: 0.2,\n        )),\n    ],\n)",
            "x".repeat(90)
        );
        assert_eq!(layout(&long), expected);
    }

    #[test]
    fn strings_with_brackets_and_commas_are_untouched() {
        assert_eq!(layout("(name:\"a, (b]: c\")"), "(\n    name: \"a, (b]: c\",\n)");
    }
}
